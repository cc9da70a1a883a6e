//! The scope of the paper's headline "mod3 is the most accurate" (issue 22, item 1).
//!
//! The paper checks it on one mesh, h = 1/6, over one period (T = 3). Here the same benchmark
//! (§4.1: u⁰ = (1−x)/2, v⁰ = 0, exact solution 3-periodic) runs on m ∈ [`SCOPE_ELEMENTS`]
//! elements with the paper's Δt, for Crank–Nicolson, backward Euler and the hybrid scheme, and
//! the L∞(0,T;L²) error
//!
//! ```text
//! e(T) = max_{t_n ≤ T} ‖u_h(t_n) − u(t_n)‖_{L²(0,L)}      (exact integral, as in the tables)
//! ```
//!
//! is read at T = 2 (end of the first contact: impact at L, release at 2L) and at T = 3 (one
//! period) from the same run. Every run is repeated from [`band::PERTURBATIONS`] initial states
//! U⁰ perturbed by ≤ [`band::PERTURBATION`] (the standard mass chatters with Crank–Nicolson), so
//! the report quotes only the digits all five runs share ([`band::stable_digits`]).

use super::band;
use super::figures::{FigureFile, mass_style};
use super::{Config, Experiment, ReproduceError};
use crate::plot::{Curve, Figure, Panel};
use massredist::driver::{Needs, Observer, Sample, integrate};
use massredist::mass::MassKind;
use massredist::models::PaperBar;
use massredist::output::fmt_f64;
use massredist::run::RunError;
use rayon::prelude::*;
use std::fmt::Write as _;

/// Stem of the figure (`.png`, `.svg`, `.csv`).
pub const SCOPE_FIGURE: &str = "mesh-scope";

/// Mesh sizes m (h = L/m): the paper's 6, refined three times.
pub const SCOPE_ELEMENTS: [usize; 4] = [6, 12, 24, 48];

/// The horizons read off each run: end of the first contact (2L) and one period (3L), L = 1.
pub const SCOPE_ENDS: [f64; 2] = [2.0, 3.0];

/// The schemes of the figure (Paoli–Schatzman gives the Crank–Nicolson errors to 3 digits at
/// m = 6, T = 3; it is left out to keep the figure readable).
pub const SCOPE_SCHEMES: [Experiment; 3] = [Experiment::CrankNicolson, Experiment::BackwardEuler, Experiment::Hybrid];

/// Header of `mesh-scope.csv`.
pub const SCOPE_COLUMNS: [&str; 9] =
    ["scheme", "mass", "elements", "end", "linf_l2_error", "band_min", "band_max", "runs", "stable_digits"];

/// One (scheme, mass, m, T) entry: the error of each of the five runs, unperturbed first.
#[derive(Debug, Clone)]
pub struct ScopeEntry {
    pub experiment: Experiment,
    pub mass: MassKind,
    pub elements: usize,
    pub end: f64,
    pub errors: Vec<f64>,
}

impl ScopeEntry {
    /// The error with the digits all runs share, else their band.
    pub fn shown(&self) -> String {
        band::stable_digits(&self.errors.iter().map(|&e| Some(e)).collect::<Vec<_>>(), 4)
    }

    /// The unperturbed run's error.
    pub fn value(&self) -> f64 {
        self.errors[0]
    }
}

/// max ‖u_h(t_n) − u(t_n)‖ over t_n ≤ each of [`SCOPE_ENDS`].
struct ErrorUpTo {
    max: [f64; 2],
}

impl Observer for ErrorUpTo {
    fn needs(&self) -> Needs {
        Needs { l2: true, ..Needs::default() }
    }

    fn observe(&mut self, s: &Sample) {
        for (m, &end) in self.max.iter_mut().zip(&SCOPE_ENDS) {
            // t_n = n·Δt carries rounding: 1e-9 relative slack keeps t_n = end in.
            if s.state.t <= end * (1.0 + 1e-9) {
                *m = m.max(s.l2_error);
            }
        }
    }
}

/// One run to the last of [`SCOPE_ENDS`]: the error up to each end.
fn run_one(config: &Config, e: Experiment, mass: &MassKind, m: usize, k: Option<usize>) -> Result<[f64; 2], RunError> {
    let mut problem = PaperBar { length: config.length, elements: m }.problem(mass).map_err(RunError::problem)?;
    if let Some(k) = k {
        problem.u0 = band::perturbed(&problem.u0, k);
    }
    let steps = (SCOPE_ENDS[1] / config.dt).round() as usize;
    let mut scheme = problem.scheme(&e.spec(), config.dt)?;
    let mut obs = ErrorUpTo { max: [0.0; 2] };
    integrate(&problem, scheme.as_mut(), steps, &mut [&mut obs])?;
    Ok(obs.max)
}

/// Every entry: [`SCOPE_SCHEMES`] × their masses × [`SCOPE_ELEMENTS`] × [`SCOPE_ENDS`], each over
/// five runs, in parallel.
pub fn mesh_scope(config: &Config) -> Result<Vec<ScopeEntry>, ReproduceError> {
    let jobs: Vec<(Experiment, MassKind, usize)> = SCOPE_SCHEMES
        .iter()
        .flat_map(|&e| e.masses().into_iter().flat_map(move |mass| SCOPE_ELEMENTS.map(|m| (e, mass.clone(), m))))
        .collect();
    let per_job = jobs
        .par_iter()
        .map(|(e, mass, m)| {
            let case = || format!("mesh scope / {} / {} / m = {m}", e.slug(), mass.name());
            let runs = std::iter::once(None)
                .chain((0..band::PERTURBATIONS).map(Some))
                .map(|k| run_one(config, *e, mass, *m, k))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|source| ReproduceError::Run { case: case(), source })?;
            Ok(SCOPE_ENDS
                .iter()
                .enumerate()
                .map(|(i, &end)| ScopeEntry {
                    experiment: *e,
                    mass: mass.clone(),
                    elements: *m,
                    end,
                    errors: runs.iter().map(|r| r[i]).collect(),
                })
                .collect::<Vec<_>>())
        })
        .collect::<Result<Vec<_>, ReproduceError>>()?;
    Ok(per_job.into_iter().flatten().collect())
}

/// The entries of (scheme, m, T), one per mass.
fn cell(entries: &[ScopeEntry], e: Experiment, m: usize, end: f64) -> Vec<&ScopeEntry> {
    entries.iter().filter(|x| x.experiment == e && x.elements == m && x.end == end).collect()
}

/// The mass with the smallest error of a cell, if every run of it is below every run of the
/// others (else None: round-off decides the ranking).
fn best<'a>(cell: &[&'a ScopeEntry]) -> Option<&'a MassKind> {
    let hi = |x: &ScopeEntry| x.errors.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let lo = |x: &ScopeEntry| x.errors.iter().copied().fold(f64::INFINITY, f64::min);
    let b = cell.iter().min_by(|a, b| a.value().total_cmp(&b.value()))?;
    cell.iter().filter(|x| !std::ptr::eq(**x, *b)).all(|x| lo(x) > hi(b)).then_some(&b.mass)
}

/// The figure: per scheme (rows) and horizon (columns), log10 of the error against log2 m,
/// one curve per mass; and its CSV ([`SCOPE_COLUMNS`]).
pub(super) fn scope_figure(config: &Config, entries: &[ScopeEntry]) -> FigureFile {
    let mut panels = Vec::new();
    for e in SCOPE_SCHEMES {
        for end in SCOPE_ENDS {
            let curves = e
                .masses()
                .iter()
                .map(|mass| Curve {
                    label: mass.name().into(),
                    points: entries
                        .iter()
                        .filter(|x| x.experiment == e && &x.mass == mass && x.end == end)
                        .map(|x| ((x.elements as f64).log2(), x.value().log10()))
                        .collect(),
                    style: mass_style(mass),
                })
                .collect();
            panels.push(Panel {
                title: format!("{}, T = {}", e.title(), fmt_f64(end)),
                x_label: "log2 m (m = 6, 12, 24, 48)".into(),
                y_label: "log10 L∞(0,T;L²) error".into(),
                curves,
                x_range: None,
                y_range: None,
            });
        }
    }
    let title = format!("Scope of \"mod3 is best\": error against the mesh, Δt = {}", fmt_f64(config.dt));
    let figure = Figure { title, panels, columns: 2, panel_size: (620, 420) };
    let rows = entries
        .iter()
        .map(|x| {
            let (lo, hi) = band::band(&x.errors);
            vec![
                x.experiment.slug().to_string(),
                x.mass.name().into(),
                x.elements.to_string(),
                fmt_f64(x.end),
                fmt_f64(x.value()),
                fmt_f64(lo),
                fmt_f64(hi),
                x.errors.len().to_string(),
                band::agreed_digits(&x.errors.iter().map(|&e| Some(e)).collect::<Vec<_>>()).to_string(),
            ]
        })
        .collect();
    FigureFile {
        stem: SCOPE_FIGURE.into(),
        figure,
        header: SCOPE_COLUMNS.map(String::from).into(),
        rows,
        periods: None,
    }
}

/// Per scheme, the meshes where mod3 is [`best`] at `end` (among the w_0 = 0 masses only if
/// `massless`): "Crank–Nicolson every m; backward Euler m = 48".
fn wins(entries: &[ScopeEntry], end: f64, massless: bool) -> String {
    let per_scheme: Vec<String> = SCOPE_SCHEMES
        .iter()
        .map(|&e| {
            let at: Vec<String> = SCOPE_ELEMENTS
                .iter()
                .filter(|&&m| {
                    let mut c = cell(entries, e, m, end);
                    c.retain(|x| !massless || super::experiments::massless_contact(&x.mass));
                    best(&c) == Some(&MassKind::Mod3)
                })
                .map(|m| m.to_string())
                .collect();
            let list = match at.len() {
                0 => "no m".to_string(),
                n if n == SCOPE_ELEMENTS.len() => "every m".to_string(),
                _ => format!("m = {}", at.join(", ")),
            };
            format!("{} {list}", e.title())
        })
        .collect();
    per_scheme.join("; ")
}

/// The report section: one table per scheme (m × horizon × mass), the smallest mass of each
/// (m, T) when all five runs agree on it, and the verdict on mod3 by horizon.
pub(super) fn scope_section(config: &Config, entries: &[ScopeEntry]) -> String {
    let mut s = format!(
        "\n## Scope of \"mod3 is the most accurate\": finer meshes and T = 2\n\n![{SCOPE_FIGURE}]({SCOPE_FIGURE}.png)\n\n\
         The paper's benchmark (§4.1) on m = {} elements, Δt = {}, L∞(0,T;L²) error up to T = 2 (end of the first contact) and T = 3 \
         (one period), read from the same run; each run also from {} initial states U⁰ perturbed by ≤ {:e} relative, so a value is given \
         with the digits all five runs share, else as their band (`{SCOPE_FIGURE}.csv`: every run's band).\n",
        SCOPE_ELEMENTS.map(|m| m.to_string()).join(", "),
        fmt_f64(config.dt),
        band::PERTURBATIONS,
        band::PERTURBATION
    );
    for e in SCOPE_SCHEMES {
        let masses = e.masses();
        let _ = write!(s, "\n{}:\n\n| m | T |", e.title());
        for m in &masses {
            let _ = write!(s, " {} |", m.name());
        }
        s.push_str(" smallest |\n|---|---|");
        s.push_str(&"---|".repeat(masses.len() + 1));
        s.push('\n');
        for m in SCOPE_ELEMENTS {
            for end in SCOPE_ENDS {
                let c = cell(entries, e, m, end);
                let vals: Vec<String> = c.iter().map(|x| x.shown()).collect();
                let b = best(&c).map_or("round-off decides".into(), |b| b.name().to_string());
                let _ = writeln!(s, "| {m} | {} | {} | {b} |", fmt_f64(end), vals.join(" | "));
            }
        }
    }
    s.push('\n');
    for end in SCOPE_ENDS {
        let _ = writeln!(
            s,
            "- T = {}: mod3 has the smallest error of all masses with {}; of the w_0 = 0 masses with {}.",
            fmt_f64(end),
            wins(entries, end, false),
            wins(entries, end, true)
        );
    }
    let everywhere = |end: f64| {
        SCOPE_SCHEMES
            .iter()
            .all(|&e| SCOPE_ELEMENTS.iter().all(|&m| best(&cell(entries, e, m, end)) == Some(&MassKind::Mod3)))
    };
    let _ = writeln!(
        s,
        "\nmod3 smallest with every scheme at every m: T = 2 {}, T = 3 {}. The paper's claim is made on m = 6 over one period; \
         the rows above give its scope.",
        if everywhere(2.0) { "yes" } else { "**no**" },
        if everywhere(3.0) { "yes" } else { "**no**" }
    );
    s
}
