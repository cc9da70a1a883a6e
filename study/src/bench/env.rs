//! The environment of a benchmark run, and the Python peer run as a subprocess (edge I/O).

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Where and with what the numbers were measured.
#[derive(Debug, Clone, Serialize)]
pub struct Environment {
    pub cpu: String,
    pub logical_cpus: usize,
    pub os: String,
    /// `rustc --version` on PATH at run time (the compiler of this binary is usually the same).
    pub rustc: String,
    pub profile: &'static str,
    pub git_commit: String,
    /// Uncommitted changes in the tree when the benchmark ran.
    pub git_dirty: bool,
    pub crate_version: &'static str,
    /// Seconds since the Unix epoch at the start of the run.
    pub unix_time: u64,
    pub rayon_threads: usize,
}

fn command_line(cmd: &str, args: &[&str], dir: Option<&Path>) -> Option<String> {
    let mut c = Command::new(cmd);
    c.args(args);
    if let Some(d) = dir {
        c.current_dir(d);
    }
    let out = c.output().ok()?;
    out.status.success().then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// The source tree of this crate (for git and the Python script).
pub fn crate_dir() -> PathBuf {
    crate::repo::root()
}

impl Environment {
    pub fn detect() -> Self {
        let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
        let cpu = cpuinfo
            .lines()
            .find(|l| l.starts_with("model name"))
            .and_then(|l| l.split(':').nth(1))
            .map_or_else(|| std::env::consts::ARCH.to_string(), |s| s.trim().to_string());
        let dir = crate_dir();
        let unknown = || "unknown".to_string();
        Self {
            cpu,
            logical_cpus: std::thread::available_parallelism().map_or(1, |n| n.get()),
            os: command_line("uname", &["-sr"], None).unwrap_or_else(|| std::env::consts::OS.to_string()),
            rustc: command_line("rustc", &["--version"], None).unwrap_or_else(unknown),
            profile: if cfg!(debug_assertions) { "debug" } else { "release" },
            git_commit: command_line("git", &["rev-parse", "HEAD"], Some(&dir)).unwrap_or_else(unknown),
            git_dirty: command_line("git", &["status", "--porcelain", "--untracked-files=no"], Some(&dir))
                .is_some_and(|s| !s.is_empty()),
            crate_version: env!("CARGO_PKG_VERSION"),
            unix_time: std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs()),
            rayon_threads: rayon::current_num_threads(),
        }
    }
}

/// One stepper timed by `python/scripts/bench_stepper.py`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PythonRun {
    /// "pttrs" (numpy + LAPACK dpttrs loop) or "stepper" (python/crosscheck/stepper.py, dense Cholesky).
    pub implementation: String,
    pub scheme: String,
    pub mass: String,
    pub steps: usize,
    pub seconds_per_step: f64,
    pub u_final: Vec<f64>,
}

/// The JSON printed by `python/scripts/bench_stepper.py`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PythonTiming {
    pub python: String,
    pub python_version: String,
    pub numpy: String,
    pub scipy: String,
    pub elements: usize,
    pub runs: Vec<PythonRun>,
    pub missing: Vec<String>,
}

/// The interpreter with numpy/scipy (Debian's; the `python3` on PATH may not see them).
pub const PYTHON: &str = "/usr/bin/python3";

/// Runs `python/scripts/NAME` with `args` under [`PYTHON`] and parses the JSON it prints; the error
/// says why it could not.
pub fn run_json<T: serde::de::DeserializeOwned>(name: &str, args: &[String]) -> Result<T, String> {
    let script = crate_dir().join("python").join("scripts").join(name);
    if !script.exists() {
        return Err(format!("{} not found", script.display()));
    }
    let out =
        Command::new(PYTHON).arg(&script).args(args).output().map_err(|e| format!("cannot start {PYTHON}: {e}"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!("{PYTHON} {} failed: {}", script.display(), err.lines().last().unwrap_or("")));
    }
    serde_json::from_slice(&out.stdout).map_err(|e| format!("cannot parse the output of {}: {e}", script.display()))
}

/// Runs `python/scripts/bench_stepper.py` and parses its JSON; the error says why it could not run.
pub fn run_python(elements: usize, steps: usize, dense_steps: usize, repeats: usize) -> Result<PythonTiming, String> {
    let args = [("--elements", elements), ("--steps", steps), ("--dense-steps", dense_steps), ("--repeats", repeats)];
    run_json("bench_stepper.py", &args.iter().flat_map(|(k, v)| [k.to_string(), v.to_string()]).collect::<Vec<_>>())
}
