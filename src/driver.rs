//! The driver: a problem, a scheme, a loop, and observers that see the states.
//!
//! Observers state what they need ([`Needs`]) and how often ([`Observer::every`]); the driver
//! keeps the cadence (argmin's `ObserverMode::Every`) and computes what the observers due at a
//! step need (energy, exact L² error, y-variation) once, for all of them. Recording, summaries,
//! progress bars and files are observers or live at the edge; nothing here does I/O.
//!
//! A run that blows up is a result, not an error: [`integrate_watched`] stops at the first state
//! that meets a [`DivergenceCriterion`] and returns where and why ([`Divergence`]); the observers
//! have then seen the finite states only, and are told ([`Observer::diverged`]). [`integrate`] is
//! the strict form for callers with no use for a diverged run (a non-finite state is its error).

use crate::exact::Exact;
use crate::linalg::sparse::SparseError;
use crate::linalg::{LinalgError, SymMatrix};
use crate::problem::{Geometry, GeometryView, LoadEnergy, Problem};
use crate::schemes::{Scheme, SchemeError, StateView};
use crate::system::ContactSystem;
use serde::Serialize;
use thiserror::Error;

/// When a run counts as diverged (and stops).
///
/// - **A non-finite state**: the scheme's step reports one ([`SchemeError::NonFinite`]), or the
///   energy of a finite state is not finite (it overflowed).
/// - **The energy criterion**: `|Eⁿ| > factor · E_ref` with `E_ref = max(|E⁰|, E_F)` and
///   `E_F = ½ F_rᵀ S_rr⁻¹ F_r`, the static energy of the load with the contact unknowns held at 0
///   (r: the other unknowns; the contact unknowns hold every geometry in place, so `S_rr` is SPD
///   even for a free bar). Why: a scheme that creates no energy keeps `Eⁿ ≤ E⁰`, and where S
///   is invertible the energy is bounded below by the static minimum
///   `min_U ½UᵀSU − UᵀF = −½FᵀS⁻¹F`, a few times `E_F` (4 E_F for a uniform load on a clamped
///   bar: f²L³/6 against f²L³/24); so a bounded run stays within a small multiple of `E_ref`,
///   and a run a factor 10⁶ above it has blown up (the paper's unstable combinations grow
///   without bound and overflow to inf/NaN hundreds of periods later). `E_F` is the floor that
///   makes `E⁰ = 0` work: a structure starting at rest under a load is measured against the
///   energy of that load; with no load and `E⁰ = 0` the state stays 0 and `|Eⁿ| > 0` never
///   holds. A time-dependent load takes the larger of `E_F` at F(0) and at its largest sample
///   over the run's horizon ([`peak_load`]; a ramp from zero has F(0) = 0).
///
/// The criterion reuses the energy that the observers get ([`Sample::energy`]): with a
/// criterion the driver computes it at every step (the summary needs it there anyway).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DivergenceCriterion {
    /// `factor` above, in (1, ∞) (scenes: `output.divergence_factor`).
    pub energy_factor: f64,
}

impl DivergenceCriterion {
    /// The default `output.divergence_factor`: six orders of magnitude above any bounded
    /// excursion (the standard mass chatters up to about 4 E⁰ by T = 3, Paoli–Schatzman with
    /// mod3 drifts to 2.4 E⁰ by T = 3000), and some 300 below overflow.
    pub const DEFAULT_ENERGY_FACTOR: f64 = 1e6;
}

impl Default for DivergenceCriterion {
    fn default() -> Self {
        Self { energy_factor: Self::DEFAULT_ENERGY_FACTOR }
    }
}

/// The divergence rule of [`DivergenceCriterion`], state by state: the one piece that decides,
/// for a run stepped here ([`integrate_watched`]) and for a run streamed from another process
/// (`crate::engine`, whose states never exist on this side).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DivergenceWatch {
    factor: f64,
    /// `E_F` of [`DivergenceCriterion`].
    load_energy: f64,
    /// `E_ref`, set by the first state shown (t_0).
    reference: Option<f64>,
    /// For a body the static solve of `E_F` cannot hold (a free body: `S_rr` singular), the
    /// free-flight scale `(F_mᵀ M_mm⁻¹ F_m, N)`: at state 1, t_1 = Δt gives the horizon
    /// T = N Δt and `E_ref` becomes at least `½ T² F_mᵀ M_mm⁻¹ F_m`, the kinetic energy the load
    /// gives the free body over the run ([`DivergenceWatch::with_free_flight`]).
    free_flight: Option<(f64, usize)>,
}

/// What [`DivergenceWatch::judge`] says of a state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Verdict {
    /// Show it and go on.
    Go,
    /// Show it; it is the last one (`|E| > factor · E_ref`).
    Last(Divergence),
    /// Do not show it: its energy is not finite.
    Hidden(Divergence),
}

impl DivergenceWatch {
    /// `load_energy`: `E_F = ½ F_rᵀ S_rr⁻¹ F_r` (0 without load).
    pub fn new(criterion: &DivergenceCriterion, load_energy: f64) -> Self {
        Self { factor: criterion.energy_factor, load_energy, reference: None, free_flight: None }
    }

    /// The same watch for a body whose static load energy does not exist (type docs): `rate` is
    /// `F_mᵀ M_mm⁻¹ F_m`, `steps` the run's N.
    pub fn with_free_flight(mut self, rate: f64, steps: usize) -> Self {
        self.free_flight = Some((rate, steps));
        self
    }

    /// Raises `E_F` (and `E_ref` if set) to `e`: a time-dependent load's largest sampled scale
    /// ([`transient_load_energy`]), given before state 1 is judged. No change for `e` ≤ them.
    pub fn raise_load_energy(&mut self, e: f64) {
        self.load_energy = self.load_energy.max(e);
        self.reference = self.reference.map(|r| r.max(e));
    }

    /// Judges state `step` at `time` by its energy (the first finite one sets `E_ref`).
    pub fn judge(&mut self, step: usize, time: f64, energy: f64) -> Verdict {
        let diverged = |reason| Divergence { step, time, reason };
        if !energy.is_finite() {
            return Verdict::Hidden(diverged(DivergenceReason::NonFiniteEnergy));
        }
        let factor = self.factor;
        if let (1, Some((rate, steps)), Some(reference)) = (step, self.free_flight, self.reference) {
            let horizon = steps as f64 * time;
            self.reference = Some(reference.max(0.5 * horizon * horizon * rate));
        }
        match self.reference {
            None => self.reference = Some(energy.abs().max(self.load_energy)),
            Some(reference) if energy.abs() > factor * reference => {
                return Verdict::Last(diverged(DivergenceReason::EnergyFactor { energy, reference, factor }));
            }
            Some(_) => {}
        }
        Verdict::Go
    }
}

/// Where a run diverged and why: the first state n that met the [`DivergenceCriterion`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Error)]
#[error("diverged at step {step} (t = {time}): {reason}")]
pub struct Divergence {
    pub step: usize,
    pub time: f64,
    #[serde(flatten)]
    pub reason: DivergenceReason,
}

/// Why a run diverged (`reason` in `summary.json`, kebab-case).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Error)]
#[serde(tag = "reason", rename_all = "kebab-case")]
pub enum DivergenceReason {
    /// The scheme's state (u or λ) is not finite; it is not shown to the observers.
    #[error("the state is not finite (the scheme is unstable for this Δt / mass)")]
    NonFiniteState,
    /// The scheme's state is not finite and so is the load at `load_time`, a time the step
    /// evaluates it at (a time-dependent force singular there, e.g. `1/(t - 0.5)`): the load,
    /// not the scheme, made it so ([`non_finite_load`]).
    #[error("the state is not finite: the load F(t) is not finite at t = {load_time} ({key} there)")]
    NonFiniteLoad { load_time: f64, key: &'static str },
    /// The state is finite but its energy is not (it overflowed); it is not shown. At t_0 (a
    /// load so large that E⁰ overflows) no state is shown at all.
    #[error("the energy is not finite (the state overflows it)")]
    NonFiniteEnergy,
    /// `|energy| > factor · reference` ([`DivergenceCriterion`]); this finite state is shown, and
    /// is the last one.
    #[error("the energy {energy:.4e} is above {factor:e} times max(|E⁰|, E_F) = {reference:.4e}")]
    EnergyFactor { energy: f64, reference: f64, factor: f64 },
}

/// How a run of [`integrate_watched`] ended.
#[must_use]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outcome {
    /// Every step was taken.
    Completed,
    /// Stopped at a divergence (a result: the observers hold the finite states before it).
    Diverged(Divergence),
}

impl Outcome {
    /// The divergence, if the run stopped at one.
    pub fn divergence(&self) -> Option<&Divergence> {
        match self {
            Outcome::Completed => None,
            Outcome::Diverged(d) => Some(d),
        }
    }
}

/// What an observer needs computed at a step, beyond the state itself.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Needs {
    /// The discrete energy ½VᵀMV + ½UᵀSU − UᵀF.
    pub energy: bool,
    /// The exact L²(Ω) error and the L² norm of the exact solution's nodal interpolant.
    pub l2: bool,
    /// The largest variation of u across y (plates).
    pub y_variation: bool,
}

impl Needs {
    /// What either needs.
    pub fn or(self, o: Needs) -> Needs {
        Needs { energy: self.energy || o.energy, l2: self.l2 || o.l2, y_variation: self.y_variation || o.y_variation }
    }
}

/// What the driver hands to observers at a step. Quantities nobody due at this step needs are
/// NaN.
#[derive(Debug, Clone, Copy)]
pub struct Sample<'a> {
    pub state: StateView<'a>,
    pub geometry: &'a dyn GeometryView,
    pub exact: Option<&'a Exact>,
    pub energy: f64,
    /// Exact ‖u_h − u(·, t_n)‖_{L²(Ω)}.
    pub l2_error: f64,
    /// ‖I_h u(·, t_n)‖_{L²(Ω)}: the norm of the nodal interpolant of the exact solution.
    pub exact_interp_norm: f64,
    /// [`GeometryView::u0`]: u at the reference contact node (x = 0, lowest y; u_0 for a bar),
    /// the plain mean of u_x over the contact-face nodes for a solid.
    pub u0: f64,
    /// Mean of u over Γ_C (u_0 for a bar).
    pub u_mean: f64,
    /// Total contact force Σ_c λ_c (≤ 0).
    pub contact_force: f64,
    /// Mean contact pressure Σ_c λ_c / |Γ_C| (λ for a bar).
    pub pressure: f64,
    /// max |u(x, y) − u(x, y_min)| (0 for a bar).
    pub y_variation: f64,
    /// Principal pivots of the step's contact solves.
    pub pivots: usize,
    /// The contact values' extremes and complementarity (node by node).
    pub contact: ContactStats,
    /// What friction did so far (None without a friction law).
    pub friction: Option<&'a crate::contact::friction::FrictionRecord>,
}

pub trait Observer {
    fn needs(&self) -> Needs {
        Needs::default()
    }
    /// The observer sees the states n with n % every == 0 (t_0 included).
    fn every(&self) -> usize {
        1
    }
    fn observe(&mut self, sample: &Sample);
    /// The run stopped at `divergence`, after the last state shown (called once, at the end).
    fn diverged(&mut self, _divergence: &Divergence) {}
    /// True once this observer cannot go on (a writer whose disk is full): the driver then takes
    /// no further step and returns as if completed; the observer reports its own error.
    fn halted(&self) -> bool {
        false
    }
}

/// Runs `steps` steps, showing the states (t_0 included) to the observers due at each; a
/// non-finite state is an error ([`SchemeError::NonFinite`]), nothing else is checked. For
/// tests, timings and cross-checks; runs that report a divergence use [`integrate_watched`].
pub fn integrate<G: Geometry>(
    problem: &Problem<G>,
    scheme: &mut dyn Scheme,
    steps: usize,
    observers: &mut [&mut dyn Observer],
) -> Result<(), SchemeError> {
    match drive(problem, scheme, steps, None, observers)? {
        Outcome::Completed => Ok(()),
        // Without a criterion the only divergence is the scheme's non-finite state.
        Outcome::Diverged(d) => Err(SchemeError::NonFinite { step: d.step, time: d.time }),
    }
}

/// Runs up to `steps` steps like [`integrate`], and stops at the first state that meets
/// `criterion` (see [`DivergenceCriterion`] for which states are shown): a divergence is an
/// [`Outcome`], not an error; errors are the scheme's other failures (contact solves).
pub fn integrate_watched<G: Geometry>(
    problem: &Problem<G>,
    scheme: &mut dyn Scheme,
    steps: usize,
    criterion: &DivergenceCriterion,
    observers: &mut [&mut dyn Observer],
) -> Result<Outcome, SchemeError> {
    drive(problem, scheme, steps, Some(criterion), observers)
}

/// The watch of a run of `steps` steps: `E_F = ½ F_rᵀ S_rr⁻¹ F_r` of [`DivergenceCriterion`]
/// (0 without load), or, where that solve fails (a free body, whose S_rr is singular), the
/// free-flight scale of [`DivergenceWatch::with_free_flight`].
/// A memory refusal of a factor is the run's error, not a reason to fall back to another scale
/// (issue 32, E4: the watch's own factor is refused where the scheme's fitted).
fn watch_of<G: Geometry>(criterion: &DivergenceCriterion, g: &G, steps: usize) -> Result<DivergenceWatch, LinalgError> {
    let s = g.system();
    let energy = match g.load_energy() {
        LoadEnergy::Known(e) => Some(e),
        LoadEnergy::Factor => load_energy(s)?,
        LoadEnergy::FreeFlight => None,
    };
    Ok(match energy {
        Some(e) => DivergenceWatch::new(criterion, e),
        None => DivergenceWatch::new(criterion, 0.0).with_free_flight(free_flight_rate(s)?, steps),
    })
}

/// Samples of a time-dependent load over a run's horizon ([`peak_load`]).
pub const LOAD_SAMPLES: usize = 16;

/// The sample of largest Euclidean norm among `F(t_k)`, `t_k = k T / LOAD_SAMPLES` (k = 1 …
/// LOAD_SAMPLES), where the load depends on time and that norm is above `F(0)`'s; None
/// otherwise. `E_F` of [`DivergenceCriterion`] takes F(0), and a load that starts at zero (a
/// ramp from rest, `force = ["0", "-t"]`) would give `E_ref = 0`: every state after it
/// "diverged" at step 1. The watch's margin (10⁶) needs the scale's order of magnitude only, so
/// the sample of largest norm stands for the load's peak.
fn peak_load<A: SymMatrix>(s: &ContactSystem<A>, horizon: f64) -> Option<Vec<f64>> {
    s.forcing.as_ref()?;
    let norm = |f: &[f64]| f.iter().map(|x| x * x).sum::<f64>();
    let (mut best, mut largest) = (None, norm(&s.load));
    let mut f = vec![0.0; s.n()];
    for k in 1..=LOAD_SAMPLES {
        s.load_at(horizon * k as f64 / LOAD_SAMPLES as f64, &mut f);
        let n = norm(&f);
        // A sample that is not finite (a force singular there) sets no scale: the run reports it
        // where the state follows it (`non_finite_load`).
        if n.is_finite() && n > largest {
            (best, largest) = (Some(f.clone()), n);
        }
    }
    best
}

/// The watch's scale of a time-dependent load over `horizon` ([`peak_load`]): `E_F` of its
/// largest sample, or where `S_rr` is singular (a free body) the free-flight scale
/// `½ T² F_mᵀ M_mm⁻¹ F_m` of it; 0 for a load that does not depend on time or never exceeds
/// F(0), and where a solve fails (the watch keeps F(0)'s scale).
fn transient_load_energy<G: Geometry>(g: &G, horizon: f64) -> f64 {
    let s = g.system();
    let Some(f) = peak_load(s, horizon) else { return 0.0 };
    match g.load_energy_of(&f) {
        LoadEnergy::Known(e) => e,
        LoadEnergy::Factor => scale_of(s, &f, horizon),
        LoadEnergy::FreeFlight => 0.5 * horizon * horizon * free_flight_rate_with(s, &f).unwrap_or(0.0),
    }
}

/// `E_F` of the load `f` by a factor of `S_rr`, or where that fails (a free body) the
/// free-flight scale `½ T² f_mᵀ M_mm⁻¹ f_m` over the horizon T (0 where that fails too).
fn scale_of<A: SymMatrix>(s: &ContactSystem<A>, f: &[f64], horizon: f64) -> f64 {
    match load_energy_with(s, f).ok().flatten() {
        Some(e) => e,
        None => 0.5 * horizon * horizon * free_flight_rate_with(s, f).unwrap_or(0.0),
    }
}

/// The first of the times a step from `t0` to `t1` evaluates a time-dependent load at (t0, the
/// midpoint, t1: every scheme's equations are written at one of them) where it is not finite;
/// None for a load that does not depend on time or is finite at all three. Validation
/// evaluates a force at t = 0 only, so a force singular later (`1/(t - 0.5)`) reaches the run.
fn non_finite_load<A: SymMatrix>(s: &ContactSystem<A>, t0: f64, t1: f64) -> Option<f64> {
    s.forcing.as_ref()?;
    let mut f = vec![0.0; s.n()];
    [t0, 0.5 * (t0 + t1), t1].into_iter().find(|&t| {
        s.load_at(t, &mut f);
        f.iter().any(|x| !x.is_finite())
    })
}

/// The error of a solve that did not fail on the matrix but on the memory limit.
fn memory_refusal(e: LinalgError) -> Result<(), LinalgError> {
    match e {
        LinalgError::Sparse(SparseError::TooLarge { .. } | SparseError::AnalysisTooLarge { .. }) => Err(e),
        _ => Ok(()),
    }
}

/// `F_mᵀ M_mm⁻¹ F_m` over the unknowns with mass (0 if that solve fails too, an error if the
/// memory limit refused it).
fn free_flight_rate<A: SymMatrix>(s: &ContactSystem<A>) -> Result<f64, LinalgError> {
    free_flight_rate_with(s, &s.load)
}

/// [`free_flight_rate`] of the load `load`.
fn free_flight_rate_with<A: SymMatrix>(s: &ContactSystem<A>, load: &[f64]) -> Result<f64, LinalgError> {
    let massive: Vec<usize> = (0..s.n()).filter(|&i| !s.massless[i]).collect();
    let f: Vec<f64> = massive.iter().map(|&i| load[i]).collect();
    let mut a = f.clone();
    match s.mass.solve_principal(&massive, &mut a, "mass") {
        Ok(()) => Ok(a.iter().zip(&f).map(|(x, y)| x * y).sum()),
        Err(e) => memory_refusal(e).map(|()| 0.0),
    }
}

/// The reference load energy of a run up to `t_end` whose states are stepped elsewhere (the
/// FEniCSx engine's bodies): `E_F`, or for a free body the free-flight scale
/// `½ t_end² F_mᵀ M_mm⁻¹ F_m` that [`DivergenceWatch::with_free_flight`] gives a run stepped here.
pub(crate) fn reference_load_energy<A: SymMatrix>(s: &ContactSystem<A>, t_end: f64) -> Result<f64, LinalgError> {
    let e = match load_energy(s)? {
        Some(e) => e,
        None => 0.5 * t_end * t_end * free_flight_rate(s)?,
    };
    // A time-dependent load: its largest sample's scale too (`transient_load_energy`).
    Ok(e.max(peak_load(s, t_end).map_or(0.0, |f| scale_of(s, &f, t_end))))
}

/// `E_F = ½ F_rᵀ S_rr⁻¹ F_r` (0 without load; None if the solve fails, an error if the memory
/// limit refused it).
fn load_energy<A: SymMatrix>(s: &ContactSystem<A>) -> Result<Option<f64>, LinalgError> {
    load_energy_with(s, &s.load)
}

/// [`load_energy`] of the load `load`.
fn load_energy_with<A: SymMatrix>(s: &ContactSystem<A>, load: &[f64]) -> Result<Option<f64>, LinalgError> {
    if load.iter().all(|&f| f == 0.0) {
        return Ok(Some(0.0));
    }
    let mut held = vec![false; s.n()];
    for &c in &s.contact {
        held[c] = true;
    }
    let rest: Vec<usize> = (0..s.n()).filter(|&i| !held[i]).collect();
    let f: Vec<f64> = rest.iter().map(|&i| load[i]).collect();
    let mut u = f.clone();
    match s.stiffness.solve_principal(&rest, &mut u, "stiffness") {
        Ok(()) => Ok(Some(0.5 * u.iter().zip(&f).map(|(a, b)| a * b).sum::<f64>())),
        Err(e) => memory_refusal(e).map(|()| None),
    }
}

/// The loop of [`integrate`] and [`integrate_watched`]. (About 80 lines: the per-step sample,
/// the cadence and the divergence test share its local state; split, they would pass it around.)
fn drive<G: Geometry>(
    problem: &Problem<G>,
    scheme: &mut dyn Scheme,
    steps: usize,
    criterion: Option<&DivergenceCriterion>,
    observers: &mut [&mut dyn Observer],
) -> Result<Outcome, SchemeError> {
    let cadence: Vec<usize> = observers.iter().map(|o| o.every().max(1)).collect();
    let needs: Vec<Needs> = observers.iter().map(|o| o.needs()).collect();
    let geometry: &dyn GeometryView = &problem.system;
    let mut watch = criterion.map(|c| watch_of(c, &problem.system, steps)).transpose()?;
    let lower = &problem.system.system().lower;
    let mut diagnostics = problem.system.diagnostics();
    let mut show = |scheme: &dyn Scheme, observers: &mut [&mut dyn Observer]| -> Option<Divergence> {
        let state = scheme.state();
        let due = |k: usize| state.n.is_multiple_of(cadence[k]);
        let mut need = (0..observers.len()).filter(|&k| due(k)).fold(Needs::default(), |n, k| n.or(needs[k]));
        need.energy |= criterion.is_some();
        let energy = if need.energy {
            scheme.energy().unwrap_or_else(|| diagnostics.energy(state.u, state.v, state.t))
        } else {
            f64::NAN
        };
        let verdict = watch.as_mut().map_or(Verdict::Go, |w| {
            if state.n == 1 {
                // t_1 = Δt: the horizon T = N Δt of a time-dependent load's samples.
                w.raise_load_energy(transient_load_energy(&problem.system, steps as f64 * state.t));
            }
            w.judge(state.n, state.t, energy)
        });
        if let Verdict::Hidden(d) = verdict {
            return Some(d);
        }
        let (l2_error, exact_interp_norm) = match (need.l2, &problem.exact) {
            (true, Some(ex)) => diagnostics.l2(state.u, ex, state.t),
            _ => (f64::NAN, f64::NAN),
        };
        let contact_force: f64 = state.lambda.iter().sum();
        let sample = Sample {
            state,
            geometry,
            exact: problem.exact.as_ref(),
            energy,
            l2_error,
            exact_interp_norm,
            u0: geometry.u0(state.u),
            u_mean: geometry.contact_mean(state.u),
            contact_force,
            pressure: contact_force / geometry.contact_measure(),
            y_variation: if need.y_variation { geometry.y_variation(state.u) } else { f64::NAN },
            pivots: scheme.pivots(),
            contact: ContactStats::of(state.u, state.lambda, geometry.contact(), lower),
            friction: scheme.friction(),
        };
        for (k, o) in observers.iter_mut().enumerate() {
            if due(k) {
                o.observe(&sample);
            }
        }
        match verdict {
            Verdict::Last(d) => Some(d),
            _ => None,
        }
    };
    let mut outcome = show(scheme, observers);
    for _ in 0..steps {
        if outcome.is_some() || observers.iter().any(|o| o.halted()) {
            break;
        }
        let before = scheme.state().t;
        outcome = match scheme.step() {
            Ok(()) => show(scheme, observers),
            Err(SchemeError::NonFinite { step, time }) => {
                let reason = match non_finite_load(problem.system.system(), before, time) {
                    Some(load_time) => DivergenceReason::NonFiniteLoad { load_time, key: problem.system.force_key() },
                    None => DivergenceReason::NonFiniteState,
                };
                Some(Divergence { step, time, reason })
            }
            Err(e) => return Err(e),
        };
    }
    Ok(match outcome {
        None => Outcome::Completed,
        Some(d) => {
            for o in observers.iter_mut() {
                o.diverged(&d);
            }
            Outcome::Diverged(d)
        }
    })
}

/// The contact values of one state, node by node: what the summary keeps of them
/// (`min_u0`, `max_lambda`, `max_complementarity_product`, impact and release). Computed where
/// the state lives: by the driver ([`ContactStats::of`]) or by the engine that streams it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactStats {
    /// `min_c u_c` (+∞ without contact unknowns).
    pub min_u: f64,
    /// `max_c λ_c` (−∞ without contact unknowns).
    pub max_lambda: f64,
    /// `max_c |(u_c − lb_c) λ_c|` (0 without contact unknowns).
    pub max_product: f64,
    /// Some contact node carries a compressive force, `λ_c < 0` (Σ R > 0): contact is read off
    /// the force, not off `u_c ≤ lb_c`, which round-off decides where a node sits at its bound
    /// (the forward-increment multiplier leaves u_c at −gap ± 1 ulp while λ_c < 0 persists;
    /// issue 32, item 1).
    pub touching: bool,
}

impl ContactStats {
    /// The statistics of `u` (unknowns) and `lambda` (contact order) over the contact unknowns
    /// `contact` with bounds `lower` (contact order).
    pub fn of(u: &[f64], lambda: &[f64], contact: &[usize], lower: &[f64]) -> Self {
        let mut s = Self { min_u: f64::INFINITY, max_lambda: f64::NEG_INFINITY, max_product: 0.0, touching: false };
        for (c, &i) in contact.iter().enumerate() {
            s.touching |= lambda[c] < 0.0;
            s.min_u = s.min_u.min(u[i]);
            s.max_lambda = s.max_lambda.max(lambda[c]);
            s.max_product = s.max_product.max(((u[i] - lower[c]) * lambda[c]).abs());
        }
        s
    }
}
