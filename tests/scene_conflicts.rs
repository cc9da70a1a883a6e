//! Every refusal names the one key to change (issue 28): the same key from the parser
//! (`SceneError::key`, what the Python package's `SceneError.key` is) and first on the CLI's
//! `check` line. The combinations of geometry, mass, scheme and contact law are refused by one
//! rule when the scene is validated (`crate::scene`'s compat), with the allowed values.

mod common;

use massredist::scene::AnyScene;

/// (scene text, the key it must name).
const CASES: [(&str, &str); 10] = [
    // Penalty with the hybrid scheme: the law yields to the scheme.
    (
        "[bar]\n[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"hybrid\"\n[contact]\nmethod = \"penalty\"\npenalty = 1e4\n",
        "contact.method",
    ),
    // Moreau–Jean with a massless contact node: the mass yields to the scheme.
    ("[bar]\n[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"moreau-jean\"\n", "mass.kind"),
    // Nitsche on a solid: the law yields to the geometry.
    ("[solid]\n[contact]\nmethod = \"nitsche\"\n", "contact.method"),
    // Paoli–Schatzman on a plate: the scheme yields to the geometry.
    ("[plate]\n[scheme]\nkind = \"paoli-schatzman\"\n", "scheme.kind"),
    ("[bar]\ncolour = \"red\"\n", "bar.colour"),
    ("[colour]\nshade = 1\n", "colour"),
    ("[bar]\ninitial = { displacement = \"1 +\", velocity = \"0\" }\n", "bar.initial.displacement"),
    ("[bar]\nforce = \"1/x\"\n", "bar.force"),
    ("[bar]\nelements = 3\n[mass]\nkind = \"custom\"\nweights = [0.0, -1.0, 1.0]\n", "mass.weights"),
    ("[solid]\nmesh = \"no/such/mesh.msh\"\n", "solid.mesh"),
];

/// The parser's key, and the CLI's first line opening with it (exit 2). (Mutation: penalty
/// allowed with `Treatment::Own` in `ContactLaw::needs` -> the first case parses: fails.)
#[test]
fn each_refusal_names_its_one_key() {
    let dir = tempfile::tempdir().unwrap();
    for (i, (text, key)) in CASES.iter().enumerate() {
        let e = AnyScene::from_toml(text).expect_err(text);
        assert_eq!(e.key().as_deref(), Some(*key), "{text}: {e}");
        let path = dir.path().join(format!("s{i}.toml"));
        std::fs::write(&path, text).unwrap();
        let out =
            std::process::Command::new(env!("CARGO_BIN_EXE_massredist")).arg("check").arg(&path).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{text}");
        let stderr = common::stderr(&out);
        let first = stderr.lines().next().unwrap_or("");
        let bracketed = format!("[{key}]");
        // `error: <scene path>: <message>`: the message opens with the key.
        let shown = first.trim_start_matches("error: ").trim_start_matches(&format!("{}: ", path.display()));
        assert!(shown.starts_with(key) || shown.starts_with(&bracketed), "{text}: {first}");
    }
}

/// A conflict lists the values of its key that go with the rest, and the same combination is
/// refused the same way whichever table comes first (`[contact]` before `[scheme]`).
#[test]
fn conflicts_list_the_allowed_values() {
    let e = AnyScene::from_toml(CASES[0].0).unwrap_err().to_string();
    assert!(e.ends_with("allowed: exact"), "{e}");
    let e = AnyScene::from_toml(CASES[1].0).unwrap_err().to_string();
    assert!(e.contains("allowed: standard"), "{e}");
    let e = AnyScene::from_toml(CASES[2].0).unwrap_err().to_string();
    assert!(e.ends_with("allowed: exact | penalty"), "{e}");
    let e = AnyScene::from_toml(CASES[3].0).unwrap_err().to_string();
    assert!(
        e.ends_with("allowed: crank-nicolson | newmark | backward-euler | hybrid | central-difference | moreau-jean"),
        "{e}"
    );
    let swapped = "[contact]\nmethod = \"penalty\"\npenalty = 1e4\n[scheme]\nkind = \"hybrid\"\n[bar]\n";
    assert_eq!(AnyScene::from_toml(swapped).unwrap_err().key().as_deref(), Some("contact.method"));
    // A key of another law is refused by name.
    let e = AnyScene::from_toml("[contact]\nmethod = \"penalty\"\npenalty = 1.0\nnitsche_theta = 1\n").unwrap_err();
    assert_eq!(e.key().as_deref(), Some("contact.nitsche_theta"), "{e}");
}
