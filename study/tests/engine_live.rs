#![cfg(feature = "python")]
//! Live trajectory cross-checks of the FEniCSx engine (issue 12): plate and solid scenes stepped by
//! `massredist run --engine fenicsx --ranks N` (dolfinx + PETSc under `mpirun`, python/engine/)
//! against the Rust run of the same scene, on 1 and 2 ranks; complementarity on the engine's side
//! at every step; a deliberately wrong cell weight on the engine side makes the check fail.
//! Gated on the `python` feature only because that is where CI installs dolfinx and mpirun
//! (tests/run-all.sh); the command itself needs no feature.
//! Run with `cargo test --features python --test engine_live` after `bash python/install-deps.sh`.

use massredist_study::crosscheck_trajectory::{self as traj, TOL, plate_scene, solid_scene};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

/// One engine run at a time: dolfinx compiles forms into a shared cache, and two first runs
/// compiling the same form race on its object file (python/crosscheck/fem_dolfinx.py); the 2 cores of CI
/// also hold at most one 2-rank run.
static ENGINE: Mutex<()> = Mutex::new(());

/// The `massredist` binary of the root package, built into the same profile folder as this test
/// (`target/<profile>/deps/engine_live-…` → `target/<profile>/massredist`): Cargo sets
/// `CARGO_BIN_EXE_massredist` only for the tests of the package that has the binary, and this
/// crate cannot have it (see study/Cargo.toml). `bash tests/run-all.sh` builds both packages
/// with the same features first.
fn bin() -> PathBuf {
    let exe = std::env::current_exe().expect("the test's own path");
    let bin = exe.parent().and_then(Path::parent).expect("target/<profile>/deps").join("massredist");
    assert!(
        bin.is_file(),
        "{} is missing: build it first (cargo build --features python --bin massredist)",
        bin.display()
    );
    bin
}

/// Writes a scene file (texts from `massredist_study::crosscheck_trajectory`, shared with
/// `massredist crosscheck`).
fn scene_file(dir: &Path, name: &str, text: String) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

fn scene(dir: &Path, name: &str, cells: &str, initial: &str, scheme: &str, mass: &str) -> PathBuf {
    scene_file(dir, name, plate_scene(cells, initial, scheme, mass))
}

/// Runs `massredist run` (Rust, or the engine on `ranks`) and returns the output folder.
fn run(scene: &Path, out: &Path, ranks: Option<usize>, perturb: Option<&str>) -> PathBuf {
    let env: Vec<(&str, &str)> = perturb.map(|p| ("MASSREDIST_ENGINE_PERTURB_WEIGHT", p)).into_iter().collect();
    let _one = ranks.map(|_| ENGINE.lock().unwrap_or_else(std::sync::PoisonError::into_inner));
    traj::run(&bin(), scene, out, ranks, &env).unwrap_or_else(|e| panic!("{e}"))
}

fn series(dir: &Path) -> Vec<std::collections::HashMap<String, f64>> {
    let mut r = csv::Reader::from_path(dir.join("series.csv")).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    r.records()
        .map(|rec| header.iter().cloned().zip(rec.unwrap().iter().map(|x| x.parse::<f64>().unwrap())).collect())
        .collect()
}

fn json(path: &Path) -> serde_json::Map<String, serde_json::Value> {
    traj::json(path).unwrap()
}

/// [`traj::difference`]: the largest difference over every series column and numeric summary
/// value; panics if the folders do not have the same columns, rows and summary keys.
fn difference(a: &Path, b: &Path) -> f64 {
    traj::difference(a, b).unwrap_or_else(|e| panic!("{e}"))
}

/// The engine's complementarity record of every step (engine.json, python/engine/schemes.py):
/// u_c ≥ lb on every contact dof (the solver projects onto the bound), λ_c ≤ 0, |(u_c − lb) λ_c|
/// = 0, and on the dofs off the bound the multiplier the residual would need, |(K U − r)_c|/σ,
/// within the solver's tolerance (its residual tolerance 1e-12 ‖r‖∞ over σ = Δt²/4 ≥ 6e-4, with
/// ‖r‖∞ = O(1): < 1e-8).
fn assert_complementarity(dir: &Path) {
    assert_complementarity_with_gap(dir, 0.0)
}

/// [`assert_complementarity`] for an obstacle at u_x = −gap (summary.json's min_u0 ≥ −gap).
fn assert_complementarity_with_gap(dir: &Path, gap: f64) {
    let e = json(&dir.join("engine.json"));
    let get = |k: &str| e[k].as_f64().unwrap_or_else(|| panic!("engine.json {k}: {:?}", e[k]));
    assert!(get("min_gap") >= 0.0, "{}: min gap {}", dir.display(), get("min_gap"));
    assert!(get("max_lambda") <= 0.0, "{}: max lambda {}", dir.display(), get("max_lambda"));
    assert_eq!(get("max_complementarity_product"), 0.0, "{}", dir.display());
    assert!(get("max_inactive_multiplier") <= 1e-8, "{}: {}", dir.display(), get("max_inactive_multiplier"));
    let s = json(&dir.join("summary.json"));
    assert!(s["min_u0"].as_f64().unwrap() >= -gap && s["max_lambda"].as_f64().unwrap() <= 0.0);
    assert_eq!(s["max_complementarity_product"].as_f64(), Some(0.0));
}

/// The run hits the obstacle and leaves it again (so the check covers all three phases).
fn assert_impact(dir: &Path) {
    let s = json(&dir.join("summary.json"));
    assert!(s["first_impact_time"].is_f64() && s["first_release_time"].is_f64(), "{}: no impact", dir.display());
    assert!(series(dir).iter().any(|r| r["lambda"] < 0.0), "{}: no contact force", dir.display());
}

// mutation: `lam[:] = np.where(active, -mu / sigma, 0.0)` -> `mu / sigma` in schemes.py
//   -> fails with "max lambda 0.18…" in assert_complementarity and a difference of 1.48 in λ.
// mutation: Newmark predictor `pred[:] = u + dt * v + c * a` -> `u + dt * v` in schemes.py
//   -> fails with a difference of 1.36 in u0 (and 350 in the energy).
#[test]
fn quad_crank_nicolson_agrees_with_rust_on_1_and_2_ranks() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), "quad", "quad", "paper", "crank-nicolson", "mod3");
    let rust = run(&s, &dir.path().join("rust"), None, None);
    let one = run(&s, &dir.path().join("one"), Some(1), None);
    let two = run(&s, &dir.path().join("two"), Some(2), None);
    assert_impact(&rust);
    for eng in [&one, &two] {
        let d = difference(&rust, eng);
        assert!(d <= TOL, "{} vs Rust: {d:e} > {TOL:e}", eng.display());
        assert_complementarity(eng);
    }
    let d = difference(&one, &two);
    assert!(d <= TOL, "1 rank vs 2 ranks: {d:e} > {TOL:e}");
    let l2 = json(&one.join("summary.json"))["linf_l2_error"].as_f64();
    assert!(l2.is_some_and(|e| e > 0.0), "the L∞(L²) error is computed: {l2:?}");
}

// mutation: hybrid `pred[:] = u + 0.5 * dt * v` -> `u + dt * v` in schemes.py -> fails with a
//   difference of 0.49 in u0 (the run blows up: energy 1.3e6).
#[test]
fn triangle_hybrid_and_backward_euler_agree_with_rust() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [("hybrid", "bump", "hybrid", "mod3", 2), ("be", "paper", "backward-euler", "mod1", 1)];
    for (name, initial, scheme, mass, ranks) in cases {
        let s = scene(dir.path(), name, "triangle", initial, scheme, mass);
        let rust = run(&s, &dir.path().join(format!("{name}-rust")), None, None);
        let eng = run(&s, &dir.path().join(format!("{name}-eng")), Some(ranks), None);
        assert_impact(&rust);
        let d = difference(&rust, &eng);
        assert!(d <= TOL, "{name} on {ranks} rank(s) vs Rust: {d:e} > {TOL:e}");
        assert_complementarity(&eng);
    }
}

/// Cell 1 of the 8 × 4 quad mesh (second column, bottom row) is in layer 1, weight 2 under mod3;
/// the engine multiplies it by 1.01 (python/engine/layers.py `PERTURB_ENV`).
#[test]
fn a_wrong_weight_on_the_engine_side_fails_the_cross_check() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), "quad", "quad", "paper", "crank-nicolson", "mod3");
    let rust = run(&s, &dir.path().join("rust"), None, None);
    let wrong = run(&s, &dir.path().join("wrong"), Some(1), Some("1:1.01"));
    let d = difference(&rust, &wrong);
    assert!(d > 100.0 * TOL, "a 1% weight error must show: difference {d:e}");
}

/// A solid case on the Rust side and on the engine's 1 and 2 ranks: each engine run agrees with
/// the Rust run, and 1 rank with 2 ranks, within [`TOL`]; complementarity at every engine step;
/// the Rust run hits the obstacle and leaves it.
fn solid_case(dir: &Path, name: &str, text: String, gap: f64) {
    let s = scene_file(dir, name, text);
    let rust = run(&s, &dir.join(format!("{name}-rust")), None, None);
    assert_impact(&rust);
    let one = run(&s, &dir.join(format!("{name}-1")), Some(1), None);
    let two = run(&s, &dir.join(format!("{name}-2")), Some(2), None);
    for eng in [&one, &two] {
        let d = difference(&rust, eng);
        assert!(d <= TOL, "{} vs Rust: {d:e} > {TOL:e}", eng.display());
        assert_complementarity_with_gap(eng, gap);
    }
    let d = difference(&one, &two);
    assert!(d <= TOL, "{name}: 1 rank vs 2 ranks: {d:e} > {TOL:e}");
}

// mutation: solid stiffness `+ 2.0 * scene.lame_mu * inner(eps, eps)` -> `+ scene.lame_mu * ...` in
//   problem.py -> fails with "quad-1 vs Rust: 9.29e-1 > 1e-6".
// mutation: hybrid Φ without the free massless unknowns (`free = ...[:0]` in schemes.py
//   QuasiStatic) -> fails with "tri-1 vs Rust: 2.26e-3 > 1e-6".
#[test]
fn solid_2d_quad_and_triangle_agree_with_rust_on_1_and_2_ranks() {
    let dir = tempfile::tempdir().unwrap();
    solid_case(dir.path(), "quad", solid_scene(2, "quad", "crank-nicolson", "mod3", ""), 0.0);
    solid_case(dir.path(), "tri", solid_scene(2, "triangle", "hybrid", "mod3", traj::ROLLER), 0.0);
    let l2 = json(&dir.path().join("quad-1").join("summary.json"))["linf_l2_error"].as_f64();
    assert!(l2.is_some_and(|e| e > 0.0), "the L∞(L²) error is computed on quads: {l2:?}");
}

// mutation: hexahedron vertex map `[0, 1, 3, 2, 4, 5, 7, 6]` -> `[0, 1, 2, 3, 4, 5, 6, 7]` in
//   problem.py -> fails: the engine run exits with status 1 (dolfinx cannot build the twisted cells).
#[test]
fn solid_3d_hex_and_tet_agree_with_rust_on_1_and_2_ranks() {
    let dir = tempfile::tempdir().unwrap();
    // Roller faces, a gap and data varying in y and z (not a plane wave: no exact solution on
    // either side; the engine has the plane wave without gap only).
    let hex = "lame_lambda = 0.25\nlateral = \"roller\"\ngap = 0.02\n\
               initial = { displacement = [\"(1-x)/2*(1+0.2*y*z)\", \"0\", \"0\"], velocity = [\"0\", \"0\", \"0\"] }";
    solid_case(dir.path(), "hex", solid_scene(3, "hex", "hybrid", "mod3", hex), 0.02);
    solid_case(dir.path(), "tet", solid_scene(3, "tet", "backward-euler", "mod1", "lame_lambda = 0.25"), 0.0);
}

/// Cell 6 of the 4 × 2 × 2 tet mesh (the first tetrahedron of the second cube along x) is in
/// layer 1, weight 2 under mod3; the engine multiplies it by 1.01 (measured: 3.5e-4 in the series
/// alone, against 3.2e-14 unperturbed).
// mutation: `Some("6:1.01")` -> `None` (no wrong weight) -> fails with "difference 3.2e-14"-class values.
#[test]
fn a_wrong_weight_on_the_engine_side_fails_the_solid_cross_check() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene_file(dir.path(), "tet", solid_scene(3, "tet", "crank-nicolson", "mod3", ""));
    let rust = run(&s, &dir.path().join("rust"), None, None);
    let wrong = run(&s, &dir.path().join("wrong"), Some(1), Some("6:1.01"));
    let d = difference(&rust, &wrong);
    assert!(d > 100.0 * TOL, "a 1% weight error must show: difference {d:e}");
}

#[test]
fn a_missing_engine_names_the_install_command() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), "quad", "quad", "paper", "crank-nicolson", "mod3");
    let out = dir.path().join("out");
    let o = Command::new(bin())
        .args(["run", s.to_str().unwrap(), "--engine", "fenicsx", "--out", out.to_str().unwrap()])
        .env("MASSREDIST_MPIRUN", dir.path().join("no-mpirun"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("mpirun") && err.contains("bash python/install-deps.sh"), "{err}");
    assert!(!out.exists(), "nothing is written");
}

/// Runs `massredist run SCENE --engine fenicsx --ranks N --out OUT` and returns its exit code and
/// stderr (for runs that are meant to stop).
fn run_status(scene: &Path, out: &Path, ranks: Option<usize>) -> (Option<i32>, String) {
    let _one = ENGINE.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let mut cmd = Command::new(bin());
    cmd.arg("run").arg(scene).arg("--out").arg(out);
    if let Some(n) = ranks {
        cmd.args(["--engine", "fenicsx", "--ranks", &n.to_string()]);
    }
    let o = cmd.output().unwrap();
    (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// The standard mass with Crank–Nicolson chatters at the impact and gains energy (up to about
/// 4 E⁰ by T = 3, src/driver.rs `DEFAULT_ENERGY_FACTOR`): with `divergence_factor = 1.01` the
/// Rust divergence rule stops the engine at the first state above 1.01 E⁰, as it stops the Rust
/// run, at the same step: exit 3, status "diverged", the series ending at that state, the
/// folders agreeing within [`TOL`] (same keys and rows), and the engine told to stop there
/// (engine.json's `steps_taken`).
// mutation: `Some(_) if energy.abs() > factor * reference` -> `... > 1e3 * factor * reference` in
//   DivergenceWatch::judge (src/driver.rs) -> fails: "the Rust run diverges" (it completes, exit 0).
// mutation: the engine ignores the reply (`if reply != "go":` -> `if False:` in run.py) -> fails:
//   "the engine sent state 23 after it was told to stop at state 22" (exit 1, not 3).
#[test]
fn the_rust_divergence_rule_stops_an_engine_run() {
    let dir = tempfile::tempdir().unwrap();
    let text = plate_scene("quad", "paper", "crank-nicolson", "standard") + "divergence_factor = 1.01\n";
    let s = scene_file(dir.path(), "chatter", text);
    let (rust, eng) = (dir.path().join("rust"), dir.path().join("eng"));
    let (code, err) = run_status(&s, &rust, None);
    assert_eq!(code, Some(3), "the Rust run diverges: {err}");
    for ranks in [1, 2] {
        let (code, err) = run_status(&s, &eng, Some(ranks));
        assert_eq!(code, Some(3), "the engine run on {ranks} rank(s) is stopped: {err}");
        let (a, b) = (json(&rust.join("summary.json")), json(&eng.join("summary.json")));
        assert_eq!(b["status"], "diverged");
        assert_eq!(a["divergence"]["step"], b["divergence"]["step"], "{:?} vs {:?}", a["divergence"], b["divergence"]);
        assert_eq!(b["divergence"]["reason"], "energy-factor");
        let step = b["divergence"]["step"].as_u64().unwrap();
        assert!(step > 20 && step < 60, "diverged after the impact at t = 1, before the end: step {step}");
        assert_eq!(json(&eng.join("engine.json"))["steps_taken"].as_u64(), Some(step), "the engine stopped there");
        assert_eq!(series(&eng).len() as u64, step + 1, "series.csv ends at the last state shown");
        let d = difference(&rust, &eng);
        assert!(d <= TOL, "{ranks} rank(s) vs Rust: {d:e} > {TOL:e}");
    }
}

/// `fields.xdmf` is a time series at `output.vtu_every`: meshio's `TimeSeriesReader` (Debian's
/// python3) reads every frame back, t = 0, 0.5, …, 3 (every 10th of the 60 steps), each with
/// both fields, and the first displacement is the paper's initial data u = (L − x)/2 at the nodes
/// (interpolated exactly: P1/Q1 hold linear functions; 1e-15 for the round-off of x).
// mutation: `if self.every and s.n % self.every == 0` -> `if self.every and s.n == 0` in run.py
//   -> fails: 1 step read instead of 7.
// mutation: no merge (`if len(cols) < 2:` -> `if True:` in run.py) -> fails: KeyError
//   'displacement' (meshio reads the last collection only, velocity).
#[test]
fn the_engine_writes_an_xdmf_time_series_at_vtu_every() {
    let dir = tempfile::tempdir().unwrap();
    let text = plate_scene("quad", "paper", "crank-nicolson", "mod3") + "vtu = true\nvtu_every = 10\n";
    let s = scene_file(dir.path(), "frames", text);
    let eng = run(&s, &dir.path().join("eng"), Some(2), None);
    let script = "import sys, meshio, numpy as np\n\
        with meshio.xdmf.TimeSeriesReader(sys.argv[1]) as r:\n\
        \x20   x, cells = r.read_points_cells()\n\
        \x20   for k in range(r.num_steps):\n\
        \x20       t, pd, cd = r.read_data(k)\n\
        \x20       d = pd['displacement'].ravel()\n\
        \x20       err = np.abs(d - (1 - x[:, 0]) / 2).max() if k == 0 else 0.0\n\
        \x20       print(repr(t), ','.join(sorted(pd)), len(d), repr(err))\n";
    let o = Command::new("/usr/bin/python3").arg("-c").arg(script).arg(eng.join("fields.xdmf")).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}\n{}", String::from_utf8_lossy(&o.stderr));
    let rows: Vec<Vec<&str>> = out.lines().map(|l| l.split(' ').collect()).collect();
    assert_eq!(rows.len(), 7, "frames at steps 0, 10, …, 60: {out}");
    for (k, r) in rows.iter().enumerate() {
        let t: f64 = r[0].parse().unwrap();
        assert!((t - 0.5 * k as f64).abs() <= 1e-12, "frame {k} at t = {t}");
        assert_eq!(r[1], "displacement,velocity", "{out}");
        assert_eq!(r[2], "45", "the 9 × 5 nodes of the 8 × 4 plate");
    }
    let err: f64 = rows[0][3].parse().unwrap();
    assert!(err <= 1e-15, "the first frame is the initial data: {err:e}");
}

/// Issue 22, D15: `--ranks` above the launcher's slots is invalid input (exit 2) with a message
/// naming `--ranks` and the processors here, and nothing is written (it used to exit 1 with
/// "exit status exit status: 1").
// mutation: `too_many_ranks` returns None (no probe) -> fails: exit code 1, "failed with exit status".
#[test]
fn ranks_above_the_available_slots_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), "quad", "quad", "paper", "crank-nicolson", "mod3");
    let out = dir.path().join("out");
    let (code, err) = run_status(&s, &out, Some(64));
    assert_eq!(code, Some(2), "{err}");
    let last = err.lines().last().unwrap_or("");
    assert!(last.contains("--ranks 64") && last.contains("processor(s)") && last.contains("slots"), "{last}");
    assert!(!out.exists(), "nothing is written");
}

/// The processes whose command line mentions `needle` (Linux `/proc`), but this one.
fn processes_mentioning(needle: &str) -> Vec<String> {
    let mut found = Vec::new();
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = e.file_name().to_string_lossy().parse::<u32>() else { continue };
        let Ok(cmd) = std::fs::read(e.path().join("cmdline")) else { continue };
        let cmd = String::from_utf8_lossy(&cmd).replace('\0', " ");
        if pid != std::process::id() && cmd.contains(needle) {
            found.push(format!("{pid}: {cmd}"));
        }
    }
    found
}

/// Issue 22, D2: SIGTERM to `massredist run --engine fenicsx` no longer orphans the engine.
/// mpirun runs in its own process group, to which massredist's signal thread forwards the signal
/// before it removes the staging folder (src/output/staging.rs); the stream's pipes are a second
/// way out (mpirun ends the job on a closed pipe, rank 0 reads the end of its input as "hide").
/// So mpirun and its ranks end within seconds, and the next run into the same --out writes.
/// Seen failing after the merge with the signal cleanup (the staging folder removed, the
/// process exiting) and before the forwarding: mpirun and both ranks still ran 20 s later.
// Before: the same steps with the starting commit's binary (/work/baseline/massredist and the
// python/ of /work/main) left mpirun and both python ranks running 20 s after SIGTERM (checked by
// hand, 2026-11-25). mutation: EOF read as "go" and write errors ignored in stream.py -> still
// passes (mpirun's broken pipe alone ends the job: two mechanisms, either suffices).
#[test]
fn sigterm_to_an_engine_run_stops_the_engine() {
    let dir = tempfile::tempdir().unwrap();
    let long = plate_scene("quad", "paper", "crank-nicolson", "mod3").replace("end = 3.0", "end = 1000.0");
    let s = scene_file(dir.path(), "long", long);
    let out = dir.path().join("out");
    let _one = ENGINE.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let mut child = Command::new(bin())
        .arg("run")
        .arg(&s)
        .args(["--engine", "fenicsx", "--ranks", "2", "--out"])
        .arg(&out)
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let staging = dir.path().join(format!(".out.tmp-{}", child.id()));
    let streaming = || std::fs::read_to_string(staging.join("series.csv")).is_ok_and(|t| t.lines().count() > 5);
    let started = std::time::Instant::now();
    while !streaming() {
        assert!(started.elapsed().as_secs() < 120, "the engine did not start streaming in 120 s");
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let needle = dir.path().to_string_lossy().into_owned();
    assert!(!processes_mentioning(&needle).is_empty(), "the engine runs");
    Command::new("kill").arg("-TERM").arg(child.id().to_string()).status().unwrap();
    child.wait().unwrap();
    let killed = std::time::Instant::now();
    while !processes_mentioning(&needle).is_empty() && killed.elapsed().as_secs() < 20 {
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let left = processes_mentioning(&needle);
    assert!(left.is_empty(), "still running 20 s after SIGTERM: {left:#?}");
    drop(_one);
    let short = scene_file(dir.path(), "short", plate_scene("quad", "paper", "crank-nicolson", "mod3"));
    run(&short, &out, Some(1), None);
    assert!(!staging.exists(), "the next run removed the partial folder {}", staging.display());
    assert!(out.join("summary.json").is_file());
}

/// A body against a plane (issue 19 item 6): the engine's run of `text` on each of `ranks`
/// agrees with the Rust run to [`TOL`] in every series column and summary key (the body's
/// included), its complementarity record holds (u_c ≥ −g_i, λ ≤ 0, product 0), and the body
/// touched the plane (a positive reaction).
fn body_case(dir: &Path, name: &str, text: String, ranks: &[usize]) -> Vec<PathBuf> {
    let s = scene_file(dir, name, text);
    let rust = run(&s, &dir.join(format!("{name}-rust")), None, None);
    let force = json(&rust.join("summary.json"))["max_contact_force"].as_f64();
    assert!(force.is_some_and(|f| f > 0.0), "{name}: the body must touch the plane: {force:?}");
    ranks
        .iter()
        .map(|&n| {
            let eng = run(&s, &dir.join(format!("{name}-{n}")), Some(n), None);
            let d = difference(&rust, &eng);
            assert!(d <= TOL, "{} vs Rust: {d:e} > {TOL:e}", eng.display());
            let e = json(&eng.join("engine.json"));
            let get = |k: &str| e[k].as_f64().unwrap_or_else(|| panic!("engine.json {k}: {:?}", e[k]));
            assert!(get("min_gap") >= 0.0 && get("max_lambda") <= 0.0, "{}", eng.display());
            assert_eq!(get("max_complementarity_product"), 0.0, "{}", eng.display());
            eng
        })
        .collect()
}

// mutation: the body's contact bound without the gap (`self.lb = 0.0 * gaps[idx]` in body.py)
//   -> fails with "disc-1 vs Rust: 1.3e1 > 1e-6".
#[test]
fn body_p1_disc_crank_nicolson_agrees_with_rust_on_1_and_2_ranks() {
    let dir = tempfile::tempdir().unwrap();
    let scene = traj::disc_scene("crank-nicolson", "[0.0, 1.0]", "[0.0, 0.0]", traj::DOWN);
    let runs = body_case(dir.path(), "disc", scene, &[1, 2]);
    let d = difference(&runs[0], &runs[1]);
    assert!(d <= TOL, "disc: 1 rank vs 2 ranks: {d:e} > {TOL:e}");
}

/// Backward Euler and the hybrid scheme, the normals −e_y and −e_x (upper bounds, run
/// reflected), a clamped Q1 body and a 3D P1 body, on 2 ranks.
#[test]
fn body_schemes_normals_clamped_and_3d_agree_with_rust_on_2_ranks() {
    let dir = tempfile::tempdir().unwrap();
    let up = "[\"0\", \"1\"]";
    body_case(dir.path(), "neg-y-be", traj::disc_scene("backward-euler", "[0.0, -1.0]", "[0.0, 2.1]", up), &[2]);
    let right = "[\"1\", \"0.3\"]";
    body_case(dir.path(), "neg-x-hybrid", traj::disc_scene("hybrid", "[-1.0, 0.0]", "[2.05, 0.0]", right), &[2]);
    body_case(dir.path(), "clamped", traj::clamped_block_scene("backward-euler"), &[2]);
    body_case(dir.path(), "tet", traj::tet_body_scene("crank-nicolson"), &[2]);
}

/// A 1 % error in one cell weight (disc cell 100, weight > 0) on the engine side only moves the
/// trajectory far beyond [`TOL`].
#[test]
fn a_wrong_weight_on_the_engine_side_fails_the_body_cross_check() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene_file(dir.path(), "disc", traj::disc_scene("crank-nicolson", "[0.0, 1.0]", "[0.0, 0.0]", traj::DOWN));
    let rust = run(&s, &dir.path().join("rust"), None, None);
    let eng = run(&s, &dir.path().join("eng"), Some(1), Some("100:1.01"));
    let d = difference(&rust, &eng);
    assert!(d > 100.0 * TOL, "a 1% weight error must show: difference {d:e}");
}

/// A plane whose normal is not a coordinate axis: exit 2, naming obstacle.normal, no folder.
#[test]
fn an_oblique_plane_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let s =
        scene_file(dir.path(), "oblique", traj::disc_scene("crank-nicolson", "[0.6, 0.8]", "[0.0, 0.0]", traj::DOWN));
    let out = dir.path().join("out");
    let o = Command::new(bin())
        .arg("run")
        .arg(&s)
        .arg("--out")
        .arg(&out)
        .args(["--engine", "fenicsx", "--ranks", "1"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("obstacle.normal") && err.contains("coordinate axis"), "{err}");
    assert!(!out.exists());
}

/// A P2 (triangle6) body: dolfinx's P2 coordinate element and field against the Rust P2
/// assembly, on 1 and 2 ranks (the mesh's straight cells: both quadratures are exact).
// mutation: the triangle6 node order unpermuted (`"triangle": [0, 1, 2, 3, 4, 5]` in body.py)
//   -> fails: the engine run exits with status 1 (dolfinx cannot build that mesh).
#[test]
fn body_p2_rectangle_agrees_with_rust_on_1_and_2_ranks() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("rect6.msh"), traj::p2_rectangle_msh(4, 2)).unwrap();
    body_case(dir.path(), "p2", traj::p2_rectangle_scene("crank-nicolson"), &[1, 2]);
}
