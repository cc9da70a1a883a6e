//! Output folders never cost the user data: `--out` at a file, at the scene file, or at a folder
//! massredist did not write is refused with exit code 2 before anything is computed; a folder
//! carrying the `.massredist-output` marker is replaced whole; `--force` replaces a foreign folder
//! but never a file, the scene's folder or the current folder; a partial folder left by a killed
//! run is removed by the next run; an unwritable place fails before computing.
//!
//! Each test runs the built binary in a temporary folder. Exit codes: 0 success, 1 failure while
//! computing or writing, 2 invalid input or refused output (nothing computed, nothing written).

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

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts a refusal: exit code 2, a message containing every needle, and no run output.
fn assert_refused(o: &Output, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    for n in needles {
        assert!(err.contains(n), "message lacks {n:?}: {err}");
    }
    assert!(!err.contains(" steps in "), "the run was computed before the refusal: {err}");
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

/// A pid that is certainly not running: a child that has exited and been reaped.
fn dead_pid() -> u32 {
    let mut child = Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    pid
}

/// A partial folder `.out.tmp-<pid>` left by a killed run is removed by the next run into
/// `out`; one of a live process, and look-alike names, are left alone.
#[test]
fn a_partial_folder_of_a_killed_run_is_removed() {
    let (tmp, scene) = with_scene();
    let stale = tmp.path().join(format!(".out.tmp-{}", dead_pid()));
    std::fs::create_dir(&stale).unwrap();
    std::fs::write(stale.join("series.csv"), vec![b'0'; 1 << 20]).unwrap();
    // The test process is alive and is not a massredist run: without the marker, its folder
    // could be anything, so it stays.
    let live = format!(".out.tmp-{}", std::process::id());
    std::fs::create_dir(tmp.path().join(&live)).unwrap();
    std::fs::create_dir(tmp.path().join(".out.tmp-notapid")).unwrap();
    // A live process that is not massredist, and a folder carrying the marker under its pid:
    // the pid was reused after the run that wrote the folder was killed.
    let mut sleeper = Command::new("sleep").arg("60").spawn().unwrap();
    let reused = tmp.path().join(format!(".out.tmp-{}", sleeper.id()));
    std::fs::create_dir(&reused).unwrap();
    std::fs::write(reused.join(MARKER), "massredist (killed)\n").unwrap();
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
    for cmd in ["reproduce", "bench"] {
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
