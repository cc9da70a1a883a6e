//! The plate run directory: `summary.json` (the 1D keys plus plate keys), `series.csv`,
//! `scene.resolved.toml`, and with VTU output `plate.pvd` + `vtu/frame_NNNNN.vtu`. Written
//! atomically ([`crate::output::write_dir_atomically`]).

use super::run::PlateRun;
use super::scene::PlateScene;
use super::vtu;
use crate::observe::{SeriesRecorder, Summary};
use crate::output::write_dir_atomically;
use serde::Serialize;
use std::io::Write;
use std::path::Path;

/// Writes `series` as CSV (header `t` then the columns).
pub fn write_series_csv<W: Write>(series: &SeriesRecorder, w: W) -> csv::Result<()> {
    let mut header = vec!["t"];
    header.extend(series.columns.iter().map(|c| c.name()));
    crate::output::write_number_csv(&header, series.iter_rows(), w)
}

#[derive(Serialize)]
struct PlateSummaryFile<'a> {
    scheme: &'a str,
    mass: &'a str,
    /// Cells along x (the bar's `elements`).
    elements: usize,
    length: f64,
    end: f64,
    height: f64,
    nx: usize,
    ny: usize,
    cells: &'a str,
    initial: &'a str,
    total_mass: f64,
    #[serde(flatten)]
    summary: &'a Summary,
}

/// `summary.json` text.
pub fn summary_json(scene: &PlateScene, run: &PlateRun) -> String {
    let p = &scene.plate;
    let file = PlateSummaryFile {
        scheme: scene.scheme.name(),
        mass: scene.mass.name(),
        elements: p.nx,
        length: p.length,
        end: scene.time.end,
        height: p.height,
        nx: p.nx,
        ny: p.ny,
        cells: p.cells.name(),
        initial: p.initial.name(),
        total_mass: run.problem.system.total_mass(),
        summary: &run.summary,
    };
    serde_json::to_string_pretty(&file).expect("summary serialises") + "\n"
}

/// Writes the run directory.
pub fn write_plate_run(dir: &Path, scene: &PlateScene, run: &PlateRun) -> std::io::Result<()> {
    write_dir_atomically(dir, |tmp| {
        if !run.series.columns.is_empty() {
            let f = std::io::BufWriter::new(std::fs::File::create(tmp.join("series.csv"))?);
            write_series_csv(&run.series, f).map_err(std::io::Error::other)?;
        }
        std::fs::write(tmp.join("summary.json"), summary_json(scene, run))?;
        std::fs::write(tmp.join("scene.resolved.toml"), scene.resolved_toml())?;
        if let Some(frames) = &run.frames {
            std::fs::create_dir(tmp.join("vtu"))?;
            let plate = &run.problem.system;
            let mut entries = Vec::with_capacity(frames.frames.len());
            for (k, fr) in frames.frames.iter().enumerate() {
                let name = format!("vtu/frame_{k:05}.vtu");
                std::fs::write(tmp.join(&name), vtu::vtu_string(&plate.mesh, &fr.u, &fr.v, &plate.weights))?;
                entries.push((fr.t, name));
            }
            std::fs::write(tmp.join("plate.pvd"), vtu::pvd_string(&entries))?;
        }
        Ok(())
    })
}
