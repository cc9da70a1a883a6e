//! The command line: every shipped scene runs (status "ok"), bad input is a clear error with exit
//! code 2 and leaves no output behind, and the output contract (series.csv, summary.json,
//! scene.resolved.toml) holds. Diverged runs (exit 3): `tests/divergence.rs`.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_massredist"))
}

fn scenes() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

#[test]
fn every_shipped_scene_checks_and_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let all = scenes();
    assert!(all.len() >= 4, "the Figure 11 scenes are shipped");
    for scene in all {
        let check = bin().arg("check").arg(&scene).output().unwrap();
        assert!(check.status.success(), "{}: {}", scene.display(), String::from_utf8_lossy(&check.stderr));
        let out = tmp.path().join(scene.file_stem().unwrap());
        let run = bin().arg("run").arg(&scene).arg("--out").arg(&out).output().unwrap();
        assert!(run.status.success(), "{}: {}", scene.display(), String::from_utf8_lossy(&run.stderr));
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
        assert!(summary["steps"].as_u64().unwrap() > 0);
        assert_eq!(summary["status"], "ok", "{}", scene.display());
        // The resolved scene is itself a valid scene describing the same run.
        let again = bin().arg("check").arg(out.join("scene.resolved.toml")).output().unwrap();
        assert!(again.status.success());
        assert_eq!(String::from_utf8_lossy(&again.stdout), String::from_utf8_lossy(&check.stdout));
    }
}

const GOOD: &str = r#"
[bar]
length = 1.0
elements = 6
initial = "paper"
[mass]
kind = "mod3"
[scheme]
kind = "crank-nicolson"
[time]
dt = 0.01
end = 3.0
[output]
series = ["lambda", "u0", "l2_error"]
every = 10
"#;

fn run_text(text: &str) -> (std::process::Output, tempfile::TempDir) {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("s.toml");
    std::fs::write(&scene, text).unwrap();
    let out = bin().arg("run").arg(&scene).arg("--out").arg(tmp.path().join("out")).output().unwrap();
    (out, tmp)
}

#[test]
fn output_contract() {
    let (out, tmp) = run_text(GOOD);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let dir = tmp.path().join("out");
    let csv = std::fs::read_to_string(dir.join("series.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), "t,lambda,u0,l2_error", "header: t then the columns in the order given");
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), 31, "every = 10 over 300 steps, t = 0 included");
    assert_eq!(rows[0], vec![0.0, 0.0, 0.5, 0.0], "t = 0: λ = 0, u0 = 1/2, interpolant error 0");
    for (k, r) in rows.iter().enumerate() {
        approx::assert_relative_eq!(r[0], k as f64 * 0.1, epsilon = 1e-12, max_relative = 0.0);
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    for key in [
        "status",
        "divergence",
        "steps",
        "h",
        "dt",
        "linf_l2_error",
        "linf_l2_error_relative",
        "max_contact_error",
        "energy_initial",
        "energy_final",
        "energy_min",
        "energy_max",
        "first_impact_time",
        "first_release_time",
        "final_u0",
        "wall_seconds",
    ] {
        assert!(s.get(key).is_some(), "summary.json has {key}");
    }
    assert_eq!(s["steps"], 300);
    assert_eq!(s["status"], "ok", "a run that ends normally; `null` divergence: not applicable");
    assert!(s["divergence"].is_null());
    // linf_l2_error is the max over all steps, so at least the max over the recorded ones.
    let recorded_max = rows.iter().map(|r| r[3]).fold(0.0, f64::max);
    assert!(s["linf_l2_error"].as_f64().unwrap() >= recorded_max);
    // Exact energy at t = 0: ½ U⁰ᵀ S U⁰ with u_x = −1/2 is 1/8 up to rounding.
    approx::assert_relative_eq!(s["energy_initial"].as_f64().unwrap(), 0.125, epsilon = 1e-15, max_relative = 0.0);
    let resolved = std::fs::read_to_string(dir.join("scene.resolved.toml")).unwrap();
    assert!(resolved.contains("formulation = \"full\"") && resolved.contains("force = 0.0"));
}

#[test]
fn summary_only_scene_writes_no_series() {
    let (out, tmp) = run_text(&GOOD.replace(r#"series = ["lambda", "u0", "l2_error"]"#, "series = []"));
    assert!(out.status.success());
    assert!(!tmp.path().join("out/series.csv").exists());
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("out/summary.json")).unwrap()).unwrap();
    assert!(s["linf_l2_error"].as_f64().unwrap() > 0.0, "computed by default");
    // Opting out of the per-step L² error leaves its keys null and the rest unchanged.
    let (out2, tmp2) =
        run_text(&GOOD.replace(r#"series = ["lambda", "u0", "l2_error"]"#, "series = []\nsummary_l2 = false"));
    assert!(out2.status.success());
    let s2: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp2.path().join("out/summary.json")).unwrap()).unwrap();
    assert!(s2["linf_l2_error"].is_null() && s2["linf_l2_error_relative"].is_null());
    for key in ["max_contact_error", "energy_final", "energy_max", "first_impact_time", "final_u0"] {
        assert_eq!(s[key], s2[key], "{key}");
    }
}

/// Each bad scene must fail with exit code 2, name the key, state the allowed range where there
/// is one, and leave no output directory. (About 100 lines: a table of bad inputs and the words
/// each message must hold; split, the table would only be spread over several functions.)
#[test]
fn bad_input_is_a_clear_error() {
    let cases: &[(&str, &str, &[&str])] = &[
        ("elements = 6", "elements = 1", &["bar.elements", "[2, 10000000]"]),
        ("dt = 0.01", "dt = -0.01", &["time.dt", "(0, ∞)"]),
        ("dt = 0.01", "dt = nan", &["time.dt"]),
        ("end = 3.0", "end = 0.0", &["time.end", "(0, ∞)"]),
        ("end = 3.0", "end = 3.005", &["time.end / time.dt", "not an integer"]),
        ("kind = \"mod3\"", "kind = \"mod4\"", &["mass.kind", "standard | mod1 | mod2 | mod3 | custom"]),
        (
            "kind = \"mod3\"",
            "kind = \"custom\"\nweights = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]",
            &["mass.weights", "massless"],
        ),
        ("kind = \"mod3\"", "kind = \"custom\"\nweights = [0.0, 1.0]", &["mass.weights", "2 entries", "6 elements"]),
        (
            "kind = \"mod3\"",
            "kind = \"custom\"\nweights = [0.0, 1.0, -1.0, 1.0, 1.0, 1.0]",
            &["mass.weights[2]", ">= 0"],
        ),
        ("kind = \"crank-nicolson\"", "kind = \"euler\"", &["scheme.kind", "backward-euler"]),
        ("kind = \"crank-nicolson\"", "kind = \"crank-nicolson\"\nbeta = 0.3", &["scheme.beta", "crank-nicolson"]),
        ("kind = \"crank-nicolson\"", "kind = \"newmark\"\nbeta = 0.0", &["scheme.beta", "(0, 1]"]),
        (
            "kind = \"crank-nicolson\"",
            "kind = \"paoli-schatzman\"\nrestitution = 1.5",
            &["scheme.restitution", "[0, 1]"],
        ),
        ("every = 10", "every = 0", &["output.every", ">= 1"]),
        ("every = 10", "every = 10\ndivergence_factor = 1.0", &["output.divergence_factor", "(1, ∞)"]),
        ("every = 10", "every = 10\nevry = 2", &["unknown field", "evry"]),
        ("elements = 6", "elements = \"six\"", &["elements"]),
        (
            "series = [\"lambda\", \"u0\", \"l2_error\"]",
            "series = [\"u0\", \"velocity\"]",
            &["output.series", "l2_error"],
        ),
        ("elements = 6", "elements = 10000001", &["bar.elements", "[2, 10000000]"]),
        ("end = 3.0", "end = 3000000000.0", &["unknowns × steps", "limit", "bar.elements"]),
        ("every = 10", "every = 1\n[bar]", &["duplicate", "bar"]),
        // Numbers in short form, never a 309-digit decimal; lengths in a range that keeps h², the
        // step matrices and the default end (3 L) finite.
        ("length = 1.0", "length = 1e308", &["bar.length = 1e308", "[1e-100, 1e100]"]),
        ("length = 1.0", "length = 1e-300", &["bar.length = 1e-300", "[1e-100, 1e100]"]),
        // Setup failures (a step matrix that cannot be factored) are found by `check` too, and
        // name the keys that shape the matrices.
        ("dt = 0.01\nend = 3.0", "dt = 5e-324\nend = 5e-324", &["cannot be set up", "time.dt"]),
    ];
    for (from, to, needles) in cases {
        assert!(GOOD.contains(from));
        let text = GOOD.replacen(from, to, 1);
        let (out, tmp) = run_text(&text);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{to}: {err}");
        for n in *needles {
            assert!(err.contains(n), "{to}: message lacks {n:?}: {err}");
        }
        // `check` refuses what `run` refuses, with the same message (mutation: `check` without
        // `run::check` passes the two setup cases above).
        let check = bin().arg("check").arg(tmp.path().join("s.toml")).output().unwrap();
        assert_eq!(check.status.code(), Some(2), "check {to}");
        assert_eq!(String::from_utf8_lossy(&check.stderr), err, "check and run say the same");
        let leftovers: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(leftovers, vec![std::ffi::OsString::from("s.toml")], "{to}: nothing written");
    }
    // Weights of 1e-308 set up (M is subnormal but factors) and overflow at the first step: an
    // honest "diverged" (exit 3, status in summary.json), not an exit 1 without a key.
    let (out, _t) = run_text(&GOOD.replacen(
        "kind = \"mod3\"",
        "kind = \"custom\"\nweights = [1e-308, 1e-308, 1e-308, 1e-308, 1e-308, 1e-308]",
        1,
    ));
    assert_eq!(out.status.code(), Some(3), "{}", String::from_utf8_lossy(&out.stderr));
    // Newmark with β = 1e-300 is all but explicit and unstable at Δt = 0.01 with the massless
    // contact row: it sets up, and overflows at its first step (exit 3, not 1).
    let (out, _t) = run_text(&GOOD.replacen("kind = \"crank-nicolson\"", "kind = \"newmark\"\nbeta = 1e-300", 1));
    assert_eq!(out.status.code(), Some(3), "{}", String::from_utf8_lossy(&out.stderr));
    // VTU frames are streamed; their disk use is bounded (100 × 100 cells, a frame every step
    // for 10⁵ steps would be about 240 GB).
    let (out, _t) =
        run_text("[plate]\nnx = 100\nny = 100\n[time]\ndt = 0.01\nend = 1000\n[output]\nvtu = true\nvtu_every = 1\n");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("output.vtu_every = 1") && err.contains("at least"), "{err}");
    // A TOML type error names the key on its first line.
    let (out, _t) = run_text(&GOOD.replacen("elements = 6", "elements = \"six\"", 1));
    let first = String::from_utf8_lossy(&out.stderr).lines().next().unwrap_or("").to_string();
    assert!(first.contains("bar.elements") && first.contains("line 4"), "{first}");
    // A scene file is read with a size cap: /dev/zero fails at once instead of filling memory.
    let zero = bin().arg("check").arg("/dev/zero").output().unwrap();
    assert_eq!(zero.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&zero.stderr).contains("larger than"), "{:?}", zero);
    // Hybrid with a massive contact node is undefined: a clear error, not a NaN.
    let (out, _t) =
        run_text(&GOOD.replace("kind = \"mod3\"", "kind = \"standard\"").replace("\"crank-nicolson\"", "\"hybrid\""));
    assert_eq!(out.status.code(), Some(2));
    let message = String::from_utf8_lossy(&out.stderr);
    // The one key to change first, the contact weight found, and the masses allowed.
    assert!(message.contains("mass.kind = \"standard\" does not go with scheme.kind = \"hybrid\""), "{message}");
    assert!(message.contains("w_0 = 1") && message.contains("allowed: mod1 | mod2 | mod3"), "{message}");
}

/// E13 (issue 32): `check X | head -c0` closes stdout before `check` prints. A closed stdout is
/// a clean exit (0, nothing on stderr), not a "Broken pipe" panic (exit 101). The pipe's read end
/// is closed before the process starts, so the write fails on every run (no race).
#[test]
fn closed_stdout_is_a_clean_exit() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("s.toml");
    std::fs::write(&scene, GOOD).unwrap();
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let out = bin().arg("check").arg(&scene).stdout(writer).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// E5 (issue 32): Δt = 0.1·0.1 = 0.010000000000000002 and end = 3 give 300 steps whose last time
/// 300·Δt = 3.0000000000000004 passes `time.end` by one rounding. The exact solution is defined on
/// the steps' own times (the last step is step 300, whatever its time rounds to), so the last row
/// of the series is finite, and the summary's maximum is the maximum over every step: it equals
/// the largest value of the series written at every step (unfixed: the last row was NaN, the
/// summary's `f64::max` dropped it, exit 0).
#[test]
fn the_last_step_is_measured_even_when_its_time_rounds_past_the_end() {
    let scene = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/rebound-free-bar.toml"))
        .unwrap()
        .replace("dt = 0.005", "dt = 0.010000000000000002")
        .replace("series = [\"u0\", \"lambda\", \"energy\"]", "series = [\"l2_error\"]\nevery = 1");
    let (out, tmp) = run_text(&scene);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let dir = tmp.path().join("out");
    let csv = std::fs::read_to_string(dir.join("series.csv")).unwrap();
    let errors: Vec<f64> = csv.lines().skip(1).map(|l| l.split(',').nth(1).unwrap().parse().unwrap()).collect();
    assert_eq!(errors.len(), 301, "steps 0..=300");
    assert!(errors.iter().all(|e| e.is_finite()), "last rows: {:?}", &errors[295..]);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    // The same f64 values, maximised in the same order: equal to the bit (the CSV prints
    // shortest round-trip decimals).
    let max = errors.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(s["linf_l2_error"].as_f64(), Some(max));
}
