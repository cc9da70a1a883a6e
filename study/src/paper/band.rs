//! Round-off sensitivity of a case: the same run from a few slightly perturbed initial states.
//!
//! After its first impact the standard mass with Crank–Nicolson chatters, and Paoli–Schatzman
//! over 1000 periods amplifies round-off until its energy leaves any bound: perturbing U⁰ by
//! 1e-13 relative changes their late numbers by orders of magnitude. Digits of such a run are
//! not results. For every case ([`is_rerun`]; [`is_sensitive`] names the known amplifiers)
//! [`super::run_case`] also runs [`PERTURBATIONS`] copies from `U⁰_i (1 + δ_{k,i})`, `|δ| ≤` [`PERTURBATION`], and the report
//! shows only what all runs agree on: the digits they share ([`stable_digits`]), else the band
//! min–max over the runs, and a verdict (bounded, grows, diverged) per run.

use super::periods::{DRIFT_FACTOR, PeriodEnergy};
use super::{Case, Experiment, Purpose};
use massredist::mass::MassKind;
use massredist::observe::{SeriesRecorder, Summary};

/// Perturbed copies per sensitive case (with the unperturbed run: five runs in the band).
pub const PERTURBATIONS: usize = 4;

/// Largest relative perturbation of U⁰: a few hundred ulps, far below any data or
/// discretisation error, so that a number that moves with it is round-off amplification.
pub const PERTURBATION: f64 = 1e-13;

/// The cases whose late numbers amplify round-off: every long Paoli–Schatzman run, and the
/// standard mass with Crank–Nicolson (it chatters after its first impact).
pub fn is_sensitive(case: &Case) -> bool {
    case.purpose == Purpose::LongEnergy
        || (case.experiment == Experiment::CrankNicolson && case.mass == MassKind::Standard)
}

/// The cases rerun from perturbed U⁰: every one (issue 22: every digit the report prints must be
/// one that a 1e-13 perturbation of the initial data leaves unchanged, and only the reruns show
/// which digits those are; a 1D run on the paper's mesh costs microseconds). [`is_sensitive`]
/// says which of them are known to amplify round-off, for the report's wording.
pub fn is_rerun(_case: &Case) -> bool {
    true
}

/// `U⁰` of copy k: `u_i (1 + δ_{k,i})` with δ_{k,i} ∈ {−1, −½, 0, ½, 1}·[`PERTURBATION`] from a
/// fixed pattern (deterministic: a rerun of `reproduce` gives the same band).
pub fn perturbed(u0: &[f64], k: usize) -> Vec<f64> {
    u0.iter()
        .enumerate()
        .map(|(i, &u)| {
            let d = ((7 * i + 3 * k + 1) % 5) as f64 / 2.0 - 1.0;
            u * (1.0 + d * PERTURBATION)
        })
        .collect()
}

/// What a perturbed copy keeps: its summary, the series of the case's columns (for the values
/// the report reads off them: events, energy variation) and per-period energy extremes.
#[derive(Debug, Clone)]
pub struct PerturbedRun {
    pub summary: Summary,
    pub series: SeriesRecorder,
    pub periods: PeriodEnergy,
}

/// The verdict on a run's energy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Verdict {
    Bounded,
    Grows,
    Diverged,
}

impl Verdict {
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Bounded => "bounded",
            Verdict::Grows => "grows",
            Verdict::Diverged => "diverged",
        }
    }

    /// Diverged (the run stopped), grows (its largest energy above [`DRIFT_FACTOR`] times the
    /// first), else bounded: the growth sections' rule (`max_ratio` = max E/E₀).
    pub fn of_growth(diverged: bool, max_ratio: f64) -> Verdict {
        if diverged {
            Verdict::Diverged
        } else if max_ratio > DRIFT_FACTOR {
            Verdict::Grows
        } else {
            Verdict::Bounded
        }
    }

    /// Diverged (the run stopped), grows (energy above 10 E(0), or the per-period maximum up by
    /// more than [`DRIFT_FACTOR`]: `growth` = last/first per-period maximum), else bounded.
    pub fn of(s: &Summary, growth: Option<f64>) -> Verdict {
        if s.divergence.is_some() {
            Verdict::Diverged
        } else if s.energy_max > 10.0 * s.energy_initial || growth.is_some_and(|g| g > DRIFT_FACTOR) {
            Verdict::Grows
        } else {
            Verdict::Bounded
        }
    }
}

/// `x` with the significant digits (at most `digits`) on which every value of `values` agrees,
/// e.g. `0.1041`, provided that value lies within the runs' range (issue 32, item 7); else the
/// band `min–max` ([`band_text`]); `—` if
/// there is no value, and `varies` if some runs have one and others not.
///
/// **Within the range** is read at the column's precision: the printed p (d ≤ `digits` digits)
/// must satisfy `sig(min, digits) ≤ p ≤ sig(max, digits)`. Rounding to the common digit can
/// leave the range: runs {18.74, 18.76} agree only on "19", which lies outside [18.74, 18.76],
/// so they print as the band `18.74–18.76`. Runs that agree on all `digits` print them (their
/// range at that precision is the one value).
pub fn stable_digits(values: &[Option<f64>], digits: usize) -> String {
    let printed = stable_digits_of(values, digits);
    let v: Vec<f64> = values.iter().flatten().copied().collect();
    audit::record(&printed, &v, Some(digits));
    printed
}

fn stable_digits_of(values: &[Option<f64>], digits: usize) -> String {
    let Some(first) = values.first() else { return "—".into() };
    if values.iter().any(|v| v.is_some() != first.is_some()) {
        return "varies".into();
    }
    let v: Vec<f64> = values.iter().flatten().copied().collect();
    let Some(&x) = v.first() else { return "—".into() };
    let (lo, hi) = band(&v);
    let at_precision = |y: f64| sig(y, digits).parse::<f64>().unwrap_or(y);
    if let Some(d) = (2..=digits).rev().find(|&d| v.iter().all(|y| sig(*y, d) == sig(x, d))) {
        let shown = sig(x, d);
        let p = shown.parse::<f64>().unwrap_or(x);
        // NaN and ±inf: every run has the same one (they agreed), printed as it is.
        if !p.is_finite() || (at_precision(lo) <= p && p <= at_precision(hi)) {
            return shown;
        }
    }
    band_text(lo, hi, digits)
}

/// The band `lo–hi` of [`stable_digits`]: ends that differ at 2 digits print with 2 (`0.41–0.52`);
/// closer ends (their common digit left the range) print as they are at `digits` digits, in
/// the fewest digits that keep that value (`18.74–18.76`).
fn band_text(lo: f64, hi: f64, digits: usize) -> String {
    if sig(lo, 2) != sig(hi, 2) || digits <= 2 {
        return format!("{}–{}", sig(lo, 2), sig(hi, 2));
    }
    let short = |y: f64| {
        let full = sig(y, digits).parse::<f64>().ok();
        (2..digits).map(|k| sig(y, k)).find(|s| s.parse::<f64>().ok() == full).unwrap_or_else(|| sig(y, digits))
    };
    format!("{}–{}", short(lo), short(hi))
}

/// The number of significant digits (at most 16) on which all `values` agree; 0 if not even
/// the first, or if some have a value and others not. All absent: 16.
pub fn agreed_digits(values: &[Option<f64>]) -> usize {
    let Some(first) = values.first() else { return 16 };
    if values.iter().any(|v| v.is_some() != first.is_some()) {
        return 0;
    }
    let v: Vec<f64> = values.iter().flatten().copied().collect();
    let Some(&x) = v.first() else { return 16 };
    (1..=16).rev().find(|&d| v.iter().all(|&y| sig(y, d) == sig(x, d))).unwrap_or(0)
}

/// Counts of several runs: the one value if all agree, else the band `min–max` (`—` if none).
pub fn count_band(counts: &[usize]) -> String {
    let printed = match (counts.iter().min(), counts.iter().max()) {
        (Some(lo), Some(hi)) if lo == hi => lo.to_string(),
        (Some(lo), Some(hi)) => format!("{lo}–{hi}"),
        _ => "—".into(),
    };
    audit::record(&printed, &counts.iter().map(|&c| c as f64).collect::<Vec<_>>(), None);
    printed
}

/// What the report printed from runs, for the test over the full report (issue 32, item 7: no
/// printed value outside its runs' range). Every cell [`stable_digits`] and [`count_band`] make
/// is recorded while [`audit::during`] runs; nothing computed or printed depends on it.
pub mod audit {
    use std::sync::Mutex;

    /// One printed cell: the text, the runs' values, and the column's digits (None: a count).
    #[derive(Debug, Clone, PartialEq)]
    pub struct Cell {
        pub printed: String,
        pub values: Vec<f64>,
        pub digits: Option<usize>,
    }

    static CELLS: Mutex<Option<Vec<Cell>>> = Mutex::new(None);

    pub(super) fn record(printed: &str, values: &[f64], digits: Option<usize>) {
        if let Ok(mut cells) = CELLS.lock()
            && let Some(cells) = cells.as_mut()
        {
            cells.push(Cell { printed: printed.to_string(), values: values.to_vec(), digits });
        }
    }

    /// `f`'s result and every cell printed while it ran (from any thread).
    pub fn during<T>(f: impl FnOnce() -> T) -> (T, Vec<Cell>) {
        *CELLS.lock().unwrap_or_else(|e| e.into_inner()) = Some(Vec::new());
        let out = f();
        let cells = CELLS.lock().unwrap_or_else(|e| e.into_inner()).take().unwrap_or_default();
        (out, cells)
    }
}

/// (min, max) of the values.
pub fn band(values: &[f64]) -> (f64, f64) {
    values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shared_digits_or_the_band() {
        // 0.10411 lies outside [0.104112, 0.104113]: the band; at 5 digits both are 0.10411.
        assert_eq!(stable_digits(&[Some(0.104112), Some(0.104113)], 6), "0.104112–0.104113");
        assert_eq!(stable_digits(&[Some(0.104112), Some(0.104113)], 5), "0.10411");
        assert_eq!(stable_digits(&[Some(0.104112), Some(0.104119)], 4), "0.1041");
        // The review's cases (issue 32, item 7): "19" and "14" left their runs' range.
        assert_eq!(stable_digits(&[Some(18.74), Some(18.76)], 4), "18.74–18.76");
        assert_eq!(stable_digits(&[Some(13.64), Some(13.66)], 4), "13.64–13.66");
        assert_eq!(stable_digits(&[Some(-18.76), Some(-18.74)], 4), "-18.76–-18.74");
        assert_eq!(stable_digits(&[Some(0.104112)], 6), "0.104112");
        assert_eq!(stable_digits(&[Some(0.41), Some(0.52), Some(0.47)], 6), "0.41–0.52");
        assert_eq!(stable_digits(&[Some(2.0e13), Some(5.0e4)], 3), "50000–2.0e13");
        assert_eq!(stable_digits(&[None, Some(1.0)], 3), "varies");
        assert_eq!(stable_digits(&[None, None], 3), "—");
        assert_eq!(agreed_digits(&[Some(0.104112), Some(0.104113)]), 5);
        assert_eq!(agreed_digits(&[Some(0.5), Some(0.5)]), 16);
        assert_eq!(agreed_digits(&[Some(0.41), Some(0.52)]), 0);
        assert_eq!(agreed_digits(&[None, Some(1.0)]), 0);
    }

    /// Over sets of 2 to 5 runs around rounding boundaries (a deterministic generator), every
    /// printed value lies within its runs' range at the column's precision, and every band's
    /// ends are the extremes rounded. mutation: return `shown` without the range test -> fails
    /// on the first set whose common digit leaves the range (e.g. {18.74, 18.76} -> "19").
    #[test]
    fn no_printed_value_leaves_its_runs_range() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut unit = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..20_000 {
            let digits = 2 + (unit() * 5.0) as usize;
            // A centre near a rounding boundary of some digit, runs spread over 1e-6 … 1e-1 of it.
            let scale = 10f64.powi((unit() * 12.0) as i32 - 6);
            let centre = (1.0 + 9.0 * unit()).mul_add(scale, 0.0) * if unit() < 0.2 { -1.0 } else { 1.0 };
            let spread = centre.abs() * 10f64.powf(-1.0 - 5.0 * unit());
            let n = 2 + (unit() * 4.0) as usize;
            let v: Vec<Option<f64>> = (0..n).map(|_| Some(centre + spread * (unit() - 0.5))).collect();
            let (lo, hi) = band(&v.iter().flatten().copied().collect::<Vec<_>>());
            let out = stable_digits(&v, digits);
            let at = |y: f64| sig(y, digits).parse::<f64>().unwrap();
            match out.split_once('–') {
                None => {
                    let p: f64 = out.parse().unwrap();
                    assert!(at(lo) <= p && p <= at(hi), "{out} outside [{lo}, {hi}] at {digits} digits");
                }
                Some((a, b)) => {
                    // Ends that differ at 2 digits print at 2; closer ones at the column's
                    // precision, so the band lies within the range at that precision.
                    let k = if sig(lo, 2) != sig(hi, 2) { 2 } else { digits };
                    let (a, b): (f64, f64) = (a.parse().unwrap(), b.parse().unwrap());
                    assert_eq!((a, b), (sig(lo, k).parse().unwrap(), sig(hi, k).parse().unwrap()), "band of {v:?}");
                }
            }
        }
    }

    #[test]
    fn perturbations_are_small_and_differ_between_copies() {
        let u = vec![0.5; 7];
        let a = perturbed(&u, 0);
        let b = perturbed(&u, 1);
        assert_ne!(a, b);
        for (x, y) in a.iter().zip(&u) {
            // δ·u rounds once more when added: a few ε|u| on top.
            assert!((x - y).abs() <= (PERTURBATION + 4.0 * f64::EPSILON) * y.abs());
        }
    }
}

/// `x` with `digits` significant digits, plain for moderate magnitudes.
pub fn sig(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return "0".into();
    }
    let e = x.abs().log10().floor() as i32;
    if (-3..5).contains(&e) {
        let decimals = (digits as i32 - 1 - e).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.*e}", digits - 1)
    }
}
