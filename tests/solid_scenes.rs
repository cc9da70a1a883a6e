//! Solid scenes (`[solid]`): the resolved scene reads back to itself, a solid scene run is the
//! bar's run extended in y and z, errors name the key and its range before anything is built,
//! the first impact and release are decided node by node, and a run folder holds the files
//! other tools read.

use massredist::driver::{Observer, Sample};
use massredist::scene::{AnyScene, BarScene, SolidScene};

fn solid(text: &str) -> SolidScene {
    SolidScene::from_toml(text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

const SECTIONS: &str = "[mass]\nkind = \"mod3\"\n[time]\ndt = 0.05\nend = 3.0\n";

#[test]
fn the_resolved_solid_scene_reads_back_to_itself() {
    for table in [
        "dim = 2\nnx = 6\nny = 2\ncells = \"triangle\"\nlame_lambda = 1.5\nlateral = \"roller\"\ngap = 0.01",
        "dim = 3\nnx = 4\nny = 2\nnz = 3\ndepth = 0.5\ncells = \"tet\"\nforce = [0, -1, 0.5]",
        "dim = 2\nnx = 4\nny = 2\ninitial = { displacement = [\"(1-x)/2*(1+y/H)\", \"0\"], velocity = [\"0\", \"x*y\"] }",
    ] {
        let text = format!("[solid]\n{table}\n{SECTIONS}[scheme]\nkind = \"backward-euler\"\n");
        let scene = solid(&text);
        let again = solid(&scene.resolved_toml());
        assert_eq!(scene, again, "{text}\n---\n{}", scene.resolved_toml());
        assert!(matches!(AnyScene::from_toml(&text), Ok(AnyScene::Solid(_))));
    }
}

/// max over the recorded steps of |u0_solid − u0_bar| and |λ_solid − λ_bar|.
fn max_series_difference(a: &massredist::observe::SeriesRecorder, b: &massredist::observe::SeriesRecorder) -> f64 {
    let (ra, rb): (Vec<&[f64]>, Vec<&[f64]>) = (a.iter_rows().collect(), b.iter_rows().collect());
    assert_eq!(ra.len(), rb.len());
    ra.iter().zip(&rb).flat_map(|(x, y)| x.iter().zip(y.iter()).map(|(p, q)| (p - q).abs())).fold(0.0, f64::max)
}

#[test]
fn a_q1_solid_scene_is_the_bar_scene_extended_in_y_and_z() {
    // With λ = 0, μ = ½, ρ = 1, Q1 cells, x-only weights and the paper's data, the solid is the
    // bar with modulus λ + 2μ = 1 (module docs of `massredist::solid`): the scene path (parsing,
    // mass, scheme, dt, observers) must give the bar's u0, λ and energy per unit section at every
    // step. Tolerance: 1e3 ε — a few hundred round-off operations per step on O(1) values over
    // 60 steps (the library-level test in tests/solid.rs measures ~1e-13 for these sizes).
    // mutation: passing MassKind::Mod1 instead of the scene's mass in run::solid::setup
    // -> fails (differences of order 1e-1).
    // The unit square and cube have section 1, so the energies compare as they are.
    for table in ["dim = 2\nny = 3\ncells = \"quad\"", "dim = 3\nny = 2\nnz = 2\ncells = \"hex\""] {
        for scheme in ["crank-nicolson", "backward-euler", "hybrid"] {
            let series = "[output]\nseries = [\"u0\", \"lambda\", \"energy\"]\n";
            let s = solid(&format!("[solid]\n{table}\nnx = 10\n{SECTIONS}[scheme]\nkind = \"{scheme}\"\n{series}"));
            let b = BarScene::from_toml(&format!(
                "[bar]\nelements = 10\n{SECTIONS}[scheme]\nkind = \"{scheme}\"\n{series}"
            ))
            .unwrap();
            let rs = massredist::run::run_scene(&s, &mut []).unwrap();
            let massredist::run::SceneRun { summary: bar_summary, series: bar_series, .. } =
                massredist::run::run_scene(&b, &mut []).unwrap();
            let d = max_series_difference(&rs.series, &bar_series);
            assert!(d < 1e3 * f64::EPSILON, "{table} {scheme}: {d:e}");
            assert!(rs.summary.first_impact_time.is_some());
            assert_eq!(rs.summary.first_impact_time, bar_summary.first_impact_time, "{table} {scheme}");
            assert_eq!(rs.summary.first_release_time, bar_summary.first_release_time, "{table} {scheme}");
        }
    }
}

#[test]
fn solid_scene_errors_name_the_key_and_its_range() {
    let err = |t: &str| AnyScene::from_toml(t).unwrap_err().to_string();
    let e = err("[solid]\n[plate]\n");
    assert!(e.contains("[plate] and [solid]") && e.contains("one geometry table"), "{e}");
    let e = err("[solid]\ndim = 3\nnx = 10000\nny = 10000\nnz = 10000\n");
    assert!(e.contains("solid.nx, solid.ny, solid.nz") && e.contains("1e7"), "{e}");
    let e = err("[solid]\ndim = 3\nny = 100\nnz = 100\n");
    assert!(e.contains("contact nodes") && e.contains("solid.ny, solid.nz"), "{e}");
    // Central differences with the exact law form no dense Schur complement of the face (forward
    // increments on massive nodes, the sparse layer on massless ones): the same box is accepted,
    // and refused again with the penalty law. (Mutation, as run: the rule's exception removed ->
    // the first assertion fails naming 10201 contact nodes.)
    let cd = "[solid]\ndim = 3\nny = 100\nnz = 100\n[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"central-difference\"\n[time]\ndt = 1e-4\nend = 1e-3\n";
    if let Err(e) = AnyScene::from_toml(cd) {
        panic!("central differences with exact contact on 10201 contact nodes: {e}");
    }
    let e = err(&format!("{cd}[contact]\nmethod = \"penalty\"\npenalty = 1e3\n"));
    assert!(e.contains("contact nodes") && e.contains("solid.ny, solid.nz"), "{e}");
    let e = err("[solid]\nheight = 1e-9\n");
    assert!(e.contains("solid.height") && e.contains("1e6"), "{e}");
    let e = err("[solid]\nlength = 1e300\n");
    assert!(e.contains("solid.length") && e.contains("1e100"), "{e}");
    let e = err("[solid]\ncells = \"triangle\"\n[output]\nseries = [\"l2_error\"]\n");
    assert!(e.contains("l2_error") && e.contains("quad and hex"), "{e}");
    let e = err("[solid]\nlame_lambda = 1\n[output]\nseries = [\"exact_u0\"]\n");
    assert!(e.contains("plane wave") && e.contains("roller"), "{e}");
    let e = err("[solid]\n[scheme]\nkind = \"paoli-schatzman\"\n");
    assert!(e.contains("a [solid] scene") && e.contains("allowed: crank-nicolson"), "{e}");
    let e = err("[solid]\ninitial = { displacement = [\"1/(x-0.5)\", \"0\"] }\n");
    assert!(e.contains("solid.initial.displacement"), "{e}");
    let e = err("[solid]\nnx = 4\nny = 2\n[mass]\nkind = \"custom\"\nweights = [1.0]\n");
    assert!(e.contains("8 cells"), "{e}");
}

/// Records, at every step, whether some contact node carries force (λ_c < 0, docs/scenes.md):
/// the first impact and release computed independently of the summary; and the first step at
/// which the face's mean u0 reaches the obstacle.
struct Touching {
    gap: f64,
    first: Option<f64>,
    release: Option<f64>,
    first_by_mean: Option<f64>,
}

impl Observer for Touching {
    fn observe(&mut self, s: &Sample) {
        let touching = s.state.lambda.iter().any(|&l| l < 0.0);
        match self.first {
            None if touching => self.first = Some(s.state.t),
            Some(_) if self.release.is_none() && !touching => self.release = Some(s.state.t),
            _ => {}
        }
        if self.first_by_mean.is_none() && s.u0 <= -self.gap {
            self.first_by_mean = Some(s.state.t);
        }
    }
}

#[test]
fn first_impact_and_release_are_decided_node_by_node() {
    // A face that arrives tilted: u_x(0, y) = (1 + y)/2, so the node at y = 0 touches first and
    // the mean u0 later. The summary's impact must be the first node's, not the mean's.
    // mutation: testing the reference node (`u0 <= self.lower[0]`) in SummaryObserver instead of
    // every node -> fails (the summary impact is later than the first node's). (This smooth case
    // does not tell the force from the position: tests/central.rs does.)
    let text = format!(
        "[solid]\nnx = 10\nny = 4\ngap = 0.0\ninitial = {{ displacement = [\"(1-x)/2*(1+y)\", \"0\"] }}\n{SECTIONS}[scheme]\nkind = \"hybrid\"\n"
    );
    let s = solid(&text);
    let mut t = Touching { gap: 0.0, first: None, release: None, first_by_mean: None };
    let run = massredist::run::run_scene(&s, &mut [&mut t]).unwrap();
    assert!(t.first.is_some() && t.first < t.first_by_mean, "{:?} {:?}", t.first, t.first_by_mean);
    assert_eq!(run.summary.first_impact_time, t.first);
    assert_eq!(run.summary.first_release_time, t.release);
}

#[test]
fn a_solid_run_folder_holds_series_summary_frames_and_the_resolved_scene() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.toml");
    let text = format!(
        "[solid]\ndim = 3\nnx = 6\nny = 2\nnz = 2\ncells = \"tet\"\nlame_lambda = 1.0\nlateral = \"roller\"\n{SECTIONS}[scheme]\nkind = \"crank-nicolson\"\n[output]\nvtu = true\nvtu_every = 20\n"
    );
    std::fs::write(&scene, &text).unwrap();
    let out = dir.path().join("out");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_massredist"))
        .args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .status()
        .unwrap();
    assert!(status.success());
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for (key, value) in [("dim", 3.0), ("nz", 2.0), ("lame_lambda", 1.0), ("steps", 60.0)] {
        assert_eq!(summary[key].as_f64(), Some(value), "{key}");
    }
    assert_eq!(summary["cells"], "tet");
    assert_eq!(summary["lateral"], "roller");
    // 60 steps, a frame every 20: frames at steps 0, 20, 40, 60.
    let pvd = std::fs::read_to_string(out.join("solid.pvd")).unwrap();
    assert_eq!(massredist::fem::vtu::read_pvd(&pvd).len(), 4);
    let frame = std::fs::read(out.join("vtu/frame_00003.vtu")).unwrap();
    let data = massredist::fem::vtu::read_vtu(&frame).unwrap();
    assert_eq!(data.point_array("displacement").unwrap().components, 3);
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    assert_eq!(series.lines().count(), 62, "header and 61 rows");
    let resolved = std::fs::read_to_string(out.join("scene.resolved.toml")).unwrap();
    assert_eq!(SolidScene::from_toml(&resolved).unwrap(), solid(&text));
}

#[test]
fn every_shipped_solid_scene_reads_back_and_runs_with_complementarity() {
    // Each `scenes/solid-*.toml`: the resolved scene reads back to itself, and the run keeps
    // u_x ≥ −gap and λ ≤ 0 on every contact node at every step (the summary's extremes) with
    // (u_x + gap) λ = 0 to round-off (the exact LCP solve: products of O(1) values, 1e3 ε).
    // mutation: the solid's obstacle moved to −(gap + 1e9) in SolidSystem::assemble (no contact)
    // -> fails on solid-3d-hex-mod3.toml (min u0 < −gap).
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !(name.starts_with("solid-") && name.ends_with(".toml")) {
            continue;
        }
        let scene = SolidScene::from_file(&path).unwrap();
        assert_eq!(scene, solid(&scene.resolved_toml()), "{name}");
        let run = massredist::run::run_scene(&scene, &mut []).unwrap();
        let s = &run.summary;
        assert_eq!(s.steps, scene.time.steps, "{name}");
        assert!(s.min_u0 >= -scene.geometry.support.gap() && s.max_lambda <= 0.0, "{name}");
        assert!(s.max_complementarity_product <= 1e3 * f64::EPSILON, "{name}: {:e}", s.max_complementarity_product);
        n += 1;
    }
    assert!(n >= 1, "expected the solid scenes, found {n}");
}

/// `solid.mesh`: a meshio file of the structured mesh (written as VTU by our writer, read by
/// meshio) gives the structured scene's run: same u0, λ and energy at every step. The file keeps
/// the node order, so the two runs do the same arithmetic; tolerance 1e3 ε as above.
/// mutation: `file_mesh` stretching the file's mesh by 1.1 in x (points and extent) -> fails
/// (the points read differ from the structured mesh's).
#[cfg(feature = "python")]
#[test]
fn a_mesh_file_of_the_structured_mesh_gives_the_structured_run() {
    use massredist::fem::vtu::{Grid, Layout, vtk_type};
    let dir = tempfile::tempdir().unwrap();
    for (table, name) in [
        ("dim = 2\nnx = 6\nny = 3\ncells = \"triangle\"", "tri.vtu"),
        ("dim = 3\nnx = 4\nny = 2\nnz = 2\ncells = \"tet\"\nlateral = \"roller\"", "tet.vtu"),
        ("dim = 3\nnx = 4\nny = 2\nnz = 2\ncells = \"hex\"", "hex.vtu"),
    ] {
        let rest =
            format!("{SECTIONS}[scheme]\nkind = \"hybrid\"\n[output]\nseries = [\"u0\", \"lambda\", \"energy\"]\n");
        let structured = solid(&format!("[solid]\n{table}\nlame_lambda = 0.5\n{rest}"));
        let mesh = structured.geometry.mesh().unwrap();
        let grid =
            Grid { points: &mesh.points, cells: &mesh.cells, verts: mesh.kind.verts(), kind: vtk_type(mesh.kind) };
        std::fs::write(dir.path().join(name), Layout::new(&grid, &[], "", &[]).frame(&[])).unwrap();
        let lateral = if table.contains("roller") { "lateral = \"roller\"\n" } else { "" };
        let dim = &table[..7];
        let scene_path = dir.path().join("s.toml");
        std::fs::write(&scene_path, format!("[solid]\n{dim}\nmesh = \"{name}\"\n{lateral}lame_lambda = 0.5\n{rest}"))
            .unwrap();
        let from_file = SolidScene::from_file(&scene_path).unwrap();
        assert_eq!(from_file.geometry.mesh().unwrap().points, mesh.points, "{name}");
        let a = massredist::run::run_scene(&structured, &mut []).unwrap();
        let b = massredist::run::run_scene(&from_file, &mut []).unwrap();
        let d = max_series_difference(&a.series, &b.series);
        assert!(d < 1e3 * f64::EPSILON, "{name}: {d:e}");
        assert_eq!(SolidScene::from_toml(&from_file.resolved_toml()).unwrap(), from_file, "{name}");
        // The FEniCSx engine builds structured meshes only: a mesh file is refused by name, not
        // run on the wrong mesh. mutation: `engine_refusal` returning None for solids -> fails.
        let refusal = massredist::engine::validate(&from_file).unwrap_err().to_string();
        assert!(refusal.contains("solid.mesh"), "{refusal}");
        assert!(massredist::engine::validate(&structured).is_ok());
    }
}
