//! The Hertz limit's outputs ([`super::hertz`]): `hertz.csv` (one row per mesh), the figure
//! `hertz-pressure` (the nodal contact pressure against Hertz's ellipse p₀√(1 − x²/a²), one
//! curve per mesh) and the report section. Pure: strings and figure data from the results.

use super::figures::FigureFile;
use super::hertz::{DT, END, HertzResult, RAMP, TARGET_A, load_density, plane_strain_modulus};
use crate::plot::{Curve, Figure, Panel, Style};
use massredist::output::fmt_f64;
use std::fmt::Write as _;

/// The section's table file and figure stem.
pub const HERTZ_TABLE: &str = "hertz.csv";
pub const HERTZ_PRESSURE: &str = "hertz-pressure";

/// Header of `hertz.csv`.
pub const HERTZ_COLUMNS: [&str; 15] = [
    "h_contact",
    "unknowns",
    "load",
    "hertz_a",
    "half_width",
    "half_width_resolution",
    "half_width_error",
    "hertz_p0",
    "peak_pressure",
    "peak_pressure_error",
    "active_nodes",
    "contact_force",
    "force_balance",
    "kinetic_final",
    "kinetic_max",
];

/// |ΣR − F|/F: 0 at rest.
fn balance(r: &HertzResult) -> f64 {
    (r.contact_force - r.load).abs() / r.load
}

/// The rows of `hertz.csv`, full precision.
pub(super) fn hertz_csv_rows(results: &[HertzResult]) -> Vec<Vec<String>> {
    results
        .iter()
        .map(|r| {
            vec![
                fmt_f64(r.h),
                r.unknowns.to_string(),
                fmt_f64(r.load),
                fmt_f64(r.hertz_a),
                fmt_f64(r.half_width),
                fmt_f64(r.edge_resolution),
                fmt_f64(r.half_width_error()),
                fmt_f64(r.hertz_p0),
                fmt_f64(r.peak),
                fmt_f64(r.peak_error()),
                r.active.to_string(),
                fmt_f64(r.contact_force),
                fmt_f64(balance(r)),
                fmt_f64(r.kinetic),
                fmt_f64(r.kinetic_max),
            ]
        })
        .collect()
}

/// Hertz's ellipse p₀√(1 − x²/a²) on |x| ≤ a, and 0 out to 2a.
fn ellipse(a: f64, p0: f64) -> Vec<(f64, f64)> {
    let n = 200;
    (0..=n)
        .map(|k| {
            let x = -2.0 * a + 4.0 * a * k as f64 / n as f64;
            (x, p0 * (1.0 - (x / a).powi(2)).max(0.0).sqrt())
        })
        .collect()
}

/// `hertz-pressure`: one panel, a curve per mesh and Hertz's ellipse of the finest mesh's load
/// (the loads differ by the meshes' areas, below 1e-6 relative); its CSV in long form
/// (h, x, p, Hertz's p at x).
pub(super) fn hertz_figure(results: &[HertzResult]) -> FigureFile {
    let mut curves: Vec<Curve> = results
        .iter()
        .enumerate()
        .map(|(k, r)| Curve {
            label: format!("h = {}", fmt_f64(r.h)),
            points: r.profile.clone(),
            style: Style::Numeric(k),
        })
        .collect();
    let (a, p0) = results.last().map_or((TARGET_A, 1.0), |r| (r.hertz_a, r.hertz_p0));
    curves.push(Curve { label: "Hertz".into(), points: ellipse(a, p0), style: Style::Exact });
    let panel = Panel {
        title: "contact pressure R_i/a_i at rest".into(),
        x_label: "x".into(),
        y_label: "p".into(),
        curves,
        x_range: Some((-2.0 * a, 2.0 * a)),
        y_range: Some((0.0, 1.15 * p0)),
    };
    let title = format!("Hertz limit: GetFEM's disc pressed by F = {:.4} (a/R = 0.1), P2, backward Euler to rest", {
        results.last().map_or(f64::NAN, |r| r.load)
    });
    let figure = Figure { title, columns: 1, panels: vec![panel], panel_size: (900, 560) };
    let header = ["h_contact", "x", "pressure", "hertz_pressure"].map(String::from).to_vec();
    let rows = results
        .iter()
        .flat_map(|r| {
            r.profile.iter().map(move |&(x, p)| {
                let hp = r.hertz_p0 * (1.0 - (x / r.hertz_a).powi(2)).max(0.0).sqrt();
                vec![fmt_f64(r.h), fmt_f64(x), fmt_f64(p), fmt_f64(hp)]
            })
        })
        .collect();
    FigureFile { stem: HERTZ_PRESSURE.into(), figure, header, rows, periods: None }
}

/// `x` to 4 significant digits, or as a percentage with 2 decimals when `pct`.
fn s4(x: f64, pct: bool) -> String {
    if pct { format!("{:+.2} %", 100.0 * x) } else { crate::paper::sig(x, 4) }
}

/// The report section: the table per mesh and the figure.
pub(super) fn hertz_section(results: &[HertzResult]) -> String {
    let mut s = format!(
        "\n### The Hertz limit: the disc pressed onto the plane until at rest\n\n\
         The disc above in plane strain (E* = E/(1 − ν²) = {}), under the volume force (0, −g·min((t + Δt)/{}, 1)), g = {} \
         (F = g|Ω| = π a² E*/(4R) for Hertz's a = {TARGET_A}, a/R = 0.1: Hertz's corrections are of relative order (a/R)² = 1 %), \
         backward Euler, standard mass, Δt = {}, T = {}, on P2 meshes of size h within distance 3 of the contact point (growing to 4 at \
         distance 15). Hertz: a = 2√(F R/(π E*)), p₀ = 2F/(π a). Measured at T: a_h from the contact nodes (each edge at the midpoint of \
         the outermost node with R_i > 0 and the next one; ± the resolution, half their spacing), p_h = max_i R_i/a_i. At rest: ½VᵀMV at T \
         (against its largest value over the run) and |ΣR − F|/F, zero at rest (1ᵀK = 0 on the vertical motion of a free body). (`{HERTZ_TABLE}`)\n\n\
         | h near contact | unknowns | Hertz a | a_h | ± resolution | a_h vs a | Hertz p₀ | p_h | p_h vs p₀ | nodes in contact | \\|ΣR − F\\|/F | ½VᵀMV at T (max) |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
        s4(plane_strain_modulus(), false),
        fmt_f64(RAMP),
        s4(load_density(), false),
        fmt_f64(DT),
        fmt_f64(END),
    );
    for r in results {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.1e} | {:.1e} ({:.1e}) |",
            fmt_f64(r.h),
            r.unknowns,
            s4(r.hertz_a, false),
            s4(r.half_width, false),
            s4(r.edge_resolution, false),
            s4(r.half_width_error(), true),
            s4(r.hertz_p0, false),
            s4(r.peak, false),
            s4(r.peak_error(), true),
            r.active,
            balance(r),
            r.kinetic,
            r.kinetic_max,
        );
    }
    let _ = writeln!(s, "\n![{HERTZ_PRESSURE}]({HERTZ_PRESSURE}.png)");
    s
}
