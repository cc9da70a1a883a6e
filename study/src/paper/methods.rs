//! Every method class of issue 20 side by side, DEP-style (Doyen, Ern, Piperno, SIAM J. Sci.
//! Comput. 33(1), 2011): implicit schemes with exact contact (Crank–Nicolson, backward Euler,
//! hybrid, Paoli–Schatzman), implicit schemes with penalty contact, explicit central differences
//! with exact (massless contact node, or the forward-increment multiplier on the standard mass)
//! and penalty contact, and Moreau–Jean's velocity-impulse scheme, on four 1D problems with exact
//! solutions by characteristics ([`PROBLEMS`]). Shared by `massredist bench --methods` (finer
//! meshes, `crate::bench::methods`) and the `reproduce` section (coarse, [`MethodsConfig::reproduce`]).
//!
//! [`METHODS`] is the one table of methods, one line per method: a new method (Nitsche) is one
//! more line. Every method runs with every mass it applies to ([`Method::masses`]).
//!
//! Each run measures, against the exact solution ([`massredist::exact::Exact`]):
//!
//! ```text
//! L∞(L²)     max_{t_n ≤ T_err} ‖u_h − u‖_L² / max_{t_n ≤ T_err} ‖I_h u‖_L²        (relative)
//! impact     (t_impact,h − t_impact)/D,  D the exact first contact's duration     (first t_n with λⁿ < 0)
//! duration   (D_h − D)/D,  D_h = first release − first impact                     (release: first later λⁿ = 0)
//!            (every event is read off the force, for every method: the forward-increment
//!            multiplier leaves u_0 at −gap ± 1 ulp while λ < 0 persists, and Nitsche's u_0 may
//!            sit above −gap while it pushes; issue 32, item 1)
//! rebound    v̄(T)/V₀,  v̄ = 1ᵀMV / 1ᵀM1 the bar's mean velocity (free rods; exact 1)
//! force TV   Σ_n |λⁿ⁺¹ − λⁿ| / Σ_n |λ(t_{n+1}) − λ(t_n)|                          (exact: 1; oscillation > 1)
//! impulse    Σ_n λⁿ / Σ_n λ(t_n)                                                  (exact: 1)
//! penetration max_n max(0, −gap − u_0ⁿ) / L
//! drift      (E(T) − E(0))/E(0) of the scheme's own energy, after the exact solution's impacts in (0, T]
//! half-step  (H(T) − H^{½})/H^{½} of Störmer–Verlet's half-step energy H^{n+½} (central
//!            differences with the exact law only; issue 32, item 4)
//! CPU        seconds of set-up and stepping alone (no diagnostics), fastest of up to 3 runs; and
//!            of the stepping alone (central differences' set-up includes its stable limit)
//! ```
//!
//! **Chaos rule.** After an impact the standard mass (massive contact node) and Paoli–Schatzman
//! amplify round-off (`super::band`): for those cases ([`sensitive`]) the run is repeated from
//! [`super::band::PERTURBATIONS`] perturbed U⁰ and V⁰ (|δ| ≤ 1e-13, relative, and absolute on V⁰
//! times a velocity scale of the problem: the free rods start from U⁰ = 0) and tables print only
//! the digits all five runs share, else the band min–max ([`super::band::stable_digits`]).

pub use super::band::agreed_digits;
use serde::Serialize;

mod run;

pub use run::{compute, run_case};

/// A contact law as the `[contact]` table of a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    Exact,
    /// `penalty = factor · E/h` (a plain spring per contact node; scaled with the mesh so that
    /// it stiffens as h → 0: κ h/E fixed).
    Penalty(f64),
    /// Any other `[contact]` body, verbatim (Nitsche: one line in [`METHODS`]).
    Toml(&'static str),
}

/// One method of the comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Method {
    /// Name in tables, figures and CSV.
    pub label: &'static str,
    /// Its class (DEP's families).
    pub class: &'static str,
    /// The `[scheme]` table body.
    pub scheme: &'static str,
    pub law: Law,
    /// The masses it applies to.
    pub masses: &'static [&'static str],
    /// How its time step is chosen.
    pub step: Step,
}

/// The time step of a method (issue 32, item 2: every explicit run of the comparison at one
/// stated safety factor).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// Δt = h/c: the implicit classes, which have no stable limit; for an explicit scheme the
    /// special case of a uniform 1D mesh, where h/c is the characteristic step (Courant 1) and
    /// lies below Δt_c only for mod3 (its Δt_c is h/c (1 + O(1/m²))). A case whose Δt_c is at
    /// or below h/c is refused, not moved.
    Courant,
    /// Δt = [`SAFETY`] · Δt_c, with Δt_c from the scheme's estimator (converged Lanczos on
    /// these bars, `stable_step_method`).
    Stable,
}

const ALL: &[&str] = &["standard", "mod1", "mod2", "mod3"];
const MASSLESS: &[&str] = &["mod1", "mod2", "mod3"];
/// The masses whose Δt_c on a uniform bar lies above h/c ([`Step::Courant`]'s special case).
const COURANT_ONE: &[&str] = &["mod3"];
/// Moreau–Jean needs inertia at the contact node (w_0 > 0).
const MASSIVE: &[&str] = &["standard"];
/// The explicit penalty sized to keep Δt_c (issue 32, item 4): κ = r E/h with
/// r = √((2/ϱ² − 1)² − 1) and ϱ = [`KEPT_STEP_FRACTION`].
///
/// On the lumped standard mass of a uniform bar (node masses ρh, ρh/2 at the end, springs
/// k = E/h) a spring κ at the end node adds a mode localised there, u_j = (−q)^j with
/// 1/q − q = 2κ/k: the interior rows give mω² = k(2 + q + 1/q), the end row
/// ½mω² = k + κ + kq. So ω² = (2k/m)(1 + √(1 + r²)), r = κ/k, above the band's edge 4k/m for
/// every κ > 0, and Δt_c falls by ϱ = √(2/(1 + √(1 + r²))): κ = E/h (r = 1) gives 0.910, the
/// Δt_c Lanczos found for the old "CD pen 1" row on the standard mass. Solving for r at
/// ϱ = 0.99 gives 0.2879: a spring that keeps 99 % of Δt_c. With a massless contact node
/// (w_0 = 0) the spring acts in series with the first element and Δt_c does not move at all.
pub const KEPT_STEP_PENALTY: f64 = 0.2879;
/// The share of the penalty-free Δt_c that [`KEPT_STEP_PENALTY`] keeps.
pub const KEPT_STEP_FRACTION: f64 = 0.99;

const CN: &str = "kind = \"crank-nicolson\"";
const BE: &str = "kind = \"backward-euler\"";
const CD: &str = "kind = \"central-difference\"";

/// The one table of methods, one line each (a new method or law: one more line).
#[rustfmt::skip]
pub const METHODS: &[Method] = &[
    Method { label: "CN", class: "implicit, exact", scheme: CN, law: Law::Exact, masses: ALL, step: Step::Courant },
    Method { label: "BE", class: "implicit, exact", scheme: BE, law: Law::Exact, masses: ALL, step: Step::Courant },
    Method { label: "hybrid", class: "implicit, exact", scheme: "kind = \"hybrid\"", law: Law::Exact, masses: MASSLESS, step: Step::Courant },
    Method { label: "PS e=1", class: "implicit, exact", scheme: "kind = \"paoli-schatzman\"\nbeta = 0.25\nrestitution = 1.0", law: Law::Exact, masses: ALL, step: Step::Courant },
    Method { label: "CN pen 1", class: "implicit, penalty", scheme: CN, law: Law::Penalty(1.0), masses: ALL, step: Step::Courant },
    Method { label: "CN pen 100", class: "implicit, penalty", scheme: CN, law: Law::Penalty(100.0), masses: ALL, step: Step::Courant },
    Method { label: "BE pen 1", class: "implicit, penalty", scheme: BE, law: Law::Penalty(1.0), masses: ALL, step: Step::Courant },
    Method { label: "BE pen 100", class: "implicit, penalty", scheme: BE, law: Law::Penalty(100.0), masses: ALL, step: Step::Courant },
    Method { label: "CD", class: "explicit, exact", scheme: CD, law: Law::Exact, masses: ALL, step: Step::Stable },
    Method { label: "CD c=1", class: "explicit, exact", scheme: CD, law: Law::Exact, masses: COURANT_ONE, step: Step::Courant },
    Method { label: "CD pen 0.29", class: "explicit, penalty", scheme: CD, law: Law::Penalty(KEPT_STEP_PENALTY), masses: ALL, step: Step::Stable },
    Method { label: "CD pen 100", class: "explicit, penalty", scheme: CD, law: Law::Penalty(100.0), masses: ALL, step: Step::Stable },
    Method { label: "CN Nitsche", class: "implicit, Nitsche", scheme: CN, law: Law::Toml("method = \"nitsche\"\nnitsche_theta = 1\nnitsche_gamma0 = 100.0"), masses: ALL, step: Step::Courant },
    Method { label: "CD Nitsche", class: "explicit, Nitsche", scheme: CD, law: Law::Toml("method = \"nitsche\"\nnitsche_theta = 1\nnitsche_gamma0 = 100.0"), masses: ALL, step: Step::Stable },
    Method { label: "MJ θ=½ e=0", class: "velocity impulse", scheme: "kind = \"moreau-jean\"\ntheta = 0.5\nrestitution = 0.0", law: Law::Exact, masses: MASSIVE, step: Step::Courant },
    Method { label: "MJ θ=½ e=½", class: "velocity impulse", scheme: "kind = \"moreau-jean\"\ntheta = 0.5\nrestitution = 0.5", law: Law::Exact, masses: MASSIVE, step: Step::Courant },
    Method { label: "MJ θ=1 e=0", class: "velocity impulse", scheme: "kind = \"moreau-jean\"\ntheta = 1.0\nrestitution = 0.0", law: Law::Exact, masses: MASSIVE, step: Step::Courant },
    Method { label: "MJ θ=1 e=½", class: "velocity impulse", scheme: "kind = \"moreau-jean\"\ntheta = 1.0\nrestitution = 0.5", law: Law::Exact, masses: MASSIVE, step: Step::Courant },
];

/// A 1D test problem with an exact solution (no body force).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Problem1d {
    pub key: &'static str,
    pub title: &'static str,
    pub length: f64,
    pub density: f64,
    pub modulus: f64,
    pub gap: f64,
    /// The `far_end` and `initial` keys of `[bar]`.
    pub rest: &'static str,
    /// Arrival speed V₀ of a free rod (its rebound velocity is measured against it), or None.
    pub v0: Option<f64>,
    /// Horizon in crossing times L/c beyond the impact at gap/V₀ (the paper's bar: 30 = 10 periods).
    pub crossings: f64,
    /// The L∞(L²) window in crossing times (None: the whole horizon).
    pub error_window: Option<f64>,
    /// The benchmark's own discretisation (elements, Δt), where it has one (issue 32, item 7:
    /// VM265's 20 elements and Δt = 2.226e-6 s), run by [`MethodsConfig::own`].
    pub own: Option<(usize, f64)>,
}

impl Problem1d {
    pub fn c(&self) -> f64 {
        (self.modulus / self.density).sqrt()
    }

    /// T₀ = gap/V₀ + crossings · L/c (the run ends at the first multiple of Δt ≥ T₀).
    pub fn horizon(&self) -> f64 {
        self.v0.map_or(0.0, |v| self.gap / v) + self.crossings * self.length / self.c()
    }
}

/// SDNV100's uniaxial-strain modulus E(1−ν)/((1+ν)(1−2ν)), E = 2e11, ν = 0.3.
const SDNV100_MODULUS: f64 = 2e11 * 0.7 / (1.3 * 0.4);

/// (a) the paper's bar (§4.1: clamped, u⁰ = (L−x)/2, 3-periodic, one impact per period), over
/// ten periods, L∞(L²) over the first; (b) the rebounding free bar (`scenes/rebound-free-bar.toml`);
/// (c) ANSYS VM265's rod (in, lbf·s²/in⁴, psi; impact at 5.0e-5 s, contact 2L/c, force ρcAV₀);
/// (d) Code_Aster SDNV100 in 1D (uniaxial strain). The free rods run to 3 crossings after the
/// impact (2 in contact, 1 of free flight).
pub const PROBLEMS: [Problem1d; 4] = [
    Problem1d {
        key: "paper-bar",
        title: "(a) paper's bar, 10 periods",
        length: 1.0,
        density: 1.0,
        modulus: 1.0,
        gap: 0.0,
        rest: "far_end = \"clamped\"\ninitial = \"paper\"",
        v0: None,
        crossings: 30.0,
        error_window: Some(3.0),
        own: None,
    },
    Problem1d {
        key: "rebound-bar",
        title: "(b) rebounding free bar",
        length: 1.0,
        density: 1.0,
        modulus: 1.0,
        gap: 0.1,
        rest: "far_end = \"free\"\ninitial = { displacement = \"0\", velocity = \"-1\" }",
        v0: Some(1.0),
        crossings: 3.0,
        error_window: None,
        own: None,
    },
    Problem1d {
        key: "vm265",
        title: "(c) ANSYS VM265 rod",
        length: 10.0,
        density: 7.3e-4,
        modulus: 3.0e7,
        gap: 0.01,
        rest: "far_end = \"free\"\ninitial = { displacement = \"0\", velocity = \"-202.2\" }",
        v0: Some(202.2),
        crossings: 3.0,
        error_window: None,
        own: Some((20, 2.226e-6)),
    },
    Problem1d {
        key: "sdnv100",
        title: "(d) Code_Aster SDNV100 (1D)",
        length: 0.2,
        density: 8000.0,
        modulus: SDNV100_MODULUS,
        gap: 2e-3,
        rest: "far_end = \"free\"\ninitial = { displacement = \"0\", velocity = \"-100\" }",
        v0: Some(100.0),
        crossings: 3.0,
        error_window: None,
        own: None,
    },
];

/// Meshes of a comparison.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MethodsConfig {
    /// Element counts of the work–precision sweep (Δt by [`Step`]: h/c, or 0.9 Δt_c for explicit runs).
    pub elements: Vec<usize>,
    /// The mesh of the tables (one of `elements`).
    pub table_elements: usize,
    /// The implicit classes' Δt sweep (issue 32, item 4): multiples k of h/c beyond 1 at which
    /// every implicit method also runs on the tables' mesh, for a work–precision comparison at
    /// a fixed mesh ([`Case::courant`]).
    pub sweep: Vec<f64>,
    /// Whether every method also runs at each problem's own discretisation ([`Problem1d::own`]).
    pub own: bool,
}

impl MethodsConfig {
    /// `bench --methods`.
    pub fn bench() -> Self {
        Self { elements: vec![25, 50, 100, 200, 400], table_elements: 100, sweep: vec![2.0, 5.0, 10.0], own: true }
    }

    /// The `reproduce` section (small: a few seconds).
    pub fn reproduce() -> Self {
        Self { elements: vec![25, 50, 100], table_elements: 50, sweep: Vec::new(), own: false }
    }
}

/// One run: a method with a mass on a problem and mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Case {
    pub method: &'static Method,
    pub mass: &'static str,
    pub problem: &'static Problem1d,
    pub elements: usize,
    /// cΔt/h of an implicit method ([`Step::Courant`]): 1, or a multiple of the Δt sweep.
    pub courant: f64,
    /// A fixed Δt, the benchmark's own ([`Problem1d::own`]), whatever the method's [`Step`] (an
    /// explicit scheme refuses it above its Δt_c).
    pub dt: Option<f64>,
}

impl Method {
    /// An implicit class: no stable limit, Δt by [`Step::Courant`] (the Δt sweep runs these).
    pub fn implicit(&self) -> bool {
        self.step == Step::Courant && self.scheme != CD
    }
}

/// Every (problem, method, mass, mesh) of `config`, and the implicit methods' Δt sweep on the
/// tables' mesh.
pub fn cases(config: &MethodsConfig) -> Vec<Case> {
    let mut out = Vec::new();
    for problem in &PROBLEMS {
        for method in METHODS {
            for &mass in method.masses {
                for &elements in &config.elements {
                    out.push(Case { method, mass, problem, elements, courant: 1.0, dt: None });
                }
                if method.implicit() {
                    let elements = config.table_elements;
                    let sweep = config.sweep.iter();
                    out.extend(sweep.map(|&courant| Case { method, mass, problem, elements, courant, dt: None }));
                }
                if let (true, Some((elements, dt))) = (config.own, problem.own) {
                    out.push(Case { method, mass, problem, elements, courant: 1.0, dt: Some(dt) });
                }
            }
        }
    }
    out
}

/// Whether a case's numbers amplify round-off (module docs): a massive contact node, or
/// Paoli–Schatzman.
pub fn sensitive(case: &Case) -> bool {
    case.mass == "standard" || case.method.scheme.contains("paoli-schatzman")
}

/// The scene text of a case at time step `dt` over `steps` steps (no series; the exact L²
/// error is computed by the observer).
pub fn scene_text(case: &Case, dt: f64, steps: usize) -> String {
    let p = case.problem;
    let h = p.length / case.elements as f64;
    let contact = match case.method.law {
        Law::Exact => String::new(),
        Law::Penalty(f) => format!("[contact]\nmethod = \"penalty\"\npenalty = {:?}\n", f * p.modulus / h),
        Law::Toml(body) => format!("[contact]\n{body}\n"),
    };
    format!(
        "[bar]\nlength = {:?}\nelements = {}\ndensity = {:?}\nmodulus = {:?}\ngap = {:?}\n{}\n[mass]\nkind = \"{}\"\n\
         [scheme]\n{}\n{contact}[time]\ndt = {dt:?}\nend = {:?}\n[output]\nseries = []\nsummary_l2 = false\n",
        p.length,
        case.elements,
        p.density,
        p.modulus,
        p.gap,
        p.rest,
        case.mass,
        case.method.scheme,
        dt * steps as f64,
    )
}

/// The measurements of one run (module docs); None where not applicable.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Metrics {
    pub l2_error: f64,
    pub impact_error: Option<f64>,
    pub duration_error: Option<f64>,
    pub rebound: Option<f64>,
    pub force_tv: Option<f64>,
    pub impulse: Option<f64>,
    pub penetration: f64,
    pub energy_drift: f64,
    /// Central differences with the exact law: the drift of Störmer–Verlet's half-step energy
    /// H^{n+½} ([`super::cd_growth::shadow_energy`]), (H_end − H^{½})/H^{½}, beside the
    /// integer-step energy's (issue 32, item 4).
    pub half_step_drift: Option<f64>,
    /// The first t_n with λⁿ < 0 and the first later one with λⁿ = 0 (seconds).
    pub first_impact: Option<f64>,
    pub first_release: Option<f64>,
}

/// A case's result: the unperturbed run and, for a [`sensitive`] case, the perturbed copies.
#[derive(Debug, Clone, Serialize)]
pub struct MethodResult {
    pub method: &'static str,
    pub class: &'static str,
    pub mass: &'static str,
    pub problem: &'static str,
    pub elements: usize,
    pub dt: f64,
    /// c Δt / h.
    pub courant: f64,
    /// A run of the implicit classes' Δt sweep ([`MethodsConfig::sweep`], cΔt/h > 1), not of
    /// the tables and mesh lines.
    pub in_sweep: bool,
    /// A run at the benchmark's own discretisation ([`Case::dt`]), not of the tables and lines.
    pub own: bool,
    pub steps: usize,
    /// Impacts of the exact solution in (0, T].
    pub exact_impacts: usize,
    /// "ok", "diverged" or "failed" (the unperturbed run's).
    pub status: &'static str,
    pub failure: Option<String>,
    /// The unperturbed run first, then the copies (empty unless status is "ok").
    pub runs: Vec<Metrics>,
    pub cpu_seconds: f64,
    /// The stepping alone, in the same fastest run.
    pub step_seconds: f64,
    /// An explicit scheme's stable limit Δt_c and the estimator that gave it (the summary's
    /// `stable_step`, `stable_step_method`); None for the implicit classes.
    pub stable_step: Option<f64>,
    pub stable_step_method: Option<&'static str>,
}

/// The one safety factor of every explicit run ([`Step::Stable`]): at Δt_c itself the highest
/// mode is marginally stable and central differences with mod1 on the paper's bar gain 160 E(0)
/// over ten periods (measured), at 0.9 Δt_c its energy stays within 1 % (the usual explicit
/// practice; issue 32, item 2).
pub const SAFETY: f64 = 0.9;

/// The largest Δt that divides `end` and is at most `at_most` (an explicit run at the one safety
/// factor, `at_most` = [`SAFETY`] · Δt_c, on a horizon it must reach exactly).
pub fn step_dividing(end: f64, at_most: f64) -> f64 {
    end / (end / at_most).ceil()
}
