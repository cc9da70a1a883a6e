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
        let ours = read_vtu(&std::fs::read_to_string(frame).unwrap()).unwrap();
        let (points, u, comps) = massredist::bridge::read_point_data(frame, "u").expect("meshio reads the frame");
        assert_eq!(comps, 1);
        // Values are written shortest-round-trip, so meshio reads back the same f64 bit for bit.
        assert_eq!(points, ours.points, "{}", frame.display());
        assert_eq!(u, ours.point_array("u").unwrap().values, "{}", frame.display());
        assert_eq!(u.len(), 9 * 7);
    }
}
