//! Output folders and the run's files: the series CSV, the summary JSON and the atomic folder
//! ([`OutputDir`]) that every writer fills (`run`, `reproduce` and `bench` commit their files into
//! one; VTU frames are written into it by `fem::frames`). A run directory appears complete or not
//! at all: it is written under a temporary sibling name and renamed into place. `massredist run`
//! streams its series into that temporary folder while computing ([`SeriesWriter`]), so its
//! memory does not depend on the number of steps. Output folders are checked before computing and
//! carry a marker listing every file written; only a marked folder holding nothing else is
//! replaced without `--force` ([`OutputDir`], `output/folder.rs`). A signal removes the temporary
//! folder (`output/staging.rs`).

use crate::driver::{Needs, Observer, Sample};
use crate::observe::Column;
use crate::observe::{SeriesRecorder, push_series_row, series_needs};
use std::io::Write;
use std::path::Path;

pub use crate::numfmt::{Shortest, fmt_f64};

/// One CSV line of numbers (`,`-separated, `\n`-terminated, shortest round-trip).
fn write_csv_row<W: Write>(w: &mut W, row: &[f64]) -> std::io::Result<()> {
    for (k, &x) in row.iter().enumerate() {
        if k > 0 {
            w.write_all(b",")?;
        }
        write!(w, "{}", Shortest(x))?;
    }
    w.write_all(b"\n")
}

/// The header line of `series.csv`: `t`, then the column names.
fn write_series_header<W: Write>(w: &mut W, columns: &[Column]) -> std::io::Result<()> {
    w.write_all(b"t")?;
    for c in columns {
        write!(w, ",{}", c.name())?;
    }
    w.write_all(b"\n")
}

/// Writes a recorded `series` as CSV (header `t` then the columns) to any writer: the same
/// text as [`SeriesWriter`] streams.
pub fn write_series_csv<W: Write>(series: &SeriesRecorder, mut w: W) -> std::io::Result<()> {
    write_series_header(&mut w, &series.columns)?;
    for row in series.iter_rows() {
        write_csv_row(&mut w, row)?;
    }
    w.flush()
}

/// Streams the series (`series.csv`) to a writer as the run produces it: one row every `every`
/// steps, written when observed, so memory does not depend on the number of steps (a
/// [`SeriesRecorder`] keeps the rows in memory instead). An observer cannot fail: the first write
/// error is kept, the run is halted ([`Observer::halted`]: no step is computed for nothing), and
/// [`SeriesWriter::finish`] returns it.
#[derive(Debug)]
pub struct SeriesWriter<W: Write> {
    columns: Vec<Column>,
    every: usize,
    row: Vec<f64>,
    out: W,
    error: Option<std::io::Error>,
}

impl<W: Write> SeriesWriter<W> {
    /// Writes the header now; rows follow as observed.
    pub fn new(columns: Vec<Column>, every: usize, mut out: W) -> std::io::Result<Self> {
        write_series_header(&mut out, &columns)?;
        Ok(Self { row: Vec::with_capacity(columns.len() + 1), columns, every: every.max(1), out, error: None })
    }

    /// Flushes the writer and returns it, or the first write error.
    pub fn finish(mut self) -> std::io::Result<W> {
        match self.error.take() {
            Some(e) => Err(e),
            None => self.out.flush().map(|()| self.out),
        }
    }
}

impl SeriesWriter<std::io::BufWriter<std::fs::File>> {
    /// `dir/series.csv`, buffered.
    pub fn create(dir: &Path, columns: Vec<Column>, every: usize) -> std::io::Result<Self> {
        Self::new(columns, every, std::io::BufWriter::new(std::fs::File::create(dir.join("series.csv"))?))
    }
}

impl<W: Write> Observer for SeriesWriter<W> {
    fn needs(&self) -> Needs {
        series_needs(&self.columns)
    }

    fn every(&self) -> usize {
        self.every
    }

    fn observe(&mut self, s: &Sample) {
        if self.error.is_some() {
            return;
        }
        self.row.clear();
        push_series_row(&self.columns, s, &mut self.row);
        if let Err(e) = write_csv_row(&mut self.out, &self.row) {
            self.error = Some(e);
        }
    }

    fn halted(&self) -> bool {
        self.error.is_some()
    }
}

/// Writes the output folder `dir` that was not prepared before computing: prepares it without
/// force ([`OutputDir::prepare`]: refused if it is a file, or a non-empty folder massredist did not
/// write), then [`OutputDir::commit`]s `fill`. The error is an [`OutputError`] inside the
/// `io::Error`. Commands prepare their folder before computing and commit it themselves.
pub fn write_dir_atomically(dir: &Path, fill: impl FnOnce(&Path) -> std::io::Result<()>) -> std::io::Result<()> {
    let out = OutputDir::prepare(dir, false, &[]).map_err(std::io::Error::other)?;
    out.commit(fill).map_err(std::io::Error::other)
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

/// Completes a run folder whose series and frames were streamed into it ([`SeriesWriter`],
/// `plate::vtu::FrameWriter`): writes `summary.json` and `scene.resolved.toml` and commits it.
pub fn commit_run(out: OutputDir, summary_json: &str, resolved_scene: &str) -> Result<(), OutputError> {
    out.commit(|tmp| {
        std::fs::write(tmp.join("summary.json"), summary_json)?;
        std::fs::write(tmp.join("scene.resolved.toml"), resolved_scene)
    })
}

// ---------------------------------------------------------------------------------------------
// Output folders: checked before computing, written complete, replaced only when they are ours
// (`output/folder.rs`); partial folders of interrupted runs and signals (`output/staging.rs`).

mod folder;
mod staging;

pub use folder::{OutputDir, OutputError};

/// The marker file in every folder massredist writes. Its first line says what wrote the folder
/// (tool, version, command line); each further line names one file (`vtu/frame-0001.vtu`) or
/// folder (`vtu/`, with the slash) written with it, relative to the folder, at any depth.
pub const MARKER: &str = ".massredist-output";

pub use staging::{ChildGroup, install_signal_cleanup, wait_if_signalled};
