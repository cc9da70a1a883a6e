//! Files: the only module that writes. A run directory appears complete or not at all: it is
//! written under a temporary sibling name and renamed into place. Output folders are checked
//! before computing and carry a marker; only a marked folder is replaced without `--force`
//! ([`OutputDir`]).

use crate::observe::{SeriesRecorder, Summary};
use crate::scene::BarScene;
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

pub use crate::numfmt::fmt_f64;

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

/// Writes the output folder `dir`: `fill` writes into a temporary sibling folder, which gets the
/// [`MARKER`] and is then renamed to `dir`; on error nothing is left behind.
///
/// The folder prepared for `dir` and handed over by [`OutputDir::stage`] is used if there is one
/// (with its `--force` and its protected inputs: the checks ran before computing). Otherwise `dir`
/// is prepared here, without force: refused if it is a file, or a non-empty folder massredist did
/// not write ([`OutputDir::prepare`]). The error is an [`OutputError`] inside the `io::Error`.
pub fn write_dir_atomically(dir: &Path, fill: impl FnOnce(&Path) -> std::io::Result<()>) -> std::io::Result<()> {
    let out = match take_staged(dir) {
        Some(out) => out,
        None => OutputDir::prepare(dir, false, &[]).map_err(std::io::Error::other)?,
    };
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

/// The run directory of `massredist run` for a bar scene (see [`write_run_files`]).
pub fn write_run(dir: &Path, scene: &BarScene, summary: &Summary, series: &SeriesRecorder) -> std::io::Result<()> {
    write_run_files(dir, &summary_json(scene, summary), &scene.resolved_toml(), series, |_| Ok(()))
}

/// The run directory of every geometry: series.csv (if any column), summary.json,
/// scene.resolved.toml, and what `extra` writes into the folder (a plate's VTU frames).
pub fn write_run_files(
    dir: &Path,
    summary_json: &str,
    resolved_scene: &str,
    series: &SeriesRecorder,
    extra: impl FnOnce(&Path) -> std::io::Result<()>,
) -> std::io::Result<()> {
    write_dir_atomically(dir, |tmp| {
        if !series.columns.is_empty() {
            let f = std::io::BufWriter::new(std::fs::File::create(tmp.join("series.csv"))?);
            write_series_csv(series, f).map_err(std::io::Error::other)?;
        }
        std::fs::write(tmp.join("summary.json"), summary_json)?;
        std::fs::write(tmp.join("scene.resolved.toml"), resolved_scene)?;
        extra(tmp)
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

    /// Partial folders of earlier killed runs that `prepare` removed.
    pub fn removed_left_overs(&self) -> &[PathBuf] {
        &self.removed
    }

    /// Writes the folder: `fill` writes into the temporary folder, the marker gets the list of
    /// what it wrote, the target is checked again (it may have changed while computing) and the
    /// temporary folder is renamed into place, replacing the old folder, which is then removed.
    pub fn commit(mut self, fill: impl FnOnce(&Path) -> std::io::Result<()>) -> Result<(), OutputError> {
        let fill_error = |source| OutputError::Fill { path: self.path.clone(), staging: self.staging.clone(), source };
        fill(&self.staging).map_err(fill_error)?;
        write_marker(&self.staging).map_err(fill_error)?;
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

    /// Hands this folder to a writer that takes only a path: [`write_dir_atomically`] called
    /// with the same path (as given to `prepare`) commits it. Dropping the returned guard
    /// discards it if no writer did. This lets `main` check and create the folder before
    /// computing while the writers keep their `&Path` signatures.
    pub fn stage(self) -> Staged {
        let path = self.path.clone();
        staged_dirs().push(self);
        Staged { path }
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

/// The guard of a staged [`OutputDir`]; see [`OutputDir::stage`].
#[derive(Debug)]
pub struct Staged {
    path: PathBuf,
}

impl Drop for Staged {
    fn drop(&mut self) {
        drop(take_staged(&self.path));
    }
}

/// Folders prepared by `main` before computing, waiting for their writer.
static STAGED: std::sync::Mutex<Vec<OutputDir>> = std::sync::Mutex::new(Vec::new());

fn staged_dirs() -> std::sync::MutexGuard<'static, Vec<OutputDir>> {
    STAGED.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

fn take_staged(path: &Path) -> Option<OutputDir> {
    let mut dirs = staged_dirs();
    let i = dirs.iter().position(|d| d.path == path)?;
    Some(dirs.swap_remove(i))
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
