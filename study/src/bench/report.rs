//! Files of `massredist bench`: CSV of the sweep, Markdown tables (rates, performance), the
//! work–precision figure (log–log error against run time, PNG and SVG), and the report that
//! gathers them. Only formatting and drawing; the numbers come from [`super::sweep`] and
//! [`super::perf`].

use super::sweep::{CaseResult, Rates};
use crate::plot::{draw_log_legend, log_log_chart};
use massredist::output::fmt_f64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// The sweep as CSV, one row per run.
pub fn results_csv(results: &[CaseResult]) -> String {
    let mut s = String::from(
        "scheme,mass,elements,h,dt_divisor,dt,steps,linf_l2_error,linf_l2_error_relative,max_contact_error,energy_spread,wall_seconds,ns_per_node_step,status,failure\n",
    );
    for r in results {
        let f = |x: f64| if x.is_nan() { String::new() } else { fmt_f64(x) };
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.scheme,
            r.mass,
            r.elements,
            f(r.h),
            r.dt_divisor,
            f(r.dt),
            r.steps,
            f(r.linf_l2_error),
            f(r.linf_l2_error_relative),
            f(r.max_contact_error),
            f(r.energy_spread),
            f(r.wall_seconds),
            f(r.ns_per_node_step),
            r.status,
            r.failure.as_deref().unwrap_or("").replace(',', ";"),
        );
    }
    s
}

fn rate(x: Option<f64>) -> String {
    x.map_or("–".into(), |v| format!("{v:.2}"))
}

/// The observed rates as a Markdown table.
pub fn rates_markdown(rates: &[Rates], finest_m: usize, divisors: &[usize]) -> String {
    let (lo, hi) = (divisors.iter().min().copied().unwrap_or(1), divisors.iter().max().copied().unwrap_or(1));
    let fit_from = rates.first().map_or(0, |r| r.fit_from);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Observed convergence rates (least-squares slopes of log error against log h or log Δt; space fits over m ≥ {fit_from}, \
         time fits at m = {finest_m} over Δt = h/{lo} … h/{hi}). L∞(L²) is max_n ‖u_h(t_n) − u(t_n)‖_L²(0,1) over one period; \
         contact is max_n |u_0ⁿ − u(0,t_n)|.\n"
    );
    let _ = writeln!(
        s,
        "| scheme | mass | L∞(L²) vs h, Δt = h/{lo} | L∞(L²) vs h, Δt = h/{hi} | contact vs h, Δt = h/{lo} | L∞(L²) vs Δt, m = {finest_m} | finest L∞(L²) error |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|");
    for r in rates {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {:.2e} |",
            r.scheme,
            r.mass,
            rate(r.l2_space),
            rate(r.l2_space_fine_dt),
            rate(r.contact_space),
            rate(r.l2_time),
            r.finest_l2_error
        );
    }
    s
}

/// Colours per scheme (tab10), fixed by position in [`super::sweep::scheme_cases`].
const COLOURS: [(u8, u8, u8); 6] =
    [(31, 119, 180), (23, 190, 207), (44, 160, 44), (214, 39, 40), (148, 103, 189), (140, 86, 75)];

/// One curve of the figure: (scheme index, dt divisor, points (seconds, error)).
struct Line<'a> {
    scheme: usize,
    label: &'a str,
    divisor_rank: usize,
    points: Vec<(f64, f64)>,
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    lines: &[Line],
    x: (f64, f64),
    y: (f64, f64),
    divisors: &[usize],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let mut chart = log_log_chart(area, title, x, y, ("run time [s]", "L∞(0,T; L²) error"), false)?;
    for l in lines {
        let (r, g, b) = COLOURS[l.scheme % COLOURS.len()];
        let colour = RGBColor(r, g, b);
        let style = colour.stroke_width(2);
        let pts = l.points.clone();
        let series = match l.divisor_rank {
            0 => chart.draw_series(LineSeries::new(pts.clone(), style)).map_err(e)?,
            1 => chart.draw_series(DashedLineSeries::new(pts.clone(), 8, 4, style)).map_err(e)?,
            _ => chart.draw_series(DashedLineSeries::new(pts.clone(), 2, 4, style)).map_err(e)?,
        };
        if l.divisor_rank == 0 {
            series
                .label(l.label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
        }
        chart.draw_series(pts.iter().map(|&p| Circle::new(p, 2, colour.filled()))).map_err(e)?;
    }
    let _ = divisors;
    draw_log_legend(&mut chart, SeriesLabelPosition::UpperRight, 13.0)?;
    Ok(())
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    results: &[CaseResult],
    schemes: &[&str],
    masses: &[&str],
    divisors: &[usize],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let styles: Vec<&str> = ["solid", "dashed", "dotted"].into_iter().take(divisors.len().min(3)).collect();
    let note = divisors
        .iter()
        .zip(styles.iter().chain(std::iter::repeat(&"dotted")))
        .map(|(d, s)| format!("Δt = h/{d}: {s}"))
        .collect::<Vec<_>>()
        .join(", ");
    let title = format!(
        "Work–precision on the impacting bar (T = 3, m = 6 … {}); {note}",
        results.iter().map(|r| r.elements).max().unwrap_or(0)
    );
    let (top, body) = root.split_vertically(34);
    top.titled(&title, ("sans-serif", 18)).map_err(e)?;
    let ok: Vec<&CaseResult> =
        results.iter().filter(|r| r.failure.is_none() && r.linf_l2_error > 0.0 && r.wall_seconds > 0.0).collect();
    let span = |v: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = v.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
        if lo.is_finite() { (lo / 1.5, hi * 1.5) } else { (1e-6, 1.0) }
    };
    let x = span(&mut ok.iter().map(|r| r.wall_seconds));
    let y = span(&mut ok.iter().map(|r| r.linf_l2_error));
    let cols = 2;
    let rows = masses.len().div_ceil(cols);
    let areas = body.split_evenly((rows, cols));
    for (area, mass) in areas.iter().zip(masses) {
        let mut lines = Vec::new();
        for (si, scheme) in schemes.iter().enumerate() {
            for (rank, d) in divisors.iter().enumerate() {
                let mut pts: Vec<(usize, f64, f64)> = ok
                    .iter()
                    .filter(|r| r.scheme == *scheme && r.mass == *mass && r.dt_divisor == *d)
                    .map(|r| (r.elements, r.wall_seconds, r.linf_l2_error))
                    .collect();
                pts.sort_by_key(|p| p.0);
                if !pts.is_empty() {
                    lines.push(Line {
                        scheme: si,
                        label: scheme,
                        divisor_rank: rank.min(2),
                        points: pts.iter().map(|p| (p.1, p.2)).collect(),
                    });
                }
            }
        }
        panel(area, &format!("mass {mass}"), &lines, x, y, divisors)?;
    }
    root.present().map_err(e)?;
    Ok(())
}

/// Draws the work–precision figure (one panel per mass, one colour per scheme, one line style
/// per Δt/h; points along a line are the meshes m) to `path` (.png or .svg).
pub fn work_precision_figure(
    path: &Path,
    results: &[CaseResult],
    schemes: &[&str],
    masses: &[&str],
    divisors: &[usize],
) -> Result<(), String> {
    let size = (1400, 1100);
    let svg = path.extension().is_some_and(|e| e == "svg");
    let r = if svg {
        draw(SVGBackend::new(path, size).into_drawing_area(), results, schemes, masses, divisors)
    } else {
        draw(BitMapBackend::new(path, size).into_drawing_area(), results, schemes, masses, divisors)
    };
    r.map_err(|m| format!("cannot draw {}: {m}", path.display()))
}
