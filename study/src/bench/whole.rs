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
//! (python/scripts/bench_stepper.py's `pttrs` hybrid stepper: numpy with LAPACK's dpttrs, its own step
//! loop timed, set-up excluded). Each figure is the fastest of repeated runs, in ns per
//! node-step (seconds / (m · steps)); a user-facing run's seconds are its CPU time (user +
//! system, as the operating system accounts the finished child), the kernel's and numpy's the
//! wall time of their loops.
//!
//! The goals (issue 13): default ≤ 1.5 × summary-only, summary-only ≤ 1.3 × bare kernel, and
//! numpy loop / whole process ≥ 5 at m = 10³ and ≥ 3 at m = 10⁵, for both user-facing forms.

use super::env;
use serde::Serialize;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// (m, steps) of the whole-process cases: 100 periods of Δt = h at m = 10³ and 2000 steps at
/// m = 10⁵ (both about a second: the CPU time of a child is counted in ticks of 10 ms).
pub const CASES: [(usize, usize); 2] = [(1_000, 300_000), (100_000, 2_000)];

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
    /// python/scripts/bench_stepper.py's `pttrs` hybrid loop.
    pub numpy_ns: Option<f64>,
}

/// Everything this module measured, and why a figure is missing.
#[derive(Debug, Clone, Serialize)]
pub struct WholeProcess {
    pub cases: Vec<WholeCase>,
    /// CPU seconds of the 100 × 100 quad plate (Crank–Nicolson, Mod 3, Δt = 1/100, T = 3) with a
    /// VTU frame every step and without VTU (issue 13: at most 1.5×).
    pub plate_vtu_seconds: Option<(f64, f64)>,
    pub notes: Vec<String>,
}

/// The plate of [`WholeProcess::plate_vtu_seconds`].
fn plate_scene(vtu: bool) -> String {
    format!(
        "[plate]\nnx = 100\nny = 100\ncells = \"quad\"\ninitial = \"paper\"\n[mass]\nkind = \"mod3\"\n\
         [scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = 0.01\nend = 3.0\n[output]\n{}",
        if vtu { "vtu = true\nvtu_every = 1\n" } else { "" }
    )
}

/// The goal of issue 13 for a VTU frame every step against none, at N = 100.
pub const VTU_EVERY_STEP_OVER_NONE: f64 = 1.5;

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

/// The CPU seconds (user + system) of this process's waited-for children so far, from
/// `/proc/self/stat` (cutime + cstime, in ticks of 1/100 s: Linux's USER_HZ); None elsewhere.
fn children_cpu() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name in parentheses: state is field 3, cutime 16, cstime 17.
    let fields: Vec<&str> = stat[stat.rfind(')')? + 1..].split_whitespace().collect();
    let ticks = |k: usize| fields.get(k - 3)?.parse::<f64>().ok();
    Some((ticks(16)? + ticks(17)?) / 100.0)
}

/// Fastest seconds of `exe run scene --out out --force` over `reps` runs (an error if a run
/// fails: it says why): the child's CPU seconds where the system reports them (on a shared
/// machine the wall time of a child also counts the time it waited for a core), else wall.
fn time_run(exe: &Path, scene: &Path, out: &Path, reps: usize) -> Result<f64, String> {
    let mut best = f64::INFINITY;
    for _ in 0..reps {
        let cpu = children_cpu();
        let started = Instant::now();
        let status = Command::new(exe)
            .arg("run")
            .arg(scene)
            .arg("--out")
            .arg(out)
            .arg("--force")
            .output()
            .map_err(|e| format!("cannot start {}: {e}", exe.display()))?;
        let wall = started.elapsed().as_secs_f64();
        let secs = cpu.zip(children_cpu()).map_or(wall, |(a, b)| b - a);
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
    let script = env::crate_dir().join("python").join("scripts").join("bench_stepper.py");
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
        .ok_or_else(|| "no pttrs hybrid run in the output of python/scripts/bench_stepper.py".into())
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
        let user_run = |summary_l2: bool| -> Result<f64, String> {
            let exe = exe.as_ref().map_err(|e| format!("no executable path: {e}"))?;
            std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            let path = dir.join(format!("m{elements}-l2-{summary_l2}.toml"));
            std::fs::write(&path, scene(elements, steps, summary_l2))
                .map_err(|e| format!("{}: {e}", path.display()))?;
            Ok(time_run(exe, &path, &dir.join("out"), reps)? * 1e9 / work)
        };
        let default_ns = note(user_run(true));
        let summary_only_ns = note(user_run(false));
        let bare = super::perf::time_scheme(
            &massredist::scene::SchemeSpec::Hybrid,
            &massredist::mass::MassKind::Mod3,
            elements,
            1,
            0.3,
        );
        let bare_ns = note(bare.ok_or_else(|| format!("bare kernel at m = {elements} failed")));
        let numpy_ns = note(numpy_ns(elements, steps, if quick { 1 } else { 3 }));
        cases.push(WholeCase { elements, steps, default_ns, summary_only_ns, bare_ns, numpy_ns });
    }
    let plate = |vtu: bool| -> Result<f64, String> {
        let exe = exe.as_ref().map_err(|e| format!("no executable path: {e}"))?;
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let path = dir.join(format!("plate-vtu-{vtu}.toml"));
        std::fs::write(&path, plate_scene(vtu)).map_err(|e| format!("{}: {e}", path.display()))?;
        time_run(exe, &path, &dir.join("out"), reps.min(3))
    };
    let plate_vtu_seconds = note(plate(true)).zip(note(plate(false)));
    let _ = std::fs::remove_dir_all(&dir);
    WholeProcess { cases, plate_vtu_seconds, notes }
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
         scene, assembly, factorisation, steps with the summary, output folder; its CPU time, fastest of repeated \
         runs) on the \
         paper's benchmark, hybrid, Mod 3, Δt = h, series off: *default* (`summary_l2 = true`: energy and exact \
         L² error every step) and *summary-only* (`summary_l2 = false`: energy every step), next to the bare kernel \
         (the steps alone, in-process) and numpy's dpttrs hybrid loop (python/scripts/bench_stepper.py, its loop alone). \
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
    if let Some((with, without)) = w.plate_vtu_seconds {
        s += &format!(
            "\n100 × 100 quad plate (Crank–Nicolson, Mod 3, Δt = 1/100, 300 steps, default output), whole process, CPU \
             seconds: {with:.3} with a binary VTU frame every step, {without:.3} without VTU: {}.\n",
            ratio(Some(with), Some(without), VTU_EVERY_STEP_OVER_NONE, true)
        );
    }
    for n in &w.notes {
        s += &format!("\nWhole process: {n}\n");
    }
    s
}
