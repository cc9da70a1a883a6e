//! Plate scenes: every shipped plate scene runs and reads back, errors name the key, the bar's
//! keys on plates (reduction to the bar with x-only data), the plane-wave reference, VTU frames
//! read back, a gmsh mesh through meshio.

use massredist::bar::BarProblem;

#[test]
fn every_plate_scene_runs() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !(name.starts_with("plate-") && name.ends_with(".toml")) {
            continue;
        }
        let scene = massredist::scene::PlateScene::from_file(&path).unwrap();
        let again = massredist::scene::PlateScene::from_toml(&scene.resolved_toml()).unwrap();
        assert_eq!(scene, again, "{name}: the resolved scene reads back to itself");
        let run = massredist::run::run_scene(&scene, &mut []).unwrap();
        assert_eq!(run.summary.steps, scene.time.steps);
        assert!(run.summary.min_u0 >= 0.0 && run.summary.max_lambda <= 0.0, "{name}");
        n += 1;
    }
    assert!(n >= 3, "expected the plate scenes, found {n}");
}

#[test]
fn plate_scene_errors_name_the_key() {
    use massredist::scene::{AnyScene, PlateScene};
    // The geometry table decides the scene's variant; a scene has one.
    assert!(matches!(AnyScene::from_toml("[plate]\nnx = 4\n"), Ok(AnyScene::Plate(_))));
    assert!(matches!(AnyScene::from_toml("[bar]\nelements = 4\n"), Ok(AnyScene::Bar(_))));
    assert!(matches!(AnyScene::from_toml("[time]\ndt = 0.5\n"), Ok(AnyScene::Bar(_))));
    let both = AnyScene::from_toml("[bar]\n[plate]\n").unwrap_err().to_string();
    assert!(both.contains("one geometry table"), "{both}");
    let err = |t: &str| PlateScene::from_toml(t).unwrap_err().to_string();
    assert!(err("[plate]\ncells = \"hex\"\n").contains("plate.cells"));
    assert!(err("[plate]\nnx = 1\n").contains("plate.nx"));
    // Cells of aspect 1e9 cannot be factored in double precision: refused by name (it failed in
    // `run` as "not positive definite").
    let e = err("[plate]\nheight = 1e-9\n");
    assert!(e.contains("plate.height = 1e-9") && e.contains("aspect ratio"), "{e}");
    let e = err("[plate]\n[scheme]\nkind = \"paoli-schatzman\"\n");
    assert!(e.contains("scheme.kind = \"paoli-schatzman\"") && e.contains("a bar's"), "{e}");
    let e = err("[plate]\n[scheme]\nkind = \"crank-nicolson\"\nformulation = \"reduced\"\n");
    assert!(e.contains("scheme.formulation = \"reduced\"") && e.contains("a bar's"), "{e}");
    assert!(err("[plate]\n[mass]\nkind = \"standard\"\n[scheme]\nkind = \"hybrid\"\n").contains("hybrid"));
    assert!(err("[plate]\ninitial = \"bump\"\n[output]\nseries = [\"l2_error\"]\n").contains("plane wave"));
    assert!(err("[plate]\nnx = 4\nny = 2\n[mass]\nkind = \"custom\"\nweights = [1.0]\n").contains("8 cells"));
    assert!(err("[plate]\n[output]\nvtu_every = 3\n").contains("vtu"));
}

#[test]
fn a_y_dependent_run_writes_vtu_that_reads_back() {
    use massredist::observe::FrameRecorder;
    use massredist::plate::vtu::{read_pvd, read_vtu};
    use massredist::run::run_scene;
    use massredist::scene::PlateScene;
    let text = "[plate]\nnx = 40\nny = 40\ncells = \"triangle\"\ninitial = \"bump\"\n[mass]\nkind = \"mod3\"\n\
                [scheme]\nkind = \"hybrid\"\n[time]\ndt = 0.01\nend = 3.0\n[output]\nvtu = true\nvtu_every = 50\n";
    let scene = PlateScene::from_toml(text).unwrap();
    let run = run_scene(&scene, &mut []).unwrap();
    eprintln!(
        "bump 40x40 P1 hybrid mod3 T=3: energy {} -> {}, min {}, largest step increase {:e} (n >= 1: {:e}), max y-variation {}",
        run.summary.energy_initial,
        run.summary.energy_final,
        run.summary.energy_min,
        run.summary.energy_max_increase,
        run.summary.energy_max_increase_after_first,
        run.summary.max_y_variation.unwrap()
    );
    // The command line's path: series and frames streamed into the folder while computing. The
    // frames and series read back are those the in-memory run recorded, bit for bit.
    // mutation: `FrameWriter::observe` writing the frame before copying the state's u and v into
    // it (each file one frame late) -> fails at the `u` comparison (left: all 0.0).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let prepared = massredist::output::OutputDir::prepare(&out, false, &[]).unwrap();
    let streamed = massredist::run::run_scene_into(&scene, prepared, &mut []).unwrap();
    assert_eq!(streamed.energy_final, run.summary.energy_final);
    let mut series = Vec::new();
    massredist::output::write_series_csv(&run.series, &mut series).unwrap();
    assert_eq!(std::fs::read(out.join("series.csv")).unwrap(), series, "streamed series.csv = the recorded one");
    let frames: &FrameRecorder = run.frames.as_ref().unwrap();
    let pvd = read_pvd(&std::fs::read_to_string(out.join("plate.pvd")).unwrap());
    assert_eq!(pvd.len(), 7); // t = 0, 0.5, …, 3
    let mesh = &run.problem.system.mesh;
    for ((t, file), frame) in pvd.iter().zip(&frames.frames) {
        assert_eq!(*t, frame.t);
        let data = read_vtu(std::fs::read(out.join(file)).unwrap()).unwrap();
        assert_eq!((data.n_points, data.n_cells), (mesh.n_nodes(), mesh.n_cells()));
        assert_eq!(data.connectivity, mesh.cells);
        assert!(data.types.iter().all(|&t| t == 5));
        // Shortest round-trip formatting: bit-for-bit equal.
        assert_eq!(data.point_array("u").unwrap().values, frame.u);
        assert_eq!(data.point_array("v").unwrap().values, frame.v);
        assert_eq!(data.cell_array("weight").unwrap().values, run.problem.system.weights);
        let xy: Vec<f64> = data.points.chunks(3).flat_map(|p| [p[0], p[1]]).collect();
        assert_eq!(xy, mesh.flat_points());
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for key in
        ["linf_l2_error", "max_contact_error", "final_u0", "energy_initial", "min_u0", "max_complementarity_product"]
    {
        assert!(summary.get(key).is_some(), "summary.json lacks {key}");
    }
}

#[test]
fn plates_take_the_bar_keys_and_reduce_to_the_bar_with_x_only_data() {
    // The same keys as bars (density, modulus, far_end, gap, expressions): with Q1 cells, x-only
    // weights and y-independent data the plate is the bar extended in y (tensor products, as in
    // the test above), so both scenes built from text must step alike to round-off, for a free
    // far end, a gap, another material and expression data. Mutation check: assembling the
    // plate's density into its stiffness, or ignoring plate.gap, breaks the comparison.
    use massredist::plate::PlateProblem;
    use massredist::scene::PlateScene;
    let body = "density = 4.0\nmodulus = 2.25\nfar_end = \"free\"\ngap = 0.05\n\
                initial = { displacement = \"0.1*x\", velocity = \"-1+0.3*x\" }";
    let tail = "[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"KIND\"\n[time]\ndt = 0.01\nend = 2.0\n[output]\nseries = [\"u0\"]\n";
    // And with a time-dependent force linear in x: the bar's Gauss rule and the plate's
    // interpolated load M_w I_h f are both exact for it, so the reduction holds for F(t) too
    // (mutation: the plate's F(t) evaluated at t/2 in `transient_load` gives 0.13).
    let forced = format!("{body}\nforce = \"x*sin(3*t)\"");
    for (kind, body) in
        ["crank-nicolson", "backward-euler", "hybrid"].into_iter().flat_map(|k| [(k, body), (k, forced.as_str())])
    {
        let tail = tail.replace("KIND", kind);
        let plate = PlateScene::from_toml(&format!("[plate]\nnx = 20\nny = 3\nheight = 0.5\n{body}\n{tail}")).unwrap();
        let bar = massredist::scene::Scene::from_toml(&format!("[bar]\nelements = 20\n{body}\n{tail}")).unwrap();
        let p2 = PlateProblem::new(&plate.geometry, &plate.mass).unwrap();
        let p1 = BarProblem::from_scene(&bar).unwrap();
        assert_eq!(p2.system.system.lower, vec![-0.05; 4], "the gap on every contact node");
        let (mut s2, mut s1) = (p2.scheme(&plate.scheme, 0.01).unwrap(), p1.scheme(&bar.scheme, 0.01).unwrap());
        let mut worst = 0.0f64;
        let mut contact = 0;
        for _ in 0..200 {
            s2.step().unwrap();
            s1.step().unwrap();
            let (a, b) = (s2.state(), s1.state());
            for (d, &node) in p2.system.dofs.iter().enumerate() {
                worst = worst.max((a.u[d] - b.u[node % 21]).abs());
            }
            contact += usize::from(b.lambda[0] < 0.0);
        }
        assert!(contact > 0, "{kind}: the bar must reach the obstacle");
        // As in the test above: linear growth of per-step round-off, 64 ε per step.
        assert!(worst <= 200.0 * 64.0 * f64::EPSILON, "{kind} {body}: max |u_2D − u_1D| = {worst:e}");
    }
    let err = |t: &str| PlateScene::from_toml(&format!("[plate]\n{t}\n")).unwrap_err().to_string();
    assert!(err("density = 0").contains("plate.density"));
    assert!(err("far_end = \"hinged\"").contains("plate.far_end"));
    assert!(err("gap = -1").contains("plate.gap"));
    assert!(err("force = \"z*t\"").contains("plate.force"));
    assert!(err("initial = { displacement = \"x+\" }").starts_with("plate.initial.displacement"));
    assert!(err("heigth = 2").contains("unknown field `heigth` in [plate]"));
    // One [output] table for every geometry: plates honour summary_l2, bars refuse the VTU keys.
    let text = "[plate]\nnx = 4\nny = 2\n[time]\ndt = 0.05\nend = 1.0\n[output]\nsummary_l2 = false\nseries = []\n";
    let run = massredist::run::run_scene(&PlateScene::from_toml(text).unwrap(), &mut []).unwrap();
    assert!(run.summary.linf_l2_error.is_none() && run.summary.max_contact_error.is_some());
    let e = massredist::scene::BarScene::from_toml("[output]\nvtu = true\n").unwrap_err().to_string();
    assert!(e.contains("output.vtu") && e.contains("[bar]"), "{e}");
    // The series-size limit holds for plates too (it did not: a 2×1 plate with Δt = 1e-6 and
    // T = 2000 recorded until memory ran out).
    let e = PlateScene::from_toml(
        "[plate]\nnx = 2\nny = 1\n[time]\ndt = 1e-6\nend = 2000\n[output]\nseries = [\"u0\", \"lambda\"]\n",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("output.series would record") && e.contains("output.every"), "{e}");
}

#[test]
fn y_independent_plates_are_measured_against_the_plane_wave() {
    // Without force and with y-independent data, the plate's reference is the bar's solution by
    // characteristics extended in y: its contact errors equal the bar's (the Q1 plate steps as
    // the bar, test above), its L² error is √H times the bar's, and exact_u0 is a column.
    // Mutation check: building the plane wave without the plate's gap changes
    // max_contact_error by O(gap); dropping the `e_lo e_hi` term of the cut integral in
    // `l2_error_plane_wave` moves the L² error by ~30 %.
    use massredist::run::run_scene;
    use massredist::scene::PlateScene;
    let body = "modulus = 4.0\nfar_end = \"free\"\ngap = 0.1\ninitial = { displacement = \"0\", velocity = \"-1\" }";
    let tail = "[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"hybrid\"\n[time]\ndt = 0.005\nend = 1.5\n";
    let plate_text =
        format!("[plate]\nnx = 40\nny = 2\nheight = 0.2\n{body}\n{tail}[output]\nseries = [\"u0\", \"exact_u0\"]\n");
    let plate = PlateScene::from_toml(&plate_text).unwrap();
    let bar = massredist::scene::BarScene::from_toml(&format!("[bar]\nelements = 40\n{body}\n{tail}")).unwrap();
    let run = run_scene(&plate, &mut []).unwrap();
    let massredist::run::SceneRun { summary, .. } = massredist::run::run_scene(&bar, &mut []).unwrap();
    let (e2, e1) = (run.summary.max_contact_error.unwrap(), summary.max_contact_error.unwrap());
    assert!(
        approx::relative_eq!(e2, e1, epsilon = 1e-12, max_relative = 0.0),
        "max contact error: plate {e2} vs bar {e1}"
    );
    let (l2, l1) = (run.summary.l2_lambda_error.unwrap(), summary.l2_lambda_error.unwrap());
    assert!(approx::relative_eq!(l2, l1, epsilon = 1e-10, max_relative = 0.0), "λ error: plate {l2} vs bar {l1}");
    let (l2, l1) = (run.summary.linf_l2_error.unwrap(), summary.linf_l2_error.unwrap());
    // The same exact rule on both sides (8-point Gauss split at the waves' breakpoints), on states
    // that agree to ~1e-12: the errors agree to that, times √H.
    assert!(
        approx::relative_eq!(l2, 0.2f64.sqrt() * l1, epsilon = 1e-10, max_relative = 0.0),
        "L∞(L²): plate {l2} vs √H · bar {}",
        0.2f64.sqrt() * l1
    );
    // Impact is the first t_n with u_0 ≤ −gap: round-off between the two may move it by a step.
    let (a, b) = (run.summary.impact_time_shift.unwrap(), summary.impact_time_shift.unwrap());
    assert!(
        approx::relative_eq!(a, b, epsilon = 0.005 * (1.0 + 1e-9), max_relative = 0.0),
        "impact shift: plate {a} vs bar {b}"
    );
    let e = PlateScene::from_toml("[plate]\ninitial = \"bump\"\n[output]\nseries = [\"exact_u0\"]\n").unwrap_err();
    assert!(e.to_string().contains("exact_u0"), "{e}");
}
