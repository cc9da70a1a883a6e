//! Files: the only module that writes. A run directory appears complete or not at all: it is
//! written under a temporary sibling name and renamed into place.

use crate::run::{SeriesRecorder, Summary};
use crate::scene::Scene;
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Shortest representation that reads back to the same f64 (Rust's `Display`/`LowerExp` are
/// both shortest round-trip); plain notation for moderate magnitudes, exponent otherwise.
pub fn fmt_f64(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || (1e-4..1e15).contains(&a) || !x.is_finite() { format!("{x}") } else { format!("{x:e}") }
}

/// Writes a CSV table of numbers (header, then one row per item, full precision).
pub fn write_number_csv<'a, W: Write>(header: &[&str], rows: impl Iterator<Item = &'a [f64]>, w: W) -> csv::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    out.write_record(header)?;
    for row in rows {
        out.write_record(row.iter().map(|&x| fmt_f64(x)))?;
    }
    out.flush()?;
    Ok(())
}

/// Writes `series` as CSV (header `t` then the columns) to any writer.
pub fn write_series_csv<W: Write>(series: &SeriesRecorder, w: W) -> csv::Result<()> {
    let mut header = vec!["t"];
    header.extend(series.columns.iter().map(|c| c.name()));
    write_number_csv(&header, series.iter_rows(), w)
}

#[derive(Serialize)]
struct SummaryFile<'a> {
    scheme: &'a str,
    mass: &'a str,
    elements: usize,
    length: f64,
    end: f64,
    #[serde(flatten)]
    summary: &'a Summary,
}

/// `summary.json` text: the summary plus the scene's identity.
pub fn summary_json(scene: &Scene, summary: &Summary) -> String {
    let file = SummaryFile {
        scheme: scene.scheme.name(),
        mass: scene.mass.name(),
        elements: scene.bar.elements,
        length: scene.bar.length,
        end: scene.time.end,
        summary,
    };
    serde_json::to_string_pretty(&file).expect("summary serialises") + "\n"
}

/// Creates `dir` atomically: `fill` writes into a fresh temporary sibling directory, which is
/// then renamed to `dir` (replacing an existing one). On error nothing is left behind.
pub fn write_dir_atomically(dir: &Path, fill: impl FnOnce(&Path) -> std::io::Result<()>) -> std::io::Result<()> {
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&parent)?;
    let name = dir.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "out".into());
    let tmp = parent.join(format!(".{name}.tmp-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir(&tmp)?;
    let result = fill(&tmp).and_then(|()| {
        if dir.exists() {
            let old = parent.join(format!(".{name}.old-{}", std::process::id()));
            std::fs::rename(dir, &old)?;
            std::fs::rename(&tmp, dir)?;
            std::fs::remove_dir_all(&old)
        } else {
            std::fs::rename(&tmp, dir)
        }
    });
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&tmp);
    }
    result
}

/// Writes a file atomically (temporary name in the same directory, then rename).
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent)?;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = parent.join(format!(".{name}.tmp-{}", std::process::id()));
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

/// The run directory of `massredist run`: series.csv (if any column), summary.json and
/// scene.resolved.toml.
pub fn write_run(dir: &Path, scene: &Scene, summary: &Summary, series: &SeriesRecorder) -> std::io::Result<()> {
    write_dir_atomically(dir, |tmp| {
        if !series.columns.is_empty() {
            let f = std::io::BufWriter::new(std::fs::File::create(tmp.join("series.csv"))?);
            write_series_csv(series, f).map_err(std::io::Error::other)?;
        }
        std::fs::write(tmp.join("summary.json"), summary_json(scene, summary))?;
        std::fs::write(tmp.join("scene.resolved.toml"), scene.resolved_toml())?;
        Ok(())
    })
}
