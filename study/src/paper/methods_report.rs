//! The comparison of [`super::methods`] as files: CSV (one row per run and copy), Markdown tables
//! (one per problem, at the tables' mesh; round-off sensitive cases as agreed digits or bands),
//! and the work–precision figure (relative L∞(L²) error against CPU time, one panel per problem,
//! one colour per method, one marker per mass). Formatting and drawing only.

use super::band::{sig, stable_digits};
use super::methods::{METHODS, MethodResult, MethodsConfig, Metrics, PROBLEMS, Problem1d};
use massredist::output::fmt_f64;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// Column names of [`methods_csv`].
pub const METHODS_COLUMNS: [&str; 26] = [
    "problem",
    "method",
    "class",
    "mass",
    "elements",
    "dt",
    "courant",
    "steps",
    "copy",
    "status",
    "l2_error_relative",
    "impact_error",
    "duration_error",
    "rebound_ratio",
    "force_tv_ratio",
    "impulse_ratio",
    "penetration",
    "energy_drift",
    "half_step_energy_drift",
    "first_impact_time",
    "first_release_time",
    "exact_impacts",
    "cpu_seconds",
    "step_seconds",
    "stable_step",
    "stable_step_method",
];

/// Every run as CSV: one row per copy (copy 0 is the unperturbed run); a diverged or failed run
/// is one row with its status and empty numbers.
pub fn methods_csv(results: &[MethodResult]) -> String {
    let mut s = METHODS_COLUMNS.join(",") + "\n";
    let f = |x: f64| if x.is_finite() { fmt_f64(x) } else { String::new() };
    let o = |x: Option<f64>| x.map_or(String::new(), f);
    for r in results {
        let head = format!(
            "{},{},{},{},{},{},{},{}",
            r.problem,
            r.method,
            r.class.replace(',', ";"),
            r.mass,
            r.elements,
            f(r.dt),
            f(r.courant),
            r.steps
        );
        let limit = format!("{},{}", o(r.stable_step), r.stable_step_method.unwrap_or(""));
        if r.runs.is_empty() {
            let _ = writeln!(s, "{head},0,{},,,,,,,,,,,,{},,,{limit}", r.status, r.exact_impacts);
        }
        for (k, m) in r.runs.iter().enumerate() {
            let _ = writeln!(
                s,
                "{head},{k},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{limit}",
                r.status,
                f(m.l2_error),
                o(m.impact_error),
                o(m.duration_error),
                o(m.rebound),
                o(m.force_tv),
                o(m.impulse),
                f(m.penetration),
                f(m.energy_drift),
                o(m.half_step_drift),
                o(m.first_impact),
                o(m.first_release),
                r.exact_impacts,
                if k == 0 { f(r.cpu_seconds) } else { String::new() },
                if k == 0 { f(r.step_seconds) } else { String::new() }
            );
        }
    }
    s
}

/// A column over the runs of a result: the agreed digits (3 at most) or the band.
fn cell(r: &MethodResult, get: impl Fn(&Metrics) -> Option<f64>) -> String {
    let v: Vec<Option<f64>> = r.runs.iter().map(get).collect();
    if v.len() == 1 {
        return v[0].map_or("—".into(), |x| sig(x, 3));
    }
    stable_digits(&v, 3)
}

/// The exact values a problem's rows are measured against, in its units (by characteristics: a
/// free rod at V₀ hits the wall at gap/V₀, stays for D = 2L/c under the force ρcV₀ per unit
/// section, and leaves at V₀; the paper's bar, §4.1: contact on [L, 2L] of each period 3L/c).
fn exact_values(p: &Problem1d) -> String {
    let c = p.c();
    match p.v0 {
        Some(v0) => format!(
            "Exact: impact at gap/V₀ = {}, contact D = 2L/c = {}, force ρcV₀ = {} per unit section, rebound V₀ = {} \
             (L = {}, ρ = {}, E = {}, gap = {}).",
            sig(p.gap / v0, 4),
            sig(2.0 * p.length / c, 4),
            sig(p.density * c * v0, 4),
            sig(v0, 4),
            sig(p.length, 4),
            sig(p.density, 4),
            sig(p.modulus, 4),
            sig(p.gap, 4)
        ),
        None => format!(
            "Exact (§4.1): contact on [L/c, 2L/c] = [{}, {}] of each period 3L/c, force −E/2 = {}.",
            sig(p.length / c, 4),
            sig(2.0 * p.length / c, 4),
            sig(-p.modulus / 2.0, 4)
        ),
    }
}

/// One Markdown table per problem at `config.table_elements`.
pub fn methods_tables(config: &MethodsConfig, results: &[MethodResult]) -> String {
    let mut s = String::new();
    for p in &PROBLEMS {
        let rows: Vec<&MethodResult> = results
            .iter()
            .filter(|r| r.problem == p.key && r.elements == config.table_elements && !r.in_sweep && !r.own)
            .collect();
        let impacts = rows.first().map_or(0, |r| r.exact_impacts);
        let _ = writeln!(
            s,
            "### {} (m = {}, Δt = h/c implicit, 0.9 Δt_c explicit)\n\n{}\n\n\
             | method | class | mass | cΔt/h | cΔt_c/h (estimator) | L∞(L²) rel. | impact err./D | duration err./D | rebound v̄/V₀ | force TV / exact | impulse / exact | penetration/L | energy drift ({impacts} impacts) | half-step drift (Verlet) | CPU s | of which steps |\n\
             |---|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
            p.title,
            config.table_elements,
            exact_values(p)
        );
        for r in rows {
            let limit = match (r.stable_step, r.stable_step_method) {
                (Some(l), Some(by)) => format!("{} ({by})", sig(l * r.courant / r.dt, 6)),
                _ => "—".into(),
            };
            let head = format!("| {} | {} | {} | {} | {limit} ", r.method, r.class, r.mass, sig(r.courant, 3));
            if r.runs.is_empty() {
                let why = r.failure.as_deref().unwrap_or("").replace('|', "/");
                let _ = writeln!(s, "{head}| {} ({why}) | | | | | | | | | | |", r.status);
                continue;
            }
            let _ = writeln!(
                s,
                "{head}| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2e} | {:.2e} |",
                cell(r, |m| Some(m.l2_error)),
                cell(r, |m| m.impact_error),
                cell(r, |m| m.duration_error),
                cell(r, |m| m.rebound),
                cell(r, |m| m.force_tv),
                cell(r, |m| m.impulse),
                cell(r, |m| Some(m.penetration)),
                cell(r, |m| Some(m.energy_drift)),
                cell(r, |m| m.half_step_drift),
                r.cpu_seconds,
                r.step_seconds
            );
        }
        let _ = writeln!(s);
    }
    s
}

/// The implicit classes' Δt sweep (issue 32, item 4): per problem, every implicit method and
/// mass at cΔt/h = 1 and each multiple of [`MethodsConfig::sweep`] on the tables' mesh, its
/// L∞(L²) error and CPU seconds, beside central differences at 0.9 Δt_c (and Courant 1) on the
/// same mesh: a work–precision comparison at a fixed mesh. Empty without a sweep.
pub fn sweep_tables(config: &MethodsConfig, results: &[MethodResult]) -> String {
    if config.sweep.is_empty() {
        return String::new();
    }
    let mut multiples = vec![1.0];
    multiples.extend(&config.sweep);
    let head: Vec<String> = multiples.iter().map(|k| format!("cΔt/h = {}", sig(*k, 3))).collect();
    let mut s = format!(
        "## The implicit classes against Δt (m = {})\n\n\
         Each cell: relative L∞(L²) error, then CPU seconds (set-up and stepping, as above). The explicit rows run at \
         their one step (0.9 Δt_c, or Courant 1 for \"CD c=1\"), in the first column.\n",
        config.table_elements
    );
    for p in &PROBLEMS {
        let _ = write!(
            s,
            "\n### {}\n\n| method | mass | {} |\n|---|---|{}\n",
            p.title,
            head.join(" | "),
            "---:|".repeat(multiples.len())
        );
        let at = |r: &&MethodResult| r.problem == p.key && r.elements == config.table_elements && !r.own;
        for m in METHODS {
            for &mass in m.masses {
                let runs: Vec<&MethodResult> =
                    results.iter().filter(at).filter(|r| r.method == m.label && r.mass == mass).collect();
                let cells: Vec<String> = if m.implicit() {
                    multiples
                        .iter()
                        .map(|k| {
                            let r = runs.iter().find(|r| (r.courant - k).abs() <= 1e-9 * k);
                            r.map_or("—".into(), |r| sweep_cell(r))
                        })
                        .collect()
                } else {
                    let mut c = vec![runs.first().map_or("—".into(), |r| sweep_cell(r))];
                    c.resize(multiples.len(), String::new());
                    c
                };
                let _ = writeln!(s, "| {} | {mass} | {} |", m.label, cells.join(" | "));
            }
        }
    }
    s
}

/// Every method at a benchmark's own discretisation ([`super::methods::Problem1d::own`]; issue
/// 32, item 7: ANSYS VM265's 20 elements and Δt = 2.226e-6 s): the contact window read off the
/// force, its errors against the exact one, and the L∞(L²) error. A scheme whose Δt_c lies below
/// the benchmark's Δt says so. Empty without such runs.
pub fn own_tables(results: &[MethodResult]) -> String {
    let mut s = String::new();
    for p in PROBLEMS.iter() {
        let Some((elements, dt)) = p.own else { continue };
        let rows: Vec<&MethodResult> = results.iter().filter(|r| r.problem == p.key && r.own).collect();
        if rows.is_empty() {
            continue;
        }
        let _ = write!(
            s,
            "\n## {} at the benchmark's own discretisation (m = {elements}, Δt = {dt:e})\n\n\
             Every method at the benchmark's own mesh and step, whatever its usual rule; {} The contact window is \
             [first t_n with λ < 0, first later t_n with λ = 0], read off the force.\n\n\
             | method | mass | cΔt/h | cΔt_c/h | contact window | impact err./D | duration err./D | impulse / exact | force TV / exact | L∞(L²) rel. |\n\
             |---|---|---:|---:|---|---:|---:|---:|---:|---:|\n",
            p.title,
            exact_values(p)
        );
        for r in rows {
            let limit = r.stable_step.map_or("—".into(), |l| sig(l * r.courant / r.dt, 6));
            if r.runs.is_empty() {
                // Refused or failed at set-up (no step taken: no cΔt/h of its own).
                let why = r.failure.as_deref().unwrap_or("").replace('|', "/");
                let courant = sig(dt * p.c() * elements as f64 / p.length, 4);
                let _ =
                    writeln!(s, "| {} | {} | {courant} | {limit} | {} ({why}) | | | | | |", r.method, r.mass, r.status);
                continue;
            }
            let _ = writeln!(
                s,
                "| {} | {} | {} | {limit} | [{}, {}] | {} | {} | {} | {} | {} |",
                r.method,
                r.mass,
                sig(r.courant, 4),
                cell(r, |m| m.first_impact),
                cell(r, |m| m.first_release),
                cell(r, |m| m.impact_error),
                cell(r, |m| m.duration_error),
                cell(r, |m| m.impulse),
                cell(r, |m| m.force_tv),
                cell(r, |m| Some(m.l2_error)),
            );
        }
    }
    s
}

/// A sweep cell: the error over the runs, then the CPU seconds (or the run's status).
fn sweep_cell(r: &MethodResult) -> String {
    if r.runs.is_empty() {
        return r.status.into();
    }
    format!("{} ({:.2e} s)", cell(r, |m| Some(m.l2_error)), r.cpu_seconds)
}

/// Colours per method, by position in [`METHODS`] (tab20; one each while there are at most 20).
const COLOURS: [(u8, u8, u8); 20] = [
    (31, 119, 180),
    (174, 199, 232),
    (255, 127, 14),
    (255, 187, 120),
    (44, 160, 44),
    (152, 223, 138),
    (214, 39, 40),
    (255, 152, 150),
    (148, 103, 189),
    (197, 176, 213),
    (140, 86, 75),
    (196, 156, 148),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
    (219, 219, 141),
    (158, 218, 229),
    (199, 199, 199),
    (247, 182, 210),
];

const MASSES: [&str; 4] = ["standard", "mod1", "mod2", "mod3"];

/// (method index, mass index, points (cpu, error) along the meshes) of one problem.
fn lines(results: &[MethodResult], problem: &str) -> Vec<(usize, usize, Vec<(f64, f64)>)> {
    let mut out = Vec::new();
    for (mi, m) in METHODS.iter().enumerate() {
        for (ki, mass) in MASSES.iter().enumerate() {
            let mut pts: Vec<(usize, f64, f64)> = results
                .iter()
                .filter(|r| r.problem == problem && r.method == m.label && r.mass == *mass && !r.in_sweep && !r.own)
                .filter_map(|r| {
                    // The largest error over the copies (a sensitive case's worst run).
                    let e = r.runs.iter().map(|x| x.l2_error).fold(f64::NAN, f64::max);
                    (e > 0.0 && r.cpu_seconds > 0.0).then_some((r.elements, r.cpu_seconds, e))
                })
                .collect();
            pts.sort_by_key(|p| p.0);
            if !pts.is_empty() {
                out.push((mi, ki, pts.iter().map(|p| (p.1, p.2)).collect()));
            }
        }
    }
    out
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    results: &[MethodResult],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (top, body) = root.split_vertically(34);
    top.titled(
        "Work–precision of the method classes: relative L∞(L²) error against CPU time (Δt = h/c, explicit 0.9 Δt_c; \
         markers: ● standard ▲ mod1 ■ mod2 ✚ mod3)",
        ("sans-serif", 16),
    )
    .map_err(e)?;
    let areas = body.split_evenly((2, 2));
    for (area, p) in areas.iter().zip(&PROBLEMS) {
        let ls = lines(results, p.key);
        let span = |f: &dyn Fn(&(f64, f64)) -> f64| {
            let (lo, hi) = ls
                .iter()
                .flat_map(|l| l.2.iter().map(f))
                .fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
            if lo.is_finite() && lo > 0.0 { (lo / 1.5, hi * 1.5) } else { (1e-6, 1.0) }
        };
        let (x, y) = (span(&|q| q.0), span(&|q| q.1));
        let mut chart =
            crate::plot::log_log_chart(area, p.title, x, y, ("CPU time [s]", "relative L∞(L²) error"), false)?;
        let mut labelled = vec![false; METHODS.len()];
        for (mi, ki, pts) in &ls {
            let (r, g, b) = COLOURS[mi % COLOURS.len()];
            let colour = RGBColor(r, g, b);
            let series = chart.draw_series(LineSeries::new(pts.clone(), colour.stroke_width(1))).map_err(e)?;
            if !labelled[*mi] {
                labelled[*mi] = true;
                series
                    .label(METHODS[*mi].label)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(3)));
            }
            let style = colour.filled();
            match ki {
                0 => chart.draw_series(pts.iter().map(|&q| Circle::new(q, 3, style))).map_err(e)?,
                1 => chart.draw_series(pts.iter().map(|&q| TriangleMarker::new(q, 4, style))).map_err(e)?,
                2 => chart
                    .draw_series(pts.iter().map(|&q| EmptyElement::at(q) + Rectangle::new([(-3, -3), (3, 3)], style)))
                    .map_err(e)?,
                _ => chart.draw_series(pts.iter().map(|&q| Cross::new(q, 4, colour.stroke_width(2)))).map_err(e)?,
            };
        }
        crate::plot::draw_log_legend(&mut chart, SeriesLabelPosition::LowerLeft, 11.0)?;
    }
    root.present().map_err(e)
}

/// Draws the work–precision figure to `path` (.png or .svg).
pub fn methods_figure(path: &Path, results: &[MethodResult]) -> Result<(), String> {
    let size = (1500, 1200);
    let r = if path.extension().is_some_and(|e| e == "svg") {
        draw(SVGBackend::new(path, size).into_drawing_area(), results)
    } else {
        draw(BitMapBackend::new(path, size).into_drawing_area(), results)
    };
    r.map_err(|m| format!("cannot draw {}: {m}", path.display()))
}

/// The report's prose and tables (`reproduce`'s section and `bench --methods`' report).
pub fn methods_markdown(config: &MethodsConfig, results: &[MethodResult], figure: &str) -> String {
    let mut s = String::new();
    let failed: Vec<String> = results
        .iter()
        .filter(|r| r.status != "ok")
        .map(|r| {
            format!(
                "- {} / {} / {} m = {}: {} ({})",
                r.problem,
                r.method,
                r.mass,
                r.elements,
                r.status,
                r.failure.as_deref().unwrap_or("")
            )
        })
        .collect();
    let _ = writeln!(
        s,
        "Every method class of issue 20 ({} methods × their masses) on four 1D problems with exact solutions by \
         characteristics; meshes m = {:?}. Δt = h/c for the implicit classes; every explicit run steps at one safety \
         factor, Δt = 0.9 Δt_c, with Δt_c from the estimator its row names (Lanczos, run to convergence); \
         \"CD c=1\" is the special case of these uniform meshes, central differences at Courant 1 (h/c), the \
         characteristic step, which lies below Δt_c only for mod3. Central differences use the lumped mass, the \
         implicit schemes the consistent one. \
         Penalty κ = factor · E/h (\"pen 1\", \"pen 100\"; the explicit \"pen 0.29\" is sized to keep 0.99 Δt_c on \
         the standard mass, `KEPT_STEP_PENALTY`). D is the exact first contact's duration; the energy drift \
         is (E(T) − E(0))/E(0) of each scheme's own energy. CPU time is set-up (factorisations; for central \
         differences the stable limit: Lanczos, full reorthogonalisation, to convergence) and stepping, fastest of up \
         to 3 runs; \"of which steps\" is the stepping alone. Standard-mass and Paoli–Schatzman runs are repeated from \
         4 perturbed U⁰ and V⁰ (|δ| ≤ 1e-13 relative, and on V⁰ absolute times V₀, or c/2 on the paper's bar): their cells show only the digits all 5 runs share, else the band min–max \
         (src/paper/methods.rs documents every column).\n\n![work–precision]({figure})\n",
        METHODS.len(),
        config.elements
    );
    s += &methods_tables(config, results);
    s += &sweep_tables(config, results);
    s += &own_tables(results);
    if !failed.is_empty() {
        let _ = writeln!(s, "Runs that diverged or failed:\n\n{}\n", failed.join("\n"));
    }
    s
}

/// The files of the comparison in a `reproduce` folder, in the order written.
pub const METHODS_FILES: [&str; 3] = ["methods.csv", "methods-work-precision.png", "methods-work-precision.svg"];

/// Writes [`METHODS_FILES`] into `dir`.
pub fn write_methods_files(dir: &Path, results: &[MethodResult]) -> std::io::Result<()> {
    std::fs::write(dir.join(METHODS_FILES[0]), methods_csv(results))?;
    for f in &METHODS_FILES[1..] {
        methods_figure(&dir.join(f), results).map_err(std::io::Error::other)?;
    }
    Ok(())
}

/// `reproduce`'s section: a heading and [`methods_markdown`].
pub fn methods_section(config: &MethodsConfig, results: &[MethodResult]) -> String {
    format!(
        "\n## Beyond the paper: every method class side by side (issue 20)\n\n`massredist bench --methods` runs the same \
         comparison on finer meshes (m up to 400).\n\n{}",
        methods_markdown(config, results, METHODS_FILES[1])
    )
}
