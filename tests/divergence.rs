//! Runs that blow up say so: `summary.json` has `status` "ok" or "diverged" with where and why
//! (`divergence`: step, time, reason), the run stops at the divergence, its folder is still
//! written (summary of the last finite state, `series.csv` up to it), stderr says it and the
//! exit code is 3. The criterion (`massredist::driver::DivergenceCriterion`): a non-finite state,
//! or `|Eⁿ| > output.divergence_factor · max(|E⁰|, E_F)` with E_F the static energy of the load.
//!
//! The seven command-line tests failed on the code before divergence detection (f7eb1ba), run
//! there with this file: the blow-ups exited 0 with no `status` key (and `null` energies or NaN
//! rows), the normal runs had no `status` key, and `output.divergence_factor` was an unknown
//! field (exit 2, but without the allowed range in the message). The two driver tests at the end
//! use `integrate_watched`, which did not exist (they did not compile).

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_massredist"))
}

fn shipped(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
    std::fs::read_to_string(path).unwrap()
}

/// A finished `run` of scene text: the process output and its folder.
struct Run {
    out: Output,
    dir: PathBuf,
    _tmp: tempfile::TempDir,
}

impl Run {
    fn new(text: &str) -> Run {
        let tmp = tempfile::tempdir().unwrap();
        let scene = tmp.path().join("s.toml");
        std::fs::write(&scene, text).unwrap();
        let dir = tmp.path().join("out");
        let out = bin().arg("run").arg(&scene).arg("--out").arg(&dir).output().unwrap();
        Run { out, dir, _tmp: tmp }
    }

    fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.out.stderr).into_owned()
    }

    fn summary(&self) -> Value {
        let text = std::fs::read_to_string(self.dir.join("summary.json"))
            .unwrap_or_else(|e| panic!("summary.json: {e}; stderr: {}", self.stderr()));
        serde_json::from_str(&text).unwrap()
    }

    /// `series.csv` as (header, rows).
    fn series(&self) -> (Vec<String>, Vec<Vec<f64>>) {
        let text = std::fs::read_to_string(self.dir.join("series.csv")).unwrap();
        let mut lines = text.lines();
        let header = lines.next().unwrap().split(',').map(String::from).collect();
        let rows = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
        (header, rows)
    }

    /// The checks every diverged run passes: exit 3, stderr names it, the folder is written with
    /// status "diverged" and a divergence object, the energies describe a finite state, and
    /// `series.csv` holds finite rows only, the last one at or just before the divergence.
    fn assert_diverged(&self) -> Value {
        let err = self.stderr();
        assert_eq!(self.out.status.code(), Some(3), "exit code 3 for a diverged run: {err}");
        assert!(err.contains("diverged"), "stderr says it: {err}");
        assert!(self.dir.join(".massredist-output").is_file(), "the folder is written (a result)");
        let s = self.summary();
        assert_eq!(s["status"], "diverged", "{s}");
        let d = &s["divergence"];
        let step = d["step"].as_u64().expect("divergence.step") as f64;
        let time = d["time"].as_f64().expect("divergence.time");
        let dt = s["dt"].as_f64().unwrap();
        // t_n = n·Δt, up to the rounding of its accumulation.
        assert!((time - step * dt).abs() <= 1e-9 * time.max(1.0), "t = {time}, step {step}, dt {dt}");
        assert!(step >= 1.0 && step <= s["steps_requested"].as_f64().unwrap(), "{d}");
        let reason = d["reason"].as_str().expect("divergence.reason");
        assert!(
            ["non-finite-state", "non-finite-load", "non-finite-energy", "energy-factor"].contains(&reason),
            "{reason}"
        );
        for key in ["energy_initial", "energy_final", "energy_min", "energy_max", "final_u0", "min_u0"] {
            assert!(s[key].as_f64().is_some_and(f64::is_finite), "{key} = {} describes a finite state", s[key]);
        }
        if self.dir.join("series.csv").exists() {
            let (_, rows) = self.series();
            assert!(rows.iter().flatten().all(|x| x.is_finite()), "series.csv holds finite rows only");
            let last = rows.last().unwrap()[0];
            // The non-finite state is not shown; the state that crossed the energy bound is.
            let expected = if reason == "energy-factor" { time } else { time - dt };
            assert!((last - expected).abs() <= 1e-9 * time.max(1.0), "last row t = {last}, divergence at {time}");
        }
        s.clone()
    }
}

/// The case: Figure 11's standard mass (Crank–Nicolson chatters and gains energy) over
/// T = 4000 blew up to inf/NaN from t ≈ 2548 and exited 0 with `null` energies.
#[test]
fn figure_11_standard_mass_over_a_long_run_diverges() {
    let run = Run::new(&shipped("fig11-standard.toml").replace("end = 3.0", "end = 4000.0"));
    let s = run.assert_diverged();
    let d = &s["divergence"];
    assert!(s["linf_l2_error"].as_f64().is_some_and(f64::is_finite), "an exact solution exists: a number");
    // With f = 0 the reference is |E⁰|, and the run stopped at the first energy above
    // factor · reference: the shown energy crossed it, no earlier one did.
    assert_eq!(d["reason"], "energy-factor");
    let (factor, reference, energy) =
        (d["factor"].as_f64().unwrap(), d["reference"].as_f64().unwrap(), d["energy"].as_f64().unwrap());
    assert_eq!(factor, 1e6, "the default output.divergence_factor");
    assert_eq!(reference, s["energy_initial"].as_f64().unwrap().abs());
    assert!(energy.abs() > factor * reference);
    let (header, rows) = run.series();
    let k = header.iter().position(|c| c == "energy").unwrap();
    let energies: Vec<f64> = rows.iter().map(|r| r[k]).collect();
    assert_eq!(*energies.last().unwrap(), energy, "the last row is the state that crossed the bound");
    assert!(energies[..energies.len() - 1].iter().all(|e| e.abs() <= factor * reference));
    assert_eq!(s["energy_max"].as_f64().unwrap(), energy);
    assert_eq!(s["energy_final"].as_f64().unwrap(), energy);
    // One row per step up to the divergence (every = 1), t_0 included.
    assert_eq!(rows.len() as u64, d["step"].as_u64().unwrap() + 1);
}

/// A force of 1e200 overflows the energy at the first step (NaN from step 1 before).
#[test]
fn a_huge_force_diverges_at_step_1() {
    let text =
        "[bar]\nelements = 6\nforce = 1e200\n[time]\ndt = 0.01\nend = 3.0\n[output]\nseries = [\"u0\", \"energy\"]\n";
    let run = Run::new(text);
    let s = run.assert_diverged();
    assert_eq!(s["divergence"]["step"], 1);
    assert!(s["divergence"]["reason"].as_str().unwrap().starts_with("non-finite"), "{s}");
    // The summary describes t_0, the last finite state.
    assert_eq!(s["energy_final"], s["energy_initial"]);
    assert_eq!(s["final_u0"], 0.5);
    let (_, rows) = run.series();
    assert_eq!(rows.len(), 1, "series.csv ends at t_0");
}

/// Paoli–Schatzman with w_0 = 0 at Δt = h gains energy without bound (mod1: E ≈ 1e288 by
/// T = 3000, and u_0 far through the obstacle); a lower `output.divergence_factor` stops it
/// earlier.
#[test]
fn paoli_schatzman_mod1_at_dt_h_diverges_and_the_factor_moves_the_stop() {
    let scene = |factor: &str| {
        format!(
            "[bar]\nelements = 6\n[mass]\nkind = \"mod1\"\n[scheme]\nkind = \"paoli-schatzman\"\n[time]\ndt = 0.16666666666666666\nend = 3000\n[output]\nseries = [\"u0\", \"lambda\", \"energy\"]\n{factor}"
        )
    };
    let default = Run::new(&scene(""));
    let s = default.assert_diverged();
    assert_eq!(s["divergence"]["reason"], "energy-factor");
    let low = Run::new(&scene("divergence_factor = 100.0"));
    let s_low = low.assert_diverged();
    assert_eq!(s_low["divergence"]["factor"], 100.0);
    assert!(
        s_low["divergence"]["step"].as_u64() < s["divergence"]["step"].as_u64(),
        "a lower factor stops earlier: {} vs {}",
        s_low["divergence"],
        s["divergence"]
    );
    let resolved = std::fs::read_to_string(low.dir.join("scene.resolved.toml")).unwrap();
    assert!(resolved.contains("divergence_factor = 100.0"), "{resolved}");
}

/// A 2D scene diverges the same way (its own summary and exit code).
#[test]
fn a_plate_with_a_huge_force_diverges() {
    let text = "[plate]\nnx = 4\nny = 1\nforce = 1e200\n[time]\ndt = 0.01\nend = 1.0\n[output]\nseries = [\"u0\", \"energy\"]\n";
    let run = Run::new(text);
    let s = run.assert_diverged();
    assert_eq!(s["divergence"]["step"], 1);
}

/// A normal scene is "ok", exit 0, with `divergence` null (not applicable).
#[test]
fn a_normal_run_is_ok() {
    let run = Run::new(&shipped("fig11-mod3.toml"));
    assert_eq!(run.out.status.code(), Some(0), "{}", run.stderr());
    let s = run.summary();
    assert_eq!(s["status"], "ok");
    assert!(s.get("divergence").is_some_and(Value::is_null), "{s}");
    assert!(!run.stderr().contains("diverged"));
}

/// E⁰ = 0 is no reason to diverge: a bar at rest under a large load (backward Euler dissipates,
/// so Eⁿ < 0 = E⁰ grows in size) is measured against the static energy of the load.
#[test]
fn a_loaded_bar_starting_at_rest_is_ok() {
    for force in ["-1.0", "-1e100"] {
        let text = format!(
            "[bar]\nelements = 8\ninitial = {{ displacement = \"0\", velocity = \"0\" }}\nforce = {force}\n[scheme]\nkind = \"backward-euler\"\n[time]\ndt = 0.01\nend = 30.0\n[output]\nseries = [\"energy\"]\n"
        );
        let run = Run::new(&text);
        assert_eq!(run.out.status.code(), Some(0), "force {force}: {}", run.stderr());
        let s = run.summary();
        assert_eq!(s["status"], "ok", "force {force}");
        assert_eq!(s["energy_initial"], 0.0);
        assert!(s["energy_final"].as_f64().unwrap() < 0.0, "backward Euler dissipated: {s}");
    }
}

/// `output.divergence_factor` is in (1, ∞): an error naming the key and the range, exit 2,
/// for bar and plate scenes.
#[test]
fn the_divergence_factor_is_validated() {
    let bar = shipped("fig11-mod3.toml");
    let plate = "[plate]\nnx = 4\nny = 1\n[output]\nseries = [\"u0\"]\n";
    for value in ["0.5", "1.0", "nan", "inf", "-3.0"] {
        for text in [&bar, plate] {
            let run = Run::new(&format!("{text}divergence_factor = {value}\n"));
            let err = run.stderr();
            assert_eq!(run.out.status.code(), Some(2), "{value}: {err}");
            assert!(err.contains("output.divergence_factor") && err.contains("(1, ∞)"), "{value}: {err}");
            assert!(!run.dir.exists(), "nothing written");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The driver itself (these two did not compile before: `integrate_watched` is new).

use massredist::bar::BarProblem;
use massredist::driver::{DivergenceCriterion, DivergenceReason, Outcome, integrate, integrate_watched};
use massredist::mass::MassKind;
use massredist::observe::{SeriesRecorder, SummaryObserver};
use massredist::scene::Column;
use massredist::scene::SchemeSpec;
use massredist::schemes::{Beta, Formulation, Restitution};

/// The paper's four schemes (Crank–Nicolson, backward Euler, Paoli–Schatzman with β = ¼, e = 1,
/// the hybrid scheme) and Crank–Nicolson's reduced formulation: `(label, scheme, needs w_0 = 0)`.
fn scheme_cases() -> [(&'static str, SchemeSpec, bool); 5] {
    let ps = SchemeSpec::PaoliSchatzman { beta: Beta::new(0.25), restitution: Restitution::new(1.0) };
    let reduced = SchemeSpec::CrankNicolson { formulation: Formulation::Reduced };
    [
        ("crank-nicolson", SchemeSpec::CRANK_NICOLSON, false),
        ("crank-nicolson-reduced", reduced, true),
        ("backward-euler", SchemeSpec::BackwardEuler, false),
        ("paoli-schatzman", ps, false),
        ("hybrid", SchemeSpec::Hybrid, true),
    ]
}

/// The summary without its wall time, as JSON.
fn numbers(s: &SummaryObserver) -> Value {
    let mut v = serde_json::to_value(s.finish()).unwrap();
    v.as_object_mut().unwrap().remove("wall_seconds");
    v
}

/// Watching for divergence changes nothing in a run that does not diverge: the same states, bit
/// for bit, and the same summary, for every scheme and mass of the sweep (3 periods, Δt = h/2).
#[test]
fn watching_changes_nothing_in_a_run_that_does_not_diverge() {
    let masses = [MassKind::Standard, MassKind::Mod1, MassKind::Mod2, MassKind::Mod3];
    for (label, spec, needs_massless) in scheme_cases() {
        for mass in masses.iter().filter(|m| !needs_massless || **m != MassKind::Standard) {
            let p = BarProblem::benchmark(1.0, 12, mass).unwrap();
            let (dt, steps) = (p.system.h() / 2.0, 3 * 3 * 12 * 2);
            let run = |watched: bool| {
                let mut s = p.scheme(&spec, dt).unwrap();
                let mut sum = SummaryObserver::new(&p, steps, dt, true);
                let mut rec = SeriesRecorder::new(Column::BAR.to_vec(), 1, steps + 1);
                if watched {
                    let c = DivergenceCriterion::default();
                    let outcome = integrate_watched(&p, s.as_mut(), steps, &c, &mut [&mut sum, &mut rec]).unwrap();
                    assert_eq!(outcome, Outcome::Completed, "{} {}", label, mass.name());
                } else {
                    integrate(&p, s.as_mut(), steps, &mut [&mut sum, &mut rec]).unwrap();
                }
                (numbers(&sum), rec.rows.iter().map(|x| x.to_bits()).collect::<Vec<u64>>())
            };
            let (strict, watched) = (run(false), run(true));
            assert_eq!(strict.1, watched.1, "{} {}: series", label, mass.name());
            assert_eq!(strict.0, watched.0, "{} {}: summary", label, mass.name());
            assert_eq!(watched.0["status"], "ok");
        }
    }
}

/// The strict `integrate` checks only finiteness; `integrate_watched` stops Paoli–Schatzman
/// (mod1, Δt = h) at the first energy above the bound, and the observers saw t_0 … that state.
#[test]
fn the_watched_driver_stops_where_the_strict_one_runs_on() {
    let p = BarProblem::benchmark(1.0, 6, &MassKind::Mod1).unwrap();
    let (dt, steps) = (p.system.h(), 18_000);
    let spec = massredist::scene::SchemeSpec::PAOLI_SCHATZMAN; // β = ¼, e = 1
    let mut strict = p.scheme(&spec, dt).unwrap();
    integrate(&p, strict.as_mut(), steps, &mut []).expect("finite states all along");
    let mut s = p.scheme(&spec, dt).unwrap();
    let mut sum = SummaryObserver::new(&p, steps, dt, true);
    let mut rec = SeriesRecorder::new(vec![Column::Energy], 1, steps + 1);
    let c = DivergenceCriterion { energy_factor: 1e3 };
    let Outcome::Diverged(d) = integrate_watched(&p, s.as_mut(), steps, &c, &mut [&mut sum, &mut rec]).unwrap() else {
        panic!("Paoli–Schatzman with mod1 at Δt = h gains energy without bound");
    };
    let e = rec.column(Column::Energy).unwrap();
    assert_eq!(e.len(), d.step + 1, "states 0 ..= {} seen", d.step);
    let DivergenceReason::EnergyFactor { energy, reference, factor } = d.reason else { panic!("{d}") };
    assert_eq!((factor, reference, energy), (1e3, e[0].abs(), e[d.step]));
    assert!(e[..d.step].iter().all(|x| x.abs() <= factor * reference) && energy.abs() > factor * reference);
    let summary = sum.finish();
    assert_eq!(summary.divergence, Some(d));
    assert_eq!(summary.energy_final, energy);
}

/// Issue 22, D12: a force finite at every node but infinite at a Gauss point of the load
/// integral (x = 1/12, the midpoint of the first of 6 elements, where assembly evaluates it) is
/// invalid input: `check` and `run` refuse it with exit 2 naming the key and the point, before
/// computing. Unfixed (a8ddfb4): `check` passed and `run` "diverged at step 0" with null
/// energies and `"steps": 10` for no step taken.
#[test]
fn a_force_infinite_between_the_nodes_is_refused_by_check() {
    for force in ["1/(x-1/12)", "1/(x-1/12) + t"] {
        let text = format!("[bar]\nelements = 6\nforce = \"{force}\"\n[time]\ndt = 0.01\nend = 0.1\n");
        let tmp = tempfile::tempdir().unwrap();
        let scene = tmp.path().join("s.toml");
        std::fs::write(&scene, &text).unwrap();
        let check = bin().arg("check").arg(&scene).output().unwrap();
        let err = String::from_utf8_lossy(&check.stderr);
        assert_eq!(check.status.code(), Some(2), "{force}: {err}");
        assert!(
            err.contains("bar.force") && err.contains("quadrature point 1") && err.contains("x = 8.3333e-2"),
            "{err}"
        );
        let out = tmp.path().join("out");
        let run = bin().arg("run").arg(&scene).arg("--out").arg(&out).output().unwrap();
        assert_eq!(run.status.code(), Some(2), "{force}: {}", String::from_utf8_lossy(&run.stderr));
        assert!(!out.exists());
    }
}

/// Issue 22, D12: a run whose very first state is not finite (v⁰ = 1e200: ½ VᵀMV overflows)
/// "diverged at step 0" with `"steps": 10` for no step taken and maxima over no state (the
/// L∞(L²) error, the contact error, the complementarity product) reported as 0.0. Now `steps`
/// counts the states described (0), `steps_requested` the scene's 10, and every extreme over
/// the empty set is null. Unfixed (ec19309): `"steps": 10`, `"linf_l2_error": 0.0`.
#[test]
fn a_run_diverged_at_t0_describes_no_step() {
    let text =
        "[bar]\nelements = 6\ninitial = { displacement = \"0\", velocity = \"1e200\" }\n[time]\ndt = 0.01\nend = 0.1\n";
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("s.toml");
    std::fs::write(&scene, text).unwrap();
    let out = tmp.path().join("out");
    let run = bin().arg("run").arg(&scene).arg("--out").arg(&out).output().unwrap();
    assert_eq!(run.status.code(), Some(3), "{}", String::from_utf8_lossy(&run.stderr));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        (s["divergence"]["step"].as_u64(), s["steps"].as_u64(), s["steps_requested"].as_u64()),
        (Some(0), Some(0), Some(10)),
        "{s}"
    );
    for key in
        ["linf_l2_error", "max_contact_error", "l2_lambda_error", "max_complementarity_product", "energy_initial"]
    {
        assert!(s[key].is_null(), "{key} = {}", s[key]);
    }
}

/// A free body at rest on the plane under gravity (GetFEM's disc benchmark starts so): E⁰ = 0,
/// and `E_F = ½ F_rᵀ S_rr⁻¹ F_r` does not exist (S_rr is singular: nothing holds the body
/// tangentially), so the reference max(|E⁰|, E_F) was 0 and the first step's round-off energy
/// "diverged at step 1" (found by the GetFEM cross-check, whose scenes slid the disc at 0.01 to
/// avoid it). The reference is now at least the free-flight scale ½ T² F_mᵀ M_mm⁻¹ F_m, and the
/// run completes, for CN, backward Euler and hybrid. Unfixed (c8bd99a): status "diverged", step 1.
#[test]
fn a_free_body_at_rest_under_gravity_does_not_diverge() {
    for scheme in ["crank-nicolson", "backward-euler", "hybrid"] {
        let text = format!(
            "[solid]\ndim = 2\nlength = 1.0\nheight = 0.5\nnx = 6\nny = 3\ncells = \"triangle\"\nlame_lambda = 1.0\nlame_mu = 1.0\n\
             force = [\"0\", \"-2\"]\n[obstacle]\nnormal = [0.0, 1.0]\npoint = [0.0, 0.0]\ncontact = \"auto\"\n[mass]\nkind = \"mod3\"\n\
             [scheme]\nkind = \"{scheme}\"\n[time]\ndt = 0.01\nend = 0.5\n"
        );
        let tmp = tempfile::tempdir().unwrap();
        let scene = tmp.path().join("s.toml");
        std::fs::write(&scene, &text).unwrap();
        let out = tmp.path().join("out");
        let run = bin().arg("run").arg(&scene).arg("--out").arg(&out).output().unwrap();
        let s: Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
        assert_eq!((run.status.code(), s["status"].as_str()), (Some(0), Some("ok")), "{scheme}: {s}");
        // It rests on the plane, never through it, pressed from the start: contact is read off
        // the force, which CN and BE start without (λ⁰ = 0: first impact t_1), while the hybrid
        // scheme's initial quasi-static contact solve presses the face at t_0 already.
        let first = if scheme == "hybrid" { 0.0 } else { 0.01 };
        assert_eq!((s["first_impact_time"].as_f64(), s["min_distance"].as_f64()), (Some(first), Some(0.0)), "{scheme}");
        assert!(s["first_release_time"].is_null(), "{scheme}: {s}");
    }
}

/// A body at rest under a load that starts from zero (`force = ["0", "-2*t"]`, a ramp):
/// `E⁰ = 0` and `E_F` of F(0) = 0 gave the reference 0, and every scheme "diverged at step 1"
/// on its first round-off energy (found trying a ramped load on `body-disc-in-cavity.toml`).
/// The watch now takes a time-dependent load's scale from its largest sample over the horizon
/// (`driver::peak_load`: here F(T)), and the runs complete: the free box on a plane (the
/// free-flight scale of that sample) and the disc held in its cavity (its `E_F`), under CN,
/// backward Euler, the hybrid scheme and central differences (the lean system's conjugate
/// gradients). (Mutation, as run: `raise_load_energy` left out -> every case diverged at step 1.)
#[test]
fn a_body_at_rest_under_a_load_ramped_from_zero_does_not_diverge() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let free_box = "[solid]\ndim = 2\nlength = 1.0\nheight = 0.5\nnx = 6\nny = 3\ncells = \"triangle\"\nlame_lambda = 1.0\nlame_mu = 1.0\n\
         force = [\"0\", \"-2*t\"]\n[obstacle]\nnormal = [0.0, 1.0]\npoint = [0.0, 0.0]\ncontact = \"auto\"\n[mass]\nkind = \"mod3\"\n\
         [scheme]\nkind = \"SCHEME\"\n[time]\ndt = 0.01\nend = 0.5\n"
        .to_string();
    let cavity = std::fs::read_to_string(root.join("scenes/body-disc-in-cavity.toml"))
        .unwrap()
        .replace("force = [\"0\", \"-1\"]", "force = [\"0\", \"-t\"]")
        .replace("kind = \"crank-nicolson\"", "kind = \"SCHEME\"")
        .replace("../fixtures", &root.join("fixtures").display().to_string());
    assert!(cavity.contains("\"-t\"") && cavity.contains("SCHEME"));
    for (name, text) in [("free box", &free_box), ("disc in a cavity", &cavity)] {
        for scheme in ["crank-nicolson", "backward-euler", "hybrid", "central-difference"] {
            let tmp = tempfile::tempdir().unwrap();
            let scene = tmp.path().join("s.toml");
            std::fs::write(&scene, text.replace("SCHEME", scheme)).unwrap();
            let out = tmp.path().join("out");
            let run = bin().arg("run").arg(&scene).arg("--out").arg(&out).output().unwrap();
            let s: Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
            assert_eq!((run.status.code(), s["status"].as_str()), (Some(0), Some("ok")), "{name}, {scheme}: {s}");
        }
    }
}

/// A force finite at t = 0 (where validation evaluates it) but singular later, `1/(t − t_s)`
/// with t_s on the time grid: the state follows the load to inf, and the run says so, naming
/// the load, its time and its key (reason `non-finite-load`), where it blamed the scheme ("the
/// scheme is unstable for this Δt / mass", found as a new user would, on the disc onto a
/// circle). A bar, a plate and a body; implicit and explicit. (Mutation, as run:
/// `non_finite_load` returning None -> reason "non-finite-state", fails.)
#[test]
fn a_force_singular_in_time_is_named_as_the_cause() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let disc = std::fs::read_to_string(root.join("scenes/body-disc-onto-circle.toml"))
        .unwrap()
        .replace("force = [\"0\", \"0\"]", "force = [\"0\", \"1/(t - 0.5)\"]")
        .replace("../fixtures", &root.join("fixtures").display().to_string());
    assert!(disc.contains("1/(t - 0.5)"));
    let cases = [
        (
            "[bar]\nelements = 6\nforce = \"1/(t - 0.25)\"\n[time]\ndt = 0.01\nend = 1.0\n".to_string(),
            0.25,
            "bar.force",
        ),
        (
            "[plate]\nnx = 4\nny = 4\nforce = \"1/(t - 0.25)\"\n[time]\ndt = 0.01\nend = 1.0\n".to_string(),
            0.25,
            "plate.force",
        ),
        (disc.clone(), 0.5, "solid.force"),
        (disc.replace("kind = \"crank-nicolson\"", "kind = \"central-difference\""), 0.5, "solid.force"),
    ];
    for (text, at, key) in cases {
        let run = Run::new(&text);
        let s = run.assert_diverged();
        let d = &s["divergence"];
        assert_eq!(
            (d["reason"].as_str(), d["load_time"].as_f64(), d["key"].as_str()),
            (Some("non-finite-load"), Some(at), Some(key)),
            "{d}"
        );
        assert!(
            run.stderr().contains(&format!("the load F(t) is not finite at t = {at} ({key} there)")),
            "{}",
            run.stderr()
        );
    }
}

/// E5 (issue 32): no summary value skips a NaN. The exact solution here is traced only up to
/// t = 0.5 of a run to t = 1, so its comparisons after t = 0.5 are NaN; the summary's maxima of
/// them are then NaN (null in summary.json), never the maximum over the steps before. Unfixed:
/// `f64::max` dropped every NaN and the summary printed the error over [0, 0.5] as the run's.
#[test]
fn no_summary_maximum_skips_a_nan() {
    use massredist::characteristics::InitialData;
    use massredist::exact::{Exact, by_characteristics, paper_data};
    use massredist::material::{FarEnd, Material};
    let mut p = BarProblem::benchmark(1.0, 12, &MassKind::Mod3).unwrap();
    let (x, u, v) = paper_data(1.0);
    let initial = InitialData::PiecewiseLinear { x: &x, u: &u, v: &v };
    let short = by_characteristics(1.0, Material::UNIT, FarEnd::Clamped, 0.0, initial, 0.5).unwrap();
    p.exact = Some(Exact::General(std::sync::Arc::new(short)));
    let (dt, steps) = (p.system.h() / 2.0, 24);
    let mut s = p.scheme(&massredist::scene::SchemeSpec::CRANK_NICOLSON, dt).unwrap();
    let mut sum = SummaryObserver::new(&p, steps, dt, true);
    integrate(&p, s.as_mut(), steps, &mut [&mut sum]).unwrap();
    let summary = sum.finish();
    for (key, value) in [
        ("linf_l2_error", summary.linf_l2_error),
        ("linf_l2_error_relative", summary.linf_l2_error_relative),
        ("max_contact_error", summary.max_contact_error),
        ("l2_lambda_error", summary.l2_lambda_error),
    ] {
        assert!(value.is_some_and(f64::is_nan), "{key} = {value:?}");
    }
}
