//! The 2D driver: a plate problem, a scheme, a loop, and observers (the 1D [`crate::run`]
//! pattern with vector contact multipliers). Nothing here does I/O.

use super::assembly::{PlateAssemblyError, PlateSystem};
use super::mesh::{CellKind, Mesh2d, MeshError};
use super::norms;
use crate::exact::ImpactingBar;
use crate::mass::MassKind;
use crate::run::{Needs, Summary};
use crate::scene::{Formulation, SchemeSpec};
use crate::schemes::{BackwardEuler, Hybrid, Newmark, Scheme, SchemeError, StateView};
use thiserror::Error;

#[derive(Debug, Error)]
pub enum PlateRunError {
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Assembly(#[from] PlateAssemblyError),
    #[error(transparent)]
    Scheme(#[from] SchemeError),
    #[error("scheme.kind = \"{scheme}\" is not available for [plate] scenes: {reason}")]
    Unsupported { scheme: String, reason: &'static str },
    #[error("the 1D reference run failed: {0}")]
    Reference(String),
}

/// Initial data of the plate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlateInitial {
    /// u⁰ = (L − x)/2, v⁰ = 0: the 1D benchmark extended constantly in y (exact solution known
    /// for f = 0: the 1D one).
    Paper,
    /// u⁰ = (L − x)/2 · (1 + ½ cos(π y/H)), v⁰ = 0: y-dependent (no exact solution). The
    /// edge x = 0 starts at heights 3/4 (y = 0) to 1/4 (y = H) above the obstacle, so its parts
    /// hit it at different times and the contact state varies along Γ_C. `∂_y u⁰ = 0` on
    /// y = 0, H (compatible with the Neumann condition) and u⁰ = 0 on x = L.
    Bump,
}

impl PlateInitial {
    pub fn name(self) -> &'static str {
        match self {
            PlateInitial::Paper => "paper",
            PlateInitial::Bump => "bump",
        }
    }

    /// `u⁰(x, y)` on the plate (0, L) × (0, H).
    pub fn displacement(self, length: f64, height: f64, x: f64, y: f64) -> f64 {
        let base = (length - x) / 2.0;
        match self {
            PlateInitial::Paper => base,
            PlateInitial::Bump => base * (1.0 + 0.5 * (std::f64::consts::PI * y / height).cos()),
        }
    }
}

/// The geometry and discretisation of a plate run.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateSpec {
    pub length: f64,
    pub height: f64,
    pub nx: usize,
    pub ny: usize,
    pub cells: CellKind,
    pub initial: PlateInitial,
    pub force: f64,
}

/// A discretised plate problem: system, initial data and (if known) exact solution.
#[derive(Debug, Clone)]
pub struct PlateProblem {
    pub plate: PlateSystem,
    pub u0: Vec<f64>,
    pub v0: Vec<f64>,
    pub exact: Option<ImpactingBar>,
}

impl PlateProblem {
    /// The structured plate of `spec`.
    pub fn new(spec: &PlateSpec, mass: &MassKind) -> Result<Self, PlateRunError> {
        let mesh = Mesh2d::structured(spec.length, spec.height, spec.nx, spec.ny, spec.cells)?;
        Self::from_mesh(mesh, mass, spec.initial, spec.force)
    }

    /// Any mesh of (0, L) × (y_min, y_min + H) (e.g. a triangle mesh read from a file with
    /// [`Mesh2d::from_arrays`]); the initial data use `y − y_min`.
    pub fn from_mesh(mesh: Mesh2d, mass: &MassKind, initial: PlateInitial, force: f64) -> Result<Self, PlateRunError> {
        let (l, h) = (mesh.length, mesh.height);
        let ymin = mesh.points.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        let plate = PlateSystem::new(mesh, mass, force)?;
        let u0 = plate.interpolate(|x, y| initial.displacement(l, h, x, y - ymin));
        let v0 = vec![0.0; u0.len()];
        let exact = (initial == PlateInitial::Paper && force == 0.0).then_some(ImpactingBar { length: l });
        Ok(Self { plate, u0, v0, exact })
    }

    /// Builds the scheme (factors its matrices once). Paoli–Schatzman and the reduced Newmark
    /// formulation have no 2D port.
    pub fn scheme(&self, spec: &SchemeSpec, dt: f64) -> Result<Box<dyn Scheme>, PlateRunError> {
        let (s, u, v) = (&self.plate.system, self.u0.clone(), self.v0.clone());
        let reduced = || PlateRunError::Unsupported {
            scheme: spec.name().into(),
            reason: "formulation = \"reduced\" has no 2D port (the full formulation gives the same steps in 1D); use \"full\"",
        };
        Ok(match *spec {
            SchemeSpec::CrankNicolson { formulation: Formulation::Full } => {
                Box::new(Newmark::crank_nicolson(s, dt, u, v)?)
            }
            SchemeSpec::Newmark { beta, gamma, formulation: Formulation::Full } => {
                Box::new(Newmark::new(s, beta, gamma, dt, u, v)?)
            }
            SchemeSpec::CrankNicolson { .. } | SchemeSpec::Newmark { .. } => return Err(reduced()),
            SchemeSpec::BackwardEuler => Box::new(BackwardEuler::new(s, dt, u, v)?),
            SchemeSpec::Hybrid => Box::new(Hybrid::new(s, dt, u, v)?),
            SchemeSpec::PaoliSchatzman { .. } => {
                return Err(PlateRunError::Unsupported {
                    scheme: spec.name().into(),
                    reason: "Paoli-Schatzman is not ported to 2D (see the plate module docs)",
                });
            }
        })
    }
}

/// What the driver hands to observers at each step. Quantities not needed are NaN.
#[derive(Debug, Clone, Copy)]
pub struct PlateSample<'a> {
    pub state: StateView<'a>,
    pub plate: &'a PlateSystem,
    pub exact: Option<&'a ImpactingBar>,
    pub energy: f64,
    /// Exact ‖u_h − u‖_{L²(Ω)}.
    pub l2_error: f64,
    /// ‖I_h u(·, t_n)‖_{L²(Ω)}.
    pub exact_interp_norm: f64,
    /// Mean of u on Γ_C.
    pub u_mean: f64,
    /// Total contact force Σ_c λ_c (≤ 0).
    pub contact_force: f64,
    /// Principal pivots of the last step's contact solves.
    pub pivots: usize,
}

pub trait PlateObserver {
    fn needs(&self) -> Needs {
        Needs::default()
    }
    fn observe(&mut self, sample: &PlateSample);
}

/// Runs `steps` steps, showing every state (t_0 included) to every observer.
pub fn integrate(
    problem: &PlateProblem,
    scheme: &mut dyn Scheme,
    steps: usize,
    observers: &mut [&mut dyn PlateObserver],
) -> Result<(), SchemeError> {
    let needs = observers.iter().fold(Needs::default(), |n, o| n.or(o.needs()));
    let plate = &problem.plate;
    let mut interp = if needs.l2 { vec![0.0; plate.system.n()] } else { Vec::new() };
    let mut show = |scheme: &dyn Scheme, observers: &mut [&mut dyn PlateObserver]| {
        let state = scheme.state();
        let energy = if needs.energy { plate.system.energy(state.u, state.v) } else { f64::NAN };
        let (l2_error, exact_interp_norm) = match (needs.l2, &problem.exact) {
            (true, Some(ex)) => {
                for (e, &v) in interp.iter_mut().zip(&plate.dofs) {
                    *e = ex.u(plate.mesh.points[v][0], state.t);
                }
                (norms::l2_error(plate, state.u, ex, state.t), norms::l2_norm(plate, &interp))
            }
            _ => (f64::NAN, f64::NAN),
        };
        let sample = PlateSample {
            state,
            plate,
            exact: problem.exact.as_ref(),
            energy,
            l2_error,
            exact_interp_norm,
            u_mean: plate.contact_mean(state.u),
            contact_force: state.lambda.iter().sum(),
            pivots: scheme.pivots(),
        };
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

/// A per-step diagnostic that can be recorded in the plate's `series.csv`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlateColumn {
    /// u at the contact node y = 0.
    U0,
    /// Mean of u on Γ_C.
    UMean,
    /// Mean contact pressure Σ_c λ_c / |Γ_C| (the 1D λ for y-independent fields).
    Lambda,
    /// Total contact force Σ_c λ_c.
    ContactForce,
    /// Discrete energy.
    Energy,
    /// Exact ‖u_h − u‖_{L²(Ω)}.
    L2Error,
    /// Exact u(0, t).
    ExactU0,
    /// Exact λ(t) (contact pressure).
    ExactLambda,
    /// Principal pivots of the step's contact solves.
    Pivots,
}

impl PlateColumn {
    pub const ALL: [PlateColumn; 9] = [
        PlateColumn::U0,
        PlateColumn::UMean,
        PlateColumn::Lambda,
        PlateColumn::ContactForce,
        PlateColumn::Energy,
        PlateColumn::L2Error,
        PlateColumn::ExactU0,
        PlateColumn::ExactLambda,
        PlateColumn::Pivots,
    ];

    pub fn name(self) -> &'static str {
        match self {
            PlateColumn::U0 => "u0",
            PlateColumn::UMean => "u_mean",
            PlateColumn::Lambda => "lambda",
            PlateColumn::ContactForce => "contact_force",
            PlateColumn::Energy => "energy",
            PlateColumn::L2Error => "l2_error",
            PlateColumn::ExactU0 => "exact_u0",
            PlateColumn::ExactLambda => "exact_lambda",
            PlateColumn::Pivots => "pivots",
        }
    }

    pub fn needs_exact(self) -> bool {
        matches!(self, PlateColumn::L2Error | PlateColumn::ExactU0 | PlateColumn::ExactLambda)
    }
}

/// Records the requested columns every `every` steps (t_0 included).
#[derive(Debug, Clone)]
pub struct PlateSeries {
    pub columns: Vec<PlateColumn>,
    pub every: usize,
    /// Row-major: t, then one value per column.
    pub rows: Vec<f64>,
}

impl PlateSeries {
    pub fn new(columns: Vec<PlateColumn>, every: usize) -> Self {
        Self { columns, every: every.max(1), rows: Vec::new() }
    }

    pub fn width(&self) -> usize {
        self.columns.len() + 1
    }

    pub fn iter_rows(&self) -> impl Iterator<Item = &[f64]> {
        self.rows.chunks(self.width())
    }

    pub fn column(&self, c: PlateColumn) -> Option<Vec<f64>> {
        let k = self.columns.iter().position(|&x| x == c)? + 1;
        Some(self.iter_rows().map(|r| r[k]).collect())
    }
}

impl PlateObserver for PlateSeries {
    fn needs(&self) -> Needs {
        Needs { energy: self.columns.contains(&PlateColumn::Energy), l2: self.columns.contains(&PlateColumn::L2Error) }
    }

    fn observe(&mut self, s: &PlateSample) {
        if self.columns.is_empty() || !s.state.n.is_multiple_of(self.every) {
            return;
        }
        let st = s.state;
        let c0 = s.plate.system.contact[0];
        let gamma = s.plate.contact_length();
        self.rows.push(st.t);
        for &c in &self.columns {
            self.rows.push(match c {
                PlateColumn::U0 => st.u[c0],
                PlateColumn::UMean => s.u_mean,
                PlateColumn::Lambda => s.contact_force / gamma,
                PlateColumn::ContactForce => s.contact_force,
                PlateColumn::Energy => s.energy,
                PlateColumn::L2Error => s.l2_error,
                PlateColumn::ExactU0 => s.exact.map_or(f64::NAN, |e| e.u0(st.t)),
                PlateColumn::ExactLambda => s.exact.map_or(f64::NAN, |e| e.lambda(st.t)),
                PlateColumn::Pivots => s.pivots as f64,
            });
        }
    }
}

/// Plate-specific additions to the 1D summary keys.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct PlateExtras {
    /// Largest per-step energy increase `max_n (E^{n+1} − Eⁿ)` (≤ 0 for a dissipative scheme).
    pub energy_max_increase: f64,
    /// The step n+1 at which it happened.
    pub energy_max_increase_step: usize,
    /// The same, over the steps n ≥ 1 only (the paper's Lemma 5.1 is stated for n > 0; the
    /// hybrid's first step starts from the interpolated, not quasi-static, contact values).
    pub energy_max_increase_after_first: f64,
    /// max over t_n of `max_{nodes} |u(x, y) − u(x, 0)|` (0 for a y-independent solution).
    pub max_y_variation: f64,
    /// Largest pivot count of one step's contact solves.
    pub max_pivots: usize,
    pub final_u_mean: f64,
    pub final_contact_force: f64,
}

/// Accumulates the 1D [`Summary`] keys (u0 and the first impact/release times from the contact
/// node at y = 0; min_u0, max_lambda and the complementarity product over all contact nodes;
/// λ in `l2_lambda_error` is the mean contact pressure) plus [`PlateExtras`].
#[derive(Debug, Clone)]
pub struct PlateSummary {
    steps: usize,
    h: f64,
    dt: f64,
    length: f64,
    /// Exact energy ½∫(u_t² + |∇u|²) = L H/8 of the y-independent benchmark.
    exact_energy: f64,
    has_exact: bool,
    with_l2: bool,
    linf_l2: f64,
    linf_interp: f64,
    max_contact: f64,
    lambda_sq: f64,
    energy: [f64; 4],
    prev_energy: f64,
    max_increase: (f64, usize),
    max_increase_after_first: f64,
    first_impact: Option<f64>,
    first_release: Option<f64>,
    final_u0: f64,
    min_u0: f64,
    max_lambda: f64,
    max_product: f64,
    max_y_variation: f64,
    max_pivots: usize,
    final_u_mean: f64,
    final_force: f64,
    /// For each free unknown, the unknown at the same x on y = 0 (for the y-variation).
    base: Vec<Option<usize>>,
    started: std::time::Instant,
}

impl PlateSummary {
    pub fn new(problem: &PlateProblem, steps: usize, dt: f64, with_l2: bool) -> Self {
        let plate = &problem.plate;
        let mesh = &plate.mesh;
        // Free unknowns on y = ymin, keyed by x (structured meshes: exact coordinates).
        let ymin = plate.dofs.iter().map(|&v| mesh.points[v][1]).fold(f64::INFINITY, f64::min);
        let bottom: std::collections::HashMap<u64, usize> = plate
            .dofs
            .iter()
            .enumerate()
            .filter(|(_, v)| mesh.points[**v][1] == ymin)
            .map(|(d, &v)| (mesh.points[v][0].to_bits(), d))
            .collect();
        let base = plate.dofs.iter().map(|&v| bottom.get(&mesh.points[v][0].to_bits()).copied()).collect();
        Self {
            steps,
            h: mesh.h(),
            dt,
            length: mesh.length,
            exact_energy: mesh.length * mesh.height / 8.0,
            has_exact: problem.exact.is_some(),
            with_l2,
            linf_l2: 0.0,
            linf_interp: 0.0,
            max_contact: 0.0,
            lambda_sq: 0.0,
            energy: [f64::NAN, f64::NAN, f64::INFINITY, f64::NEG_INFINITY],
            prev_energy: f64::NAN,
            max_increase: (f64::NEG_INFINITY, 0),
            max_increase_after_first: f64::NEG_INFINITY,
            first_impact: None,
            first_release: None,
            final_u0: f64::NAN,
            min_u0: f64::INFINITY,
            max_lambda: f64::NEG_INFINITY,
            max_product: 0.0,
            max_y_variation: 0.0,
            max_pivots: 0,
            final_u_mean: f64::NAN,
            final_force: f64::NAN,
            base,
            started: std::time::Instant::now(),
        }
    }

    pub fn finish(&self) -> (Summary, PlateExtras) {
        let exact = |v: f64| self.has_exact.then_some(v);
        let l2 = |v: f64| (self.has_exact && self.with_l2).then_some(v);
        let summary = Summary {
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
            energy_exact: exact(self.exact_energy),
            first_impact_time: self.first_impact,
            first_release_time: self.first_release,
            impact_time_shift: self.first_impact.filter(|_| self.has_exact).map(|t| t - self.length),
            release_time_shift: self.first_release.filter(|_| self.has_exact).map(|t| t - 2.0 * self.length),
            final_u0: self.final_u0,
            min_u0: self.min_u0,
            max_lambda: self.max_lambda,
            max_complementarity_product: self.max_product,
            wall_seconds: self.started.elapsed().as_secs_f64(),
        };
        let extras = PlateExtras {
            energy_max_increase: self.max_increase.0,
            energy_max_increase_step: self.max_increase.1,
            energy_max_increase_after_first: self.max_increase_after_first,
            max_y_variation: self.max_y_variation,
            max_pivots: self.max_pivots,
            final_u_mean: self.final_u_mean,
            final_contact_force: self.final_force,
        };
        (summary, extras)
    }
}

impl PlateObserver for PlateSummary {
    fn needs(&self) -> Needs {
        Needs { energy: true, l2: self.with_l2 && self.has_exact }
    }

    fn observe(&mut self, s: &PlateSample) {
        let st = s.state;
        let e = s.energy;
        if st.n == 0 {
            self.energy[0] = e;
        } else {
            let de = e - self.prev_energy;
            if de > self.max_increase.0 {
                self.max_increase = (de, st.n);
            }
            if st.n >= 2 {
                self.max_increase_after_first = self.max_increase_after_first.max(de);
            }
        }
        self.prev_energy = e;
        self.energy[1] = e;
        self.energy[2] = self.energy[2].min(e);
        self.energy[3] = self.energy[3].max(e);
        let contact = &s.plate.system.contact;
        let u0 = st.u[contact[0]];
        self.final_u0 = u0;
        for (c, &i) in contact.iter().enumerate() {
            self.min_u0 = self.min_u0.min(st.u[i]);
            self.max_lambda = self.max_lambda.max(st.lambda[c]);
            self.max_product = self.max_product.max((st.u[i] * st.lambda[c]).abs());
        }
        for (d, b) in self.base.iter().enumerate() {
            if let Some(b) = *b {
                self.max_y_variation = self.max_y_variation.max((st.u[d] - st.u[b]).abs());
            }
        }
        self.max_pivots = self.max_pivots.max(s.pivots);
        self.final_u_mean = s.u_mean;
        self.final_force = s.contact_force;
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
            let pressure = s.contact_force / s.plate.contact_length();
            self.lambda_sq += w * self.dt * (pressure - ex.lambda(st.t)).powi(2);
            if self.with_l2 {
                self.linf_l2 = self.linf_l2.max(s.l2_error);
                self.linf_interp = self.linf_interp.max(s.exact_interp_norm);
            }
        }
    }
}

/// One recorded frame of the displacement and velocity at all mesh nodes.
#[derive(Debug, Clone)]
pub struct Frame {
    pub t: f64,
    pub u: Vec<f64>,
    pub v: Vec<f64>,
}

/// Records [`Frame`]s every `every` steps (for VTU output at the edge).
#[derive(Debug, Clone)]
pub struct FrameRecorder {
    pub every: usize,
    pub frames: Vec<Frame>,
}

impl FrameRecorder {
    pub fn new(every: usize) -> Self {
        Self { every: every.max(1), frames: Vec::new() }
    }
}

impl PlateObserver for FrameRecorder {
    fn observe(&mut self, s: &PlateSample) {
        if !s.state.n.is_multiple_of(self.every) {
            return;
        }
        let n = s.plate.mesh.n_nodes();
        let mut u = vec![0.0; n];
        let mut v = vec![0.0; n];
        s.plate.to_nodes(s.state.u, &mut u);
        s.plate.to_nodes(s.state.v, &mut v);
        self.frames.push(Frame { t: s.state.t, u, v });
    }
}

/// Energies `Eⁿ` of every step (for energy analyses).
#[derive(Debug, Clone, Default)]
pub struct EnergyRecorder {
    pub energy: Vec<f64>,
}

impl PlateObserver for EnergyRecorder {
    fn needs(&self) -> Needs {
        Needs { energy: true, l2: false }
    }

    fn observe(&mut self, s: &PlateSample) {
        self.energy.push(s.energy);
    }
}

/// Everything a plate scene run produces (the problem is kept for the VTU writer).
#[derive(Debug)]
pub struct PlateRun {
    pub problem: PlateProblem,
    pub summary: Summary,
    pub extras: PlateExtras,
    pub series: PlateSeries,
    pub frames: Option<FrameRecorder>,
}

/// Runs a plate scene: the summary always, plus the requested series and VTU frames.
pub fn run_plate_scene(
    scene: &super::scene::PlateScene,
    extra: &mut [&mut dyn PlateObserver],
) -> Result<PlateRun, PlateRunError> {
    let problem = match &scene.mesh_file {
        None => PlateProblem::new(&scene.plate, &scene.mass)?,
        Some(path) => {
            let mesh = read_mesh_file(path)?;
            PlateProblem::from_mesh(mesh, &scene.mass, scene.plate.initial, scene.plate.force)?
        }
    };
    let mut scheme = problem.scheme(&scene.scheme, scene.time.dt)?;
    let steps = scene.time.steps;
    let mut summary = PlateSummary::new(&problem, steps, scene.time.dt, true);
    let mut series = PlateSeries::new(scene.output.series.clone(), scene.output.every);
    let mut frames = scene.output.vtu_every.map(FrameRecorder::new);
    {
        let mut observers: Vec<&mut dyn PlateObserver> = vec![&mut summary, &mut series];
        if let Some(f) = frames.as_mut() {
            observers.push(f);
        }
        for o in extra.iter_mut() {
            observers.push(&mut **o);
        }
        integrate(&problem, scheme.as_mut(), steps, &mut observers)?;
    }
    let (summary, extras) = summary.finish();
    Ok(PlateRun { problem, summary, extras, series, frames })
}

#[cfg(feature = "python")]
fn read_mesh_file(path: &std::path::Path) -> Result<Mesh2d, PlateRunError> {
    Ok(Mesh2d::read_file(path)?)
}

/// Unreachable in practice: scene validation already rejects `plate.mesh` without the feature.
#[cfg(not(feature = "python"))]
fn read_mesh_file(path: &std::path::Path) -> Result<Mesh2d, PlateRunError> {
    Err(super::mesh::MeshError::Arrays(format!("{}: mesh files need the `python` feature", path.display())).into())
}
