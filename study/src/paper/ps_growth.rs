//! Paoli–Schatzman's energy growth against Δt/h, on the energy the scheme conserves (issue 22,
//! item 4).
//!
//! The paper calls the scheme stable, citing [DuP06VBCD]. Without contact, with β = ¼, it
//! conserves the half-step energy (`schemes/paoli_schatzman.rs`)
//!
//! ```text
//! E^{n+½} = ½ DᵀMD + ½ ΣᵀSΣ,   D = (U^{n+1} − Uⁿ)/Δt,   Σ = (U^{n+1} + Uⁿ)/2,
//! ```
//!
//! not the central-velocity energy ½VᵀMV + ½UᵀSU of the tables (which moves up and down before
//! any impact). So growth is measured on E^{n+½}, relative to E₀ = E^{3/2} (after the start-up
//! step, one Crank–Nicolson step), on the paper's mesh
//! over [`PS_PERIODS`] periods, for Δt = h/k, k ∈ [`PS_DT_DIVISORS`]; each run also from
//! [`band::PERTURBATIONS`] initial states U⁰ perturbed by ≤ [`band::PERTURBATION`] (the growth
//! amplifies round-off), and it stops where the project's divergence rule says (energy above
//! 10⁶ E(0)). Reported: the verdicts and the band of max E^{n+½}/E₀ over the five runs.

use super::band::{self, Verdict};
use super::periods::DRIFT_FACTOR;
use super::runs::energy_floor;
use super::{Config, Experiment, ReproduceError, masses};
use massredist::bar::BarProblem;
use massredist::driver::{DivergenceCriterion, Needs, Observer, Sample, integrate_watched};
use massredist::linalg::tridiag::SymTridiag;
use massredist::mass::MassKind;
use massredist::models::PaperBar;
use massredist::output::fmt_f64;
use massredist::run::RunError;
use rayon::prelude::*;
use std::fmt::Write as _;

/// Δt = h/k for these k.
pub const PS_DT_DIVISORS: [usize; 3] = [1, 4, 8];

/// Length of the growth runs, in periods 3L of the exact solution.
pub const PS_PERIODS: usize = 100;

/// The half-step energy E^{n−½} of each step n ≥ 2 (from U^{n−1} and Uⁿ), and u_0ⁿ.
struct HalfStep<'a> {
    mass: &'a SymTridiag,
    stiffness: &'a SymTridiag,
    dt: f64,
    prev: Vec<f64>,
    d: Vec<f64>,
    sigma: Vec<f64>,
    work: Vec<f64>,
    /// The step of the first impact (the first contact force, λⁿ < 0: issue 32, item 1), once seen.
    impact: Option<usize>,
    /// E^{3/2}, E^{n−½} for n ≥ 2 (only if `keep`), the largest, and the largest |E − E^{3/2}|
    /// before the first impact.
    first: Option<f64>,
    series: Vec<f64>,
    keep: bool,
    max: f64,
    pre_impact_drift: f64,
}

impl<'a> HalfStep<'a> {
    fn new(problem: &'a BarProblem, dt: f64, keep: bool) -> Self {
        let s = &problem.system.system;
        let n = s.n();
        Self {
            mass: &s.mass,
            stiffness: &s.stiffness,
            dt,
            prev: Vec::new(),
            d: vec![0.0; n],
            sigma: vec![0.0; n],
            work: vec![0.0; n],
            impact: None,
            first: None,
            series: Vec::new(),
            keep,
            max: f64::NEG_INFINITY,
            pre_impact_drift: 0.0,
        }
    }

    /// xᵀ A x.
    fn quad(a: &SymTridiag, x: &[f64], work: &mut [f64]) -> f64 {
        a.mul_into(x, work);
        x.iter().zip(work.iter()).map(|(p, q)| p * q).sum()
    }
}

impl Observer for HalfStep<'_> {
    fn needs(&self) -> Needs {
        Needs::default()
    }

    fn observe(&mut self, s: &Sample) {
        let u = s.state.u;
        // The first state in contact: E^{n−½}, which spans the step into it, is after the impact.
        if self.impact.is_none() && s.state.lambda[0] < 0.0 {
            self.impact = Some(s.state.n);
        }
        if !self.prev.is_empty() {
            for i in 0..u.len() {
                self.d[i] = (u[i] - self.prev[i]) / self.dt;
                self.sigma[i] = 0.5 * (u[i] + self.prev[i]);
            }
            let e = 0.5 * Self::quad(self.mass, &self.d, &mut self.work)
                + 0.5 * Self::quad(self.stiffness, &self.sigma, &mut self.work);
            if s.state.n < 2 {
                // E^{½} spans the start-up step (one Crank–Nicolson step, which with w_0 = 0 also
                // projects U⁰ and loses about h/8): the baseline is E^{3/2}.
                self.prev.clear();
                self.prev.extend_from_slice(u);
                return;
            }
            let e0 = *self.first.get_or_insert(e);
            self.max = self.max.max(e);
            if self.impact.is_none() {
                self.pre_impact_drift = self.pre_impact_drift.max((e - e0).abs());
            }
            if self.keep {
                self.series.push(e);
            }
        }
        self.prev.clear();
        self.prev.extend_from_slice(u);
    }
}

/// One growth run: max E^{n+½}/E₀, the largest pre-impact |E^{n+½} − E₀|/E₀ (E₀ = E^{3/2}), and
/// whether the divergence rule stopped it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GrowthRun {
    pub max_ratio: f64,
    pub pre_impact_drift: f64,
    pub diverged: bool,
}

impl GrowthRun {
    pub fn verdict(&self) -> Verdict {
        Verdict::of_growth(self.diverged, self.max_ratio)
    }
}

/// Five runs (unperturbed first) of one mass and Δt = h/k.
#[derive(Debug, Clone)]
pub struct Growth {
    pub mass: MassKind,
    pub divisor: usize,
    pub runs: Vec<GrowthRun>,
}

fn problem(config: &Config, mass: &MassKind, k: Option<usize>) -> Result<BarProblem, RunError> {
    let mut p =
        PaperBar { length: config.length, elements: config.elements }.problem(mass).map_err(RunError::problem)?;
    if let Some(k) = k {
        p.u0 = band::perturbed(&p.u0, k);
    }
    Ok(p)
}

fn run_one(config: &Config, mass: &MassKind, divisor: usize, k: Option<usize>) -> Result<GrowthRun, RunError> {
    let p = problem(config, mass, k)?;
    let dt = config.h() / divisor as f64;
    let end = PS_PERIODS as f64 * config.exact().period();
    let steps = (end / dt).round() as usize;
    let mut scheme = p.scheme(&Experiment::PaoliSchatzman.spec(), dt)?;
    let mut half = HalfStep::new(&p, dt, false);
    let outcome = integrate_watched(&p, scheme.as_mut(), steps, &DivergenceCriterion::default(), &mut [&mut half])?;
    let e0 = half.first.unwrap_or(f64::NAN);
    Ok(GrowthRun {
        max_ratio: half.max / e0,
        pre_impact_drift: half.pre_impact_drift / e0,
        diverged: outcome.divergence().is_some(),
    })
}

/// Up/down step counts of (central-velocity, half-step) energy, each (before, after) the first
/// impact, each (up, down).
pub type Moves = [[(usize, usize); 2]; 2];

/// The section's runs: the growth runs and, per mass, where the energy moves over one period.
#[derive(Debug, Clone)]
pub struct PsGrowth {
    pub growth: Vec<Growth>,
    pub moves: Vec<(MassKind, Moves)>,
}

/// Every mass × Δt = h/k, five runs each, in parallel; and [`up_down`].
pub fn ps_growth(config: &Config) -> Result<PsGrowth, ReproduceError> {
    let jobs: Vec<(MassKind, usize)> =
        masses().into_iter().flat_map(|m| PS_DT_DIVISORS.map(|k| (m.clone(), k))).collect();
    let growth = jobs
        .par_iter()
        .map(|(mass, k)| {
            let runs = std::iter::once(None)
                .chain((0..band::PERTURBATIONS).map(Some))
                .map(|p| run_one(config, mass, *k, p))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|source| ReproduceError::Run {
                    case: format!("Paoli–Schatzman growth / {} / dt = h/{k}", mass.name()),
                    source,
                })?;
            Ok(Growth { mass: mass.clone(), divisor: *k, runs })
        })
        .collect::<Result<Vec<_>, ReproduceError>>()?;
    Ok(PsGrowth { growth, moves: up_down(config)? })
}

/// Up and down steps of an energy series above `floor`, before and from step `impact` on.
fn moves(e: &[f64], impact: usize, floor: f64) -> [(usize, usize); 2] {
    let mut out = [(0, 0); 2];
    for (n, w) in e.windows(2).enumerate() {
        let d = w[1] - w[0];
        let o = &mut out[usize::from(n + 1 >= impact)];
        o.0 += usize::from(d > floor);
        o.1 += usize::from(d < -floor);
    }
    out
}

/// Up to the paper's horizon with the paper's Δt, for each mass: the up/down steps of the
/// central-velocity energy and of the half-step energy, before the first impact and after it.
fn up_down(config: &Config) -> Result<Vec<(MassKind, Moves)>, ReproduceError> {
    struct Central(Vec<f64>);
    impl Observer for Central {
        fn needs(&self) -> Needs {
            Needs { energy: true, ..Needs::default() }
        }
        fn observe(&mut self, s: &Sample) {
            self.0.push(s.energy);
        }
    }
    let floor = energy_floor(config);
    masses()
        .into_iter()
        .map(|mass| {
            let wrap =
                |source| ReproduceError::Run { case: format!("Paoli–Schatzman energy / {}", mass.name()), source };
            let p = problem(config, &mass, None).map_err(wrap)?;
            let steps = (config.exact().period() / config.dt).round() as usize;
            let mut scheme = p.scheme(&Experiment::PaoliSchatzman.spec(), config.dt).map_err(|e| wrap(e.into()))?;
            let (mut half, mut central) = (HalfStep::new(&p, config.dt, true), Central(Vec::new()));
            // One period: no run diverges (the T = 3 tables); a stop would only shorten the counts.
            let _outcome = integrate_watched(
                &p,
                scheme.as_mut(),
                steps,
                &DivergenceCriterion::default(),
                &mut [&mut half, &mut central],
            )
            .map_err(|e| wrap(e.into()))?;
            let impact = half.impact.unwrap_or(steps + 1);
            // Both from the second step on (the first is the start-up step). central.0[n] is Eⁿ,
            // its window n' of [1..] the step n'+1 → n'+2; half.series[j] is E^{j+3/2}, its window j
            // the change that U^{j+3} makes: each counts as after the impact from that state on.
            let c = moves(&central.0[1..], impact.saturating_sub(1), floor);
            let h = moves(&half.series, impact.saturating_sub(2), floor);
            Ok((mass, [c, h]))
        })
        .collect()
}

/// The report section: verdicts and bands of max E^{n+½}/E₀ per mass and Δt/h, and where the
/// energy moves before and after the first impact.
pub(super) fn ps_section(config: &Config, ps: &PsGrowth) -> String {
    let growth = &ps.growth;
    let mut s = format!(
        "\n## Paoli–Schatzman: energy growth against Δt/h\n\n\
         The paper calls Paoli–Schatzman (β = 1/4, e = 1) stable, citing [DuP06]; it does not measure it. Measured here on the energy the \
         scheme conserves without contact, the half-step energy E^{{n+½}} = ½DᵀMD + ½ΣᵀSΣ (D = (U^{{n+1}} − Uⁿ)/Δt, Σ = (U^{{n+1}} + Uⁿ)/2), \
         relative to E₀ = E^{{3/2}} (after the start-up step, one Crank–Nicolson step that with w_0 = 0 also loses about h/8): m = {}, {PS_PERIODS} periods (T = {}), Δt = h/k; each run also from {} initial states U⁰ perturbed by ≤ {:e}, \
         so each entry is the verdicts of the five runs (bounded: max E/E₀ ≤ {DRIFT_FACTOR}; grows: above; diverged: stopped by the divergence \
         rule, central-velocity energy above 10⁶ E(0)) and the band of max E^{{n+½}}/E₀ over the runs that did not diverge.\n\n",
        config.elements,
        fmt_f64(PS_PERIODS as f64 * config.exact().period()),
        band::PERTURBATIONS,
        band::PERTURBATION
    );
    s.push_str("| mass |");
    for k in PS_DT_DIVISORS {
        let _ = write!(s, " Δt = h/{k} |");
    }
    s.push_str("\n|---|");
    s.push_str(&"---|".repeat(PS_DT_DIVISORS.len()));
    s.push('\n');
    for mass in masses() {
        let _ = write!(s, "| {} |", mass.name());
        for k in PS_DT_DIVISORS {
            let g = growth.iter().find(|g| g.mass == mass && g.divisor == k);
            let _ = write!(s, " {} |", g.map_or("—".into(), growth_cell));
        }
        s.push('\n');
    }
    let drift = growth.iter().flat_map(|g| g.runs.iter().map(|r| r.pre_impact_drift)).fold(0.0, f64::max);
    // Round-off of a sum of O(m) products over ~1e4 steps: 1e-10 relative leaves room.
    let verdict = if drift < 1e-10 { "constant to round-off" } else { "**not constant**" };
    // Its digits are round-off themselves: below 1e-13 only the bound is printed.
    let size = if drift < 1e-13 { "below 1e-13".to_string() } else { band::sig(drift, 2) };
    let _ = writeln!(
        s,
        "\nBefore the first impact E^{{n+½}} is {verdict}: its largest change over all these runs is {size} of E₀."
    );
    let floor = energy_floor(config);
    let rows: Vec<String> = ps
        .moves
        .iter()
        .map(|(m, [c, h])| {
            format!(
                "{}: central {}↑ {}↓ before, {}↑ {}↓ after; half-step {}↑ {}↓ before, {}↑ {}↓ after",
                m.name(),
                c[0].0,
                c[0].1,
                c[1].0,
                c[1].1,
                h[0].0,
                h[0].1,
                h[1].0,
                h[1].1
            )
        })
        .collect();
    let _ = writeln!(
        s,
        "\nWhere the energy moves (Δt = {}, T = {}, from the second step on, steps moving it by more than {} up ↑ / down ↓, before the first impact and from it on): {}. \
         The central-velocity energy of the tables moves before any impact too, so its moves after the impact are no evidence of the \
         contact's effect; the half-step energy is the one to read.",
        fmt_f64(config.dt),
        fmt_f64(config.exact().period()),
        band::sig(floor, 2),
        rows.join("; ")
    );
    s
}

/// "diverged" or "grows: ×1.1–8.8" or "bounded–grows: ×1.0–1.2": the verdicts of the runs (the one
/// they share, else their range: how many fall on each side is itself round-off) and the band of
/// max E^{n+½}/E₀ over those that did not diverge.
fn growth_cell(g: &Growth) -> String {
    let verdicts: Vec<Verdict> = g.runs.iter().map(GrowthRun::verdict).collect();
    let range = super::tables::verdict_range(&verdicts);
    let finite: Vec<Option<f64>> = g.runs.iter().filter(|r| !r.diverged).map(|r| Some(r.max_ratio)).collect();
    if finite.is_empty() {
        return range;
    }
    format!("{range}: ×{}", band::stable_digits(&finite, 3))
}
