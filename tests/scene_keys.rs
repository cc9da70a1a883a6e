//! `docs/scenes.md` lists exactly the keys the scene parser accepts.
//!
//! The accepted keys are read off the parser itself, not written here: every table is closed
//! (serde's `deny_unknown_fields`, or the parser's own "unknown field" check of flattened and
//! tagged tables), and its refusal of an unknown key lists the keys it takes ("expected one of
//! …"). A tagged table (`kind = …`, `method = …`) is probed once per tag value, the values read
//! off the refusal of an unknown one ("allowed range is a | b | …"). Keys of inline tables
//! (`bar.initial.displacement`) are read off resolved scenes (every default written), of the
//! shipped scenes and of one scene per geometry with its initial data as a table.
//!
//! Mutation: a key removed from `docs/scenes.md` (or a field added to a `Raw*` table) fails here
//! with the key named.

use massredist::scene::AnyScene;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// A key no table takes.
const UNKNOWN: &str = "zzz_not_a_key";

/// The message of parsing `text`, which must be refused.
fn refusal(text: &str) -> String {
    match AnyScene::from_toml(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// The names after "expected" in an unknown-key refusal (serde's `one of `a`, `b``, `` `a` or
/// `b` ``, `` `a` ``, or the parser's `one of a, b`); None if the message is not one.
fn expected_keys(message: &str) -> Option<Vec<String>> {
    let at = message.find(&format!("unknown field `{UNKNOWN}`"))?;
    let rest = &message[at..];
    // serde's message may end with the position: "… `output` (line 1, column 1)".
    let line = rest.lines().next().unwrap();
    let line = line.split(" (line ").next().unwrap();
    if line.contains("there are no fields") {
        return Some(Vec::new());
    }
    let list = line.split_once("expected ")?.1;
    let list = list.strip_prefix("one of ").unwrap_or(list);
    Some(
        list.split(", ")
            .flat_map(|s| s.split(" or "))
            .map(|s| s.trim().trim_matches('`').to_string())
            .filter(|s| !s.is_empty())
            .collect(),
    )
}

/// The values of a tag key, read off the refusal of an unknown value (`allowed range is a | b`).
fn tag_values(table: &str, tag: &str) -> Vec<String> {
    let message = refusal(&format!("[{table}]\n{tag} = \"{UNKNOWN}\"\n"));
    let range = message
        .split_once("allowed range is ")
        .unwrap_or_else(|| panic!("{table}.{tag}: no allowed range in {message}"))
        .1
        .lines()
        .next()
        .unwrap();
    range.split(" | ").map(|v| v.split_whitespace().next().unwrap().trim_matches('"').to_string()).collect()
}

/// The keys of one table, `table.key`, from its refusals of an unknown key (one per tag value
/// for tagged tables).
fn table_keys(table: &str) -> BTreeSet<String> {
    let mut message = refusal(&format!("[{table}]\n{UNKNOWN} = 1\n"));
    // An array of tables (`[[pair]]`) is probed as one.
    if message.contains("expected a sequence") {
        message = refusal(&format!("[[{table}]]\n{UNKNOWN} = 1\n"));
    }
    let keys = expected_keys(&message).unwrap_or_else(|| panic!("[{table}]: no key list in {message}"));
    let mut out: BTreeSet<String> = keys.iter().map(|k| format!("{table}.{k}")).collect();
    for tag in ["kind", "method"].into_iter().filter(|t| keys.iter().any(|k| k == t)) {
        for value in tag_values(table, tag) {
            let message = refusal(&format!("[{table}]\n{tag} = \"{value}\"\n{UNKNOWN} = 1\n"));
            // A kind may refuse something else first (custom without weights): the other
            // kinds' probes list the shared keys.
            if let Some(keys) = expected_keys(&message) {
                out.extend(keys.iter().map(|k| format!("{table}.{k}")));
            }
        }
    }
    out
}

/// Keys of inline tables (`table.key.sub`) in a resolved scene.
fn nested_keys(resolved: &str) -> BTreeSet<String> {
    let doc: toml::Table = resolved.parse().expect("a resolved scene is TOML");
    let mut out = BTreeSet::new();
    for (table, value) in &doc {
        let Some(inner) = value.as_table() else { continue };
        for (key, value) in inner {
            if let Some(sub) = value.as_table() {
                out.extend(sub.keys().map(|s| format!("{table}.{key}.{s}")));
            }
        }
    }
    out
}

fn shipped_scenes(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            shipped_scenes(&path, out);
        } else if path.extension().is_some_and(|e| e == "toml") {
            out.push(path);
        }
    }
}

/// Every key the parser accepts.
fn accepted() -> BTreeSet<String> {
    let message = refusal(&format!("[{UNKNOWN}]\n"));
    let tables = expected_keys(&message).unwrap_or_else(|| panic!("no table list in {message}"));
    assert!(tables.len() >= 5, "the tables of a scene: {tables:?}");
    let mut keys: BTreeSet<String> = tables.iter().cloned().collect();
    for table in &tables {
        keys.extend(table_keys(table));
    }
    // Inline tables: one scene per geometry with initial data as a table, and every shipped
    // scene that loads without the `python` feature (a meshio mesh file needs it).
    let own = [
        "[bar]\ninitial = { displacement = \"0\", velocity = \"0\" }\n",
        "[plate]\nnx = 2\nny = 2\ninitial = { displacement = \"0\", velocity = \"0\" }\n",
        "[solid]\nnx = 2\nny = 2\ninitial = { displacement = [\"0\", \"0\"], velocity = [\"0\", \"0\"] }\n",
    ];
    for text in own {
        let scene = AnyScene::from_toml(text).unwrap_or_else(|e| panic!("{text}: {e}"));
        keys.extend(nested_keys(&scene.resolved_toml()));
    }
    let mut paths = Vec::new();
    shipped_scenes(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes"), &mut paths);
    assert!(paths.len() >= 10, "the shipped scenes");
    for path in paths {
        if let Ok(scene) = AnyScene::from_file(&path) {
            keys.extend(nested_keys(&scene.resolved_toml()));
        }
    }
    keys
}

/// The keys in the first column of the key tables of `docs/scenes.md` (section "Keys").
fn documented() -> BTreeSet<String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scenes.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let start = text.find("\n## Keys\n").expect("a section \"## Keys\" in docs/scenes.md");
    let section = &text[start + 1..];
    let section = &section[..section[3..].find("\n## ").map_or(section.len(), |e| e + 3)];
    let mut keys = BTreeSet::new();
    for line in section.lines().filter(|l| l.starts_with("| `")) {
        let first = line[1..].split(" | ").next().unwrap();
        keys.extend(first.split('`').skip(1).step_by(2).map(str::to_string));
    }
    keys
}

#[test]
fn docs_scenes_md_lists_every_key_the_parser_accepts() {
    let (accepted, documented) = (accepted(), documented());
    let undocumented: Vec<_> = accepted.difference(&documented).collect();
    let unknown: Vec<_> = documented.difference(&accepted).collect();
    assert!(
        undocumented.is_empty() && unknown.is_empty(),
        "accepted but not in docs/scenes.md: {undocumented:?}\nin docs/scenes.md but not accepted: {unknown:?}"
    );
    // The probes reached every kind of table: tagged, flattened, serde-closed and inline.
    for key in ["scheme.theta", "mass.weights", "plate.force", "obstacle.contact", "contact.nitsche_gamma0"] {
        assert!(accepted.contains(key), "{key} was not found by the probes: {accepted:?}");
    }
    assert!(accepted.contains("solid.initial.velocity"), "inline tables: {accepted:?}");
}

#[test]
fn an_unknown_key_of_an_inline_table_is_refused() {
    // The inline tables are read off resolved scenes, which shows they accept those keys; that
    // they accept no other is this test's.
    for text in [
        format!("[bar]\ninitial = {{ displacement = \"0\", {UNKNOWN} = \"0\" }}\n"),
        format!("[solid]\nnx = 2\nny = 2\ninitial = {{ displacement = [\"0\", \"0\"], {UNKNOWN} = [\"0\", \"0\"] }}\n"),
    ] {
        refusal(&text);
    }
}
