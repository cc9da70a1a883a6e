//! The work–precision sweep: scheme × mass × h × Δt on the exact benchmark (paper §4.1), and
//! the observed convergence rates fitted from it.
//!
//! Every run is the impacting bar of length L = 1 over one period T = 3 (free flight, contact,
//! release), started from the nodal interpolant of u⁰ = (1 − x)/2, v⁰ = 0. For each run we record
//! the L∞(0,T; L²(0,L)) error (exact, see [`massredist::bar::norms::l2_error`]), the maximum error of the
//! contact displacement max_n |u_0ⁿ − u(0,t_n)|, the wall time of the solve alone (no
//! diagnostics) and the ns per node-step.

use super::timing::best_timed;
use crate::paper::Experiment;
pub use crate::paper::masses;
use massredist::driver::{DivergenceCriterion, Outcome, integrate, integrate_watched};
use massredist::mass::MassKind;
use massredist::models::PaperBar;
use massredist::observe::SummaryObserver;
use massredist::scene::{Formulation, SchemeSpec};
use serde::Serialize;
use std::time::Instant;

/// A scheme of the sweep, under the label used in files and figures.
#[derive(Debug, Clone, PartialEq)]
pub struct SchemeCase {
    pub label: &'static str,
    pub spec: SchemeSpec,
    /// Defined only for a massless contact node (w_0 = 0).
    pub needs_massless: bool,
}

/// The paper's schemes ([`Experiment::ALL`], in that order; labels are their slugs), with
/// Crank–Nicolson also in its reduced formulation (P^mod_U, w_0 = 0) right after the full one.
pub fn scheme_cases() -> Vec<SchemeCase> {
    let mut out = Vec::new();
    for e in Experiment::ALL {
        out.push(SchemeCase { label: e.slug(), spec: e.spec(), needs_massless: e.needs_massless() });
        if e == Experiment::CrankNicolson {
            out.push(SchemeCase {
                label: "crank-nicolson-reduced",
                spec: SchemeSpec::CrankNicolson { formulation: Formulation::Reduced },
                needs_massless: true,
            });
        }
    }
    out
}

/// What to sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepConfig {
    /// Numbers of elements m (h = 1/m).
    pub elements: Vec<usize>,
    /// Δt = h / divisor.
    pub dt_divisors: Vec<usize>,
    /// Final time, an integer (one period of the benchmark is 3).
    pub end: f64,
    /// Minimum seconds spent re-timing one run (the fastest repetition is kept).
    pub min_timing_seconds: f64,
}

impl SweepConfig {
    /// `bench --quick`: m = 6·2^k up to 1536, Δt = h, h/2, h/4 (a few seconds per core).
    pub fn quick() -> Self {
        Self {
            elements: (0..=8).map(|k| 6 << k).collect(),
            dt_divisors: vec![1, 2, 4],
            end: 3.0,
            min_timing_seconds: 0.005,
        }
    }

    /// The full sweep: m = 6·2^k up to 12288 (> 10⁴), Δt = h … h/8.
    pub fn full() -> Self {
        Self {
            elements: (0..=11).map(|k| 6 << k).collect(),
            dt_divisors: vec![1, 2, 4, 8],
            end: 3.0,
            min_timing_seconds: 0.02,
        }
    }
}

/// One run of the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    pub scheme: SchemeCase,
    pub mass: MassKind,
    pub elements: usize,
    pub dt_divisor: usize,
}

impl Case {
    /// Node-steps of the run, to schedule the largest first.
    pub fn work(&self, end: f64) -> f64 {
        let m = self.elements as f64;
        m * (end * m * self.dt_divisor as f64)
    }
}

/// Every applicable (scheme, mass, m, Δt), skipping schemes that need w_0 = 0 on the standard
/// mass.
pub fn cases(cfg: &SweepConfig) -> Vec<Case> {
    let mut out = Vec::new();
    for scheme in scheme_cases() {
        for mass in masses() {
            if scheme.needs_massless && matches!(mass, MassKind::Standard) {
                continue;
            }
            for &elements in &cfg.elements {
                for &dt_divisor in &cfg.dt_divisors {
                    out.push(Case { scheme: scheme.clone(), mass: mass.clone(), elements, dt_divisor });
                }
            }
        }
    }
    out
}

/// The measurements of one run (one CSV row).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseResult {
    pub scheme: &'static str,
    pub mass: &'static str,
    pub elements: usize,
    pub h: f64,
    pub dt_divisor: usize,
    pub dt: f64,
    pub steps: usize,
    /// max_n ‖u_h(t_n) − u(t_n)‖_{L²(0,L)}.
    pub linf_l2_error: f64,
    /// `linf_l2_error` / max_n ‖I_h u(t_n)‖_{L²}.
    pub linf_l2_error_relative: f64,
    /// max_n |u_0ⁿ − u(0, t_n)|.
    pub max_contact_error: f64,
    /// (max − min)/E_exact of the discrete energy over the run.
    pub energy_spread: f64,
    /// Wall time of building the scheme (factorisations) plus stepping, no diagnostics.
    pub wall_seconds: f64,
    /// Stepping only, per node and step.
    pub ns_per_node_step: f64,
    /// "ok"; "diverged": a result, the run stopped at a divergence ([`DivergenceCriterion`],
    /// default factor) that `failure` describes, and is left out of the fits; "failed": an
    /// error, in `failure`. The numbers above are NaN unless "ok".
    pub status: &'static str,
    /// Where and why the run diverged, or the error.
    pub failure: Option<String>,
}

/// Runs one case twice: once with the exact-error observer (errors), once bare (time).
pub fn run_case(case: &Case, cfg: &SweepConfig) -> CaseResult {
    let mut r = CaseResult {
        scheme: case.scheme.label,
        mass: case.mass.name(),
        elements: case.elements,
        h: 1.0 / case.elements as f64,
        dt_divisor: case.dt_divisor,
        dt: f64::NAN,
        steps: 0,
        linf_l2_error: f64::NAN,
        linf_l2_error_relative: f64::NAN,
        max_contact_error: f64::NAN,
        energy_spread: f64::NAN,
        wall_seconds: f64::NAN,
        ns_per_node_step: f64::NAN,
        status: "failed",
        failure: None,
    };
    let problem = match PaperBar::unit(case.elements).problem(&case.mass) {
        Ok(p) => p,
        Err(e) => {
            r.failure = Some(e.to_string());
            return r;
        }
    };
    let dt = problem.system.h() / case.dt_divisor as f64;
    // T/Δt = T m · divisor: an integer for the integer end times of the configurations.
    let steps = (cfg.end * (case.elements * case.dt_divisor) as f64).round() as usize;
    r.dt = dt;
    r.steps = steps;
    let errors = problem.scheme(&case.scheme.spec, dt).map_err(|e| e.to_string()).and_then(|mut s| {
        let mut obs = SummaryObserver::new(&problem, steps, dt, true);
        let criterion = DivergenceCriterion::default();
        let outcome = integrate_watched(&problem, s.as_mut(), steps, &criterion, &mut [&mut obs]);
        Ok((outcome.map_err(|e| e.to_string())?, obs.finish()))
    });
    let summary = match errors {
        Ok((Outcome::Completed, s)) => s,
        Ok((Outcome::Diverged(d), _)) => {
            r.status = "diverged";
            r.failure = Some(d.to_string());
            return r;
        }
        Err(e) => {
            r.failure = Some(e);
            return r;
        }
    };
    r.status = "ok";
    r.linf_l2_error = summary.linf_l2_error.unwrap_or(f64::NAN);
    r.linf_l2_error_relative = summary.linf_l2_error_relative.unwrap_or(f64::NAN);
    r.max_contact_error = summary.max_contact_error.unwrap_or(f64::NAN);
    let e_exact = summary.energy_exact.unwrap_or(f64::NAN);
    r.energy_spread = (summary.energy_max - summary.energy_min) / e_exact;

    let node_steps = (steps * case.elements) as f64;
    let mut best_wall = f64::INFINITY;
    r.ns_per_node_step = best_timed(node_steps, 1, 50, cfg.min_timing_seconds, || {
        let t0 = Instant::now();
        let mut s = problem.scheme(&case.scheme.spec, dt).expect("built above");
        let t1 = Instant::now();
        integrate(&problem, s.as_mut(), steps, &mut []).expect("ran above");
        let stepping = t1.elapsed().as_secs_f64();
        best_wall = best_wall.min(t0.elapsed().as_secs_f64());
        stepping
    });
    r.wall_seconds = best_wall;
    r
}

/// Least-squares slope of log y against log x over the finite positive pairs (None with fewer
/// than two).
pub fn fit_slope(x: &[f64], y: &[f64]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(a, b)| a.is_finite() && b.is_finite() && **a > 0.0 && **b > 0.0)
        .map(|(a, b)| (a.ln(), b.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// Observed convergence rates of one (scheme, mass).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Rates {
    pub scheme: &'static str,
    pub mass: &'static str,
    /// Slope of the L∞(L²) error against h at fixed Δt = h (h and Δt refined together), fitted
    /// over m ≥ `fit_from`.
    pub l2_space: Option<f64>,
    /// The same at the smallest Δt/h of the sweep.
    pub l2_space_fine_dt: Option<f64>,
    /// Slope of the contact-displacement error against h at Δt = h.
    pub contact_space: Option<f64>,
    /// Slope of the L∞(L²) error against Δt at the finest h (Δt = h … h/k).
    pub l2_time: Option<f64>,
    /// The L∞(L²) error of the finest run (finest h, smallest Δt).
    pub finest_l2_error: f64,
    pub fit_from: usize,
}

/// Fits the rates of every (scheme, mass) in `results`; the space fits use m ≥ `fit_from`
/// (the coarsest meshes are pre-asymptotic).
pub fn rates(results: &[CaseResult], fit_from: usize) -> Vec<Rates> {
    let mut keys: Vec<(&'static str, &'static str)> = Vec::new();
    for r in results {
        if !keys.contains(&(r.scheme, r.mass)) {
            keys.push((r.scheme, r.mass));
        }
    }
    keys.into_iter()
        .map(|(scheme, mass)| {
            let rows: Vec<&CaseResult> =
                results.iter().filter(|r| r.scheme == scheme && r.mass == mass && r.failure.is_none()).collect();
            let space = |div: usize, err: fn(&CaseResult) -> f64| {
                let pts: Vec<&&CaseResult> =
                    rows.iter().filter(|r| r.dt_divisor == div && r.elements >= fit_from).collect();
                fit_slope(&pts.iter().map(|r| r.h).collect::<Vec<_>>(), &pts.iter().map(|r| err(r)).collect::<Vec<_>>())
            };
            let min_div = rows.iter().map(|r| r.dt_divisor).min().unwrap_or(1);
            let max_div = rows.iter().map(|r| r.dt_divisor).max().unwrap_or(1);
            let finest = rows.iter().map(|r| r.elements).max().unwrap_or(0);
            let at_finest: Vec<&&CaseResult> = rows.iter().filter(|r| r.elements == finest).collect();
            let l2_time = fit_slope(
                &at_finest.iter().map(|r| r.dt).collect::<Vec<_>>(),
                &at_finest.iter().map(|r| r.linf_l2_error).collect::<Vec<_>>(),
            );
            let finest_l2_error =
                at_finest.iter().find(|r| r.dt_divisor == max_div).map_or(f64::NAN, |r| r.linf_l2_error);
            Rates {
                scheme,
                mass,
                l2_space: space(min_div, |r| r.linf_l2_error),
                l2_space_fine_dt: space(max_div, |r| r.linf_l2_error),
                contact_space: space(min_div, |r| r.max_contact_error),
                l2_time,
                finest_l2_error,
                fit_from,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law_is_its_exponent() {
        let x = [0.1, 0.05, 0.025, 0.0125];
        let y: Vec<f64> = x.iter().map(|h: &f64| 3.0 * h.powf(1.5)).collect();
        // Exact power law: the fit is exact up to a few ulps of the logs (|ln| < 10).
        assert!((fit_slope(&x, &y).unwrap() - 1.5).abs() < 1e-12);
        assert_eq!(fit_slope(&x[..1], &y[..1]), None);
    }

    #[test]
    fn rates_recover_the_exponents_of_synthetic_power_laws() {
        // e = C h^p Δt^q on a grid of (m, Δt = h/d): the space fit at fixed d gives p + q, the
        // time fit at the finest m gives q (exact power laws: a few ulps of the logs).
        let (p, q) = (0.75, 0.5);
        let mut results = Vec::new();
        for m in [6, 12, 24, 48, 96] {
            for d in [1, 2, 4] {
                let h = 1.0 / m as f64;
                let dt = h / d as f64;
                let e = 2.0 * h.powf(p) * dt.powf(q);
                results.push(CaseResult {
                    scheme: "s",
                    mass: "mod3",
                    elements: m,
                    h,
                    dt_divisor: d,
                    dt,
                    steps: 3 * m * d,
                    linf_l2_error: e,
                    linf_l2_error_relative: e,
                    max_contact_error: e,
                    energy_spread: 0.0,
                    wall_seconds: 1.0,
                    ns_per_node_step: 1.0,
                    status: "ok",
                    failure: None,
                });
            }
        }
        let r = &rates(&results, 24)[0];
        assert!((r.l2_space.unwrap() - (p + q)).abs() < 1e-12);
        assert!((r.l2_space_fine_dt.unwrap() - (p + q)).abs() < 1e-12);
        assert!((r.l2_time.unwrap() - q).abs() < 1e-12);
        assert_eq!(r.finest_l2_error, results.last().unwrap().linf_l2_error);
    }

    #[test]
    fn scheme_cases_are_the_paper_schemes_in_file_and_colour_order() {
        // The labels name the sweep's files and fix each scheme's colour (report.rs, by position).
        let labels: Vec<&str> = scheme_cases().iter().map(|c| c.label).collect();
        assert_eq!(labels, ["crank-nicolson", "crank-nicolson-reduced", "backward-euler", "paoli-schatzman", "hybrid"]);
        let massless: Vec<bool> = scheme_cases().iter().map(|c| c.needs_massless).collect();
        assert_eq!(massless, [false, true, false, false, true]);
        assert!(scheme_cases().iter().all(|c| c.spec.name() == c.label.trim_end_matches("-reduced")));
    }

    #[test]
    fn a_diverged_run_is_reported_as_such_and_left_out_of_the_fits() {
        // Paoli–Schatzman with mod1 at Δt = h passes 10⁶ E(0) after some 440 steps (m = 6).
        let ps = scheme_cases().into_iter().find(|c| c.label == "paoli-schatzman").unwrap();
        let case = Case { scheme: ps, mass: MassKind::Mod1, elements: 6, dt_divisor: 1 };
        let long = SweepConfig { elements: vec![6], dt_divisors: vec![1], end: 3000.0, min_timing_seconds: 0.0 };
        let r = run_case(&case, &long);
        assert_eq!(r.status, "diverged");
        assert!(r.failure.as_deref().is_some_and(|f| f.starts_with("diverged at step")), "{:?}", r.failure);
        assert!(r.linf_l2_error.is_nan() && r.wall_seconds.is_nan());
        assert!(rates(std::slice::from_ref(&r), 6)[0].l2_space.is_none());
        let one_period = SweepConfig { end: 3.0, ..long };
        assert_eq!(run_case(&case, &one_period).status, "ok");
    }

    #[test]
    fn cases_skip_massless_only_schemes_on_the_standard_mass() {
        let cfg = SweepConfig { elements: vec![6], dt_divisors: vec![1], end: 3.0, min_timing_seconds: 0.0 };
        let c = cases(&cfg);
        // 3 schemes × 4 masses + 2 schemes × 3 masses.
        assert_eq!(c.len(), 18);
        assert!(!c.iter().any(|c| c.scheme.needs_massless && c.mass == MassKind::Standard));
    }
}
