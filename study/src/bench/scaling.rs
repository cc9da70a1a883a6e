//! The engine-scaling figure: time per step against unknowns, drawn from the table that
//! `python/scripts/bench_engine.py` measures (`docs/bench/engine-scaling.csv`), one panel per
//! geometry, one line per engine × linear solver × ranks (log–log).
//!
//! `massredist bench --scaling-figure docs/bench/engine-scaling.csv` writes
//! `engine-scaling.png` and `engine-scaling.svg` next to the table. Reading and drawing only:
//! the numbers are the script's measurements.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// One row of engine-scaling.csv.
#[derive(Debug, Clone, PartialEq)]
pub struct ScalingRow {
    /// "plate" or "solid" (rows written before solids were measured have no column: plate).
    pub geometry: String,
    pub unknowns: f64,
    /// "rust", "fenicsx direct", "fenicsx cg-amg".
    pub engine: String,
    pub ranks: usize,
    pub per_step_ms: f64,
}

/// Parses the table (header names the columns; `geometry` optional).
pub fn read_rows(text: &str) -> Result<Vec<ScalingRow>, String> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<&str> = lines.next().ok_or("empty table")?.split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name);
    let need = |name: &str| col(name).ok_or(format!("the table has no column `{name}`"));
    let (u, e, r, p) = (need("unknowns")?, need("engine")?, need("ranks")?, need("per_step_ms")?);
    let g = col("geometry");
    lines
        .enumerate()
        .map(|(k, line)| {
            let f: Vec<&str> = line.split(',').collect();
            let bad = |what: &str| format!("row {}: {what}: {line}", k + 1);
            let num = |i: usize| f.get(i).and_then(|s| s.parse::<f64>().ok()).ok_or_else(|| bad(header[i]));
            Ok(ScalingRow {
                geometry: g.and_then(|i| f.get(i)).map_or("plate", |s| s).to_string(),
                unknowns: num(u)?,
                engine: f.get(e).ok_or_else(|| bad("engine"))?.to_string(),
                ranks: num(r)? as usize,
                per_step_ms: num(p)?,
            })
        })
        .collect()
}

const COLOURS: [RGBColor; 6] = [
    RGBColor(0, 0, 0),
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
];

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, rows: &[ScalingRow]) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let mut geometries: Vec<&str> = rows.iter().map(|r| r.geometry.as_str()).collect();
    geometries.dedup();
    geometries.sort_unstable();
    geometries.dedup();
    let mut series: Vec<(String, usize)> = rows.iter().map(|r| (r.engine.clone(), r.ranks)).collect();
    series.sort();
    series.dedup();
    let (top, body) = root.split_vertically(34);
    top.titled("Time per step against unknowns (python/scripts/bench_engine.py)", ("sans-serif", 18)).map_err(e)?;
    let areas = body.split_evenly((1, geometries.len().max(1)));
    for (area, geometry) in areas.iter().zip(&geometries) {
        let mine: Vec<&ScalingRow> = rows.iter().filter(|r| r.geometry == *geometry && r.per_step_ms > 0.0).collect();
        let span = |v: &mut dyn Iterator<Item = f64>| {
            let (lo, hi) = v.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
            if lo.is_finite() { (lo / 1.5, hi * 1.5) } else { (1.0, 10.0) }
        };
        let x = span(&mut mine.iter().map(|r| r.unknowns));
        let y = span(&mut mine.iter().map(|r| r.per_step_ms));
        let mut chart = crate::plot::log_log_chart(area, geometry, x, y, ("unknowns", "time per step [ms]"), true)?;
        for (k, (engine, ranks)) in series.iter().enumerate() {
            let mut pts: Vec<(f64, f64)> = mine
                .iter()
                .filter(|r| &r.engine == engine && r.ranks == *ranks)
                .map(|r| (r.unknowns, r.per_step_ms))
                .collect();
            if pts.is_empty() {
                continue;
            }
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let colour = COLOURS[k % COLOURS.len()];
            let style = colour.stroke_width(2);
            let line = if *ranks == 1 {
                chart.draw_series(LineSeries::new(pts.clone(), style)).map_err(e)?
            } else {
                chart.draw_series(DashedLineSeries::new(pts.clone(), 8, 4, style)).map_err(e)?
            };
            line.label(format!("{engine}, {ranks} rank(s)"))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, colour.filled()))).map_err(e)?;
        }
        crate::plot::draw_log_legend(&mut chart, SeriesLabelPosition::UpperLeft, 13.0)?;
    }
    root.present().map_err(e)?;
    Ok(())
}

/// Reads `csv` and writes the figure as `<stem>.png` and `<stem>.svg` next to it; returns the
/// paths written.
pub fn scaling_figure(csv: &Path) -> Result<Vec<PathBuf>, String> {
    let text = std::fs::read_to_string(csv).map_err(|e| format!("{}: {e}", csv.display()))?;
    let rows = read_rows(&text).map_err(|m| format!("{}: {m}", csv.display()))?;
    let size = (1400, 600);
    let mut written = Vec::new();
    for ext in ["png", "svg"] {
        let path = csv.with_extension(ext);
        let r = if ext == "svg" {
            draw(SVGBackend::new(&path, size).into_drawing_area(), &rows)
        } else {
            draw(BitMapBackend::new(&path, size).into_drawing_area(), &rows)
        };
        r.map_err(|m| format!("cannot draw {}: {m}", path.display()))?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_read_with_and_without_the_geometry_column() {
        let old = "n,unknowns,engine,ranks,setup_s,per_step_ms\n16,272,rust,1,0.03,0.02\n";
        let rows = read_rows(old).unwrap();
        assert_eq!(rows[0].geometry, "plate");
        assert_eq!((rows[0].unknowns, rows[0].ranks, rows[0].per_step_ms), (272.0, 1, 0.02));
        let new =
            "geometry,n,unknowns,engine,ranks,solver,setup_s,per_step_ms\nsolid,4,375,fenicsx direct,2,x,1.0,3.5\n";
        let rows = read_rows(new).unwrap();
        assert_eq!((rows[0].geometry.as_str(), rows[0].engine.as_str(), rows[0].ranks), ("solid", "fenicsx direct", 2));
        // mutation: `num(p)?` -> `num(u)?` for per_step_ms -> fails with 375 != 3.5.
        assert_eq!(rows[0].per_step_ms, 3.5);
        assert!(read_rows("n,engine\n1,rust\n").unwrap_err().contains("unknowns"));
    }
}
