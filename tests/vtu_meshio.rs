//! The plate's VTU output opens in meshio (feature `python`): points, and the displacement of the
//! first and last frames, read back through meshio equal what the Rust reader finds.
#![cfg(feature = "python")]

use massredist::plate::vtu::read_vtu;
use std::process::Command;

#[test]
fn plate_vtu_frames_read_back_through_meshio() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("bump.toml");
    std::fs::write(
        &scene,
        r#"
[plate]
length = 1.0
height = 1.0
nx = 8
ny = 6
cells = "triangle"
initial = "bump"
[mass]
kind = "mod3"
[scheme]
kind = "hybrid"
[time]
dt = 0.02
end = 1.2
[output]
series = ["u0", "energy"]
vtu = true
vtu_every = 20
"#,
    )
    .unwrap();
    let out = tmp.path().join("out");
    let run =
        Command::new(env!("CARGO_BIN_EXE_massredist")).arg("run").arg(&scene).arg("--out").arg(&out).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let mut frames: Vec<_> = std::fs::read_dir(out.join("vtu")).unwrap().map(|e| e.unwrap().path()).collect();
    frames.sort();
    assert_eq!(frames.len(), 4, "frames at steps 0, 20, 40, 60");
    for frame in [&frames[0], frames.last().unwrap()] {
        let ours = read_vtu(std::fs::read(frame).unwrap()).unwrap();
        let (points, u, comps) = massredist::bridge::read_point_data(frame, "u").expect("meshio reads the frame");
        assert_eq!(comps, 1);
        // Values are written as raw little-endian f64 (appended data), so meshio reads back the
        // same f64 bit for bit.
        assert_eq!(points, ours.points, "{}", frame.display());
        assert_eq!(u, ours.point_array("u").unwrap().values, "{}", frame.display());
        assert_eq!(u.len(), 9 * 7);
    }
}

#[test]
fn a_plate_scene_runs_on_a_gmsh_mesh_read_by_meshio() {
    let tmp = tempfile::tempdir().unwrap();
    let mesh = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes/square_4x3_tri.msh");
    std::fs::copy(&mesh, tmp.path().join("square.msh")).unwrap();
    let scene = tmp.path().join("scene.toml");
    std::fs::write(
        &scene,
        "[plate]\nmesh = \"square.msh\"\n[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"hybrid\"\n[time]\ndt = 0.01\nend = 3.0\n",
    )
    .unwrap();
    let out = tmp.path().join("out");
    let run =
        Command::new(env!("CARGO_BIN_EXE_massredist")).arg("run").arg(&scene).arg("--out").arg(&out).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["cells"], "triangle");
    // The mesh is the unit square: total mass ∫ w = 1 for mod3 (mass moved, not lost), to rounding.
    assert!((s["total_mass"].as_f64().unwrap() - 1.0).abs() < 1e-14);
    // Hybrid: the energy never increases (the lemma, 2D form), so it ends at most where it starts.
    assert!(s["energy_final"].as_f64().unwrap() <= s["energy_initial"].as_f64().unwrap());
    // Giving the geometry twice is an error naming the key.
    std::fs::write(&scene, "[plate]\nmesh = \"square.msh\"\nnx = 4\n[time]\ndt = 0.01\n").unwrap();
    let bad = Command::new(env!("CARGO_BIN_EXE_massredist")).arg("check").arg(&scene).output().unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("plate.nx"));
}
