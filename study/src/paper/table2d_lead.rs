//! The best lead on the paper's Table 1 (issue 22, item 2): 20² Q1 cells, Crank–Nicolson,
//! Δt = h/2 = 0.025, T = 2 (the end of the first contact phase).
//!
//! With u⁰ = (1−x)/2 (the paper's 1D data) it gives the paper's error ratios at about twice its
//! scale; with u⁰ = (1−x)/4 it gives about the paper's values. The problem (gap 0, f = 0) and the
//! schemes are positively homogeneous, so halving u⁰ halves every error; the factor ½ contradicts
//! the paper's (0,1)×(0,1) with its 1D data, so this is a lead, not a reproduction. Both rows are
//! computed here by plate runs ([`lead_rows`]). How fragile it is ([`sensitivity`]): the ratios
//! mod1/mod3 and mod2/mod3 over T ∈ [`SENS_T`] for Δt within ±20 % of h/2, on the 1D bar with
//! h = 0.05 (the Q1 plate with y-independent data is that bar to round-off, `tests/plate.rs`), as
//! a small figure.

use super::band::{PERTURBATION, PERTURBATIONS, stable_digits};
use super::figures::FigureFile;
use super::tables::sig;
use crate::plot::{Curve, Figure, Panel, Style};
use massredist::mass::MassKind;
use massredist::models::PaperBar;
use massredist::output::fmt_f64;
use massredist::scene::PlateScene;
use std::fmt::Write as _;

/// Stem of the sensitivity figure (`.png`, `.svg`, `.csv`).
pub const LEAD_FIGURE: &str = "table-2d-lead";

/// The lead's Δt (h/2 with h = 0.05) and T.
pub const LEAD_DT: f64 = 0.025;
pub const LEAD_END: f64 = 2.0;

/// Δt of the sensitivity curves: h/2 × (0.8, 0.9, 1, 1.1, 1.2).
pub const SENS_DT: [f64; 5] = [0.02, 0.0225, 0.025, 0.0275, 0.03];

/// The window of T of the sensitivity figure.
pub const SENS_T: (f64, f64) = (1.9, 2.2);

const MASSES: [MassKind; 3] = [MassKind::Mod1, MassKind::Mod2, MassKind::Mod3];

/// The paper's ratios mod1/mod3 and mod2/mod3 (0.0104/0.0038 and 0.0046/0.0038).
fn paper_ratios() -> (f64, f64) {
    let p = crate::paper::plate_table::PAPER_TABLE;
    (p[0].1 / p[2].1, p[1].1 / p[2].1)
}

/// The lead's errors (mod1, mod2, mod3) for u⁰ = `displacement`, by plate runs of a scene; with
/// `copy`, from the scene's U⁰ perturbed as copy `copy` of [`super::band::perturbed`] (the exact
/// solution stays the scene's: the perturbation is round-off, not data).
fn lead_row(displacement: &str, copy: Option<usize>) -> Option<[f64; 3]> {
    use massredist::driver::integrate;
    use massredist::observe::SummaryObserver;
    use massredist::run::GeometrySpec;
    let mut out = [0.0; 3];
    for (o, m) in out.iter_mut().zip(&MASSES) {
        let text = format!(
            "[plate]\nlength = 1.0\nheight = 1.0\nnx = 20\nny = 20\ncells = \"quad\"\n\
             initial = {{ displacement = \"{displacement}\", velocity = \"0\" }}\n[mass]\nkind = \"{}\"\n\
             [scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = {LEAD_DT:?}\nend = {LEAD_END:?}\n[output]\nseries = []\n",
            m.name()
        );
        let scene = PlateScene::from_toml(&text).ok()?;
        let Some(k) = copy else {
            *o = massredist::run::run_scene(&scene, &mut []).ok()?.summary.linf_l2_error?;
            continue;
        };
        let mut problem = massredist::scene::PlateSpec::problem(&scene).ok()?;
        problem.u0 = super::band::perturbed(&problem.u0, k);
        let mut scheme = problem.scheme(&scene.scheme, scene.time.dt).ok()?;
        let mut summary = SummaryObserver::new(&problem, scene.time.steps, scene.time.dt, true);
        integrate(&problem, scheme.as_mut(), scene.time.steps, &mut [&mut summary]).ok()?;
        *o = summary.finish().linf_l2_error?;
    }
    Some(out)
}

/// The lead with u⁰ = (1−x)/2 and with u⁰ = (1−x)/4 (None where a run failed).
pub fn lead_rows() -> [Option<[f64; 3]>; 2] {
    [lead_row("(1-x)/2", None), lead_row("(1-x)/4", None)]
}

/// [`lead_rows`] from u⁰ perturbed by ≤ 1e-13 relative, [`PERTURBATIONS`] copies (the round-off
/// check of the printed digits).
pub fn lead_copies() -> Vec<[Option<[f64; 3]>; 2]> {
    (0..PERTURBATIONS).map(|k| [lead_row("(1-x)/2", Some(k)), lead_row("(1-x)/4", Some(k))]).collect()
}

/// One sensitivity curve: Δt and, per grid time t_n in [`SENS_T`], (t_n, e1, e2, e3), each e the
/// max over t_k ≤ t_n of the L² error of that mass.
pub type SensCurve = (f64, Vec<(f64, [f64; 3])>);

/// The 1D bar with h = 0.05 for each Δt of [`SENS_DT`] and each mass.
pub fn sensitivity() -> Vec<SensCurve> {
    sensitivity_from(None)
}

/// [`sensitivity`] from U⁰ perturbed as copy `copy` of [`super::band::perturbed`] if given.
pub fn sensitivity_from(copy: Option<usize>) -> Vec<SensCurve> {
    use massredist::driver::{Needs, Observer, Sample, integrate};
    struct Running(Vec<(f64, f64)>, f64);
    impl Observer for Running {
        fn needs(&self) -> Needs {
            Needs { l2: true, ..Needs::default() }
        }
        fn observe(&mut self, s: &Sample) {
            self.1 = self.1.max(s.l2_error);
            self.0.push((s.state.t, self.1));
        }
    }
    SENS_DT
        .iter()
        .map(|&dt| {
            let steps = (SENS_T.1 / dt).ceil() as usize;
            let per_mass: Vec<Vec<(f64, f64)>> = MASSES
                .iter()
                .map(|m| {
                    let Ok(mut p) = PaperBar::unit(20).problem(m) else { return Vec::new() };
                    if let Some(k) = copy {
                        p.u0 = super::band::perturbed(&p.u0, k);
                    }
                    let Ok(mut scheme) = p.scheme(&massredist::scene::SchemeSpec::CRANK_NICOLSON, dt) else {
                        return Vec::new();
                    };
                    let mut r = Running(Vec::new(), 0.0);
                    // A failed run leaves a short curve, which the zip below cuts the others to.
                    let _ = integrate(&p, scheme.as_mut(), steps, &mut [&mut r]);
                    r.0
                })
                .collect();
            let pts = per_mass[0]
                .iter()
                .zip(&per_mass[1])
                .zip(&per_mass[2])
                .filter(|((a, _), _)| a.0 >= SENS_T.0 - 1e-9 && a.0 <= SENS_T.1 + 1e-9)
                .map(|((a, b), c)| (a.0, [a.1, b.1, c.1]))
                .collect();
            (dt, pts)
        })
        .collect()
}

/// The sensitivity figure: mod1/mod3 (left) and mod2/mod3 (right) against T, one curve per Δt,
/// the paper's ratio as the dashed line; and its CSV.
pub(super) fn lead_figure(curves: &[SensCurve]) -> FigureFile {
    let (p13, p23) = paper_ratios();
    let panel = |k: usize, paper: f64, what: &str| {
        let mut cs: Vec<Curve> = curves
            .iter()
            .enumerate()
            .map(|(i, (dt, pts))| Curve {
                label: format!("Δt = {}", fmt_f64(*dt)),
                points: pts.iter().map(|(t, e)| (*t, e[k] / e[2])).collect(),
                style: Style::Numeric(i),
            })
            .collect();
        cs.push(Curve {
            label: "paper".into(),
            points: vec![(SENS_T.0, paper), (SENS_T.1, paper)],
            style: Style::Exact,
        });
        Panel {
            title: format!("{what} (paper {})", sig(paper, 3)),
            x_label: "T".into(),
            y_label: what.into(),
            curves: cs,
            x_range: Some(SENS_T),
            y_range: None,
        }
    };
    let panels = vec![panel(0, p13, "mod1 / mod3"), panel(1, p23, "mod2 / mod3")];
    let title = "Table 1 lead: error ratios against T and Δt (20 Q1 cells across, Crank–Nicolson)".to_string();
    let figure = Figure { title, panels, columns: 2, panel_size: (620, 420) };
    let header = ["dt", "end", "mod1", "mod2", "mod3", "mod1_over_mod3", "mod2_over_mod3"].map(String::from).into();
    let rows = curves
        .iter()
        .flat_map(|(dt, pts)| {
            pts.iter().map(move |(t, e)| {
                vec![
                    fmt_f64(*dt),
                    fmt_f64(*t),
                    fmt_f64(e[0]),
                    fmt_f64(e[1]),
                    fmt_f64(e[2]),
                    fmt_f64(e[0] / e[2]),
                    fmt_f64(e[1] / e[2]),
                ]
            })
        })
        .collect();
    FigureFile { stem: LEAD_FIGURE.into(), figure, header, rows, periods: None }
}

/// The lead's values over its five runs (u⁰ and four perturbed copies, [`lead_copies`]).
pub struct LeadRuns {
    pub rows: [Option<[f64; 3]>; 2],
    pub copies: Vec<[Option<[f64; 3]>; 2]>,
    /// The sensitivity curves of the unperturbed run, then of each copy ([`sensitivity_from`]).
    pub curves: Vec<Vec<SensCurve>>,
}

/// All of the lead's runs ([`LeadRuns`]).
pub fn lead_runs() -> LeadRuns {
    let curves = std::iter::once(None).chain((0..PERTURBATIONS).map(Some)).map(sensitivity_from).collect();
    LeadRuns { rows: lead_rows(), copies: lead_copies(), curves }
}

/// `f` of a row over the five runs, agreed digits only (3 at most).
fn agreed(runs: &LeadRuns, row: usize, f: impl Fn(&[f64; 3]) -> f64) -> String {
    let v: Vec<Option<f64>> = std::iter::once(&runs.rows[row])
        .chain(runs.copies.iter().map(|c| &c[row]))
        .map(|r| r.as_ref().map(&f))
        .collect();
    stable_digits(&v, 3)
}

/// The window of grid times of one sensitivity curve at which both ratios are within 10 % of the
/// paper's.
fn window(pts: &[(f64, [f64; 3])]) -> String {
    let (p13, p23) = paper_ratios();
    let ok: Vec<f64> = pts
        .iter()
        .filter(|(_, e)| ((e[0] / e[2]) / p13 - 1.0).abs() <= 0.1 && ((e[1] / e[2]) / p23 - 1.0).abs() <= 0.1)
        .map(|(t, _)| *t)
        .collect();
    match (ok.first(), ok.last()) {
        (Some(a), Some(b)) => {
            format!("{} of {} grid times, first {}, last {}", ok.len(), pts.len(), sig(*a, 4), sig(*b, 4))
        }
        _ => format!("none of {} grid times", pts.len()),
    }
}

/// The report's lead subsection: both rows with their ratios and scale, and the window of T per
/// Δt in which both ratios are within 10 % of the paper's; every number as its five runs agree
/// (digits they share, else a band; a window that differs between runs is given per run).
pub(super) fn lead_section(runs: &LeadRuns) -> String {
    let (p13, p23) = paper_ratios();
    let paper = crate::paper::plate_table::PAPER_TABLE.map(|(_, v)| v);
    let mut s = format!(
        "\n### The best lead: Δt = h/2 = {}, T = {}\n\n20×20 Q1 cells, Crank–Nicolson, Δt = {}, T = {} (the end of the first contact phase; both were added to the sweep). \
         Ratios mod1/mod3 and mod2/mod3 (paper {} and {}) and scale (ours/paper per mass); each value the same to the digits shown in five runs from u⁰ perturbed by ≤ {:e}:\n\n\
         | u⁰ | Mod1 | Mod2 | Mod3 | mod1/mod3 | mod2/mod3 | ours/paper |\n|---|---|---|---|---|---|---|\n",
        fmt_f64(LEAD_DT),
        fmt_f64(LEAD_END),
        fmt_f64(LEAD_DT),
        fmt_f64(LEAD_END),
        sig(p13, 3),
        sig(p23, 3),
        PERTURBATION
    );
    for (k, u0) in ["(1−x)/2", "(1−x)/4"].iter().enumerate() {
        if runs.rows[k].is_none() {
            let _ = writeln!(s, "| {u0} | failed | | | | | |");
            continue;
        }
        let scale: Vec<String> = (0..3).map(|m| agreed(runs, k, |e| e[m] / paper[m])).collect();
        let _ = writeln!(
            s,
            "| {u0} | {} | {} | {} | {} | {} | {} |",
            agreed(runs, k, |e| e[0]),
            agreed(runs, k, |e| e[1]),
            agreed(runs, k, |e| e[2]),
            agreed(runs, k, |e| e[0] / e[2]),
            agreed(runs, k, |e| e[1] / e[2]),
            scale.join(", ")
        );
    }
    s.push_str(
        "\nWith u⁰ = (1−x)/2 (the paper's 1D data on its (0,1)²) this is the paper's ranking and ratios at about twice its scale; \
         u⁰ = (1−x)/4 (or, equivalently, a domain of area ¼) gives about its values, but that factor ½ contradicts the paper's \
         (0,1)×(0,1) with its 1D data: **a lead, not a reproduction**.\n",
    );
    let windows: Vec<String> = (0..runs.curves[0].len())
        .map(|i| {
            let per_run: Vec<String> = runs.curves.iter().map(|c| window(&c[i].1)).collect();
            let w = if per_run.iter().all(|w| *w == per_run[0]) {
                per_run[0].clone()
            } else {
                format!("differs between the runs ({})", per_run.join(" / "))
            };
            format!("Δt = {}: {w}", fmt_f64(runs.curves[0][i].0))
        })
        .collect();
    let _ = writeln!(
        s,
        "\nIts sensitivity (`{LEAD_FIGURE}.png`, `.csv`; the 1D bar with h = 0.05, which the Q1 plate with y-independent data equals to round-off; \
         the same in five runs from U⁰ perturbed by ≤ {:e}): \
         grid times T in [{}, {}] at which both ratios are within 10 % of the paper's, for Δt within ±20 % of h/2: {}.\n\n![{LEAD_FIGURE}]({LEAD_FIGURE}.png)\n",
        PERTURBATION,
        fmt_f64(SENS_T.0),
        fmt_f64(SENS_T.1),
        windows.join("; ")
    );
    s
}
