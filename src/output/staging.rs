//! The temporary sibling `.NAME.tmp-<pid>` of an output folder while it is written: who owns
//! it, when a later run may remove it, and its removal on a signal.
//!
//! Issue 22 found three ways this cost data or left litter:
//! * D10: an unmarked folder a user named `.res.tmp-<dead pid>` was removed as a left-over. Only
//!   a folder carrying a marker massredist wrote is ever removed now.
//! * D11: whether the pid still runs the owner was judged by the program's name, so a
//!   `massredist` binary under another name had its live folder removed by a concurrent run.
//!   The staging folder now records its owner's pid *and start time* ([`OWNER`]); it is over
//!   when that pid runs no more, or runs a process started at another time (the pid was reused).
//! * D13: SIGTERM, SIGINT and SIGHUP killed the process with its folder in place. A signal
//!   thread ([`install_signal_cleanup`]) removes every live staging folder (and the parents
//!   `prepare` created, if empty) and exits with status 128 + signal, as a shell reports a
//!   process killed by that signal. SIGXFSZ (file size limit exceeded) is caught and otherwise
//!   ignored: the write that crossed the limit then fails with EFBIG, and the run takes its
//!   ordinary write-error path (exit 1, a message naming the folder, the staging folder
//!   removed) instead of dying by the signal.

use super::MARKER;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicI32, AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// The first word of a marker's first line: a folder is massredist's only if its marker starts
/// with it.
pub(super) const MARKER_TOOL: &str = "massredist";

/// The owner file of a staging folder: `pid <pid> start <ticks>`, the start time being field 22
/// of `/proc/<pid>/stat` (clock ticks after boot). Removed just before the folder is renamed
/// into place, so it never reaches a finished folder.
pub(super) const OWNER: &str = ".massredist-staging";

/// The text of the marker in `dir` if massredist wrote it (a regular file whose first line
/// starts with [`MARKER_TOOL`] and a space).
pub(super) fn read_marker_text(dir: &Path) -> Option<String> {
    let marker = dir.join(MARKER);
    if !std::fs::symlink_metadata(&marker).is_ok_and(|m| m.is_file()) {
        return None;
    }
    let text = std::fs::read_to_string(marker).ok()?;
    text.starts_with(&format!("{MARKER_TOOL} ")).then_some(text)
}

/// Writes the owner file of this process into `staging`; the error names the file.
pub(super) fn write_owner(staging: &Path) -> Result<(), (PathBuf, std::io::Error)> {
    let pid = std::process::id();
    let start = match process(pid) {
        Process::Started(start) => start.to_string(),
        _ => "unknown".into(),
    };
    let path = staging.join(OWNER);
    std::fs::write(&path, format!("pid {pid} start {start}\n")).map_err(|e| (path, e))
}

pub(super) fn remove_owner(staging: &Path) -> std::io::Result<()> {
    match std::fs::remove_file(staging.join(OWNER)) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(e),
        _ => Ok(()),
    }
}

/// The (pid, start) an owner file records, if it is well formed.
fn read_owner(staging: &Path) -> Option<(u32, u64)> {
    let text = std::fs::read_to_string(staging.join(OWNER)).ok()?;
    let mut words = text.split_whitespace();
    match (words.next(), words.next(), words.next(), words.next()) {
        (Some("pid"), Some(pid), Some("start"), Some(start)) => Some((pid.parse().ok()?, start.parse().ok()?)),
        _ => None,
    }
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
    /// Running, started this many clock ticks after boot.
    Started(u64),
}

/// Reads `/proc/<pid>/stat` (Linux): a zombie counts as gone.
fn process(pid: u32) -> Process {
    if !Path::new("/proc/self/stat").exists() {
        return Process::Unknown;
    }
    match std::fs::read_to_string(format!("/proc/{pid}/stat")) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Process::Gone,
        Err(_) => Process::Unknown,
        // "<pid> (<comm>) <state> <ppid> …": comm may itself hold ") "; after it come fields
        // 3 (state) to 52, the start time being field 22.
        Ok(stat) => {
            let Some(b) = stat.rfind(") ") else { return Process::Unknown };
            let fields: Vec<&str> = stat[b + 2..].split_whitespace().collect();
            match (fields.first(), fields.get(22 - 3).and_then(|s| s.parse().ok())) {
                (Some(&("Z" | "X")), _) => Process::Gone,
                (Some(_), Some(start)) => Process::Started(start),
                _ => Process::Unknown,
            }
        }
    }
}

/// Whether the run that made the partial folder `dir` (named with `pid`) is over: its pid is
/// this process's, or runs no more, or (owner file present) runs a process started at another
/// time than the owner. Without an owner file (a folder aside `-old`, an older version, or the
/// instant before the rename) only a pid that runs no more counts.
fn run_is_over(dir: &Path, pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    match (read_owner(dir), process(pid)) {
        (_, Process::Gone) => true,
        (Some((owner, start)), Process::Started(now)) => owner == pid && start != now,
        _ => false,
    }
}

/// Removes the partial folders of target `name` in `parent` that carry massredist's marker and
/// whose run is over; returns them.
pub(super) fn remove_left_overs(parent: &Path, name: &str) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(parent) else { return Vec::new() };
    let mut removed = Vec::new();
    for e in entries.flatten() {
        let Some(pid) = partial_folder_pid(&e.file_name().to_string_lossy(), name) else { continue };
        let path = e.path();
        let ours = e.file_type().is_ok_and(|t| t.is_dir()) && read_marker_text(&path).is_some();
        if ours && run_is_over(&path, pid) && std::fs::remove_dir_all(&path).is_ok() {
            removed.push(path);
        }
    }
    removed
}

// ---------------------------------------------------------------------------------------------
// Live staging folders, for the signal thread.

/// A live staging folder: id, path, and the parents `prepare` created (innermost first).
type Entry = (u64, PathBuf, Vec<PathBuf>);

static LIVE: Mutex<Vec<Entry>> = Mutex::new(Vec::new());
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

fn live() -> MutexGuard<'static, Vec<Entry>> {
    LIVE.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Removes a staging folder (a few tries: a writer may add a file while it goes) and the
/// created parents that are empty.
fn remove_tree(staging: &Path, parents: &[PathBuf]) {
    for _ in 0..3 {
        if std::fs::remove_dir_all(staging).is_ok() || !staging.exists() {
            break;
        }
    }
    // Only empty ones go: remove_dir fails on a folder holding anything.
    for p in parents {
        let _ = std::fs::remove_dir(p);
    }
}

/// The registration of one staging folder in the list the signal thread empties.
#[derive(Debug)]
pub(super) struct Live {
    id: u64,
    staging: PathBuf,
    parents: Vec<PathBuf>,
}

impl Live {
    pub fn register(staging: PathBuf, parents: Vec<PathBuf>) -> Live {
        let id = NEXT_ID.fetch_add(1, Ordering::Relaxed);
        live().push((id, staging.clone(), parents.clone()));
        Live { id, staging, parents }
    }

    /// Holds the list: a signal arriving meanwhile waits (used around the final renames).
    pub fn hold(&self) -> MutexGuard<'static, Vec<Entry>> {
        live()
    }

    /// The folder was renamed into place: nothing to remove any more.
    pub fn done(&self, mut held: MutexGuard<'static, Vec<Entry>>) {
        held.retain(|e| e.0 != self.id);
    }

    /// Removes the folder now (an uncommitted `OutputDir` dropped) and unregisters it.
    pub fn remove_now(&self) {
        let mut held = live();
        if held.iter().any(|e| e.0 == self.id) {
            remove_tree(&self.staging, &self.parents);
            held.retain(|e| e.0 != self.id);
        }
    }
}

/// Process groups of children that write into a staging folder (the FEniCSx engine's `mpirun`
/// and its ranks): the signal thread forwards the signal to them first.
static GROUPS: Mutex<Vec<i32>> = Mutex::new(Vec::new());

/// A child's process group registered for signal forwarding while the guard lives (the child
/// was started with `process_group(0)`, so its group id is its pid).
#[derive(Debug)]
pub struct ChildGroup(i32);

impl ChildGroup {
    pub fn register(pid: u32) -> ChildGroup {
        let pgid = pid as i32;
        GROUPS.lock().unwrap_or_else(PoisonError::into_inner).push(pgid);
        ChildGroup(pgid)
    }
}

impl Drop for ChildGroup {
    fn drop(&mut self) {
        GROUPS.lock().unwrap_or_else(PoisonError::into_inner).retain(|&g| g != self.0);
    }
}

/// The signal the signal thread is handling (0: none yet).
static SIGNALLED: AtomicI32 = AtomicI32::new(0);

/// Once a stopping signal arrived, blocks for ever: the signal thread ends the process with
/// 128 + the signal after it removed the temporary folders. Called by the main thread before it
/// reports an error or exits, since a child stopped by the forwarded signal makes the main
/// thread's work fail first (issue 32, E15: `run --engine fenicsx` exited 1, not 143). Returns
/// at once when no signal arrived.
pub fn wait_if_signalled() {
    while SIGNALLED.load(Ordering::SeqCst) != 0 {
        std::thread::park_timeout(std::time::Duration::from_secs(1));
    }
}

/// Sends `signal` to every registered group and waits (at most 5 s) until they are gone, so
/// that nothing writes into a staging folder while it is removed.
fn stop_groups(signal: i32) {
    let groups = GROUPS.lock().unwrap_or_else(PoisonError::into_inner).clone();
    for &g in &groups {
        // SAFETY: kill(2) with a negative pid signals a process group; no memory is involved.
        unsafe { libc::kill(-g, signal) };
    }
    let started = std::time::Instant::now();
    // kill(-g, 0) fails (ESRCH) once no process of the group is left.
    while groups.iter().any(|&g| unsafe { libc::kill(-g, 0) } == 0) && started.elapsed().as_secs() < 5 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// Starts the signal thread (module docs): on SIGTERM, SIGINT or SIGHUP it forwards the signal
/// to the registered child groups ([`ChildGroup`]), removes every live staging folder and exits
/// with 128 + the signal; SIGXFSZ is caught so that the write fails instead. Call once, early in
/// `main`.
pub fn install_signal_cleanup() -> std::io::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM, SIGXFSZ};
    let mut signals = signal_hook::iterator::Signals::new([SIGTERM, SIGINT, SIGHUP, SIGXFSZ])?;
    std::thread::Builder::new().name("signals".into()).spawn(move || {
        for signal in signals.forever() {
            if signal == SIGXFSZ {
                continue;
            }
            SIGNALLED.store(signal, Ordering::SeqCst);
            stop_groups(signal);
            let held = live();
            for (_, staging, parents) in held.iter() {
                remove_tree(staging, parents);
            }
            std::process::exit(128 + signal);
        }
    })?;
    Ok(())
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

    #[test]
    fn this_process_has_a_start_time() {
        if Path::new("/proc/self/stat").exists() {
            assert!(matches!(process(std::process::id()), Process::Started(_)));
        }
    }
}
