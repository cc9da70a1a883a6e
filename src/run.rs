//! The driver: a problem, a scheme, a loop, and observers that see each step.
//!
//! Observers state what they need ([`Needs`]); the driver computes only that (energy, exact L²
//! error) once per step and hands it to all of them. Recording, summaries, progress bars and
//! files are observers or live at the edge (see `output`); nothing here does I/O.

use crate::assembly::{AssemblyError, Bar, BarSystem};
use crate::exact::ImpactingBar;
use crate::norms;
use crate::scene::{Column, Formulation, Initial, Scene, SchemeSpec};
use crate::schemes::{BackwardEuler, Hybrid, Newmark, NewmarkReduced, PaoliSchatzman, Scheme, SchemeError, StateView};
use serde::Serialize;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum RunError {
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error(transparent)]
    Scheme(#[from] SchemeError),
}

/// A discretised problem: the system, its initial data and (if known) its exact solution.
#[derive(Debug, Clone)]
pub struct Problem {
    pub system: BarSystem,
    pub u0: Vec<f64>,
    pub v0: Vec<f64>,
    pub exact: Option<ImpactingBar>,
}

impl Problem {
    /// The paper's benchmark (u⁰ = (L−x)/2, v⁰ = 0) with a constant body force.
    pub fn from_scene(scene: &Scene) -> Result<Problem, RunError> {
        let bar = Bar { length: scene.bar.length, elements: scene.bar.elements };
        let system = BarSystem::new(bar, &scene.mass, scene.bar.force)?;
        match scene.bar.initial {
            Initial::Paper => {
                let exact = ImpactingBar { length: bar.length };
                let u0 = system.interpolate(|x| exact.initial_displacement(x));
                let v0 = vec![0.0; bar.elements];
                Ok(Problem { system, u0, v0, exact: scene.has_exact_solution().then_some(exact) })
            }
        }
    }

    /// The benchmark problem for a mass on a bar of length L with m elements (f = 0).
    pub fn benchmark(length: f64, elements: usize, mass: &crate::mass::MassKind) -> Result<Problem, RunError> {
        let system = BarSystem::new(Bar { length, elements }, mass, 0.0)?;
        let exact = ImpactingBar { length };
        let u0 = system.interpolate(|x| exact.initial_displacement(x));
        Ok(Problem { system, u0, v0: vec![0.0; elements], exact: Some(exact) })
    }

    /// Builds the scheme of a scene on this problem (factors its matrices once).
    pub fn scheme(&self, spec: &SchemeSpec, dt: f64) -> Result<Box<dyn Scheme>, SchemeError> {
        let (s, u, v) = (&self.system, self.u0.clone(), self.v0.clone());
        Ok(match *spec {
            SchemeSpec::CrankNicolson { formulation } => newmark(s, 0.25, 0.5, formulation, dt, u, v)?,
            SchemeSpec::Newmark { beta, gamma, formulation } => newmark(s, beta, gamma, formulation, dt, u, v)?,
            SchemeSpec::BackwardEuler => Box::new(BackwardEuler::new(&s.system, dt, u, v)?),
            SchemeSpec::PaoliSchatzman { beta, restitution } => {
                Box::new(PaoliSchatzman::new(s, beta, restitution, dt, u, v)?)
            }
            SchemeSpec::Hybrid => Box::new(Hybrid::new(&s.system, dt, u, v)?),
        })
    }
}

fn newmark(
    s: &BarSystem,
    beta: f64,
    gamma: f64,
    formulation: Formulation,
    dt: f64,
    u: Vec<f64>,
    v: Vec<f64>,
) -> Result<Box<dyn Scheme>, SchemeError> {
    Ok(match formulation {
        Formulation::Full => Box::new(Newmark::new(&s.system, beta, gamma, dt, u, v)?),
        Formulation::Reduced => Box::new(NewmarkReduced::new(s, beta, gamma, dt, u, v)?),
    })
}

/// What an observer needs computed at each step, beyond the state itself.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Needs {
    /// The discrete energy ½VᵀMV + ½UᵀSU − UᵀF.
    pub energy: bool,
    /// The exact L²(0,L) error and the L² norm of the exact solution's nodal interpolant.
    pub l2: bool,
}

impl Needs {
    /// What either needs.
    pub fn or(self, o: Needs) -> Needs {
        Needs { energy: self.energy || o.energy, l2: self.l2 || o.l2 }
    }
}

/// What the driver hands to observers at each step. Quantities not needed are NaN.
#[derive(Debug, Clone, Copy)]
pub struct Sample<'a> {
    pub state: StateView<'a>,
    pub exact: Option<&'a ImpactingBar>,
    pub energy: f64,
    pub l2_error: f64,
    /// ‖I_h u(·, t_n)‖_{L²}: the norm of the nodal interpolant of the exact solution.
    pub exact_interp_norm: f64,
}

pub trait Observer {
    fn needs(&self) -> Needs {
        Needs::default()
    }
    fn observe(&mut self, sample: &Sample);
}

/// Runs `steps` steps, showing every state (t_0 included) to every observer.
pub fn integrate(
    problem: &Problem,
    scheme: &mut dyn Scheme,
    steps: usize,
    observers: &mut [&mut dyn Observer],
) -> Result<(), SchemeError> {
    let needs = observers.iter().fold(Needs::default(), |n, o| n.or(o.needs()));
    let sys = &problem.system;
    let mut interp = if needs.l2 { vec![0.0; sys.m()] } else { Vec::new() };
    let mut show = |scheme: &dyn Scheme, observers: &mut [&mut dyn Observer]| {
        let state = scheme.state();
        let energy = if needs.energy { sys.energy(state.u, state.v) } else { f64::NAN };
        let (l2_error, exact_interp_norm) = match (needs.l2, &problem.exact) {
            (true, Some(ex)) => {
                for (i, e) in interp.iter_mut().enumerate() {
                    *e = ex.u(sys.bar.x(i), state.t);
                }
                (norms::l2_error(&sys.bar, state.u, ex, state.t), norms::l2_norm_p1(&sys.bar, &interp))
            }
            _ => (f64::NAN, f64::NAN),
        };
        let sample = Sample { state, exact: problem.exact.as_ref(), energy, l2_error, exact_interp_norm };
        for o in observers.iter_mut() {
            o.observe(&sample);
        }
    };
    show(scheme, observers);
    for _ in 0..steps {
        scheme.step()?;
        show(scheme, observers);
    }
    Ok(())
}

/// Records the requested columns every `every` steps (t_0 included).
#[derive(Debug, Clone)]
pub struct SeriesRecorder {
    pub columns: Vec<Column>,
    pub every: usize,
    /// Row-major: t, then one value per column.
    pub rows: Vec<f64>,
}

impl SeriesRecorder {
    pub fn new(columns: Vec<Column>, every: usize, expected_rows: usize) -> Self {
        let rows = Vec::with_capacity(expected_rows * (columns.len() + 1));
        Self { columns, every: every.max(1), rows }
    }

    pub fn width(&self) -> usize {
        self.columns.len() + 1
    }

    /// Iterates over recorded rows (t first).
    pub fn iter_rows(&self) -> impl Iterator<Item = &[f64]> {
        self.rows.chunks(self.width())
    }

    /// The recorded values of one column (None if not recorded).
    pub fn column(&self, c: Column) -> Option<Vec<f64>> {
        let k = self.columns.iter().position(|&x| x == c)? + 1;
        Some(self.iter_rows().map(|r| r[k]).collect())
    }

    pub fn times(&self) -> Vec<f64> {
        self.iter_rows().map(|r| r[0]).collect()
    }
}

impl Observer for SeriesRecorder {
    fn needs(&self) -> Needs {
        Needs { energy: self.columns.contains(&Column::Energy), l2: self.columns.contains(&Column::L2Error) }
    }

    fn observe(&mut self, s: &Sample) {
        if self.columns.is_empty() || !s.state.n.is_multiple_of(self.every) {
            return;
        }
        let st = s.state;
        self.rows.push(st.t);
        for &c in &self.columns {
            self.rows.push(match c {
                Column::U0 => st.u[0],
                Column::U1 => st.u[1],
                Column::Lambda => st.lambda[0],
                Column::Energy => s.energy,
                Column::L2Error => s.l2_error,
                Column::ExactU0 => s.exact.map_or(f64::NAN, |e| e.u0(st.t)),
                Column::ExactLambda => s.exact.map_or(f64::NAN, |e| e.lambda(st.t)),
            });
        }
    }
}

/// The summary of a run (`summary.json`), accumulated in the step loop.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub steps: usize,
    pub h: f64,
    pub dt: f64,
    /// max over t_n of ‖u_h(t_n) − u(t_n)‖_{L²(0,L)} (null without exact solution).
    pub linf_l2_error: Option<f64>,
    /// `linf_l2_error` / max over t_n of ‖I_h u(t_n)‖_{L²(0,L)}.
    pub linf_l2_error_relative: Option<f64>,
    /// max over n of |u_0ⁿ − u(0, t_n)|.
    pub max_contact_error: Option<f64>,
    /// sqrt(Σ_n w_n Δt (λⁿ − λ(t_n))²) with trapezoidal weights w_n: the L²(0,T) error of λ.
    pub l2_lambda_error: Option<f64>,
    pub energy_initial: f64,
    pub energy_final: f64,
    pub energy_min: f64,
    pub energy_max: f64,
    /// Exact energy L/8 (null without exact solution).
    pub energy_exact: Option<f64>,
    /// First t_n with u_0ⁿ ≤ 0.
    pub first_impact_time: Option<f64>,
    /// First t_n after the first impact with u_0ⁿ > 0.
    pub first_release_time: Option<f64>,
    /// `first_impact_time` − L (exact first impact), null if no impact or no exact solution.
    pub impact_time_shift: Option<f64>,
    /// `first_release_time` − 2L (exact release), null if no release or no exact solution.
    pub release_time_shift: Option<f64>,
    pub final_u0: f64,
    /// min over n of u_0ⁿ (≥ 0 by complementarity).
    pub min_u0: f64,
    /// max over n of λⁿ (≤ 0 by complementarity).
    pub max_lambda: f64,
    /// max over n of |u_0ⁿ λⁿ| (0 by complementarity).
    pub max_complementarity_product: f64,
    pub wall_seconds: f64,
}

/// Accumulates a [`Summary`] in the step loop (O(1) memory).
#[derive(Debug, Clone)]
pub struct SummaryObserver {
    steps: usize,
    h: f64,
    dt: f64,
    linf_l2: f64,
    linf_interp: f64,
    max_contact: f64,
    lambda_sq: f64,
    has_exact: bool,
    energy: [f64; 4],
    first_impact: Option<f64>,
    first_release: Option<f64>,
    final_u0: f64,
    min_u0: f64,
    max_lambda: f64,
    max_product: f64,
    length: f64,
    started: std::time::Instant,
    with_l2: bool,
}

impl SummaryObserver {
    /// `with_l2 = false` skips the per-step L² error (the L² fields are then null).
    pub fn new(problem: &Problem, steps: usize, dt: f64, with_l2: bool) -> Self {
        Self {
            steps,
            h: problem.system.h(),
            dt,
            linf_l2: 0.0,
            linf_interp: 0.0,
            max_contact: 0.0,
            lambda_sq: 0.0,
            has_exact: problem.exact.is_some(),
            energy: [f64::NAN, f64::NAN, f64::INFINITY, f64::NEG_INFINITY],
            first_impact: None,
            first_release: None,
            final_u0: f64::NAN,
            min_u0: f64::INFINITY,
            max_lambda: f64::NEG_INFINITY,
            max_product: 0.0,
            length: problem.system.bar.length,
            started: std::time::Instant::now(),
            with_l2,
        }
    }

    pub fn finish(&self) -> Summary {
        let exact = |v: f64| self.has_exact.then_some(v);
        let l2 = |v: f64| (self.has_exact && self.with_l2).then_some(v);
        Summary {
            steps: self.steps,
            h: self.h,
            dt: self.dt,
            linf_l2_error: l2(self.linf_l2),
            linf_l2_error_relative: l2(self.linf_l2 / self.linf_interp),
            max_contact_error: exact(self.max_contact),
            l2_lambda_error: exact(self.lambda_sq.sqrt()),
            energy_initial: self.energy[0],
            energy_final: self.energy[1],
            energy_min: self.energy[2],
            energy_max: self.energy[3],
            energy_exact: exact(self.length / 8.0),
            first_impact_time: self.first_impact,
            first_release_time: self.first_release,
            impact_time_shift: self.first_impact.filter(|_| self.has_exact).map(|t| t - self.length),
            release_time_shift: self.first_release.filter(|_| self.has_exact).map(|t| t - 2.0 * self.length),
            final_u0: self.final_u0,
            min_u0: self.min_u0,
            max_lambda: self.max_lambda,
            max_complementarity_product: self.max_product,
            wall_seconds: self.started.elapsed().as_secs_f64(),
        }
    }
}

impl Observer for SummaryObserver {
    fn needs(&self) -> Needs {
        Needs { energy: true, l2: self.with_l2 && self.has_exact }
    }

    fn observe(&mut self, s: &Sample) {
        let st = s.state;
        if st.n == 0 {
            self.energy[0] = s.energy;
        }
        self.energy[1] = s.energy;
        self.energy[2] = self.energy[2].min(s.energy);
        self.energy[3] = self.energy[3].max(s.energy);
        let u0 = st.u[0];
        self.final_u0 = u0;
        self.min_u0 = self.min_u0.min(u0);
        let lambda = st.lambda[0];
        self.max_lambda = self.max_lambda.max(lambda);
        self.max_product = self.max_product.max((u0 * lambda).abs());
        if self.first_impact.is_none() {
            if u0 <= 0.0 {
                self.first_impact = Some(st.t);
            }
        } else if self.first_release.is_none() && u0 > 0.0 {
            self.first_release = Some(st.t);
        }
        if let Some(ex) = s.exact {
            self.max_contact = self.max_contact.max((u0 - ex.u0(st.t)).abs());
            let w = if st.n == 0 || st.n == self.steps { 0.5 } else { 1.0 };
            self.lambda_sq += w * self.dt * (lambda - ex.lambda(st.t)).powi(2);
            if self.with_l2 {
                self.linf_l2 = self.linf_l2.max(s.l2_error);
                self.linf_interp = self.linf_interp.max(s.exact_interp_norm);
            }
        }
    }
}

/// Runs a scene: the summary always, plus the requested series.
pub fn run_scene(scene: &Scene, extra: &mut [&mut dyn Observer]) -> Result<(Summary, SeriesRecorder), RunError> {
    let problem = Problem::from_scene(scene)?;
    let mut scheme = problem.scheme(&scene.scheme, scene.time.dt)?;
    let steps = scene.time.steps;
    let mut summary = SummaryObserver::new(&problem, steps, scene.time.dt, scene.output.summary_l2);
    let rows = if scene.output.series.is_empty() { 0 } else { steps / scene.output.every + 1 };
    let mut series = SeriesRecorder::new(scene.output.series.clone(), scene.output.every, rows);
    let mut observers: Vec<&mut dyn Observer> = vec![&mut summary, &mut series];
    for o in extra.iter_mut() {
        observers.push(&mut **o);
    }
    integrate(&problem, scheme.as_mut(), steps, &mut observers)?;
    Ok((summary.finish(), series))
}
