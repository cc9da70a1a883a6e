//! Output folders never cost the user data: `--out` at a file, at the scene file, or at a folder
//! massredist did not write is refused with exit code 2 before anything is computed; a folder
//! carrying the `.massredist-output` marker is replaced whole; `--force` replaces a foreign folder
//! but never a file, the scene's folder or the current folder; a partial folder left by a killed
//! run is removed by the next run (also after a real `kill -9` while the series streams); an
//! unwritable place fails before computing; a write error while streaming fails the run (exit 1)
//! and leaves nothing.
//!
//! Each test runs the built binary in a temporary folder. Exit codes: 0 success, 1 failure while
//! computing or writing, 2 invalid input or refused output (nothing computed, nothing written).

mod common;
use common::{assert_refused, dead_pid, stderr};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const MARKER: &str = ".massredist-output";

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_massredist"))
}

/// The shipped Figure 11 scene (300 steps: a fraction of a second).
fn shipped_scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/fig11-mod3.toml")
}

/// Its series line, to be replaced by `series = []`.
const SERIES: &str = r#"series = ["u0", "lambda", "energy", "l2_error"]"#;

/// The names in `dir` (hidden ones included), sorted.
fn names(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect()
}

fn set(items: &[&str]) -> BTreeSet<String> {
    items.iter().map(|s| s.to_string()).collect()
}

/// `massredist run SCENE --out OUT [extra…]`.
fn run(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    bin().arg("run").arg(scene).arg("--out").arg(out).args(extra).output().unwrap()
}

/// A temporary folder holding the test scene as `s.toml`.
fn with_scene() -> (tempfile::TempDir, PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("s.toml");
    std::fs::copy(shipped_scene(), &scene).unwrap();
    (tmp, scene)
}

/// The issue's example: a project folder holding the scene and the user's notes, given as
/// `--out`. Refused (even with `--force`) before computing; both files stay as they were.
#[test]
fn out_at_the_project_folder_holding_the_scene_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let proj = tmp.path().join("proj");
    std::fs::create_dir(&proj).unwrap();
    std::fs::copy(shipped_scene(), proj.join("scene.toml")).unwrap();
    std::fs::write(proj.join("notes.txt"), "notes\n").unwrap();
    for extra in [&[][..], &["--force"]] {
        let o = run(&proj.join("scene.toml"), &proj, extra);
        assert_refused(&o, &["scene.toml", "choose another --out"]);
        assert_eq!(names(&proj), set(&["notes.txt", "scene.toml"]), "{extra:?}");
        assert_eq!(std::fs::read_to_string(proj.join("notes.txt")).unwrap(), "notes\n");
        assert_eq!(std::fs::read(proj.join("scene.toml")).unwrap(), std::fs::read(shipped_scene()).unwrap());
        assert_eq!(names(tmp.path()), set(&["proj"]), "no temporary or old sibling is left");
    }
}

/// `--out` naming an existing regular file, or the scene file itself: refused (even with
/// `--force`), the file untouched, nothing else created.
#[test]
fn out_at_a_file_or_at_the_scene_file_is_refused() {
    let (tmp, scene) = with_scene();
    let file = tmp.path().join("results.txt");
    std::fs::write(&file, "mine\n").unwrap();
    for extra in [&[][..], &["--force"]] {
        let o = run(&scene, &file, extra);
        assert_refused(&o, &["results.txt", "is a file", "choose another --out"]);
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine\n");
        let o = run(&scene, &scene, extra);
        assert_refused(&o, &["s.toml", "choose another --out"]);
        assert_eq!(std::fs::read(&scene).unwrap(), std::fs::read(shipped_scene()).unwrap());
        assert_eq!(names(tmp.path()), set(&["results.txt", "s.toml"]), "{extra:?}: nothing else created");
    }
    // The same for a plate scene (the 2D path of `run`).
    let plate = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/plate-table-mod3.toml");
    assert_refused(&run(&plate, &file, &[]), &["results.txt", "is a file"]);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine\n");
    assert_eq!(names(tmp.path()), set(&["results.txt", "s.toml"]));
}

/// `reproduce --out FILE` is refused before its experiments run; the file stays.
#[cfg(feature = "study")]
#[test]
fn reproduce_out_at_a_file_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("report");
    std::fs::write(&file, "mine\n").unwrap();
    let o = bin().args(["reproduce", "--quick", "--force", "--out"]).arg(&file).output().unwrap();
    assert_refused(&o, &["report", "is a file"]);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine\n");
    assert_eq!(names(tmp.path()), set(&["report"]));
}

/// A folder massredist wrote carries the marker; running again into it replaces it whole: the
/// old entries are gone, the new ones and the marker are there, no sibling is left.
#[test]
fn a_marked_folder_is_replaced_whole() {
    let (tmp, scene) = with_scene();
    let out = tmp.path().join("out");
    let o = run(&scene, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(names(&out), set(&[MARKER, "scene.resolved.toml", "series.csv", "summary.json"]));
    let marker = std::fs::read_to_string(out.join(MARKER)).unwrap();
    assert!(marker.lines().next().unwrap().contains("massredist"), "{marker}");
    // Second run without a series: series.csv must disappear with the old folder.
    let text = std::fs::read_to_string(&scene).unwrap();
    assert!(text.contains(SERIES));
    std::fs::write(&scene, text.replace(SERIES, "series = []")).unwrap();
    let o = run(&scene, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(names(&out), set(&[MARKER, "scene.resolved.toml", "summary.json"]));
    assert_eq!(names(tmp.path()), set(&["out", "s.toml"]), "no .out.old-* or .out.tmp-* left");
}

/// A marked folder to which the user added a file is no longer massredist's alone: refused
/// without `--force` (the file kept), replaced with it.
#[test]
fn a_marked_folder_with_a_users_file_needs_force() {
    let (tmp, scene) = with_scene();
    let out = tmp.path().join("out");
    assert!(run(&scene, &out, &[]).status.success());
    std::fs::write(out.join("notes.txt"), "mine\n").unwrap();
    let o = run(&scene, &out, &[]);
    assert_refused(&o, &["notes.txt", "--force"]);
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).unwrap(), "mine\n");
    let o = run(&scene, &out, &["--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(names(&out), set(&[MARKER, "scene.resolved.toml", "series.csv", "summary.json"]));
    assert_eq!(names(tmp.path()), set(&["out", "s.toml"]));
}

/// `--force` rule: a non-empty folder without the marker is refused, and replaced with
/// `--force`; an empty folder is used as it is; the current folder is never replaced.
#[test]
fn force_replaces_a_foreign_folder_but_never_the_current_one() {
    let (tmp, scene) = with_scene();
    let other = tmp.path().join("other");
    std::fs::create_dir_all(other.join("sub")).unwrap();
    std::fs::write(other.join("sub/data.csv"), "1\n").unwrap();
    let o = run(&scene, &other, &[]);
    assert_refused(&o, &["other", "--force"]);
    assert_eq!(std::fs::read_to_string(other.join("sub/data.csv")).unwrap(), "1\n");
    assert_eq!(names(tmp.path()), set(&["other", "s.toml"]));
    let o = run(&scene, &other, &["--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(names(&other), set(&[MARKER, "scene.resolved.toml", "series.csv", "summary.json"]));
    assert_eq!(names(tmp.path()), set(&["other", "s.toml"]));

    let empty = tmp.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let o = run(&scene, &empty, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(empty.join("summary.json").is_file());

    // The current folder (here a fresh one holding only a user's file) is never replaced.
    let cwd = tmp.path().join("work");
    std::fs::create_dir(&cwd).unwrap();
    std::fs::write(cwd.join("keep.txt"), "mine\n").unwrap();
    for out in [".", "../work"] {
        let o = bin().current_dir(&cwd).arg("run").arg(&scene).args(["--out", out, "--force"]).output().unwrap();
        assert_refused(&o, &["current folder"]);
        assert_eq!(names(&cwd), set(&["keep.txt"]), "{out}");
    }
}

/// A partial folder `.out.tmp-<pid>` left by a killed run (it carries the marker) is removed by
/// the next run into `out`; one of a live process, and look-alike names, are left alone (an
/// unmarked one too, even under a dead pid: `tests/outputs_hostile.rs`).
#[test]
fn a_partial_folder_of_a_killed_run_is_removed() {
    let (tmp, scene) = with_scene();
    let stale = tmp.path().join(format!(".out.tmp-{}", dead_pid()));
    std::fs::create_dir(&stale).unwrap();
    std::fs::write(stale.join("series.csv"), vec![b'0'; 1 << 20]).unwrap();
    std::fs::write(stale.join(MARKER), "massredist 0.1.0 wrote this folder\n").unwrap();
    // The test process is alive and is not a massredist run: without the marker, its folder
    // could be anything, so it stays.
    let live = format!(".out.tmp-{}", std::process::id());
    std::fs::create_dir(tmp.path().join(&live)).unwrap();
    std::fs::create_dir(tmp.path().join(".out.tmp-notapid")).unwrap();
    // A live process, and a folder carrying the marker and an owner file under its pid with
    // another start time: the pid was reused after the run that wrote the folder was killed.
    let mut sleeper = Command::new("sleep").arg("60").spawn().unwrap();
    let reused = tmp.path().join(format!(".out.tmp-{}", sleeper.id()));
    std::fs::create_dir(&reused).unwrap();
    std::fs::write(reused.join(MARKER), "massredist (killed)\n").unwrap();
    std::fs::write(reused.join(".massredist-staging"), format!("pid {} start 1\n", sleeper.id())).unwrap();
    let o = run(&scene, &tmp.path().join("out"), &[]);
    sleeper.kill().unwrap();
    sleeper.wait().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stale.exists(), "the partial folder of the dead run is removed");
    assert!(!reused.exists(), "the marked partial folder under a reused pid is removed");
    assert!(stderr(&o).contains(&stale.file_name().unwrap().to_string_lossy().into_owned()), "{}", stderr(&o));
    assert_eq!(names(tmp.path()), set(&[".out.tmp-notapid", &live, "out", "s.toml"]));
}

/// An output folder that cannot be created fails before computing, with exit code 2 and
/// nothing written: a path under a regular file (which stops root too), for run, reproduce
/// and bench.
#[test]
fn an_unwritable_place_fails_before_computing() {
    let (tmp, scene) = with_scene();
    let file = tmp.path().join("file");
    std::fs::write(&file, "mine\n").unwrap();
    let under = file.join("sub");
    let o = run(&scene, &under, &[]);
    assert_refused(&o, &["file/sub"]);
    // The study's subcommands are in the binary with the default feature `study`.
    let study: &[&str] = if cfg!(feature = "study") { &["reproduce", "bench"] } else { &[] };
    for cmd in study {
        let o = bin().args([cmd, "--quick", "--out"]).arg(&under).output().unwrap();
        assert_refused(&o, &["file/sub"]);
    }
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine\n");
    assert_eq!(names(tmp.path()), set(&["file", "s.toml"]));
}

/// The same with a read-only parent folder. Root is not stopped by permissions: then the
/// case is skipped, saying so.
#[cfg(unix)]
#[test]
fn a_read_only_parent_fails_before_computing() {
    use std::os::unix::fs::PermissionsExt;
    let (tmp, scene) = with_scene();
    let parent = tmp.path().join("ro");
    std::fs::create_dir(&parent).unwrap();
    std::fs::set_permissions(&parent, std::fs::Permissions::from_mode(0o555)).unwrap();
    if std::fs::create_dir(parent.join("probe")).is_ok() {
        eprintln!("skipped: permissions do not stop this user (root?) from writing into a 0555 folder");
        return;
    }
    let o = run(&scene, &parent.join("out"), &[]);
    std::fs::set_permissions(&parent, std::fs::Permissions::from_mode(0o755)).unwrap();
    assert_refused(&o, &["ro/out", "Permission denied"]);
    assert!(names(&parent).is_empty());
}

/// A bar scene of 10⁸ steps writing a series of 10⁷ rows (about 400 MB): it runs far longer
/// than the tests below wait for it, and its series grows from the first steps.
const LONG: &str = "[bar]\nlength = 1.0\nelements = 20\ninitial = \"paper\"\n[mass]\nkind = \"mod3\"\n\
                    [scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = 1e-5\nend = 1000.0\n\
                    [output]\nseries = [\"u0\", \"lambda\"]\nevery = 10\n";

/// Every file under `dir` with its bytes (sorted by path).
fn contents(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(contents(&p));
        } else {
            out.push((p.clone(), std::fs::read(&p).unwrap()));
        }
    }
    out.sort();
    out
}

/// Starts `run LONG --out out` and kills it with SIGKILL once its temporary folder holds more
/// than 256 KiB of series (so it is killed while writing); returns the partial folder.
#[cfg(unix)]
fn kill_while_writing(scene: &Path, out: &Path) -> PathBuf {
    use std::os::unix::process::ExitStatusExt;
    let mut child =
        bin().arg("run").arg(scene).arg("--out").arg(out).stderr(std::process::Stdio::null()).spawn().unwrap();
    let partial = out.with_file_name(format!(".{}.tmp-{}", out.file_name().unwrap().to_string_lossy(), child.id()));
    // Wherever the run writes it (the checks below say where it must).
    let grown =
        || [&partial, out].iter().any(|d| std::fs::metadata(d.join("series.csv")).is_ok_and(|m| m.len() > 256 << 10));
    // Polls the state of the folders (a deadline only so that a broken build cannot hang the
    // suite: the run needs about 10⁸ steps to finish on its own).
    for _ in 0..6000 {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the long run ended before it was killed: {status}");
        }
        if grown() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(grown(), "the series grows");
    child.kill().unwrap();
    assert_eq!(child.wait().unwrap().signal(), Some(9));
    partial
}

/// `kill -9` while the series is being written: the final `--out` does not exist (first case) or
/// the older marked folder there is intact, byte for byte (second case); the user's file beside
/// it is untouched; the partial folder `.out.tmp-<pid>` is left, and the next run into `out`
/// removes it, says so, and succeeds.
/// mutation: `OutputDir::prepare` staging into the target itself (`staging: path.into()`, so
/// the series streams into `out`) -> fails with "the killed run left no final folder".
#[cfg(unix)]
#[test]
fn a_run_killed_while_writing_leaves_no_final_folder_and_the_next_run_cleans_up() {
    let (tmp, short) = with_scene();
    let long = tmp.path().join("long.toml");
    std::fs::write(&long, LONG).unwrap();
    let notes = tmp.path().join("notes.txt");
    std::fs::write(&notes, "mine\n").unwrap();
    let out = tmp.path().join("out");

    // 1. Nothing at `out` before: nothing there after.
    let partial = kill_while_writing(&long, &out);
    assert!(!out.exists(), "the killed run left no final folder");
    assert!(partial.is_dir(), "the partial folder of the killed run is left (nothing can remove it at kill -9)");
    let o = run(&short, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains(&format!("removed {}", partial.display())), "{}", stderr(&o));
    assert_eq!(names(tmp.path()), set(&["long.toml", "notes.txt", "out", "s.toml"]));

    // 2. A marked folder at `out` (the run above): intact after a killed run into it.
    let before = contents(&out);
    let partial = kill_while_writing(&long, &out);
    assert_eq!(contents(&out), before, "the older folder is intact");
    assert!(partial.is_dir());
    let o = run(&short, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains(&format!("removed {}", partial.display())), "{}", stderr(&o));
    assert_eq!(names(tmp.path()), set(&["long.toml", "notes.txt", "out", "s.toml"]));
    assert_eq!(std::fs::read_to_string(&notes).unwrap(), "mine\n");
}

/// A write error while streaming (here a file-size limit, `ulimit -f`, standing in for a full
/// disk; SIGXFSZ ignored so that the write fails with EFBIG instead of killing the process): the
/// run fails with exit code 1, the message names the folder and the error, the temporary folder is
/// removed and an older marked folder at `out` is intact.
/// mutation: `SeriesWriter::finish` ignoring the kept error and the flush's (`Ok(self.out)`) ->
/// fails with "exit code Some(0)" (a truncated series.csv committed in place of the old folder).
#[cfg(unix)]
#[test]
fn a_write_error_while_streaming_fails_and_leaves_nothing() {
    let (tmp, short) = with_scene();
    let out = tmp.path().join("out");
    let o = run(&short, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = contents(&out);
    // 3·10⁵ steps, a row every step: about 10 MB of series, far above the limit (100 blocks of
    // 512 B or 1 KiB, depending on the shell).
    let scene = tmp.path().join("mid.toml");
    std::fs::write(&scene, LONG.replace("end = 1000.0", "end = 3.0").replace("every = 10", "every = 1")).unwrap();
    let o = Command::new("sh")
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 100; exec \"$0\" run \"$1\" --out \"$2\"")
        .arg(env!("CARGO_BIN_EXE_massredist"))
        .arg(&scene)
        .arg(&out)
        .output()
        .unwrap();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "exit code {:?}: {err}", o.status.code());
    assert!(err.contains("out") && err.contains("File too large"), "{err}");
    assert_eq!(contents(&out), before, "the older folder is intact");
    assert_eq!(names(tmp.path()), set(&["mid.toml", "out", "s.toml"]), "no temporary folder is left");
}
