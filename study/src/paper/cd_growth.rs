//! Central differences with a massless contact node over long horizons: the energy growth against
//! Δt/Δt_c (issue 32, item 5), beside Paoli–Schatzman's ([`super::ps_growth`]).
//!
//! The paper's bar (clamped, u⁰ = (L − x)/2, one impact per period 3L/c) with [`ELEMENTS`]
//! elements, every mass with w_0 = 0 (mod1, mod2, mod3), central differences with exact contact
//! (the massless contact node quasi-static), Δt = f Δt_c for f ∈ [`FRACTIONS`] (Δt_c by the
//! scheme's estimator, named), over [`PERIODS`] periods ([`PERIODS_QUICK`] with `--quick`). Each
//! run also from [`band::PERTURBATIONS`] initial states U⁰ perturbed by ≤ [`band::PERTURBATION`],
//! and it stops where the project's divergence rule says (energy above 10⁶ E(0)).
//!
//! **What is measured, and why.** With node 0 massless, the step is Störmer–Verlet on the
//! condensed Hamiltonian `½pᵀM⁻¹p + V(q)`, `V(q) = min_{u_0 ≥ −gap} ½uᵀKu` (q the massive
//! unknowns): the quasi-static solve is that minimisation, and by the envelope theorem its force
//! on q is `−∇V(q)`. So each kick is the exact flow of V, and the step is symplectic wherever it
//! is differentiable. V is convex and C¹ but only piecewise quadratic: one quadratic while the
//! node is free, another while it is in contact. Inside one phase the step is the linear
//! leapfrog of that quadratic, which conserves exactly its shadow energy
//!
//! ```text
//! H^{n+½} = ½ DᵀM_L D + ½ Uⁿᵀ K U^{n+1},   D = (U^{n+1} − Uⁿ)/Δt   (full vectors, u_0 included)
//! ```
//!
//! (positive for Δt < Δt_c). So `H^{n+½} − H^{n−½} = 0` up to round-off whenever U^{n−1}, Uⁿ and
//! U^{n+1} are in the same phase, and all of H's change happens at the steps that straddle a
//! switch. Backward error analysis, which bounds a smooth symplectic integrator's energy over
//! exponentially long times, needs V smooth; across the kink there is no modified Hamiltonian,
//! and nothing bounds the sum of the switch jumps. [`Shadow`] measures this per run: the largest
//! |ΔH| inside a phase, and the sum of the jumps at the switches against H's whole change. The
//! tables report both the growth of the integer-step energy E (the scheme's, ½VᵀM_LV + ½UᵀKU)
//! and of H.

use super::band;
pub use super::band::Verdict;
use super::figures::FigureFile;
use super::periods::DRIFT_FACTOR;
use super::{ReproduceError, tables};
use crate::plot::{Curve, Figure, Panel, Style};
use massredist::bar::BarProblem;
use massredist::driver::{DivergenceCriterion, Needs, Observer, Sample, integrate_watched};
use massredist::linalg::tridiag::SymTridiag;
use massredist::mass::MassKind;
use massredist::models::PaperBar;
use massredist::output::fmt_f64;
use massredist::run::RunError;
use massredist::scene::SchemeSpec;
use massredist::schemes::StiffnessOperator;
use rayon::prelude::*;
use std::fmt::Write as _;

/// Elements of the bar (the issue's m = 50).
pub const ELEMENTS: usize = 50;
/// Δt/Δt_c of the runs (Δt = Δt_c itself is refused: it is not stable).
pub const FRACTIONS: [f64; 8] = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.99];
/// Length of the runs, in periods 3L/c of the exact solution.
pub const PERIODS: usize = 1000;
/// With `--quick`.
pub const PERIODS_QUICK: usize = 100;
/// The figure's (and its CSV's) file stem.
pub const CD_GROWTH_FIGURE: &str = "cd-growth";

/// The masses with a massless contact node.
fn masses() -> [MassKind; 3] {
    [MassKind::Mod1, MassKind::Mod2, MassKind::Mod3]
}

fn spec() -> SchemeSpec {
    SchemeSpec::CentralDifference { operator: StiffnessOperator::Auto }
}

/// The observer of one run (module docs): E and H, and where H moves.
struct Shadow<'a> {
    stiffness: &'a SymTridiag,
    lumped: &'a [f64],
    dt: f64,
    /// Uⁿ⁻¹ and the phases (in contact: λ < 0) of the last three states, newest last.
    prev: Vec<f64>,
    phases: [Option<bool>; 3],
    work: Vec<f64>,
    e0: Option<f64>,
    e_max: f64,
    h0: Option<f64>,
    h_last: f64,
    h_max: f64,
    /// max |H| over the run.
    h_abs: f64,
    /// The largest |ΔH|/|H| over steps inside one phase, the sum of ΔH over the others, their count.
    within: f64,
    switch_sum: f64,
    switch_steps: usize,
}

impl<'a> Shadow<'a> {
    fn new(problem: &'a BarProblem, dt: f64) -> Self {
        let n = problem.u0.len();
        Self {
            stiffness: &problem.system.system.stiffness,
            lumped: &problem.system.lumped,
            dt,
            prev: Vec::new(),
            phases: [None; 3],
            work: vec![0.0; n],
            e0: None,
            e_max: f64::NEG_INFINITY,
            h0: None,
            h_last: f64::NAN,
            h_max: f64::NEG_INFINITY,
            h_abs: 0.0,
            within: 0.0,
            switch_sum: 0.0,
            switch_steps: 0,
        }
    }
}

impl Observer for Shadow<'_> {
    fn needs(&self) -> Needs {
        Needs { energy: true, ..Needs::default() }
    }

    fn observe(&mut self, s: &Sample) {
        let u = s.state.u;
        let e0 = *self.e0.get_or_insert(s.energy);
        self.e_max = self.e_max.max(s.energy / e0);
        self.phases = [self.phases[1], self.phases[2], Some(s.state.lambda[0] < 0.0)];
        if !self.prev.is_empty() {
            let h = shadow_energy(self.stiffness, self.lumped, &self.prev, u, self.dt, &mut self.work);
            match self.h0 {
                None => self.h0 = Some(h),
                Some(_) => {
                    let dh = h - self.h_last;
                    let same = self.phases[0] == self.phases[1] && self.phases[1] == self.phases[2];
                    if same {
                        self.within = self.within.max(dh.abs() / self.h_last.abs());
                    } else {
                        self.switch_sum += dh;
                        self.switch_steps += 1;
                    }
                }
            }
            self.h_last = h;
            self.h_max = self.h_max.max(h);
            self.h_abs = self.h_abs.max(h.abs());
        }
        self.prev.clear();
        self.prev.extend_from_slice(u);
    }
}

/// Störmer–Verlet's half-step (shadow) energy of a bar from two consecutive states (Uⁿ, U^{n+1}) =
/// (`prev`, `u`): H^{n+½} = ½ DᵀM_L D + ½ UⁿᵀK U^{n+1}, D = (U^{n+1} − Uⁿ)/Δt (no force; the
/// exact contact law adds no energy). `work` holds K U^{n+1}.
pub fn shadow_energy(
    stiffness: &SymTridiag,
    lumped: &[f64],
    prev: &[f64],
    u: &[f64],
    dt: f64,
    work: &mut [f64],
) -> f64 {
    stiffness.mul_into(u, work);
    let mixed: f64 = prev.iter().zip(work.iter()).map(|(a, b)| a * b).sum();
    let kinetic: f64 = lumped
        .iter()
        .zip(u.iter().zip(prev))
        .map(|(m, (a, b))| {
            let d = (a - b) / dt;
            m * d * d
        })
        .sum();
    0.5 * (kinetic + mixed)
}

/// One run's measurements (module docs), relative to E₀ = E(0) and H₀ = H^{½}.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CdRun {
    /// max E/E₀ and max H/H₀ over the run (up to the divergence stop).
    pub e_max: f64,
    pub h_max: f64,
    /// The time the divergence rule stopped the run, if it did.
    pub diverged_at: Option<f64>,
    /// max |ΔH^{n+½}|/|H^{n−½}| over the steps inside one phase (round-off of the step: relative
    /// to H itself, which grows by up to 10⁶ before a divergence stop).
    pub within: f64,
    /// (H_end − H₀ − Σ switch jumps)/max |H|: what the switches do not account for.
    pub unexplained: f64,
    /// (H_end − H₀)/H₀.
    pub h_change: f64,
    pub switch_steps: usize,
}

impl CdRun {
    pub fn verdict(&self) -> Verdict {
        Verdict::of_growth(self.diverged_at.is_some(), self.e_max)
    }
}

/// Five runs (unperturbed first) of one mass and Δt = f Δt_c.
#[derive(Debug, Clone)]
pub struct CdGrowth {
    pub mass: MassKind,
    pub fraction: f64,
    pub dt: f64,
    /// Δt_c and its estimator.
    pub limit: f64,
    pub method: &'static str,
    pub runs: Vec<CdRun>,
}

fn problem(mass: &MassKind, k: Option<usize>) -> Result<BarProblem, RunError> {
    let mut p = PaperBar { length: 1.0, elements: ELEMENTS }.problem(mass).map_err(RunError::problem)?;
    if let Some(k) = k {
        p.u0 = band::perturbed(&p.u0, k);
    }
    Ok(p)
}

/// Δt_c of central differences on the bar with `mass`, and its estimator.
fn stable_limit(mass: &MassKind) -> Result<(f64, &'static str), ReproduceError> {
    let case = format!("CD growth / {} / Δt_c", mass.name());
    let run = |source| ReproduceError::Run { case: case.clone(), source };
    let p = problem(mass, None).map_err(run)?;
    let scheme = p.scheme(&spec(), 1e-9).map_err(|e| run(e.into()))?;
    scheme.stable_limit().ok_or(ReproduceError::NoStableLimit { case: case.clone() })
}

fn run_one(mass: &MassKind, dt: f64, periods: usize, k: Option<usize>) -> Result<CdRun, RunError> {
    let p = problem(mass, k)?;
    let end = periods as f64 * 3.0;
    let steps = (end / dt).ceil() as usize;
    let mut scheme = p.scheme(&spec(), dt)?;
    let mut shadow = Shadow::new(&p, dt);
    let outcome = integrate_watched(&p, scheme.as_mut(), steps, &DivergenceCriterion::default(), &mut [&mut shadow])?;
    let h0 = shadow.h0.unwrap_or(f64::NAN);
    let h_change = shadow.h_last - h0;
    Ok(CdRun {
        e_max: shadow.e_max,
        h_max: shadow.h_max / h0,
        diverged_at: outcome.divergence().map(|d| d.time),
        within: shadow.within,
        unexplained: (h_change - shadow.switch_sum) / shadow.h_abs,
        h_change: h_change / h0,
        switch_steps: shadow.switch_steps,
    })
}

/// Every mass × fraction, five runs each, in parallel.
pub fn cd_growth(quick: bool) -> Result<Vec<CdGrowth>, ReproduceError> {
    compute(&masses(), &FRACTIONS, if quick { PERIODS_QUICK } else { PERIODS })
}

/// mod1 alone at `fractions`, over [`PERIODS`] (the test against the issue's numpy run).
pub fn mod1_runs(fractions: &[f64]) -> Result<Vec<CdGrowth>, ReproduceError> {
    compute(&[MassKind::Mod1], fractions, PERIODS)
}

fn compute(masses: &[MassKind], fractions: &[f64], periods: usize) -> Result<Vec<CdGrowth>, ReproduceError> {
    let wrap = |case: String| move |source| ReproduceError::Run { case, source };
    let mut jobs = Vec::new();
    for mass in masses {
        let (limit, method) = stable_limit(mass)?;
        jobs.extend(fractions.iter().map(|&f| (mass.clone(), f, limit, method)));
    }
    jobs.par_iter()
        .map(|(mass, fraction, limit, method)| {
            let dt = fraction * limit;
            let runs = std::iter::once(None)
                .chain((0..band::PERTURBATIONS).map(Some))
                .map(|k| run_one(mass, dt, periods, k))
                .collect::<Result<Vec<_>, _>>()
                .map_err(wrap(format!("CD growth / {} / Δt = {fraction} Δt_c", mass.name())))?;
            Ok(CdGrowth { mass: mass.clone(), fraction: *fraction, dt, limit: *limit, method, runs })
        })
        .collect()
}

/// The largest fraction f such that every run (of `mass`, or of every mass for None) at every
/// fraction ≤ f is bounded, or None if some run at the smallest fraction is not.
pub fn safe_fraction(growth: &[CdGrowth], mass: Option<&MassKind>) -> Option<f64> {
    let mut safe = None;
    for f in FRACTIONS {
        let all_bounded = growth
            .iter()
            .filter(|g| g.fraction == f && mass.is_none_or(|m| g.mass == *m))
            .all(|g| g.runs.iter().all(|r| r.verdict() == Verdict::Bounded));
        if !all_bounded {
            break;
        }
        safe = Some(f);
    }
    safe
}

/// "diverged (t = 588–640)" or "grows: ×1.4–2.6" or "bounded: ×1.00": the verdicts of the runs
/// (the one they share, else their range), the divergence times, and the band of max E/E₀ over
/// those that did not diverge.
fn cell(g: &CdGrowth) -> String {
    let verdicts: Vec<Verdict> = g.runs.iter().map(CdRun::verdict).collect();
    let range = tables::verdict_range(&verdicts);
    let times: Vec<Option<f64>> = g.runs.iter().filter_map(|r| r.diverged_at.map(Some)).collect();
    let finite: Vec<Option<f64>> = g.runs.iter().filter(|r| r.diverged_at.is_none()).map(|r| Some(r.e_max)).collect();
    let mut out = range;
    if !times.is_empty() {
        let _ = write!(out, " (t = {})", band::stable_digits(&times, 2));
    }
    if !finite.is_empty() {
        let _ = write!(out, ": ×{}", band::stable_digits(&finite, 3));
    }
    out
}

/// The report section: the table, the safe region and the shadow energy's account.
pub(super) fn cd_growth_section(growth: &[CdGrowth], quick: bool) -> String {
    let periods = if quick { PERIODS_QUICK } else { PERIODS };
    let mut s = format!(
        "\n## Central differences with a massless contact node: energy growth against Δt/Δt_c\n\n\
         The paper's bar (m = {ELEMENTS}, clamped, one impact per period) over {periods} periods (T = {}), central differences \
         with exact contact and a massless contact node, Δt = f Δt_c (Δt_c and its estimator in the table); each run also \
         from {} initial states U⁰ perturbed by ≤ {:e}. Each cell: the verdicts of the five runs (bounded: max E/E₀ ≤ \
         {DRIFT_FACTOR}; grows: above; diverged: stopped by the divergence rule, E above 10⁶ E(0), at the times given), and \
         the band of max E/E₀ over the runs that did not diverge (E the scheme's energy ½VᵀM_LV + ½UᵀKU).\n\n| mass | Δt_c (estimator) |",
        fmt_f64(periods as f64 * 3.0),
        band::PERTURBATIONS,
        band::PERTURBATION
    );
    for f in FRACTIONS {
        let _ = write!(s, " {f} Δt_c |");
    }
    s.push_str("\n|---|---|");
    s.push_str(&"---|".repeat(FRACTIONS.len()));
    s.push('\n');
    for mass in masses() {
        let row: Vec<&CdGrowth> = growth.iter().filter(|g| g.mass == mass).collect();
        let head = row
            .first()
            .map_or("—".into(), |g| format!("{} h/c ({})", band::sig(g.limit * ELEMENTS as f64, 6), g.method));
        let _ = write!(s, "| {} | {head} |", mass.name());
        for f in FRACTIONS {
            let g = row.iter().find(|g| g.fraction == f);
            let _ = write!(s, " {} |", g.map_or("—".into(), |g| cell(g)));
        }
        s.push('\n');
    }
    let region = |f: Option<f64>| f.map_or("none".to_string(), |f| format!("Δt ≤ {f} Δt_c"));
    let per_mass: Vec<String> =
        masses().iter().map(|m| format!("{} {}", m.name(), region(safe_fraction(growth, Some(m))))).collect();
    let safe = format!(
        "**Safe region** (every run bounded, max E/E₀ ≤ {DRIFT_FACTOR}, at every fraction up to it, over {periods} periods): \
         for every w_0 = 0 mass {}; per mass: {}.",
        region(safe_fraction(growth, None)),
        per_mass.join(", ")
    );
    let all = growth.iter().flat_map(|g| g.runs.iter());
    let within = all.clone().map(|r| r.within).fold(0.0, f64::max);
    let unexplained = all.clone().map(|r| r.unexplained.abs()).fold(0.0, f64::max);
    // Round-off sizes: only the power of ten above them is printed (their digits are round-off).
    let below = |x: f64| format!("below 1e{}", x.max(f64::MIN_POSITIVE).log10().ceil() as i32);
    let _ = writeln!(
        s,
        "\n{safe}\n\nWhy (module docs of `study/src/paper/cd_growth.rs`): with node 0 massless the step is Störmer–Verlet on the \
         condensed Hamiltonian ½pᵀM⁻¹p + V(q), V(q) = min over u_0 ≥ −gap of ½UᵀKU, convex and C¹ but one quadratic while the \
         node is free and another in contact. Inside one phase the step is a linear leapfrog and conserves its shadow energy \
         H^{{n+½}} = ½DᵀM_LD + ½UⁿᵀKU^{{n+1}} exactly: over every run, the largest change of H in a step inside one phase is {} \
         of H (round-off). All of H's change comes at the steps that straddle a switch: their jumps add up to H's whole \
         change to {} of the largest |H| of the run. Backward error analysis, which keeps a smooth symplectic integrator's energy near a modified \
         Hamiltonian, needs V smooth; across the kink nothing bounds the sum of the jumps, and at large Δt/Δt_c it \
         grows. H grows with E (the figure's right panel against its left; `cd-growth.csv` lists both for every run).",
        below(within),
        below(unexplained),
    );
    let _ = writeln!(s, "\n![{CD_GROWTH_FIGURE}]({CD_GROWTH_FIGURE}.png)");
    s
}

/// The figure: log₁₀ of the largest max E/E₀ and max H/H₀ over the five runs against Δt/Δt_c,
/// one curve per mass (a diverged run counts with its value at the stop), and the CSV of every run.
pub(super) fn cd_growth_figure(growth: &[CdGrowth]) -> FigureFile {
    let curve = |i: usize, mass: &MassKind, f: &dyn Fn(&CdRun) -> f64| Curve {
        label: mass.name().into(),
        points: growth
            .iter()
            .filter(|g| g.mass == *mass)
            .map(|g| (g.fraction, g.runs.iter().map(f).fold(f64::NEG_INFINITY, f64::max).log10()))
            .collect(),
        style: Style::Numeric(i),
    };
    let panel = |title: &str, y: &str, f: &dyn Fn(&CdRun) -> f64| Panel {
        title: title.into(),
        x_label: "Δt/Δt_c".into(),
        y_label: y.into(),
        curves: masses().iter().enumerate().map(|(i, m)| curve(i, m, f)).collect(),
        x_range: None,
        y_range: None,
    };
    let panels = vec![
        panel("integer-step energy E", "log₁₀ max E/E₀", &|r| r.e_max),
        panel("shadow energy H (half-step)", "log₁₀ max H/H₀", &|r| r.h_max),
    ];
    let header = [
        "mass",
        "fraction",
        "dt",
        "stable_step",
        "stable_step_method",
        "copy",
        "max_e_ratio",
        "max_h_ratio",
        "diverged_at",
        "within_phase_dh",
        "h_change",
        "unexplained_dh",
        "switch_steps",
    ]
    .map(String::from)
    .to_vec();
    let rows = growth
        .iter()
        .flat_map(|g| {
            g.runs.iter().enumerate().map(move |(k, r)| {
                vec![
                    g.mass.name().to_string(),
                    fmt_f64(g.fraction),
                    fmt_f64(g.dt),
                    fmt_f64(g.limit),
                    g.method.to_string(),
                    k.to_string(),
                    fmt_f64(r.e_max),
                    fmt_f64(r.h_max),
                    r.diverged_at.map_or(String::new(), fmt_f64),
                    fmt_f64(r.within),
                    fmt_f64(r.h_change),
                    fmt_f64(r.unexplained),
                    r.switch_steps.to_string(),
                ]
            })
        })
        .collect();
    FigureFile {
        stem: CD_GROWTH_FIGURE.into(),
        figure: Figure {
            title: format!(
                "Central differences with a massless contact node, paper's bar m = {ELEMENTS}: largest energy growth of five runs against Δt/Δt_c"
            ),
            panels,
            columns: 2,
            panel_size: (620, 480),
        },
        header,
        rows,
        periods: None,
    }
}
