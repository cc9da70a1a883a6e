//! Beyond the paper: the classic rebounding bar, run by every scheme with every mass.
//!
//! A free bar (far end free) at rest shape, moving at v⁰ = −1 towards the obstacle `gap` away
//! (`scenes/rebound-free-bar.toml`: L = 1, ρ = E = 1, gap = 0.1). Its exact solution
//! (`massredist::characteristics`, d'Alembert waves reflected evenly at the free end):
//!
//! ```text
//! t ∈ [0, g]:          rigid flight,  u = −t                   (first impact at t = g/|v⁰| = g)
//! t ∈ [g, g + 2L/c]:   contact, u(0,t) = −g, λ = −√(Eρ)·|v⁰|   (the compression wave goes to
//!                      the free end and back: 2L/c)
//! t ≥ g + 2L/c:        rigid flight,  u = −g + (t − g − 2L/c)  (uniform velocity +|v⁰|)
//! ```
//!
//! The momentum balance ρL v̄' = −λ turns the velocity −1 into +1 over the contact.
//!
//! Each run uses the mesh and Δt of the paper's runs ([`Config::elements`], [`Config::dt`]) and
//! T = [`REBOUND_END`]; it records (observer [`BarMotion`]) u_0, λ and the centre of mass of
//! the discrete bar, from which the contact events and the rebound velocity are read. The exact
//! facts the section relies on are computed from the characteristics solution
//! ([`exact_rebound`]), none is typed in.

use super::{Config, Experiment, ReproduceError};
use massredist::bar::BarProblem;
use massredist::driver::{Needs, Observer, Sample, integrate};
use massredist::exact::Exact;
use massredist::mass::MassKind;
use massredist::observe::{Summary, SummaryObserver};
use massredist::run::RunError;
use massredist::scene::{Scene, SchemeSpec};
use massredist::schemes::SchemeError;
use rayon::prelude::*;

/// The `[bar]` keys of `scenes/rebound-free-bar.toml` but its length and mesh (which are the
/// configuration's): ρ = E = 1, free far end, gap 0.1, u⁰ = 0, v⁰ = −1.
pub const REBOUND_BAR: &str = "density = 1.0\nmodulus = 1.0\nfar_end = \"free\"\ngap = 0.1\n\
                               initial = { displacement = \"0\", velocity = \"-1\" }";

/// Final time: covers the impact (t = gap = 0.1), the release (gap + 2L/c = 2.1) and
/// [`REBOUND_WINDOW`] of free flight after it.
pub const REBOUND_END: f64 = 3.0;

/// Length of the window [T − w, T] over which the rebound velocity is measured.
pub const REBOUND_WINDOW: f64 = 0.5;

/// The runs of the section: every scheme of the paper with each of its masses (the hybrid
/// scheme, defined for w_0 = 0 only, without the standard mass).
pub fn rebound_cases() -> Vec<(Experiment, MassKind)> {
    Experiment::ALL.iter().flat_map(|&e| e.masses().into_iter().map(move |m| (e, m))).collect()
}

/// The `[scheme]` table of a scheme specification (its serde form, every key written).
fn scheme_toml(spec: &SchemeSpec) -> String {
    toml::to_string(spec).expect("a scheme always serialises").trim_end().to_string()
}

/// The scene of one run, as TOML text: [`REBOUND_BAR`] on the configuration's mesh, the
/// scheme as the paper runs it ([`Experiment::spec`]), Δt of the configuration, T =
/// [`REBOUND_END`], no series, the exact L² error at every step.
pub fn rebound_scene_text(config: &Config, e: Experiment, mass: &MassKind) -> String {
    scene_text(config, e, mass, 0.0)
}

/// [`rebound_scene_text`] with v⁰ = −1 + `dv` (`dv` = 0 gives it exactly).
fn scene_text(config: &Config, e: Experiment, mass: &MassKind, dv: f64) -> String {
    let bar = if dv == 0.0 {
        REBOUND_BAR.to_string()
    } else {
        REBOUND_BAR.replace("velocity = \"-1\"", &format!("velocity = \"-1{dv:+e}\""))
    };
    format!(
        "[bar]\nlength = {:?}\nelements = {}\n{bar}\n[mass]\nkind = \"{}\"\n[scheme]\n{}\n\
         [time]\ndt = {:?}\nend = {REBOUND_END:?}\n[output]\nseries = []\nsummary_l2 = true\n",
        config.length,
        config.elements,
        mass.name(),
        scheme_toml(&e.spec()),
        config.dt,
    )
}

/// The changes of v⁰ of the reruns of a round-off sensitive case (with the unperturbed run: five
/// runs, v⁰ changed by 0, ±1e-13, ±2e-13).
pub const REBOUND_DV: [f64; 4] = [1e-13, -1e-13, 2e-13, -2e-13];

/// The case whose numbers amplify round-off: the standard mass with Crank–Nicolson chatters
/// after its impact (a 1e-13 change of v⁰ moves its L∞(0,T;L²) error from 0.37 to 0.65); every
/// other case gives the same four digits in the five runs.
pub fn rebound_sensitive(e: Experiment, mass: &MassKind) -> bool {
    e == Experiment::CrankNicolson && *mass == MassKind::Standard
}

/// Records, at every step, t, u_0, λ and the centre of mass of the discrete bar,
///
/// ```text
/// ū = 1ᵀM U / 1ᵀM 1   (M the redistributed mass: each node weighted by its share of the mass)
/// ```
///
/// whose slope is the bar's mean velocity: `1ᵀM V / 1ᵀM 1` is momentum over mass, and
/// `1ᵀM (U^{n+1} − Uⁿ) = Δt 1ᵀM (V^{n+1} + Vⁿ)/2` for Crank–Nicolson. A massless contact node
/// (w_0 = 0) has no share.
#[derive(Debug, Clone)]
pub struct BarMotion {
    /// `M 1`: the nodal masses (row sums of M), and their sum.
    weights: Vec<f64>,
    total: f64,
    /// The obstacle bound −gap of the contact node.
    pub lower: f64,
    pub t: Vec<f64>,
    pub u0: Vec<f64>,
    pub lambda: Vec<f64>,
    pub centre: Vec<f64>,
}

impl BarMotion {
    /// For `problem`, with room for `steps` + 1 samples.
    pub fn new(problem: &BarProblem, steps: usize) -> Self {
        let system = &problem.system.system;
        let ones = vec![1.0; system.n()];
        let mut weights = vec![0.0; system.n()];
        system.mass.mul_into(&ones, &mut weights);
        let total = weights.iter().sum();
        let column = || Vec::with_capacity(steps + 1);
        Self { weights, total, lower: system.lower[0], t: column(), u0: column(), lambda: column(), centre: column() }
    }

    /// The last t_n with contact force, λⁿ < 0, after which the bar leaves (some later t_n has
    /// λ = 0); None if there was no contact or the bar is still in contact at the last step.
    /// Contact is read off the force, not off u_0ⁿ ≤ −gap (issue 32, item 1).
    pub fn last_contact(&self) -> Option<f64> {
        let n = self.lambda.iter().rposition(|&l| l < 0.0)?;
        (n + 1 < self.u0.len()).then(|| self.t[n])
    }

    /// Number of contact episodes: maximal runs of consecutive steps with λⁿ < 0 (1 for a
    /// single clean contact; more if the contact force chatters).
    pub fn contact_episodes(&self) -> usize {
        let on: Vec<bool> = self.lambda.iter().map(|&l| l < 0.0).collect();
        on.iter().enumerate().filter(|&(n, &c)| c && (n == 0 || !on[n - 1])).count()
    }

    /// The mean velocity of the bar over the last `window` time units,
    /// `(ū(t_N) − ū(t_N − window)) / window` (on the grid); None if the run is shorter.
    pub fn rebound_velocity(&self, window: f64) -> Option<f64> {
        let last = self.t.len().checked_sub(1)?;
        let t_from = self.t[last] - window;
        // The first grid time at or after t_N − window; 1e-9 relative slack for the rounding
        // of n·Δt, which may put t_n a few ulps below it.
        let first = self.t.iter().position(|&t| t >= t_from - 1e-9 * window.abs().max(1.0))?;
        (first < last).then(|| (self.centre[last] - self.centre[first]) / (self.t[last] - self.t[first]))
    }
}

impl Observer for BarMotion {
    fn needs(&self) -> Needs {
        Needs::default()
    }

    fn observe(&mut self, s: &Sample) {
        let moment: f64 = self.weights.iter().zip(s.state.u).map(|(w, u)| w * u).sum();
        self.t.push(s.state.t);
        self.u0.push(s.u0);
        self.lambda.push(s.pressure);
        self.centre.push(moment / self.total);
    }
}

/// One run of the section.
#[derive(Debug, Clone)]
pub struct ReboundResult {
    pub experiment: Experiment,
    pub mass: MassKind,
    pub summary: Summary,
    pub motion: BarMotion,
    /// A scheme that fails mid-run keeps what was observed up to the failure.
    pub failure: Option<SchemeError>,
    /// [`BarMotion::last_contact`], and minus the exact end of the first contact.
    pub last_contact_time: Option<f64>,
    pub last_contact_shift: Option<f64>,
    pub contact_episodes: usize,
    /// [`BarMotion::rebound_velocity`] over [`REBOUND_WINDOW`] (exact: +1).
    pub rebound_velocity: Option<f64>,
    /// The reruns from v⁰ changed by [`REBOUND_DV`] of a [`rebound_sensitive`] case (else empty).
    pub copies: Vec<ReboundCopy>,
}

/// What a rerun of a round-off sensitive case keeps.
#[derive(Debug, Clone)]
pub struct ReboundCopy {
    pub summary: Summary,
    pub last_contact_time: Option<f64>,
    pub contact_episodes: usize,
    pub rebound_velocity: Option<f64>,
}

impl ReboundResult {
    pub fn name(&self) -> String {
        case_name(self.experiment, &self.mass)
    }

    /// `value` of this run (summary, last contact, contact episodes, rebound velocity), then of
    /// each rerun.
    pub fn over_runs<T>(&self, value: impl Fn(&Summary, Option<f64>, usize, Option<f64>) -> T) -> Vec<T> {
        std::iter::once(value(&self.summary, self.last_contact_time, self.contact_episodes, self.rebound_velocity))
            .chain(
                self.copies
                    .iter()
                    .map(|c| value(&c.summary, c.last_contact_time, c.contact_episodes, c.rebound_velocity)),
            )
            .collect()
    }
}

fn case_name(e: Experiment, mass: &MassKind) -> String {
    format!("rebound / {} / {}", e.slug(), mass.name())
}

/// The scene and its problem (with the exact solution by characteristics attached).
fn problem_of(
    config: &Config,
    e: Experiment,
    mass: &MassKind,
    dv: f64,
) -> Result<(Scene<massredist::bar::BarSpec>, BarProblem), ReproduceError> {
    let case = case_name(e, mass);
    let scene = Scene::from_toml(&scene_text(config, e, mass, dv))
        .map_err(|source| ReproduceError::Scene { case: case.clone(), source })?;
    let problem =
        BarProblem::from_scene(&scene).map_err(|e| ReproduceError::Run { case, source: RunError::problem(e) })?;
    Ok((scene, problem))
}

/// Runs scheme `e` with `mass` on the rebounding bar: the summary (L² error at every step) and
/// the [`BarMotion`]; a [`rebound_sensitive`] case also from v⁰ changed by each of [`REBOUND_DV`].
pub fn run_rebound(config: &Config, e: Experiment, mass: &MassKind) -> Result<ReboundResult, ReproduceError> {
    let mut r = run_rebound_dv(config, e, mass, 0.0)?;
    if rebound_sensitive(e, mass) {
        for dv in REBOUND_DV {
            let c = run_rebound_dv(config, e, mass, dv)?;
            r.copies.push(ReboundCopy {
                summary: c.summary,
                last_contact_time: c.last_contact_time,
                contact_episodes: c.contact_episodes,
                rebound_velocity: c.rebound_velocity,
            });
        }
    }
    Ok(r)
}

/// One run of [`run_rebound`] from v⁰ = −1 + `dv`.
fn run_rebound_dv(config: &Config, e: Experiment, mass: &MassKind, dv: f64) -> Result<ReboundResult, ReproduceError> {
    let (scene, problem) = problem_of(config, e, mass, dv)?;
    let wrap = |source: SchemeError| ReproduceError::Run { case: case_name(e, mass), source: RunError::from(source) };
    let mut scheme = problem.scheme(&scene.scheme, scene.time.dt).map_err(wrap)?;
    let steps = scene.time.steps;
    let mut summary = SummaryObserver::new(&problem, steps, scene.time.dt, true);
    let mut motion = BarMotion::new(&problem, steps);
    let failure = integrate(&problem, scheme.as_mut(), steps, &mut [&mut summary, &mut motion]).err();
    let exact_release = problem.exact.as_ref().and_then(Exact::first_contact).map(|c| c.1);
    let last_contact_time = motion.last_contact();
    Ok(ReboundResult {
        experiment: e,
        mass: mass.clone(),
        summary: summary.finish(),
        last_contact_shift: last_contact_time.zip(exact_release).map(|(t, r)| t - r),
        last_contact_time,
        contact_episodes: motion.contact_episodes(),
        rebound_velocity: motion.rebound_velocity(REBOUND_WINDOW),
        motion,
        failure,
        copies: Vec::new(),
    })
}

/// The exact facts the section compares with, read off the exact solution by characteristics.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactRebound {
    /// The contact phases up to T, `[start, end)` (one: [gap, gap + 2L/c)).
    pub contacts: Vec<(f64, f64)>,
    /// min and max of λ(t_n) over the grid times strictly inside the first contact (−√(Eρ)).
    pub force: (f64, f64),
    /// `(ū(T) − ū(T − w)) / w` of the nodal interpolant of the exact u, ū its mean (P1
    /// integral over L), w = [`REBOUND_WINDOW`] (exact: +1, the motion being rigid there).
    pub rebound_velocity: f64,
    /// The energy ½∫ρu_t² + ½∫E u_x² (constant: ½ρL for v⁰ = −1).
    pub energy: f64,
}

/// [`ExactRebound`] of a solution by characteristics on `[0, end]`, sampled on the grid
/// `n·dt` and on m elements of [0, L]; None for the paper's closed form or without contact.
pub fn exact_rebound(exact: &Exact, elements: usize, dt: f64, end: f64) -> Option<ExactRebound> {
    let Exact::General(c) = exact else { return None };
    let contacts = c.contact_intervals().to_vec();
    let &(start, stop) = contacts.first()?;
    let steps = (end / dt).round() as usize;
    let inside = (0..=steps).map(|n| n as f64 * dt).filter(|&t| t > start && t < stop);
    let force = inside.map(|t| c.lambda(t)).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), l| (a.min(l), b.max(l)));
    let h = c.length() / elements as f64;
    // ∫ I_h u(·, t) dx / L by the trapezoidal rule, exact for the P1 interpolant.
    let mean = |t: f64| {
        let sum: f64 =
            (0..=elements).map(|i| if i == 0 || i == elements { 0.5 } else { 1.0 } * c.u(i as f64 * h, t)).sum();
        sum * h / c.length()
    };
    let rebound_velocity = (mean(end) - mean(end - REBOUND_WINDOW)) / REBOUND_WINDOW;
    Some(ExactRebound { contacts, force, rebound_velocity, energy: c.energy(0.0) })
}

/// Every run of the section and the exact facts.
#[derive(Debug, Clone)]
pub struct Rebound {
    pub runs: Vec<ReboundResult>,
    pub exact: ExactRebound,
    /// The exact solution (for the figure's exact curves).
    pub solution: Exact,
}

/// Runs every case of [`rebound_cases`] in parallel (`done` after each) and reads the exact
/// facts off the solution by characteristics.
pub fn compute_rebound(config: &Config, done: &(dyn Fn() + Sync)) -> Result<Rebound, ReproduceError> {
    let runs = rebound_cases()
        .par_iter()
        .map(|(e, m)| {
            let r = run_rebound(config, *e, m);
            done();
            r
        })
        .collect::<Result<Vec<_>, _>>()?;
    let (scene, problem) = problem_of(config, Experiment::CrankNicolson, &MassKind::Mod3, 0.0)?;
    let no_exact = || ReproduceError::NoExact { case: "rebound".into() };
    let solution = problem.exact.ok_or_else(no_exact)?;
    let exact = exact_rebound(&solution, config.elements, config.dt, scene.time.end).ok_or_else(no_exact)?;
    Ok(Rebound { runs, exact, solution })
}
