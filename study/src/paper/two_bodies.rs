//! Two bodies in contact (issue 30, check 5): the two-bar impacts (a)–(c) of
//! [`massredist::models::TwoBars`] for every mass and scheme that takes two bodies, and the
//! penalty law, at [`N`] cells per unit length with cΔt/h = 1 (central differences: the largest
//! Δt dividing T at most [`SAFETY`] × the stable limit): the contact duration between the
//! half-force crossings, the plateau force and the final momenta against d'Alembert, the peak
//! force, the force's total variation over Z V/2 (its chatter; exact: 2, up and down), the
//! fraction of the steps of the exact contact window with Σ R > 0 (exact: all), and E(T)/E(0).
//! Every run is repeated five times from a striker speed perturbed by at most
//! [`super::bodies::PERTURBATION`] (the standard mass's runs are chaotic after the impact): cells
//! keep the digits all five share, else their band. The figure `two-bars` draws the force of
//! (a) and (b) for mod3, the standard mass and the penalty law.

use super::ReproduceError;
use super::band::stable_digits;
use super::bodies::PERTURBATION;
use super::figures::{FigureFile, grid_rows};
use super::methods::{SAFETY, step_dividing};
use super::replicate::{Copies, Printed, replicate};
use crate::plot::{Curve, Figure, Panel, Style};
use massredist::models::{TwoBarCase, TwoBarErrors, TwoBars};
use massredist::scene::SolidScene;
use massredist::schemes::SchemeError;
use massredist::solid::SolidSpec;
use massredist::spec::GeometrySpec;
use rayon::prelude::*;
use std::fmt::Write as _;

/// Cells per unit length (one across).
pub const N: usize = 100;
/// The penalty law's κ per contact node: 10 × the bar's axial stiffness per node, (λ + 2μ) A / h
/// over the two nodes of the interface.
pub const PENALTY_FACTOR: f64 = 10.0;
/// The figure's stem, and the CSV of every run.
pub const TWO_BARS_FIGURE: &str = "two-bars";
pub const TWO_BARS_TABLE: &str = "two-bars-table.csv";

/// A method: its label, `scheme.kind`, `mass.kind`, and whether it is the penalty law.
pub struct Method {
    pub label: &'static str,
    pub scheme: &'static str,
    pub mass: &'static str,
    pub penalty: bool,
}

/// Every scheme and mass that takes two bodies, and the penalty law.
pub const METHODS: [Method; 8] = [
    Method { label: "CN mod3", scheme: "crank-nicolson", mass: "mod3", penalty: false },
    Method { label: "CN standard", scheme: "crank-nicolson", mass: "standard", penalty: false },
    Method { label: "BE mod3", scheme: "backward-euler", mass: "mod3", penalty: false },
    Method { label: "BE standard", scheme: "backward-euler", mass: "standard", penalty: false },
    Method { label: "hybrid mod3", scheme: "hybrid", mass: "mod3", penalty: false },
    Method { label: "CD mod3", scheme: "central-difference", mass: "mod3", penalty: false },
    Method { label: "Moreau–Jean standard", scheme: "moreau-jean", mass: "standard", penalty: false },
    Method { label: "CN standard penalty", scheme: "crank-nicolson", mass: "standard", penalty: true },
];

/// One run's numbers, and (kept for the figure) its t and Σ R.
#[derive(Debug, Clone)]
pub struct Run {
    /// The time step, and (central differences) Δt_c and its estimator.
    pub dt: f64,
    pub stable: Option<(f64, &'static str)>,
    pub errors: TwoBarErrors,
    pub force_tv: f64,
    pub in_contact: f64,
    pub energy_ratio: f64,
    pub series: [Vec<f64>; 2],
}

/// A case × method's five runs, the unperturbed first.
#[derive(Debug, Clone)]
pub struct CaseRuns {
    pub case: TwoBarCase,
    pub method: &'static str,
    pub runs: Vec<Run>,
}

fn run_one(case: TwoBarCase, m: &Method, copy: usize) -> Result<Run, ReproduceError> {
    let bars = TwoBars::new(case, N);
    let h = 1.0 / N as f64;
    let dt = h / bars.wave_speed();
    let contact = if m.penalty {
        let kappa = PENALTY_FACTOR * 2.0 * bars.mu * bars.height / h / 2.0;
        format!("[contact]\nmethod = \"penalty\"\npenalty = {kappa:?}\n")
    } else {
        String::new()
    };
    let tail = if copy == 0 { String::new() } else { format!(" + {:e}", PERTURBATION * copy as f64) };
    let name = format!("two bars {} {} copy {copy}", case.name(), m.label);
    let scene_at = |dt: f64| {
        SolidScene::from_toml(&bars.text(m.mass, m.scheme, &contact, dt, &tail))
            .map_err(|source| ReproduceError::Scene { case: name.clone(), source })
    };
    // h/c for the implicit schemes; central differences at the largest Δt dividing T that is at
    // most the study's one safety factor times Δt_c (issue 32, item 2; Δt_c from the scheme,
    // built at h/c, which it refuses where h/c is above Δt_c).
    let scene = scene_at(dt)?;
    let problem = <SolidSpec as GeometrySpec>::problem(&scene)
        .map_err(|e| ReproduceError::Run { case: name.clone(), source: massredist::run::RunError::problem(e) })?;
    let stable = match problem.scheme_with(&scene.scheme, &scene.contact, dt) {
        Err(SchemeError::AboveStableLimit { limit, .. }) => {
            let rebuilt = problem.scheme_with(&scene.scheme, &scene.contact, SAFETY * limit);
            rebuilt.ok().and_then(|s| s.stable_limit())
        }
        Ok(s) => s.stable_limit(),
        Err(e) => return Err(ReproduceError::Run { case: name, source: e.into() }),
    };
    let (scene, dt) = match stable {
        Some((limit, _)) => {
            let dt = step_dividing(bars.end(), SAFETY * limit);
            (scene_at(dt)?, dt)
        }
        None => (scene, dt),
    };
    let (errors, s) = bars.measure(&scene);
    let f = bars.force();
    let window: Vec<f64> =
        s.t.iter().zip(&s.force).filter(|(t, _)| **t > 0.0 && **t <= bars.duration()).map(|x| *x.1).collect();
    Ok(Run {
        dt,
        stable,
        errors,
        force_tv: s.force.windows(2).map(|w| (w[1] - w[0]).abs()).sum::<f64>() / f,
        in_contact: window.iter().filter(|&&x| x > 0.0).count() as f64 / window.len() as f64,
        energy_ratio: s.energy[s.energy.len() - 1] / s.energy[0],
        series: [s.t, s.force],
    })
}

fn printed(r: &Run) -> Vec<Printed> {
    let e = &r.errors;
    [e.duration, e.plateau, e.momentum, e.peak, r.force_tv, r.in_contact, r.energy_ratio]
        .into_iter()
        .map(|v| Printed::Value(Some(v), 3))
        .collect()
}

/// Every case × method with its perturbed copies, in parallel.
pub fn compute_two_bodies() -> Result<Vec<CaseRuns>, ReproduceError> {
    let all: Vec<(TwoBarCase, &Method)> =
        TwoBarCase::ALL.iter().flat_map(|&c| METHODS.iter().map(move |m| (c, m))).collect();
    all.par_iter()
        .map(|&(case, m)| {
            let runs = replicate(
                Copies::All,
                |c| run_one(case, m, c.index().map_or(0, |k| k + 1)),
                |r| r.as_ref().map_or(vec![Printed::Value(None, 0)], printed),
            );
            Ok(CaseRuns { case, method: m.label, runs: runs.into_iter().collect::<Result<Vec<_>, _>>()? })
        })
        .collect()
}

/// The report's section (its table; the figure below it).
pub fn two_bodies_markdown(results: &[CaseRuns]) -> String {
    let mut out = format!(
        "\n### Two bodies: two bars meeting end to end\n\n\
         Two 2D strips (λ = 0, μ = ½, ρ = 1: c = 1, Z = ρ c A = 0.1), the striker at V = 1 touching the target at \
         t = 0 (`[[solid]]`, `[[pair]]`, [scenes.md](../scenes.md#two-bodies-in-contact-solid-and-pair); \
         `src/models/two_bars.rs`): (a) onto a free bar of the same length, (b) onto a bar clamped at its far end \
         (Code_Aster SDNL111), (c) onto a free bar twice as long. {N} cells per unit length, T = twice the exact \
         contact plus 1; the implicit schemes at cΔt/h = 1 with the consistent mass, central differences with the \
         lumped mass at the largest Δt dividing T that is at most {SAFETY} Δt_c (Δt_c and its estimator: the CSV's \
         `stable_step`, `stable_step_method`). Errors are relative: the duration between the crossings of Z V/4, the mean force over \
         the middle half of the exact window against Z V/2, the final momenta against d'Alembert (over ρ A V); the \
         peak and the force's total variation are over Z V/2 (exact: 1 and 2); \"in contact\" is the fraction of the \
         exact window's steps with Σ R > 0 (exact: 1). The penalty law: κ = {PENALTY_FACTOR} × the bar's axial \
         stiffness per interface node. Each run is repeated five times from a speed perturbed by at most \
         {:e}: cells keep the digits all five runs share, else their band.\n\n\
         | case | method | cΔt/h | duration | plateau | momenta | peak | force TV | in contact | E(T)/E(0) |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        PERTURBATION * 4.0
    );
    for r in results {
        let d = |f: &dyn Fn(&Run) -> f64| stable_digits(&r.runs.iter().map(|x| Some(f(x))).collect::<Vec<_>>(), 3);
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.case.name(),
            r.method,
            d(&|x| x.dt * N as f64),
            d(&|x| x.errors.duration),
            d(&|x| x.errors.plateau),
            d(&|x| x.errors.momentum),
            d(&|x| x.errors.peak),
            d(&|x| x.force_tv),
            d(&|x| x.in_contact),
            d(&|x| x.energy_ratio),
        );
    }
    let _ = write!(out, "\n![{TWO_BARS_FIGURE}]({TWO_BARS_FIGURE}.png)\n");
    out
}

/// The CSV rows, one per run.
pub fn two_bodies_csv(results: &[CaseRuns]) -> String {
    let mut out = String::from(
        "case,method,copy,dt,stable_step,stable_step_method,duration_error,plateau_error,momentum_error,peak,force_tv,in_contact,energy_ratio,contact_time\n",
    );
    for r in results {
        for (k, x) in r.runs.iter().enumerate() {
            let e = &x.errors;
            let _ = writeln!(
                out,
                "{},{},{k},{:e},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
                r.case.name(),
                r.method,
                x.dt,
                x.stable.map_or(String::new(), |(l, _)| format!("{l:e}")),
                x.stable.map_or("", |(_, by)| by),
                e.duration,
                e.plateau,
                e.momentum,
                e.peak,
                x.force_tv,
                x.in_contact,
                x.energy_ratio,
                e.contact_time
            );
        }
    }
    out
}

/// The figure: Σ R over Z V/2 against t for (a) and (b), the standard mass (CN), the penalty law
/// and mod3 (CN; unperturbed runs), with its CSV.
pub(super) fn two_bodies_figure(results: &[CaseRuns]) -> FigureFile {
    // mod3 drawn last, on top of the chatter.
    let shown = ["CN standard", "CN standard penalty", "CN mod3"];
    let f = TwoBars::new(TwoBarCase::Free, N).force();
    let cases = [TwoBarCase::Free, TwoBarCase::Clamped];
    let panels = cases
        .iter()
        .map(|&case| Panel {
            title: case.name().into(),
            x_label: "t".into(),
            y_label: "Σ R / (Z V/2)".into(),
            curves: shown
                .iter()
                .filter_map(|m| results.iter().find(|r| r.case == case && r.method == *m))
                .enumerate()
                .map(|(i, r)| {
                    let [t, force] = &r.runs[0].series;
                    Curve {
                        label: r.method.into(),
                        points: t.iter().copied().zip(force.iter().map(|x| x / f)).collect(),
                        style: Style::Numeric(i),
                    }
                })
                .collect(),
            x_range: None,
            y_range: None,
        })
        .collect();
    let title = format!("Two bars: contact force, {N} cells per unit length, cΔt/h = 1");
    let first = results.iter().find(|r| r.case == TwoBarCase::Clamped);
    let times = first.map(|r| r.runs[0].series[0].clone()).unwrap_or_default();
    let mut header = vec!["t".to_string()];
    let mut columns = Vec::new();
    for r in results.iter().filter(|r| cases.contains(&r.case) && shown.contains(&r.method)) {
        header.push(format!("{} {}", r.case.name(), r.method).replace(' ', "_"));
        columns.push(r.runs[0].series[1].iter().map(|x| x / f).collect());
    }
    FigureFile {
        stem: TWO_BARS_FIGURE.into(),
        figure: Figure { title, panels, columns: 2, panel_size: (620, 480) },
        header,
        rows: grid_rows(&times, &columns),
        periods: None,
    }
}
