//! What the body tests share: a shipped scene run through the command line.
#![allow(dead_code)]

use std::path::Path;

/// `massredist run <scene> --out <out>`.
pub fn run_cli(scene: &Path, out: &Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_massredist"))
        .arg("run")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

/// Runs a scene of the repository (path relative to it) into `out` and returns its summary.
pub fn shipped_summary(scene: &str, out: &Path) -> serde_json::Value {
    let o = run_cli(&Path::new(env!("CARGO_MANIFEST_DIR")).join(scene), out);
    assert!(o.status.success(), "{scene}: {}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}
