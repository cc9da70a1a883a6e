//! One elastic body (issue 28): a solid scene builds its mesh, contact set and weights once,
//! when it is validated, and its run uses them; a spec changed since is built again; a mesh
//! given as arrays is passed to the validation explicitly (no state outside the call).

use massredist::mass::MassKind;
use massredist::scene::mesh_file::{ArrayMesh, MeshInputs};
use massredist::scene::{AnyScene, SolidScene};
use massredist::solid::{MeshSource, Support};
use std::path::Path;
use std::sync::Arc;

const REST: &str = "[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"backward-euler\"\n[time]\ndt = 0.05\nend = 0.5\n";

fn solid(text: &str) -> SolidScene {
    SolidScene::from_toml(text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The validated scene's mesh is the run's (the same object, not a second build), for the box
/// and for a body; and the weights the run assembles are the ones the validation learnt w_0
/// from.
/// (Mutation, as run: `BuildCache::get` without its early return (a build per call) -> the
/// `Arc::ptr_eq` assertion fails for both scenes.)
#[test]
fn a_validated_solid_is_built_once_and_run_on_what_was_built() {
    let body = "[obstacle]\nnormal = [0, 1]\npoint = [0, -0.01]\n";
    for extra in ["", body] {
        let scene = solid(&format!("[solid]\nnx = 4\nny = 3\ncells = \"triangle\"\n{extra}{REST}"));
        let built = scene.geometry.built().unwrap();
        let setup = massredist::run::setup(&scene).unwrap();
        assert!(Arc::ptr_eq(&built.mesh, &setup.problem.system.mesh), "{extra}: the mesh was built again");
        assert_eq!(setup.problem.system.weights, built.weights(&MassKind::Mod3).unwrap(), "{extra}");
        assert_eq!(setup.problem.system.contact_nodes, built.contact.nodes, "{extra}");
    }
}

/// A spec changed after validation is built again from its new fields (library users and tests
/// edit specs): here the box's cells and its gap.
/// (Mutation, as run: the key comparison in `BuildCache::get` replaced by `true` -> the cell
/// count assertion fails: the old mesh is reused.)
#[test]
fn a_changed_spec_is_built_again() {
    let mut scene = solid(&format!("[solid]\nnx = 4\nny = 3\n{REST}"));
    let before = scene.geometry.built().unwrap();
    assert_eq!(before.mesh.n_cells(), 12);
    scene.geometry.cells_per_axis = [6, 3, 1];
    let Support::Face { lateral, force, .. } = scene.geometry.support else { panic!("the box") };
    scene.geometry.support = Support::Face { gap: 0.25, lateral, force };
    let after = scene.geometry.built().unwrap();
    assert_eq!(after.mesh.n_cells(), 18);
    assert_eq!(after.contact.gaps, vec![0.25; 4]);
    let setup = massredist::run::setup(&scene).unwrap();
    assert_eq!(setup.problem.system.system.lower, vec![-0.25; 4]);
}

/// A mesh given as arrays stands for `mesh = "<arrays>"` in the call that is given them, and
/// only there: the same text without arrays names a file "<arrays>", which does not exist
/// (refused, naming `solid.mesh`). The arrays' scene runs as the generated mesh's (the same
/// points and cells).
/// (Mutation, as run: `MeshInputs::resolve` ignoring the arrays -> the first `unwrap` fails
/// with the missing file.)
#[test]
fn arrays_are_passed_with_the_scene_not_beside_it() {
    let generated = solid(&format!("[solid]\nnx = 4\nny = 2\ncells = \"triangle\"\n{REST}"));
    let mesh = generated.geometry.mesh().unwrap();
    let arrays = ArrayMesh {
        points: mesh.points.iter().flat_map(|p| [p[0], p[1]]).collect(),
        columns: 2,
        blocks: vec![("triangle".into(), mesh.cells.iter().map(|&v| v as i64).collect(), 3)],
    };
    let text = format!("[solid]\nmesh = \"<arrays>\"\n{REST}");
    let inputs = MeshInputs { base: Path::new("."), arrays: Some(&arrays) };
    let AnyScene::Solid(given) = AnyScene::from_toml_with(&text, inputs).unwrap() else { panic!("a solid") };
    assert!(matches!(given.geometry.source, MeshSource::Arrays(_)));
    assert!(given.resolved_toml().contains("mesh = \"<arrays>\""));
    let err = AnyScene::from_toml(&text).unwrap_err().to_string();
    assert!(err.starts_with("solid.mesh = \"./<arrays>\" cannot be opened"), "{err}");
    let (a, b) = (
        massredist::run::run_scene(&given, &mut []).unwrap(),
        massredist::run::run_scene(&generated, &mut []).unwrap(),
    );
    assert_eq!(a.summary.energy_final, b.summary.energy_final);
    assert_eq!(a.last.u, b.last.u);
}
