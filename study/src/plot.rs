//! Line charts for `massredist reproduce`: a [`Figure`] (panels of curves) in, PNG or SVG out.
//!
//! This is an edge module: it only draws data it is given (plotters, PNG through the bitmap
//! backend, SVG through the SVG backend) and computes nothing about the problem. The pure helpers
//! ([`clip_polyline`], [`data_range`], [`tick_decimals`]) are unit-tested.
//!
//! Exact solutions are drawn as thick black dashed lines on top of the numerical curves, so they
//! stay visible where a numerical curve coincides with them. Colours are fixed per
//! [`Style::Numeric`] index, so one mass has the same colour in every figure.

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor;
use std::path::Path;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum PlotError {
    #[error("cannot draw {path}: {message}")]
    Draw { path: String, message: String },
}

/// How a curve is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// The exact solution: thick, black, dashed, drawn last.
    Exact,
    /// A numerical curve in colour `PALETTE[i % PALETTE.len()]`.
    Numeric(usize),
}

/// Colours of numerical curves (the "tab10" colours: distinguishable, also in grey print).
pub const PALETTE: [(u8, u8, u8); 6] =
    [(148, 103, 189), (31, 119, 180), (255, 127, 14), (214, 39, 40), (44, 160, 44), (140, 86, 75)];

#[derive(Debug, Clone)]
pub struct Curve {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
}

#[derive(Debug, Clone)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub curves: Vec<Curve>,
    /// Axis ranges; `None` takes the range of the data (padded). Curves are clipped to them.
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
}

/// A figure: a title, one legend row for all panels (each distinct label once, in order of
/// appearance, so panels stay uncovered), and a grid of panels.
#[derive(Debug, Clone)]
pub struct Figure {
    pub title: String,
    pub panels: Vec<Panel>,
    /// Panels per row.
    pub columns: usize,
    /// Size in pixels of one panel.
    pub panel_size: (u32, u32),
}

/// Heights in pixels of the title band and of the legend band below it.
const TITLE_BAND: u32 = 40;
const LEGEND_BAND: u32 = 30;

impl Figure {
    fn rows(&self) -> usize {
        self.panels.len().div_ceil(self.columns.max(1))
    }

    /// Total size in pixels.
    pub fn size(&self) -> (u32, u32) {
        let (w, h) = self.panel_size;
        (w * self.columns.max(1) as u32, h * self.rows() as u32 + TITLE_BAND + LEGEND_BAND)
    }
}

/// Writes the figure as a PNG.
pub fn write_png(figure: &Figure, path: &Path) -> Result<(), PlotError> {
    let root = BitMapBackend::new(path, figure.size()).into_drawing_area();
    draw(&root, figure, Joins::Split).and_then(|()| root.present()).map_err(|e| err(path, e))
}

/// Writes the figure as an SVG.
pub fn write_svg(figure: &Figure, path: &Path) -> Result<(), PlotError> {
    let root = SVGBackend::new(path, figure.size()).into_drawing_area();
    draw(&root, figure, Joins::Path).and_then(|()| root.present()).map_err(|e| err(path, e))
}

fn err(path: &Path, e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw { path: path.display().to_string(), message: e.to_string() }
}

fn stroke(style: Style) -> ShapeStyle {
    match style {
        Style::Exact => BLACK.stroke_width(3),
        Style::Numeric(i) => {
            let (r, g, b) = PALETTE[i % PALETTE.len()];
            RGBColor(r, g, b).stroke_width(2)
        }
    }
}

/// Dash length and gap of exact curves, in pixels.
const DASH: (u32, u32) = (12, 7);

/// How wide numerical curves are drawn. The bitmap backend strokes a wide polyline as polygons
/// with mitred joins, and a spike that turns back on itself within a pixel (λ at an impact) gets
/// a miter running off the image; drawing each segment on its own has no joins. SVG renderers
/// handle joins themselves, and one path per curve keeps the file small.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Joins {
    Path,
    Split,
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    figure: &Figure,
    joins: Joins,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let (w, _) = figure.size();
    let (top, rest) = root.split_vertically(TITLE_BAND);
    let (legend, body) = rest.split_vertically(LEGEND_BAND);
    let centered = |size: u32| {
        TextStyle::from(("sans-serif", size).into_font())
            .pos(text_anchor::Pos::new(text_anchor::HPos::Center, text_anchor::VPos::Center))
    };
    top.draw_text(&figure.title, &centered(21), (w as i32 / 2, TITLE_BAND as i32 / 2))?;
    draw_legend(&legend, figure, w)?;
    let areas = body.split_evenly((figure.rows(), figure.columns.max(1)));
    for (panel, area) in figure.panels.iter().zip(&areas) {
        draw_panel(area, panel, joins)?;
    }
    Ok(())
}

/// One centred row: a line sample and the label of each distinct curve.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    figure: &Figure,
    width: u32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let mut entries: Vec<(&str, Style)> = Vec::new();
    for c in figure.panels.iter().flat_map(|p| &p.curves) {
        if !entries.iter().any(|(l, _)| *l == c.label) {
            entries.push((&c.label, c.style));
        }
    }
    let font = TextStyle::from(("sans-serif", 15).into_font());
    let (sample, gap, sep) = (30i32, 6i32, 26i32);
    let widths: Vec<i32> = entries
        .iter()
        .map(|(l, _)| area.estimate_text_size(l, &font).map(|(tw, _)| tw as i32))
        .collect::<Result<_, _>>()?;
    let total: i32 = widths.iter().map(|tw| sample + gap + tw).sum::<i32>() + sep * (entries.len() as i32 - 1).max(0);
    let y = LEGEND_BAND as i32 / 2;
    let mut x = (width as i32 - total).max(0) / 2;
    let text = font.pos(text_anchor::Pos::new(text_anchor::HPos::Left, text_anchor::VPos::Center));
    for ((label, style), tw) in entries.iter().zip(&widths) {
        let line = vec![(x, y), (x + sample, y)];
        match style {
            Style::Exact => area.draw(&DashedPathElement::new(line, 8, 4, stroke(*style)))?,
            Style::Numeric(_) => area.draw(&PathElement::new(line, stroke(*style)))?,
        }
        area.draw_text(label, &text, (x + sample + gap, y))?;
        x += sample + gap + tw + sep;
    }
    Ok(())
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    p: &Panel,
    joins: Joins,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let all = || p.curves.iter().flat_map(|c| c.points.iter().copied());
    let (x0, x1) = p.x_range.unwrap_or_else(|| data_range(all().map(|q| q.0), 0.0));
    let (y0, y1) = p.y_range.unwrap_or_else(|| data_range(all().map(|q| q.1), 0.05));
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, ("sans-serif", 17))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(86)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    let (xd, yd) = (tick_decimals(x1 - x0), tick_decimals(y1 - y0));
    chart
        .configure_mesh()
        .x_desc(&p.x_label)
        .y_desc(&p.y_label)
        .axis_desc_style(("sans-serif", 16))
        .label_style(("sans-serif", 13))
        .x_label_formatter(&|v| tick_label(*v, xd))
        .y_label_formatter(&|v| tick_label(*v, yd))
        .max_light_lines(1)
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()?;
    // Numerical curves first, exact curves on top.
    let numeric = p.curves.iter().filter(|c| c.style != Style::Exact);
    for c in numeric.chain(p.curves.iter().filter(|c| c.style == Style::Exact)) {
        let style = stroke(c.style);
        for piece in clip_polyline(&c.points, (x0, x1), (y0, y1)) {
            match c.style {
                Style::Exact => chart.draw_series(DashedLineSeries::new(piece, DASH.0, DASH.1, style))?,
                Style::Numeric(_) if joins == Joins::Split => {
                    chart.draw_series(piece.windows(2).map(|w| PathElement::new(vec![w[0], w[1]], style)))?
                }
                Style::Numeric(_) => chart.draw_series(LineSeries::new(piece, style))?,
            };
        }
    }
    Ok(())
}

/// The range of finite values, widened by `pad` × its length on both sides; a degenerate range
/// (one value, or none) is widened to a unit-relative interval so that an axis can be drawn.
pub fn data_range(values: impl Iterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (lo, hi) =
        values.filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    // No finite value: the fold leaves lo = +∞ > hi = −∞.
    if lo > hi {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    // A flat curve (span at round-off level) gets ± 1e-3 of its magnitude (or ± 1e-3 at 0).
    if span <= 1e-12 * lo.abs().max(hi.abs()) || span == 0.0 {
        let d = 1e-3 * lo.abs().max(1.0);
        return (lo - d, hi + d);
    }
    (lo - pad * span, hi + pad * span)
}

/// Decimals needed to tell apart ~10 ticks on an axis of length `span`: one more than the
/// position of the leading digit of span/10.
pub fn tick_decimals(span: f64) -> usize {
    if !(span.is_finite() && span > 0.0) {
        return 2;
    }
    let lead = (span / 10.0).log10().floor();
    if lead >= 0.0 { 0 } else { (-lead) as usize }.min(12)
}

/// A tick value with `decimals` decimals, without the "-0.00" of a value that rounds to zero.
pub fn tick_label(v: f64, decimals: usize) -> String {
    let text = format!("{v:.decimals$}");
    if text.starts_with('-') && text[1..].chars().all(|c| c == '0' || c == '.') { text[1..].to_string() } else { text }
}

/// Clips a polyline to the rectangle `[x0, x1] × [y0, y1]`: the parts inside, as separate
/// polylines (a segment that leaves and re-enters the box splits the line). Non-finite points
/// break the line. Each segment is clipped exactly (Liang–Barsky), so a curve that leaves the
/// axes ends on the boundary instead of being drawn over the margins.
pub fn clip_polyline(points: &[(f64, f64)], (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    let finite = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let inside = |p: (f64, f64)| p.0 >= x0 && p.0 <= x1 && p.1 >= y0 && p.1 <= y1;
    if points.len() == 1 && finite(&points[0]) && inside(points[0]) {
        return vec![points.to_vec()];
    }
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let clipped = if finite(&a) && finite(&b) { clip_segment(a, b, (x0, x1), (y0, y1)) } else { None };
        match clipped {
            Some((p, q)) => {
                if current.last() != Some(&p) {
                    if current.len() > 1 {
                        out.push(std::mem::take(&mut current));
                    }
                    current.clear();
                    current.push(p);
                }
                current.push(q);
                // The segment left the box: the piece ends here.
                if q != b {
                    out.push(std::mem::take(&mut current));
                }
            }
            None => {
                if current.len() > 1 {
                    out.push(std::mem::take(&mut current));
                }
                current.clear();
            }
        }
    }
    if current.len() > 1 {
        out.push(current);
    }
    // Zero-length pieces and repeated points are dropped: the bitmap backend draws a wide line
    // as a polygon from the segment's normal, which a zero-length segment does not have.
    for piece in &mut out {
        piece.dedup();
    }
    out.retain(|piece| piece.len() > 1);
    out
}

/// Liang–Barsky clipping of the segment a→b: the parameters t ∈ [0, 1] with a + t(b−a) inside
/// the box form an interval [t0, t1]; None if it is empty.
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [(-dx, a.0 - x0), (dx, x1 - a.0), (-dy, a.1 - y0), (dy, y1 - a.1)] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            (a.0 + t * dx, a.1 + t * dy)
        }
    };
    Some((at(t0), at(t1)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_polyline_inside_is_kept_whole() {
        let p = vec![(0.0, 0.0), (0.5, 0.5), (1.0, 0.0)];
        assert_eq!(clip_polyline(&p, (0.0, 1.0), (0.0, 1.0)), vec![p]);
    }

    #[test]
    fn a_spike_splits_the_line_at_the_boundary() {
        // (1, 3) is above y1 = 1: the segments to and from it are cut where they cross y = 1.
        let p = vec![(0.0, 0.0), (1.0, 3.0), (2.0, 0.0)];
        let pieces = clip_polyline(&p, (0.0, 2.0), (0.0, 1.0));
        assert_eq!(pieces.len(), 2);
        // y = 3x reaches 1 at x = 1/3; y = 3(2 − x) at x = 5/3. Exact up to one rounding of r.
        let tol = 4.0 * f64::EPSILON;
        assert_eq!(pieces[0][0], (0.0, 0.0));
        assert!((pieces[0][1].0 - 1.0 / 3.0).abs() < tol && (pieces[0][1].1 - 1.0).abs() < tol);
        assert!((pieces[1][0].0 - 5.0 / 3.0).abs() < tol && (pieces[1][0].1 - 1.0).abs() < tol);
        assert_eq!(pieces[1][1], (2.0, 0.0));
    }

    #[test]
    fn a_segment_touching_a_corner_leaves_no_zero_length_piece() {
        // (0, 0) → (1, −1) meets the box [0, 1]² only at its corner (0, 0).
        let p = vec![(-1.0, 1.0), (0.0, 0.0), (1.0, -1.0)];
        assert!(clip_polyline(&p, (0.0, 1.0), (0.0, 1.0)).is_empty());
        let q = vec![(0.5, 0.5), (0.5, 0.5), (0.7, 0.5)];
        assert_eq!(clip_polyline(&q, (0.0, 1.0), (0.0, 1.0)), vec![vec![(0.5, 0.5), (0.7, 0.5)]]);
    }

    #[test]
    fn non_finite_points_break_the_line() {
        let p = vec![(0.0, 0.0), (1.0, 0.5), (2.0, f64::NAN), (3.0, 0.5), (4.0, 0.5)];
        let pieces = clip_polyline(&p, (0.0, 4.0), (0.0, 1.0));
        assert_eq!(pieces, vec![vec![(0.0, 0.0), (1.0, 0.5)], vec![(3.0, 0.5), (4.0, 0.5)]]);
    }

    #[test]
    fn ranges_and_decimals() {
        assert_eq!(data_range([1.0, 3.0, f64::NAN].into_iter(), 0.5), (0.0, 4.0));
        let (lo, hi) = data_range([0.125, 0.125].into_iter(), 0.0);
        assert!(lo < 0.125 && hi > 0.125);
        assert_eq!(tick_decimals(3.0), 1);
        assert_eq!(tick_decimals(30.0), 0);
        assert_eq!(tick_decimals(2e-5), 6);
        assert_eq!(tick_label(-1e-17, 2), "0.00");
        assert_eq!(tick_label(-0.25, 2), "-0.25");
    }
}

/// A log–log chart on `area` in the style of the log–log figures of `bench` and `reproduce` (caption, axis descriptions, labels
/// `1e-3`…); `fine_grid` keeps the light grid lines.
pub fn log_log_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    title: &str,
    x: (f64, f64),
    y: (f64, f64),
    (x_desc, y_desc): (&str, &str),
    fine_grid: bool,
) -> Result<ChartContext<'a, DB, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>, String>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(56)
        .build_cartesian_2d((x.0..x.1).log_scale(), (y.0..y.1).log_scale())
        .map_err(e)?;
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"));
    if !fine_grid {
        mesh.light_line_style(WHITE.mix(0.0));
    }
    mesh.draw().map_err(e)?;
    Ok(chart)
}

/// The legend of every log–log figure ([`log_log_chart`]): translucent white box, grey border,
/// at `position`, labels in `font_size`-point sans-serif.
pub fn draw_log_legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>,
    position: SeriesLabelPosition,
    font_size: f64,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .label_font(("sans-serif", font_size))
        .draw()
        .map_err(|e| e.to_string())
}
