//! Whole-process timings of user-facing 1D runs, next to the bare kernel and the numpy
//! reference (issue 13's 1D goals).
//!
//! A user runs `massredist run scene.toml`: the process starts, reads the scene, assembles,
//! factors, steps with the summary observer (the energy every step, and by default the exact L²
//! error every step: `output.summary_l2`), and writes its folder. This module times exactly
//! that, as a child process of this one (`massredist run` of the running executable), for the
//! paper's benchmark with the hybrid scheme and Mod 3 (series off), in two forms:
//!
//! - **default**: `summary_l2 = true` (the energy and the exact L² error every step);
//! - **summary-only**: `summary_l2 = false` (the energy every step);
//!
//! next to the **bare kernel** (the scheme's steps through the driver with no observer, timed in
//! this process: [`super::perf::time_scheme`]) and the **numpy reference**
//! (python/bench_stepper.py's `pttrs` hybrid stepper: numpy with LAPACK's dpttrs, its own step
//! loop timed, set-up excluded). Each figure is the fastest of repeated runs, in ns per
//! node-step (whole-process seconds / (m · steps)).
//!
//! The goals (issue 13): default ≤ 1.5 × summary-only, summary-only ≤ 1.3 × bare kernel, and
//! numpy loop / whole process ≥ 5 at m = 10³ and ≥ 3 at m = 10⁵, for both user-facing forms.

use super::env;
use serde::Serialize;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// (m, steps) of the whole-process cases: 30 periods of Δt = h at m = 10³ (a typical long 1D
/// run, 0.1–0.5 s), and 1000 steps at m = 10⁵ (the same order of seconds).
pub const CASES: [(usize, usize); 2] = [(1_000, 30_000), (100_000, 1_000)];

/// The goals of issue 13, as (what, bound).
pub const DEFAULT_OVER_SUMMARY: f64 = 1.5;
pub const SUMMARY_OVER_BARE: f64 = 1.3;
/// numpy / whole process at m = 10³ and at m = 10⁵.
pub const NUMPY_OVER_RUN: [(usize, f64); 2] = [(1_000, 5.0), (100_000, 3.0)];

/// One size: ns per node-step of each form.
#[derive(Debug, Clone, Serialize)]
pub struct WholeCase {
    pub elements: usize,
    pub steps: usize,
    /// `massredist run`, `summary_l2 = true` (whole process).
    pub default_ns: Option<f64>,
    /// `massredist run`, `summary_l2 = false` (whole process).
    pub summary_only_ns: Option<f64>,
    /// The scheme's steps alone, in this process.
    pub bare_ns: Option<f64>,
    /// python/bench_stepper.py's `pttrs` hybrid loop.
    pub numpy_ns: Option<f64>,
}

/// Everything this module measured, and why a figure is missing.
#[derive(Debug, Clone, Serialize)]
pub struct WholeProcess {
    pub cases: Vec<WholeCase>,
    pub notes: Vec<String>,
}

/// The scene of a case: the paper's benchmark, hybrid, Mod 3, Δt = h, series off.
fn scene(elements: usize, steps: usize, summary_l2: bool) -> String {
    let dt = 1.0 / elements as f64;
    let end = steps as f64 / elements as f64;
    format!(
        "[bar]\nlength = 1.0\nelements = {elements}\ninitial = \"paper\"\n[mass]\nkind = \"mod3\"\n\
         [scheme]\nkind = \"hybrid\"\n[time]\ndt = {dt:?}\nend = {end:?}\n\
         [output]\nseries = []\nsummary_l2 = {summary_l2}\n"
    )
}

/// Fastest wall seconds of `exe run scene --out out --force` over `reps` runs (None if a run
/// fails: the error says why).
fn time_run(exe: &Path, scene: &Path, out: &Path, reps: usize) -> Result<f64, String> {
    let mut best = f64::INFINITY;
    for _ in 0..reps {
        let started = Instant::now();
        let status = Command::new(exe)
            .arg("run")
            .arg(scene)
            .arg("--out")
            .arg(out)
            .arg("--force")
            .output()
            .map_err(|e| format!("cannot start {}: {e}", exe.display()))?;
        let secs = started.elapsed().as_secs_f64();
        if !status.status.success() {
            let err = String::from_utf8_lossy(&status.stderr);
            return Err(format!("{} run failed: {}", scene.display(), err.lines().last().unwrap_or("")));
        }
        best = best.min(secs);
    }
    Ok(best)
}

/// numpy's `pttrs` hybrid loop, ns per node-step.
fn numpy_ns(elements: usize, steps: usize, repeats: usize) -> Result<f64, String> {
    let script = env::crate_dir().join("python").join("bench_stepper.py");
    let out = Command::new(env::PYTHON)
        .arg(&script)
        .args(["--elements", &elements.to_string(), "--steps", &steps.to_string()])
        .args(["--repeats", &repeats.to_string(), "--skip-dense"])
        .output()
        .map_err(|e| format!("cannot start {}: {e}", env::PYTHON))?;
    if !out.status.success() {
        return Err(format!("{} failed: {}", script.display(), String::from_utf8_lossy(&out.stderr).trim()));
    }
    let timing: env::PythonTiming =
        serde_json::from_slice(&out.stdout).map_err(|e| format!("cannot parse {}: {e}", script.display()))?;
    timing
        .runs
        .iter()
        .find(|r| r.implementation == "pttrs" && r.scheme == "hybrid")
        .map(|r| r.seconds_per_step * 1e9 / elements as f64)
        .ok_or_else(|| "no pttrs hybrid run in the output of python/bench_stepper.py".into())
}

/// Times every case (sequentially, one thread busy); `quick` takes fewer repetitions.
pub fn measure(quick: bool) -> WholeProcess {
    let reps = if quick { 2 } else { 5 };
    let mut notes = Vec::new();
    let mut note = |r: Result<f64, String>| r.map_err(|e| notes.push(e)).ok();
    let dir = std::env::temp_dir().join(format!("massredist-whole-{}", std::process::id()));
    let exe = std::env::current_exe();
    let mut cases = Vec::new();
    for (elements, steps) in CASES {
        let work = (elements * steps) as f64;
        let mut user_run = |summary_l2: bool| -> Result<f64, String> {
            let exe = exe.as_ref().map_err(|e| format!("no executable path: {e}"))?;
            std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            let path = dir.join(format!("m{elements}-l2-{summary_l2}.toml"));
            std::fs::write(&path, scene(elements, steps, summary_l2))
                .map_err(|e| format!("{}: {e}", path.display()))?;
            Ok(time_run(exe, &path, &dir.join("out"), reps)? * 1e9 / work)
        };
        let default_ns = note(user_run(true));
        let summary_only_ns = note(user_run(false));
        let bare =
            super::perf::time_scheme(&crate::scene::SchemeSpec::Hybrid, &crate::mass::MassKind::Mod3, elements, 1, 0.3);
        let bare_ns = note(bare.ok_or_else(|| format!("bare kernel at m = {elements} failed")));
        let numpy_ns = note(numpy_ns(elements, steps, if quick { 1 } else { 3 }));
        cases.push(WholeCase { elements, steps, default_ns, summary_only_ns, bare_ns, numpy_ns });
    }
    let _ = std::fs::remove_dir_all(&dir);
    WholeProcess { cases, notes }
}

/// `a / b` to two decimals, and whether it meets `goal` (`at_most`: a / b ≤ goal, else ≥).
fn ratio(a: Option<f64>, b: Option<f64>, goal: f64, at_most: bool) -> String {
    match a.zip(b) {
        Some((a, b)) => {
            let r = a / b;
            let met = if at_most { r <= goal } else { r >= goal };
            format!("{r:.2} ({}: {} {goal})", if met { "met" } else { "NOT met" }, if at_most { "≤" } else { "≥" })
        }
        None => "–".into(),
    }
}

/// The whole-process table in Markdown.
pub fn markdown(w: &WholeProcess) -> String {
    let ns = |v: Option<f64>| v.map_or("failed".into(), |v| format!("{v:.2}"));
    let mut s = String::from(
        "\nWhole process, user-facing runs (`massredist run` of this executable as a child process: start-up, \
         scene, assembly, factorisation, steps with the summary, output folder; fastest of repeated runs) on the \
         paper's benchmark, hybrid, Mod 3, Δt = h, series off: *default* (`summary_l2 = true`: energy and exact \
         L² error every step) and *summary-only* (`summary_l2 = false`: energy every step), next to the bare kernel \
         (the steps alone, in-process) and numpy's dpttrs hybrid loop (python/bench_stepper.py, its loop alone). \
         ns per node-step.\n\n\
         | m | steps | default | summary-only | bare kernel | numpy loop | default / summary-only | summary-only / bare | numpy / default | numpy / summary-only |\n\
         |---:|---:|---:|---:|---:|---:|---|---|---|---|\n",
    );
    for c in &w.cases {
        let goal = NUMPY_OVER_RUN.iter().find(|g| g.0 == c.elements).map_or(f64::NAN, |g| g.1);
        s += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            c.elements,
            c.steps,
            ns(c.default_ns),
            ns(c.summary_only_ns),
            ns(c.bare_ns),
            ns(c.numpy_ns),
            ratio(c.default_ns, c.summary_only_ns, DEFAULT_OVER_SUMMARY, true),
            ratio(c.summary_only_ns, c.bare_ns, SUMMARY_OVER_BARE, true),
            ratio(c.numpy_ns, c.default_ns, goal, false),
            ratio(c.numpy_ns, c.summary_only_ns, goal, false),
        );
    }
    for n in &w.notes {
        s += &format!("\nWhole process: {n}\n");
    }
    s
}
