//! Mesh files as hostile input (issue 22 item 7): the gmsh fixtures with their bytes edited, read
//! as a body's `solid.mesh` by `massredist check` and `massredist run` (the properties of
//! tests/fuzz.rs: no panic or abort, a documented exit code, nothing left behind by a failed run).

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRunner};
use std::path::Path;
use std::sync::Mutex;

mod fuzz_common;
use fuzz_common::{code, left_in, massredist, no_panic};

/// One edit of a mesh file's bytes.
#[derive(Debug, Clone)]
enum ByteEdit {
    /// Cut the file at `at` (modulo its length).
    Truncate { at: usize },
    /// Overwrite the byte at `at` with `value`.
    Set { at: usize, value: u8 },
    /// Overwrite the bytes at `at` with `text` (huge, negative and non-finite numbers, a tag 0).
    Splice { at: usize, text: &'static str },
}

fn byte_edit() -> impl Strategy<Value = ByteEdit> {
    prop_oneof![
        1 => any::<usize>().prop_map(|at| ByteEdit::Truncate { at }),
        2 => (any::<usize>(), any::<u8>()).prop_map(|(at, value)| ByteEdit::Set { at, value }),
        3 => (any::<usize>(), prop::sample::select(vec!["999999999999", "-1", "0 ", "nan", "1e400", "\n$EndNodes\n", "4294967297"]))
            .prop_map(|(at, text)| ByteEdit::Splice { at, text }),
    ]
}

/// Mesh files (issue 22 item 7, the fuzzer's new surface): the gmsh fixtures (MSH 2.2 and 4.1,
/// ASCII and binary, P1 and P2, 2D and 3D), their bytes cut, flipped or overwritten by hostile
/// numbers, read as a body's `solid.mesh` by `check` and `run` (the pure-Rust reader of every
/// build). The properties of `one_case` (tests/fuzz.rs): no panic or abort, a documented exit code, nothing
/// left behind by a failed run. 96 seeded cases.
#[test]
fn mutated_mesh_files_never_panic_and_fail_cleanly() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes");
    let files: Vec<(Vec<u8>, usize)> = [
        ("disc_p1.msh", 2),
        ("disc_p2_22a.msh", 2),
        ("disc_p2_22b.msh", 2),
        ("disc_p2_41a.msh", 2),
        ("disc_p2_41b.msh", 2),
        ("hemisphere_tet.msh", 3),
        ("sphere_tet10_41b.msh", 3),
    ]
    .into_iter()
    .map(|(name, dim)| (std::fs::read(root.join(name)).unwrap(), dim))
    .collect();
    let config = Config { cases: 96, failure_persistence: None, ..Config::default() };
    let rng = proptest::test_runner::TestRng::deterministic_rng(RngAlgorithm::ChaCha);
    let mut runner = TestRunner::new_with_rng(config, rng);
    let strategy = (0..files.len(), proptest::collection::vec(byte_edit(), 1..=3));
    let codes = Mutex::new(Vec::new());
    runner
        .run(&strategy, |(i, edits)| {
            let (mut bytes, dim) = files[i].clone();
            for e in &edits {
                let n = bytes.len().max(1);
                match e {
                    ByteEdit::Truncate { at } => bytes.truncate(at % n),
                    ByteEdit::Set { at, value } => {
                        if !bytes.is_empty() {
                            bytes[at % n] = *value;
                        }
                    }
                    ByteEdit::Splice { at, text } => {
                        let at = at % n;
                        let end = (at + text.len()).min(bytes.len());
                        bytes.splice(at..end, text.bytes());
                    }
                }
            }
            // A plane far below the body: no contact, the reader and the checks are under test.
            let (normal, point) = if dim == 2 { ("[0.0, 1.0]", "[0.0, -100.0]") } else { ("[0.0, 0.0, 1.0]", "[0.0, 0.0, -100.0]") };
            let zeros = vec!["\"0\""; dim].join(", ");
            let text = format!(
                "[solid]\ndim = {dim}\nmesh = \"m.msh\"\nlame_lambda = 1.0\nlame_mu = 1.0\ninitial = {{ displacement = [{zeros}], velocity = [{zeros}] }}\n\
                 [obstacle]\nnormal = {normal}\npoint = {point}\ncontact = \"auto\"\n[mass]\nkind = \"standard\"\n[time]\ndt = 0.01\nend = 0.02\n"
            );
            let tmp = tempfile::tempdir().unwrap();
            let logs = tempfile::tempdir().unwrap();
            std::fs::write(tmp.path().join("m.msh"), &bytes).unwrap();
            let path = tmp.path().join("scene.toml");
            std::fs::write(&path, &text).unwrap();
            let what = format!("{edits:?} on fixture {i}");
            let check = massredist(&["check".as_ref(), path.as_os_str()], logs.path());
            no_panic("check", &check, &what)?;
            let out = tmp.path().join("out");
            let run = massredist(&["run".as_ref(), path.as_os_str(), "--out".as_ref(), out.as_os_str()], logs.path());
            no_panic("run", &run, &what)?;
            let left: Vec<String> = left_in(tmp.path()).into_iter().filter(|n| n != "m.msh").collect();
            let c = code(&run);
            prop_assert!(left.iter().all(|n| !n.contains(".tmp-")), "{what}: partial folder {left:?}");
            if c == 1 || c == 2 {
                prop_assert!(left.is_empty(), "{what}: a failed run (exit {c}) left {left:?}");
            }
            prop_assert!(!(code(&check) == 0 && c == 1), "{what}: passed check, failed in run: {}", String::from_utf8_lossy(&run.stderr));
            codes.lock().unwrap().push((code(&check), c));
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{e}"));
    let codes = codes.into_inner().unwrap();
    eprintln!("mesh-file cases (check, run): {codes:?}");
    // Some edits (a flipped byte in a coordinate's digits) leave a valid mesh: the run half is reached.
    assert!(codes.iter().any(|&(c, _)| c == 0), "no mutated mesh passed check");
    assert!(codes.iter().any(|&(c, _)| c == 2), "no mutated mesh was refused");
}
