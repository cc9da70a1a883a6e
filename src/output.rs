//! Output folders and the run's files: the series CSV, the summary JSON and the atomic folder
//! ([`OutputDir`]) that every writer fills (`run`, `reproduce` and `bench` commit their files into
//! one; VTU frames are written into it by `fem::frames`). A run directory appears complete or not
//! at all: it is written under a temporary sibling name and renamed into place. `massredist run`
//! streams its series into that temporary folder while computing ([`SeriesWriter`]), so its
//! memory does not depend on the number of steps. Output folders are checked before computing and
//! carry a marker; only a marked folder is replaced without `--force` ([`OutputDir`]).

use crate::driver::{Needs, Observer, Sample};
use crate::observe::{SeriesRecorder, Summary, push_series_row, series_needs};
use crate::scene::{BarScene, Column};
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

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
pub fn summary_json(scene: &BarScene, summary: &Summary) -> String {
    let file = SummaryFile {
        scheme: scene.scheme.name(),
        mass: scene.mass.name(),
        elements: scene.geometry.elements,
        length: scene.geometry.length,
        end: scene.time.end,
        summary,
    };
    serde_json::to_string_pretty(&file).expect("summary serialises") + "\n"
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
// Output folders: checked before computing, written complete, replaced only when they are ours.

/// The marker file in every folder massredist writes. Its first line says what wrote the folder
/// (tool, version, command line); each further line names one top-level entry written with it.
pub const MARKER: &str = ".massredist-output";

/// Why an output folder cannot be used or written. Each message names the path and says how to
/// go on.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The path is, or contains, something massredist never replaces (an input of the command,
    /// the current folder, the home folder).
    #[error(
        "{} is or contains {} ({what}), which massredist never replaces, not even with --force; choose another --out",
        path.display(),
        protected.display()
    )]
    Protected { path: PathBuf, protected: PathBuf, what: &'static str },
    /// The path exists and is not a folder.
    #[error(
        "{} is {kind}, not a folder; massredist never replaces it, not even with --force; choose another --out",
        path.display()
    )]
    NotAFolder { path: PathBuf, kind: &'static str },
    /// A non-empty folder without the marker.
    #[error(
        "{} is a folder massredist did not write (no {MARKER} in it; it holds {}); use --force to replace it and delete what it holds, or choose another --out",
        path.display(),
        entries_phrase(*count, example)
    )]
    Foreign { path: PathBuf, count: usize, example: String },
    /// A folder with the marker that also holds entries the marker does not list.
    #[error(
        "{} was written by massredist but also holds {} it did not write; move them out, use --force to replace the folder and delete them, or choose another --out",
        path.display(),
        entries_phrase(*count, example)
    )]
    Unlisted { path: PathBuf, count: usize, example: String },
    /// The path names no folder (`.`, `..`, `/`).
    #[error("{} does not name a folder; give one such as results/run1", path.display())]
    NoName { path: PathBuf },
    /// The folder or its temporary sibling cannot be created (missing permission, a file on
    /// the way, …); found before computing.
    #[error("cannot create the output folder {}: {}: {source}; choose another --out", path.display(), at.display())]
    Unwritable { path: PathBuf, at: PathBuf, source: std::io::Error },
    /// Writing the content into the temporary folder failed.
    #[error("writing {} (to become {}): {source}", staging.display(), path.display())]
    Fill { path: PathBuf, staging: PathBuf, source: std::io::Error },
    /// Renaming into place failed; the previous folder, if any, is back in place.
    #[error("renaming {} to {}: {source}", from.display(), to.display())]
    Rename { from: PathBuf, to: PathBuf, source: std::io::Error },
    /// The new folder is in place, but the one it replaced could not be removed.
    #[error(
        "{} is written, but the folder it replaced, moved to {}, could not be removed: {source}; delete it by hand (the next massredist run into {} tries again)",
        path.display(),
        old.display(),
        path.display()
    )]
    OldKept { path: PathBuf, old: PathBuf, source: std::io::Error },
}

/// `"a"`, `"a" and 1 other entry`, `"a" and 4 other entries`.
fn entries_phrase(count: usize, example: &str) -> String {
    match count {
        0 | 1 => format!("{example:?}"),
        2 => format!("{example:?} and 1 other entry"),
        n => format!("{example:?} and {} other entries", n - 1),
    }
}

/// An output folder checked before computing, with its temporary sibling `.NAME.tmp-<pid>`
/// already created (so an unwritable place fails before any work). [`OutputDir::commit`] writes
/// the content and renames it into place; dropping an uncommitted `OutputDir` removes the
/// temporary folder (and the parents `prepare` created).
///
/// What may be replaced:
/// - nothing there, or an empty folder: always used;
/// - a folder carrying the [`MARKER`] and holding only the entries it lists: replaced whole;
/// - with `force`, also a non-empty folder without the marker, or one holding entries the marker
///   does not list: replaced, and what it held deleted;
/// - never, not even with `force`: something that is not a folder (a file, a symbolic link), or
///   a folder that is or contains a protected path (the given inputs, such as the scene file;
///   the current folder; the home folder).
///
/// The replaced folder is moved aside to `.NAME.tmp-<pid>-old` and removed; if that removal
/// fails the error names it. Partial folders `.NAME.tmp-<pid>[-old]` next to the target are
/// removed when their run is over: the pid runs no more, or it runs a program other than
/// massredist and the folder carries the marker (the pid was reused). Where running processes
/// cannot be listed (no `/proc`), they are left alone.
#[derive(Debug)]
pub struct OutputDir {
    path: PathBuf,
    staging: PathBuf,
    force: bool,
    protected: Vec<(PathBuf, &'static str)>,
    /// Folders `prepare` created above the target, innermost first.
    created_parents: Vec<PathBuf>,
    removed: Vec<PathBuf>,
    committed: bool,
}

/// What stands at an output path that may be used.
enum Existing {
    /// Nothing, or an empty folder.
    Free,
    /// A folder to replace (ours, or forced).
    Replace,
}

impl OutputDir {
    /// Checks `path` (see [`OutputDir`] for what is refused), then creates the missing parents
    /// and the temporary sibling folder with the marker, and removes partial folders of earlier
    /// killed runs. `protect` are inputs never to be replaced, such as the scene file.
    pub fn prepare(path: &Path, force: bool, protect: &[&Path]) -> Result<OutputDir, OutputError> {
        let protected = protected_paths(protect);
        classify(path, force, &protected)?;
        let name = path.file_name().ok_or_else(|| OutputError::NoName { path: path.into() })?.to_string_lossy();
        let parent = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let created_parents: Vec<PathBuf> = parent
            .ancestors()
            .take_while(|a| !a.as_os_str().is_empty() && !a.exists())
            .map(Path::to_path_buf)
            .collect();
        let unwritable = |at: &Path, source| OutputError::Unwritable { path: path.into(), at: at.into(), source };
        std::fs::create_dir_all(&parent).map_err(|e| unwritable(&parent, e))?;
        let removed = remove_left_overs(&parent, &name);
        let out = OutputDir {
            path: path.into(),
            staging: parent.join(format!(".{name}.tmp-{}", std::process::id())),
            force,
            protected,
            created_parents,
            removed,
            committed: false,
        };
        if let Err(e) = std::fs::create_dir(&out.staging) {
            return Err(unwritable(&out.staging, e));
        }
        // From here on Drop removes the staging folder; the marker makes it recognisable as
        // ours should this process be killed.
        let marker = out.staging.join(MARKER);
        std::fs::write(&marker, marker_head()).map_err(|e| unwritable(&marker, e))?;
        Ok(out)
    }

    /// The path the folder will have.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The temporary folder `.NAME.tmp-<pid>` the content is written into (streamed while
    /// computing, or by [`OutputDir::commit`]'s `fill`); renamed to [`OutputDir::path`] by
    /// `commit`, removed if the `OutputDir` is dropped uncommitted.
    pub fn staging(&self) -> &Path {
        &self.staging
    }

    /// The error of a failed write into the temporary folder.
    pub fn fill_error(&self, source: std::io::Error) -> OutputError {
        OutputError::Fill { path: self.path.clone(), staging: self.staging.clone(), source }
    }

    /// Partial folders of earlier killed runs that `prepare` removed.
    pub fn removed_left_overs(&self) -> &[PathBuf] {
        &self.removed
    }

    /// Writes the folder: `fill` writes into the temporary folder, the marker gets the list of
    /// what it wrote, the target is checked again (it may have changed while computing) and the
    /// temporary folder is renamed into place, replacing the old folder, which is then removed.
    pub fn commit(mut self, fill: impl FnOnce(&Path) -> std::io::Result<()>) -> Result<(), OutputError> {
        fill(&self.staging).map_err(|e| self.fill_error(e))?;
        write_marker(&self.staging).map_err(|e| self.fill_error(e))?;
        let rename = |from: &Path, to: &Path| {
            std::fs::rename(from, to).map_err(|source| OutputError::Rename { from: from.into(), to: to.into(), source })
        };
        match classify(&self.path, self.force, &self.protected)? {
            // A rename replaces an empty folder.
            Existing::Free => rename(&self.staging, &self.path)?,
            Existing::Replace => {
                let old = PathBuf::from(format!("{}-old", self.staging.display()));
                let _ = std::fs::remove_dir_all(&old);
                rename(&self.path, &old)?;
                if let Err(e) = rename(&self.staging, &self.path) {
                    let _ = std::fs::rename(&old, &self.path);
                    return Err(e);
                }
                self.committed = true;
                return std::fs::remove_dir_all(&old).map_err(|source| OutputError::OldKept {
                    path: self.path.clone(),
                    old,
                    source,
                });
            }
        }
        self.committed = true;
        Ok(())
    }
}

impl Drop for OutputDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
            // Only empty ones go: remove_dir fails on a folder holding anything.
            for p in &self.created_parents {
                let _ = std::fs::remove_dir(p);
            }
        }
    }
}

/// The canonical forms of `inputs`, the current folder and the home folder, with what each is.
fn protected_paths(inputs: &[&Path]) -> Vec<(PathBuf, &'static str)> {
    let inputs = inputs.iter().filter_map(|p| p.canonicalize().ok()).map(|p| (p, "an input of this command"));
    let cwd = std::env::current_dir().and_then(|d| d.canonicalize()).ok().map(|p| (p, "the current folder"));
    let home =
        std::env::var_os("HOME").and_then(|h| PathBuf::from(h).canonicalize().ok()).map(|p| (p, "the home folder"));
    inputs.chain(cwd).chain(home).collect()
}

/// Decides whether `path` may be written (see [`OutputDir`]); reads only.
fn classify(path: &Path, force: bool, protected: &[(PathBuf, &'static str)]) -> Result<Existing, OutputError> {
    let meta = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Existing::Free),
        Err(source) => return Err(OutputError::Unwritable { path: path.into(), at: path.into(), source }),
    };
    if let Ok(canonical) = path.canonicalize()
        && let Some((p, what)) = protected.iter().find(|(p, _)| p.starts_with(&canonical))
    {
        return Err(OutputError::Protected { path: path.into(), protected: p.clone(), what });
    }
    if !meta.is_dir() {
        let kind = if meta.is_file() {
            "a file"
        } else if meta.is_symlink() {
            "a symbolic link"
        } else {
            "neither a file nor a folder"
        };
        return Err(OutputError::NotAFolder { path: path.into(), kind });
    }
    let unreadable = |source| OutputError::Unwritable { path: path.into(), at: path.into(), source };
    let mut entries = Vec::new();
    for e in std::fs::read_dir(path).map_err(unreadable)? {
        entries.push(e.map_err(unreadable)?.file_name().to_string_lossy().into_owned());
    }
    entries.sort();
    if entries.is_empty() {
        return Ok(Existing::Free);
    }
    let listed = read_marker(path);
    let unlisted: Vec<&String> =
        entries.iter().filter(|n| *n != MARKER && !listed.as_ref().is_some_and(|l| l.contains(*n))).collect();
    match (&listed, unlisted.first()) {
        (Some(_), None) => Ok(Existing::Replace),
        _ if force => Ok(Existing::Replace),
        (Some(_), Some(&first)) => {
            Err(OutputError::Unlisted { path: path.into(), count: unlisted.len(), example: first.clone() })
        }
        (None, _) => Err(OutputError::Foreign { path: path.into(), count: entries.len(), example: entries[0].clone() }),
    }
}

/// The entries the marker in `dir` lists, or `None` without a readable marker.
fn read_marker(dir: &Path) -> Option<std::collections::BTreeSet<String>> {
    let text = std::fs::read_to_string(dir.join(MARKER)).ok()?;
    Some(text.lines().skip(1).map(String::from).collect())
}

/// The marker's first line: tool, version and the command line that wrote the folder.
fn marker_head() -> String {
    let mut args = std::env::args_os().map(|a| a.to_string_lossy().replace('\n', " "));
    let program = args.next().map(|a| Path::new(&a).file_name().map_or(a.clone(), |n| n.to_string_lossy().into()));
    let command: Vec<String> = program.into_iter().chain(args).collect();
    format!(
        "massredist {} wrote this folder (`{}`); a later massredist run may replace it. Entries written:\n",
        env!("CARGO_PKG_VERSION"),
        command.join(" ")
    )
}

/// Completes the marker in `dir` with the names of the entries written (sorted).
fn write_marker(dir: &Path) -> std::io::Result<()> {
    let mut text = marker_head();
    let mut names = Vec::new();
    for e in std::fs::read_dir(dir)? {
        names.push(e?.file_name().to_string_lossy().into_owned());
    }
    names.sort();
    for n in names.iter().filter(|n| *n != MARKER) {
        text.push_str(n);
        text.push('\n');
    }
    std::fs::write(dir.join(MARKER), text)
}

/// The pid in `entry` if it is a partial folder name of target `name`: `.NAME.tmp-<pid>` or
/// `.NAME.tmp-<pid>-old`.
fn partial_folder_pid(entry: &str, name: &str) -> Option<u32> {
    let rest = entry.strip_prefix('.')?.strip_prefix(name)?.strip_prefix(".tmp-")?;
    let digits = rest.strip_suffix("-old").unwrap_or(rest);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// What runs under a pid, as far as this system tells.
enum Process {
    Unknown,
    Gone,
    Running(String),
}

/// Reads `/proc/<pid>/stat` (Linux): a zombie counts as gone.
fn process(pid: u32) -> Process {
    if !Path::new("/proc/self/stat").exists() {
        return Process::Unknown;
    }
    match std::fs::read_to_string(format!("/proc/{pid}/stat")) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Process::Gone,
        Err(_) => Process::Unknown,
        // "<pid> (<comm>) <state> …"; comm may itself hold ") ".
        Ok(stat) => match (stat.find('('), stat.rfind(") ")) {
            (Some(a), Some(b)) if a < b => match stat[b + 2..].chars().next() {
                Some('Z' | 'X') => Process::Gone,
                _ => Process::Running(stat[a + 1..b].to_string()),
            },
            _ => Process::Unknown,
        },
    }
}

/// Removes the partial folders of target `name` in `parent` whose run is over (see
/// [`OutputDir`]); returns them.
fn remove_left_overs(parent: &Path, name: &str) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(parent) else { return Vec::new() };
    let mut removed = Vec::new();
    for e in entries.flatten() {
        let Some(pid) = partial_folder_pid(&e.file_name().to_string_lossy(), name) else { continue };
        let path = e.path();
        let over = pid == std::process::id()
            || match process(pid) {
                Process::Gone => true,
                Process::Running(program) => program != "massredist" && path.join(MARKER).is_file(),
                Process::Unknown => false,
            };
        if over && e.file_type().is_ok_and(|t| t.is_dir()) && std::fs::remove_dir_all(&path).is_ok() {
            removed.push(path);
        }
    }
    removed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partial_folder_names() {
        assert_eq!(partial_folder_pid(".out.tmp-123", "out"), Some(123));
        assert_eq!(partial_folder_pid(".out.tmp-123-old", "out"), Some(123));
        for other in [".out.tmp-", ".out.tmp-12a", ".out.tmp-123-new", ".outx.tmp-1", "out.tmp-1", ".out.old-1"] {
            assert_eq!(partial_folder_pid(other, "out"), None, "{other}");
        }
    }
}
