//! The runs and what is derived from them: one pure run per [`Case`] with only the observers its
//! outputs need ([`run_case`]), all of them in parallel ([`compute`]), and the quantities the
//! figures, tables and claims read off the recorded series (period events, energy variation,
//! per-period growth).

use super::periods::PeriodEnergy;
use super::{Case, Config, Purpose, ReproduceError, band, cases};
use massredist::bar::BarProblem;
use massredist::driver::{Divergence, DivergenceCriterion, integrate_watched};
use massredist::exact::ImpactingBar;
use massredist::models::PaperBar;
use massredist::observe::{SeriesRecorder, Summary, SummaryObserver};
use massredist::run::RunError;
use massredist::scene::Column;
use rayon::prelude::*;
use serde::Serialize;

/// The outcome of one case. A run that diverges ([`DivergenceCriterion`], default factor: a
/// non-finite state or an energy above 10⁶ E(0)) stops there and keeps what was observed up to
/// it; the divergence is reported, not hidden.
#[derive(Debug, Clone)]
pub struct CaseResult {
    pub case: Case,
    pub summary: Summary,
    pub series: SeriesRecorder,
    /// Per-period energy extremes (long runs only; empty otherwise).
    pub periods: PeriodEnergy,
    /// Where and why the run diverged (also in `summary.divergence`).
    pub failure: Option<Divergence>,
    /// The runs from perturbed initial states of a round-off sensitive case (empty otherwise).
    pub copies: Vec<band::PerturbedRun>,
}

impl CaseResult {
    /// A recorded column (empty if not recorded).
    pub(super) fn col(&self, c: Column) -> Vec<f64> {
        self.series.column(c).unwrap_or_default()
    }

    /// Whether this run's extremes may change with a 1e-13 perturbation of its initial state:
    /// it was rerun from perturbed states (`copies`), or it has the standard mass, which chatters
    /// after its first impact (the guide's chaotic digits; figure notes give no digits for it).
    pub(super) fn sensitive(&self) -> bool {
        band::is_sensitive(&self.case) || self.case.mass == massredist::mass::MassKind::Standard
    }

    /// `value` of this run's summary, then of each perturbed copy's.
    pub(super) fn over_runs<T>(&self, value: impl Fn(&Summary) -> T) -> Vec<T> {
        std::iter::once(&self.summary).chain(self.copies.iter().map(|c| &c.summary)).map(value).collect()
    }

    /// `value` of this run's series, then of each perturbed copy's.
    pub(super) fn over_series<T>(&self, value: impl Fn(&Summary, &SeriesRecorder) -> T) -> Vec<T> {
        std::iter::once(value(&self.summary, &self.series))
            .chain(self.copies.iter().map(|c| value(&c.summary, &c.series)))
            .collect()
    }

    /// `value` of the summary, with only the digits every run shares
    /// ([`band::stable_digits`]; all `digits` for a case without copies).
    pub(super) fn stable(&self, value: impl Fn(&Summary) -> Option<f64>, digits: usize) -> String {
        band::stable_digits(&self.over_runs(value), digits)
    }

    /// The verdict of each run (this one first) and its per-period growth (last/first).
    pub(super) fn verdicts(&self) -> Vec<(band::Verdict, Option<f64>)> {
        let runs =
            std::iter::once((&self.summary, &self.periods)).chain(self.copies.iter().map(|c| (&c.summary, &c.periods)));
        runs.map(|(s, p)| {
            let g = p.growth(self.case.end).map(|(a, b, _)| b / a);
            (band::Verdict::of(s, g), g)
        })
        .collect()
    }
}

/// Runs one case on the paper's benchmark with a [`SummaryObserver`] (L² error on: every case
/// has a table row) and a [`SeriesRecorder`] of [`Case::columns`]; every case (`band::is_rerun`)
/// also from `band::PERTURBATIONS` perturbed initial states.
pub fn run_case(config: &Config, case: &Case) -> Result<CaseResult, ReproduceError> {
    let wrap = |source: RunError| ReproduceError::Run { case: case.name(), source };
    let long = case.purpose == Purpose::LongEnergy;
    let steps = config.steps(if long { "long_ends" } else { "horizons" }, case.end)?;
    let mut problem = PaperBar { length: config.length, elements: config.elements }
        .problem(&case.mass)
        .map_err(|e| wrap(RunError::problem(e)))?;
    let every = if long { config.long_every(steps) } else { 1 };
    let (summary, series, periods) = run_one(config, case, &problem, steps, case.columns(), every).map_err(wrap)?;
    let mut copies = Vec::new();
    if band::is_rerun(case) {
        let u0 = problem.u0.clone();
        for k in 0..band::PERTURBATIONS {
            problem.u0 = band::perturbed(&u0, k);
            let (summary, series, periods) =
                run_one(config, case, &problem, steps, case.columns(), every).map_err(wrap)?;
            copies.push(band::PerturbedRun { summary, series, periods });
        }
    }
    let failure = summary.divergence;
    Ok(CaseResult { case: case.clone(), summary, series, periods, failure, copies })
}

/// One run of `case` on `problem`: its summary, the series of `columns` every `every` steps and
/// the per-period energy extremes (long runs only).
fn run_one(
    config: &Config,
    case: &Case,
    problem: &BarProblem,
    steps: usize,
    columns: Vec<Column>,
    every: usize,
) -> Result<(Summary, SeriesRecorder, PeriodEnergy), RunError> {
    let mut scheme = problem.scheme(&case.experiment.spec(), config.dt)?;
    let mut summary = SummaryObserver::new(problem, steps, config.dt, true);
    let mut series = SeriesRecorder::new(columns, every, steps / every + 1);
    let mut periods = PeriodEnergy::new(config.exact().period(), config.dt);
    let criterion = DivergenceCriterion::default();
    // The divergence, if any, is in the summary.
    let _outcome = if case.purpose == Purpose::LongEnergy {
        integrate_watched(problem, scheme.as_mut(), steps, &criterion, &mut [&mut summary, &mut series, &mut periods])
    } else {
        integrate_watched(problem, scheme.as_mut(), steps, &criterion, &mut [&mut summary, &mut series])
    }?;
    Ok((summary.finish(), series, periods))
}

/// Runs every case of [`cases`] in parallel; `done` is called after each.
pub fn compute(config: &Config, done: &(dyn Fn() + Sync)) -> Result<Vec<CaseResult>, ReproduceError> {
    cases(config)
        .par_iter()
        .map(|c| {
            let r = run_case(config, c);
            done();
            r
        })
        .collect()
}

/// The results of `purpose` at horizon `end`, in the order of [`cases`].
pub(super) fn runs_of(results: &[CaseResult], purpose: Purpose, end: f64) -> Vec<&CaseResult> {
    results.iter().filter(|r| r.case.purpose == purpose && r.case.end == end).collect()
}

/// Groups results by (purpose, horizon, scheme), in the order of [`cases`].
pub(super) fn groups(results: &[CaseResult]) -> Vec<Vec<&CaseResult>> {
    let mut out: Vec<Vec<&CaseResult>> = Vec::new();
    for r in results {
        let key = |c: &Case| (c.purpose, c.end.to_bits(), c.experiment);
        match out.iter_mut().find(|g| key(&g[0].case) == key(&r.case)) {
            Some(g) => g.push(r),
            None => out.push(vec![r]),
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Quantities derived from the recorded series (pure).

/// Contact events in one period of the exact solution.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PeriodEvents {
    /// Period index j: the window [3jL, 3(j+1)L), exact impact (3j+1)L, release (3j+2)L.
    pub period: usize,
    /// First t_n in the window with u_0ⁿ ≤ 0, minus (3j+1)L (the rule of
    /// [`Summary::impact_time_shift`], period by period).
    pub impact_shift: Option<f64>,
    /// First t_n after that impact with u_0ⁿ > 0 and λⁿ = 0, minus (3j+2)L. Unlike
    /// [`Summary::release_time_shift`] (u_0ⁿ > 0 alone) this also reads Paoli–Schatzman right,
    /// whose contact condition holds for (u_0^{n+1} + u_0^{n−1})/2, so that u_0ⁿ alternates in sign
    /// while λⁿ < 0. For the other schemes (u_0ⁿ λⁿ = 0) both rules agree.
    pub release_shift: Option<f64>,
    /// The last t_n in the window with u_0ⁿ ≤ 0 or λⁿ < 0, after the impact (the end of the
    /// contact, chatter included); None without impact.
    pub last_contact: Option<f64>,
}

/// Impact and release shifts of every period that the series covers completely.
pub fn period_events(times: &[f64], u0: &[f64], lambda: &[f64], exact: &ImpactingBar, dt: f64) -> Vec<PeriodEvents> {
    let l = exact.length;
    let period = exact.period();
    let end = times.last().copied().unwrap_or(0.0);
    // Periods that end by the last recorded time (up to half a step of rounding in t_n).
    let full = ((end + 0.5 * dt) / period).floor() as usize;
    (0..full)
        .map(|j| {
            let (lo, hi) = (j as f64 * period, (j + 1) as f64 * period);
            let start = times.partition_point(|&t| t < lo - 0.5 * dt);
            let stop = times.partition_point(|&t| t < hi - 0.5 * dt);
            let impact = (start..stop).find(|&n| u0[n] <= 0.0);
            let release = impact.and_then(|i| (i + 1..times.len()).find(|&n| u0[n] > 0.0 && lambda[n] == 0.0));
            let t_impact = lo + l;
            let last = impact.and_then(|i| (i..stop).rev().find(|&n| u0[n] <= 0.0 || lambda[n] < 0.0));
            PeriodEvents {
                period: j,
                impact_shift: impact.map(|n| times[n] - t_impact),
                release_shift: release.map(|n| times[n] - (t_impact + l)),
                last_contact: last.map(|n| times[n]),
            }
        })
        .collect()
}

/// How the energy moves from t ≥ `from` on.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct EnergyVariation {
    /// Σ (E_{n+1} − E_n)⁺.
    pub up: f64,
    /// Σ (E_{n+1} − E_n)⁻ (≥ 0).
    pub down: f64,
    /// Steps with E_{n+1} − E_n > `floor`, and < −`floor`.
    pub up_steps: usize,
    pub down_steps: usize,
}

/// The energy's total upward and downward variation from t ≥ `from` on, and how many steps move
/// it by more than `floor` each way. A conserving scheme has both at round-off level, a
/// dissipative one (Lemma 5.1) no upward steps, an oscillating one both.
pub fn energy_variation(times: &[f64], energy: &[f64], from: f64, floor: f64) -> EnergyVariation {
    let start = times.partition_point(|&t| t < from);
    energy[start.min(energy.len())..].windows(2).fold(EnergyVariation::default(), |mut v, w| {
        let d = w[1] - w[0];
        if d > 0.0 {
            v.up += d;
        } else {
            v.down -= d;
        }
        v.up_steps += usize::from(d > floor);
        v.down_steps += usize::from(d < -floor);
        v
    })
}

/// Round-off floor of an energy step: E is a sum of O(m) products, each rounded to ε relative,
/// so 1e3·ε·E bounds the noise of one step with room to spare for m ≤ 100 (here m = 6).
pub(super) fn energy_floor(config: &Config) -> f64 {
    1e3 * f64::EPSILON * config.exact().energy()
}

/// [`energy_variation`] of each run of a case (this one first) from one step before its first
/// impact (so the impact step itself counts); None for a run without impact.
pub(super) fn variation_after_impact(config: &Config, r: &CaseResult) -> Vec<Option<EnergyVariation>> {
    r.over_series(|summary, series| {
        let from = summary.first_impact_time? - config.dt;
        let energy = series.column(Column::Energy).unwrap_or_default();
        Some(energy_variation(&series.times(), &energy, from - 0.5 * config.dt, energy_floor(config)))
    })
}

/// The steps n → n+1 (n ≥ 1: after the first step) that move the energy by more than the
/// round-off floor: (t_{n+1}, whether the contact state λ < 0 switches in that step).
pub(super) fn energy_jumps(config: &Config, series: &SeriesRecorder) -> Vec<(f64, bool)> {
    let column = |c| series.column(c).unwrap_or_default();
    let (t, e, lambda) = (series.times(), column(Column::Energy), column(Column::Lambda));
    let floor = energy_floor(config);
    (1..e.len().saturating_sub(1).min(lambda.len().saturating_sub(1)))
        .filter(|&n| (e[n + 1] - e[n]).abs() > floor)
        .map(|n| (t[n + 1], (lambda[n] < 0.0) != (lambda[n + 1] < 0.0)))
        .collect()
}

/// The case's contact events per period (none for the long runs, which record no u_0).
pub fn events(config: &Config, r: &CaseResult) -> Vec<PeriodEvents> {
    events_of(config, &r.series)
}

/// The contact events per period of one run's series ([`events`]).
pub(super) fn events_of(config: &Config, series: &SeriesRecorder) -> Vec<PeriodEvents> {
    match (series.column(Column::U0), series.column(Column::Lambda)) {
        (Some(u0), Some(lambda)) => period_events(&series.times(), &u0, &lambda, &config.exact(), config.dt),
        _ => Vec::new(),
    }
}

/// Period j's events of every run of `r` (this one first); runs that stopped before period j
/// are left out.
pub(super) fn period_over_runs(config: &Config, r: &CaseResult, j: usize) -> Vec<PeriodEvents> {
    r.over_series(|_, series| events_of(config, series).get(j).copied()).into_iter().flatten().collect()
}

/// (max energy over the first k full periods, over the last k, k) with k = min(10, full/2).
pub(super) fn period_growth(r: &CaseResult) -> Option<(f64, f64, usize)> {
    r.periods.growth(r.case.end)
}

#[cfg(test)]
mod tests {
    use super::*;
    use massredist::mass::MassKind;

    #[test]
    fn period_events_of_the_exact_solution_are_on_time() {
        // The exact u(0, t) sampled on the grid: impacts at 1, 4 and releases just after 2, 5
        // (u(0, t) > 0 starts one step after 2L).
        let b = ImpactingBar { length: 1.0 };
        let dt = 0.01;
        let t: Vec<f64> = (0..=600).map(|n| n as f64 * dt).collect();
        let u: Vec<f64> = t.iter().map(|&t| b.u0(t)).collect();
        let lambda: Vec<f64> = t.iter().map(|&t| b.lambda(t)).collect();
        let ev = period_events(&t, &u, &lambda, &b, dt);
        assert_eq!(ev.len(), 2);
        for p in ev {
            // Grid times n·dt differ from the exact event by rounding of n·dt only.
            assert!(p.impact_shift.unwrap().abs() < 1e-12);
            assert!((p.release_shift.unwrap() - dt).abs() < 1e-12);
        }
    }

    #[test]
    fn a_diverged_case_is_a_result() {
        // Paoli–Schatzman with mod1 over the paper's long run: the energy passes 10⁶ E(0) after
        // t = 1000 (t = 1500–1621 over U⁰ perturbed by ≤ 1e-13: the time is round-off amplified);
        // the run stops there, kept.
        use super::super::Experiment;
        use massredist::driver::DivergenceReason;
        use massredist::observe::Status;
        let case = Case {
            experiment: Experiment::PaoliSchatzman,
            mass: MassKind::Mod1,
            end: 3000.0,
            purpose: Purpose::LongEnergy,
        };
        let r = run_case(&Config::paper(), &case).unwrap();
        let d = r.failure.expect("diverged");
        let DivergenceReason::EnergyFactor { energy, .. } = d.reason else { panic!("{d}") };
        assert_eq!((r.summary.status, r.summary.divergence), (Status::Diverged, Some(d)));
        assert_eq!(r.summary.energy_final, energy, "the summary ends at the state that crossed the bound");
        // The long runs record every k-th step: the last row is at or before the divergence.
        assert!(r.series.times().last().is_some_and(|&t| t <= d.time && t > 1000.0));
    }

    #[test]
    fn energy_variation_splits_up_and_down() {
        let t = [0.0, 1.0, 2.0, 3.0, 4.0];
        let e = [5.0, 1.0, 2.0, 1.5, 1.5];
        // From t = 1 on: +1 (1→2), −0.5 (2→1.5), 0 (1.5→1.5, below any floor).
        let v = energy_variation(&t, &e, 1.0, 1e-12);
        assert_eq!(v, EnergyVariation { up: 1.0, down: 0.5, up_steps: 1, down_steps: 1 });
    }
}
