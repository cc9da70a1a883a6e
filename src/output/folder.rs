//! Output folders: checked before computing, written complete, replaced only when they are ours.
//!
//! The marker [`MARKER`] lists every file and folder massredist wrote into the folder, at any
//! depth (issue 22, D6: a file a user adds inside a listed subfolder, such as `vtu/state.pvsm`,
//! is not ours, so a rerun refuses to replace the folder without `--force`).

use super::staging::{self, Live};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use super::MARKER;

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
    /// A folder with the marker that also holds files or folders, at any depth, that the marker
    /// does not list.
    #[error(
        "{} was written by massredist but also holds {} it did not write; move them out, use --force to replace the folder and delete them, or choose another --out",
        path.display(),
        entries_phrase(*count, example)
    )]
    Unlisted { path: PathBuf, count: usize, example: String },
    /// The path names no folder (`.`, `..`, `/`).
    #[error("{} does not name a folder; give one such as results/run1", path.display())]
    NoName { path: PathBuf },
    /// The path ends in `.` or `..` after a folder (`NEW/.`): it names that folder only through
    /// itself, and a folder cannot be renamed into place under such a name.
    #[error("--out {} ends in '{last}', which cannot be the name of a new folder; write the folder's own name ({})", path.display(), plain.display())]
    Dotted { path: PathBuf, last: &'static str, plain: PathBuf },
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
/// temporary folder (and the parents `prepare` created), and so does SIGTERM, SIGINT or SIGHUP
/// once [`super::install_signal_cleanup`] ran.
///
/// What may be replaced:
/// - nothing there, or an empty folder: always used;
/// - a folder carrying the [`MARKER`] and holding only what it lists (at any depth): its listed
///   files and folders are deleted;
/// - with `force`, also a non-empty folder without the marker, or one holding anything the
///   marker does not list: replaced, and what it held deleted;
/// - never, not even with `force`: something that is not a folder (a file, a symbolic link, also
///   when written `LINK/`), or a folder that is or contains a protected path (the given inputs,
///   such as the scene file; the current folder; the home folder). A path ending in `/.` or
///   `/..` is refused; trailing slashes are dropped.
///
/// The replaced folder is moved aside to `.NAME.tmp-<pid>-old` and emptied; if that fails the
/// error names it. Partial folders `.NAME.tmp-<pid>[-old]` next to the target are removed when
/// they carry the marker and their run is over (`staging.rs`).
#[derive(Debug)]
pub struct OutputDir {
    path: PathBuf,
    staging: PathBuf,
    force: bool,
    protected: Vec<(PathBuf, &'static str)>,
    removed: Vec<PathBuf>,
    /// The staging folder and created parents, registered for removal on a signal.
    live: Live,
    committed: bool,
}

/// What stands at an output path that may be used.
enum Existing {
    /// Nothing, or an empty folder.
    Free,
    /// A folder of ours holding only these listed entries (relative paths; folders end in `/`).
    Ours(BTreeSet<String>),
    /// A folder replaced by force: everything in it goes.
    Forced,
}

/// `path` without trailing slashes; refused when it then ends in `.` or `..` after a folder
/// (issue 22, D14: such a path passed the checks and failed at the final rename, after the
/// whole computation).
fn plain(path: &Path) -> Result<PathBuf, OutputError> {
    use std::os::unix::ffi::OsStrExt;
    let bytes = path.as_os_str().as_bytes();
    let end = bytes.iter().rposition(|&b| b != b'/').map_or(bytes.len().min(1), |i| i + 1);
    let trimmed = Path::new(std::ffi::OsStr::from_bytes(&bytes[..end]));
    let last = trimmed.as_os_str().as_bytes().rsplit(|&b| b == b'/').next().unwrap_or_default();
    let dotted = match last {
        b"." => Some("."),
        b".." => Some(".."),
        _ => None,
    };
    match dotted {
        Some(last) if end > last.len() => {
            let rest = &bytes[..end - last.len()];
            let keep = rest.iter().rposition(|&b| b != b'/').map_or(rest.len().min(1), |i| i + 1);
            let plain = PathBuf::from(std::ffi::OsStr::from_bytes(&rest[..keep]));
            Err(OutputError::Dotted { path: path.into(), last, plain })
        }
        _ => Ok(trimmed.to_path_buf()),
    }
}

impl OutputDir {
    /// Checks `path` (see [`OutputDir`] for what is refused), then creates the missing parents
    /// and the temporary sibling folder with the marker, and removes partial folders of earlier
    /// interrupted runs. `protect` are inputs never to be replaced, such as the scene file.
    pub fn prepare(path: &Path, force: bool, protect: &[&Path]) -> Result<OutputDir, OutputError> {
        let path = &plain(path)?;
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
        let removed = staging::remove_left_overs(&parent, &name);
        let staging_dir = parent.join(format!(".{name}.tmp-{}", std::process::id()));
        // Registered before it exists, so that a signal from here on removes what was made.
        let live = Live::register(staging_dir.clone(), created_parents);
        let out =
            OutputDir { path: path.into(), staging: staging_dir, force, protected, removed, live, committed: false };
        if let Err(e) = std::fs::create_dir(&out.staging) {
            return Err(unwritable(&out.staging, e));
        }
        // From here on Drop removes the staging folder; the marker makes it recognisable as
        // ours, the owner file tells a later run whether this run still goes on.
        let marker = out.staging.join(MARKER);
        std::fs::write(&marker, marker_head()).map_err(|e| unwritable(&marker, e))?;
        staging::write_owner(&out.staging).map_err(|(at, e)| unwritable(&at, e))?;
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

    /// Partial folders of earlier interrupted runs that `prepare` removed.
    pub fn removed_left_overs(&self) -> &[PathBuf] {
        &self.removed
    }

    /// Writes the folder: `fill` writes into the temporary folder, the marker gets the list of
    /// what it wrote, the target is checked again (it may have changed while computing) and the
    /// temporary folder is renamed into place; the old folder is moved aside and its listed
    /// entries (or, forced, all of it) deleted.
    pub fn commit(mut self, fill: impl FnOnce(&Path) -> std::io::Result<()>) -> Result<(), OutputError> {
        fill(&self.staging).map_err(|e| self.fill_error(e))?;
        staging::remove_owner(&self.staging).map_err(|e| self.fill_error(e))?;
        write_marker(&self.staging).map_err(|e| self.fill_error(e))?;
        let rename = |from: &Path, to: &Path| {
            std::fs::rename(from, to).map_err(|source| OutputError::Rename { from: from.into(), to: to.into(), source })
        };
        // A signal waits until the renames are done (and then finds nothing to remove).
        let guard = self.live.hold();
        let old = PathBuf::from(format!("{}-old", self.staging.display()));
        let listed = match classify(&self.path, self.force, &self.protected)? {
            // A rename replaces an empty folder.
            Existing::Free => {
                rename(&self.staging, &self.path)?;
                None
            }
            existing => {
                let _ = std::fs::remove_dir_all(&old);
                rename(&self.path, &old)?;
                if let Err(e) = rename(&self.staging, &self.path) {
                    let _ = std::fs::rename(&old, &self.path);
                    return Err(e);
                }
                Some(existing)
            }
        };
        self.committed = true;
        self.live.done(guard);
        let removal = match listed {
            None => return Ok(()),
            Some(Existing::Ours(entries)) => remove_listed(&old, &entries),
            Some(_) => std::fs::remove_dir_all(&old),
        };
        removal.map_err(|source| OutputError::OldKept { path: self.path.clone(), old, source })
    }
}

impl Drop for OutputDir {
    fn drop(&mut self) {
        if !self.committed {
            self.live.remove_now();
        }
    }
}

/// Deletes from `dir` the listed files, then the listed folders (deepest first) and the marker,
/// then `dir`: anything else in it makes the last step fail, and it is kept.
fn remove_listed(dir: &Path, entries: &BTreeSet<String>) -> std::io::Result<()> {
    for file in entries.iter().filter(|e| !e.ends_with('/')) {
        std::fs::remove_file(dir.join(file))?;
    }
    for folder in entries.iter().rev().filter(|e| e.ends_with('/')) {
        std::fs::remove_dir(dir.join(folder))?;
    }
    std::fs::remove_file(dir.join(MARKER))?;
    std::fs::remove_dir(dir)
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
    let entries = walk(path).map_err(unreadable)?;
    if entries.is_empty() {
        return Ok(Existing::Free);
    }
    let Some(listed) = read_marker(path) else {
        let top: Vec<&String> = entries.iter().filter(|e| !e.trim_end_matches('/').contains('/')).collect();
        let example = top.first().map_or_else(String::new, |e| e.trim_end_matches('/').to_string());
        return if force {
            Ok(Existing::Forced)
        } else {
            Err(OutputError::Foreign { path: path.into(), count: top.len(), example })
        };
    };
    let unlisted: Vec<&String> = entries.iter().filter(|e| *e != MARKER && !listed.contains(*e)).collect();
    match unlisted.first() {
        None => Ok(Existing::Ours(entries.into_iter().filter(|e| e != MARKER).collect())),
        Some(_) if force => Ok(Existing::Forced),
        Some(first) => {
            Err(OutputError::Unlisted { path: path.into(), count: unlisted.len(), example: (*first).clone() })
        }
    }
}

/// Everything under `dir`, at any depth, as paths relative to it (`a/b.csv`; folders `a/`),
/// sorted. Symbolic links are entries, not followed.
fn walk(dir: &Path) -> std::io::Result<BTreeSet<String>> {
    let mut out = BTreeSet::new();
    walk_each(dir, |name| {
        out.insert(name.to_string());
        Ok(())
    })?;
    Ok(out)
}

/// [`walk`]'s entries handed to `each` one at a time, in directory order, without collecting
/// them: the marker of a run with 10⁵ frames is written in constant memory.
fn walk_each(dir: &Path, mut each: impl FnMut(&str) -> std::io::Result<()>) -> std::io::Result<()> {
    let mut pending = vec![(dir.to_path_buf(), String::new())];
    while let Some((at, prefix)) = pending.pop() {
        for e in std::fs::read_dir(&at)? {
            let e = e?;
            let name = format!("{prefix}{}", e.file_name().to_string_lossy());
            if e.file_type()?.is_dir() {
                let folder = format!("{name}/");
                each(&folder)?;
                pending.push((e.path(), folder));
            } else {
                each(&name)?;
            }
        }
    }
    Ok(())
}

/// What the marker in `dir` lists, or `None` without a marker massredist wrote.
fn read_marker(dir: &Path) -> Option<BTreeSet<String>> {
    let text = staging::read_marker_text(dir)?;
    Some(text.lines().skip(1).map(String::from).collect())
}

/// The marker's first line: tool, version and the command line that wrote the folder.
fn marker_head() -> String {
    let mut args = std::env::args_os().map(|a| a.to_string_lossy().replace('\n', " "));
    let program = args.next().map(|a| Path::new(&a).file_name().map_or(a.clone(), |n| n.to_string_lossy().into()));
    let command: Vec<String> = program.into_iter().chain(args).collect();
    format!(
        "{} {} wrote this folder (`{}`); a later massredist run may replace it. Files and folders written (folders end in /):\n",
        staging::MARKER_TOOL,
        env!("CARGO_PKG_VERSION"),
        command.join(" ")
    )
}

/// Completes the marker in `dir` with everything written into it, at any depth (sorted).
fn write_marker(dir: &Path) -> std::io::Result<()> {
    use std::io::Write;
    // Written beside the folder's entries and renamed in, so that the walk skips it by name.
    let part_name = format!("{MARKER}.part");
    let part = dir.join(&part_name);
    let mut w = std::io::BufWriter::new(std::fs::File::create(&part)?);
    w.write_all(marker_head().as_bytes())?;
    walk_each(dir, |n| if n == MARKER || n == part_name { Ok(()) } else { writeln!(w, "{n}") })?;
    w.flush()?;
    drop(w);
    std::fs::rename(part, dir.join(MARKER))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trailing_slashes_are_dropped_and_dots_refused() {
        assert_eq!(plain(Path::new("a/b//")).unwrap(), Path::new("a/b"));
        assert_eq!(plain(Path::new("/")).unwrap(), Path::new("/"));
        assert_eq!(plain(Path::new(".")).unwrap(), Path::new("."));
        assert_eq!(plain(Path::new("a/.b")).unwrap(), Path::new("a/.b"));
        for (dotted, last) in [("new/.", "."), ("new/./", "."), ("m/..", ".."), ("/.", ".")] {
            match plain(Path::new(dotted)) {
                Err(OutputError::Dotted { last: l, .. }) => assert_eq!(l, last, "{dotted}"),
                other => panic!("{dotted}: {other:?}"),
            }
        }
    }
}
