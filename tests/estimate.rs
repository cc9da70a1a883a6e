//! Issue 22, D3 (time): `check` sets a scene up as `run` does, then times its first steps and
//! says how long the run will take (stderr), instead of leaving the user with the unknowns ×
//! steps cap (10¹⁰ "≈ 2 minutes" of a bar: the shipped 3D scene scaled to that cap showed an ETA
//! of 41 minutes). No timing is asserted: what is checked is that the estimate describes the
//! scene (its unknowns are those of the run's summary, its probe takes at most the scene's
//! steps) and that `run_seconds` is the set-up plus steps × the mean step.

use massredist::run::Estimate;
use massredist::scene::AnyScene;
use std::process::Command;

#[test]
fn check_estimates_the_run_of_the_scene_it_checked() {
    let root = env!("CARGO_MANIFEST_DIR");
    // The bar: m = 6 nodes (x = L clamped); the plate: nx (ny + 1) = 20 · 21 nodes off x = L;
    // the solid: its summary's `unknowns`.
    for (name, unknowns) in
        [("fig11-mod3", Some(6)), ("plate-table-mod3", Some(420)), ("solid-2d-roller-triangle", None)]
    {
        let path = format!("{root}/scenes/{name}.toml");
        let scene = AnyScene::from_file(std::path::Path::new(&path)).unwrap();
        let e: Estimate = massredist::run::check(&scene).unwrap();
        let steps = match &scene {
            AnyScene::Bar(s) => s.time.steps,
            AnyScene::Plate(s) => s.time.steps,
            AnyScene::Solid(s) => s.time.steps,
        };
        assert_eq!(e.steps, steps, "{name}");
        assert!(e.probe_steps >= 1 && e.probe_steps <= Estimate::PROBE_STEPS.min(steps), "{name}: {e:?}");
        let step = e.step_seconds.expect("a step was taken");
        assert_eq!(e.run_seconds(), Some(e.setup_seconds + step * steps as f64));

        // The CLI says the same unknowns as the run's summary.
        let dir = tempfile::tempdir().unwrap();
        let check = Command::new(env!("CARGO_BIN_EXE_massredist")).arg("check").arg(&path).output().unwrap();
        let err = String::from_utf8_lossy(&check.stderr);
        assert!(check.status.success(), "{err}");
        let run = Command::new(env!("CARGO_BIN_EXE_massredist"))
            .args(["run", &path, "--out"])
            .arg(dir.path().join("out"))
            .output()
            .unwrap();
        assert!(run.status.success());
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap()).unwrap();
        let expected = unknowns
            .unwrap_or_else(|| summary["unknowns"].as_u64().unwrap_or_else(|| panic!("{name}: {summary}")) as usize);
        assert_eq!(e.unknowns, expected, "{name}");
        assert!(
            err.contains(&format!("{expected} unknowns, set up in")) && err.contains(&format!("for the {steps} steps")),
            "{err}"
        );
    }
}

/// E14 (issue 32): the estimate was 10–70× low when the cost starts after the timed first steps
/// (the exact error evaluated by the summary at every step, an impact), and the work cap's
/// message promised "about 2 minutes". The probe now steps with the run's summary (the exact
/// L² error included), and `check` says what the estimate covers: the rebounding bar meets the
/// obstacle at t = 0.1, step 20, after the 16 probe steps, so the line says that no contact was
/// in them. The work cap names the work, not a time.
#[test]
fn the_estimate_says_what_it_covers() {
    let path = format!("{}/scenes/rebound-free-bar.toml", env!("CARGO_MANIFEST_DIR"));
    let scene = AnyScene::from_file(std::path::Path::new(&path)).unwrap();
    let e = massredist::run::check(&scene).unwrap();
    assert!(e.probe_steps <= 16 && !e.touched && e.exact_error, "{e:?}");
    let check = Command::new(env!("CARGO_BIN_EXE_massredist")).arg("check").arg(&path).output().unwrap();
    let err = String::from_utf8_lossy(&check.stderr);
    assert!(err.contains("exact L² error") && err.contains("no contact"), "{err}");
    let dir = tempfile::tempdir().unwrap();
    let long = dir.path().join("long.toml");
    std::fs::write(&long, std::fs::read_to_string(&path).unwrap().replace("end = 3.0", "end = 3e8")).unwrap();
    let check = Command::new(env!("CARGO_BIN_EXE_massredist")).arg("check").arg(&long).output().unwrap();
    let err = String::from_utf8_lossy(&check.stderr);
    assert_eq!(check.status.code(), Some(2), "{err}");
    assert!(err.contains("unknowns × steps") && !err.contains("minutes"), "{err}");
}
