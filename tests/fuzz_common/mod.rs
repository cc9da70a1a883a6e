//! What the fuzzers share (tests/fuzz.rs, tests/fuzz_mesh.rs): the binary run under a patience
//! guard and the properties every hostile case asserts (no panic, a documented exit code).
#![allow(dead_code)]

use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use std::path::Path;
use std::process::{Command, Output};

/// The documented exit codes: 0 success, 1 failure while computing or writing, 2 invalid input
/// (nothing computed), 3 diverged.
pub const DOCUMENTED: [i32; 4] = [0, 1, 2, 3];

/// Runs the binary with `args`, its output in `logs` (not next to the scene). A case is a
/// 5-step run: one that has not finished after [`PATIENCE`] is killed and reported (it would be
/// a scene that passes `check` and then runs without end).
pub fn massredist(args: &[&std::ffi::OsStr], logs: &Path) -> Output {
    let (out, err) = (logs.join("stdout"), logs.join("stderr"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_massredist"))
        .args(args)
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .expect("the binary starts");
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > PATIENCE {
            child.kill().unwrap();
            panic!("massredist {args:?} did not finish in {PATIENCE:?}");
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    };
    Output { status, stdout: std::fs::read(out).unwrap(), stderr: std::fs::read(err).unwrap() }
}

/// A guard against runs without end, not a timing assertion: a 5-step case takes milliseconds.
pub const PATIENCE: std::time::Duration = std::time::Duration::from_secs(120);

/// Exit code (signals as 128 + n, as a shell shows them).
pub fn code(o: &Output) -> i32 {
    use std::os::unix::process::ExitStatusExt;
    o.status.code().unwrap_or_else(|| 128 + o.status.signal().unwrap_or(0))
}

/// Names in `dir` other than the scene file.
pub fn left_in(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "scene.toml")
        .collect()
}

pub fn no_panic(what: &str, o: &Output, text: &str) -> Result<(), TestCaseError> {
    let err = String::from_utf8_lossy(&o.stderr);
    let c = code(o);
    prop_assert!(!err.contains("panicked"), "{what} panicked: {err}\nscene:\n{text}");
    prop_assert!(c != 101 && c != 134, "{what}: exit code {c}: {err}\nscene:\n{text}");
    prop_assert!(DOCUMENTED.contains(&c), "{what}: exit code {c} is not documented: {err}\nscene:\n{text}");
    Ok(())
}
