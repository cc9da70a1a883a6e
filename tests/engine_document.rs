//! The engine reads what massredist writes and nothing else (issue 28 item 6): for shipped
//! plate, solid and body scenes, python/engine/scene.py loads the document of
//! src/engine/document.rs, takes every value as written (the loaded scene repeats them), and
//! refuses a document that lacks any one key, naming that key, instead of taking a default.
//! Mutation: `_take` in scene.py returning `table.get(k)` for a missing key -> every "missing"
//! line fails; `dt=` read as `t["dt"] * 2` -> the values line fails.
#![cfg(feature = "python")]

use massredist::engine::document::{document, key_paths, to_json};
use massredist::scene::AnyScene;
use serde_json::Value;
use std::process::Command;

/// Runs [`SCRIPT`] with Debian's python3 (python/ on its path) on the document text (stdin),
/// with the document's key paths as its arguments.
fn python(doc: &str, keys: &[String]) -> String {
    use std::io::Write;
    let mut child = Command::new("timeout")
        .args(["60", "/usr/bin/python3", "-c", SCRIPT])
        .args(keys)
        .env("PYTHONPATH", concat!(env!("CARGO_MANIFEST_DIR"), "/python"))
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("timeout and /usr/bin/python3 run (bash python/install-deps.sh)");
    child.stdin.take().unwrap().write_all(doc.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "exit {:?}: {}", out.status, String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// For every key of the document: the document without it, loaded by scene.py, fails with a
/// SceneError whose message starts with the key's path; the whole document loads and gives back
/// the values written.
const SCRIPT: &str = r#"
import copy, json, sys
from engine import scene as sm
doc = json.load(sys.stdin)
s = sm.parse(json.dumps(doc))
g = doc["geometry"]
print("values", s.geometry == g["kind"], s.dt == doc["time"]["dt"], s.steps == doc["time"]["steps"],
      s.mass == doc["mass"]["kind"], s.scheme == doc["scheme"]["kind"], s.density == g["density"],
      all(getattr(s, k) == v for k, v in g.items() if k != "kind"),
      all(getattr(s, k) == v for k, v in doc["output"].items()))
for path in sys.argv[1:]:
    d = copy.deepcopy(doc)
    *tables, key = path.split(".")
    t = d
    for name in tables:
        t = t[name]
    del t[key]
    try:
        sm.parse(json.dumps(d))
        print("missing", path, "accepted")
    except sm.SceneError as e:
        named = str(e).startswith(path + ":")
        print("missing", path, "named" if named else "unnamed: " + str(e))
"#;

#[test]
fn the_engine_takes_every_value_and_refuses_a_missing_key_by_name() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scenes =
        ["scenes/plate-bump-triangle-hybrid.toml", "scenes/solid-3d-hex-mod3.toml", "scenes/body-block-drop-mod3.toml"];
    let mut kinds = Vec::new();
    for name in scenes {
        let scene = AnyScene::from_file(&root.join(name)).unwrap();
        let doc = match &scene {
            AnyScene::Plate(s) => document(s),
            AnyScene::Solid(s) => document(s),
            AnyScene::Bar(_) => unreachable!("the engine runs plates and solids"),
        }
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let text = to_json(&doc);
        let value: Value = serde_json::from_str(&text).unwrap();
        kinds.push(value["geometry"]["kind"].as_str().unwrap().to_string());
        let keys = key_paths(&value);
        let out = python(&text, &keys);
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[0], "values True True True True True True True True", "{name}: {out}");
        assert_eq!(lines.len(), 1 + keys.len(), "{name}: {out}");
        for (key, line) in keys.iter().zip(&lines[1..]) {
            assert_eq!(*line, format!("missing {key} named"), "{name}");
        }
    }
    assert_eq!(kinds, ["plate", "solid", "body"]);
}
