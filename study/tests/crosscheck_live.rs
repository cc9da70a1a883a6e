//! Live cross-check against dolfinx and scikit-fem through the pyo3 bridge (feature `python`;
//! `bash python/install-deps.sh` installs what it needs).
#![cfg(feature = "python")]

use massredist::fem::{Cell, Mesh};
use massredist_study::crosscheck::{Physics, Tamper, cases_2d, matrix_cases, run, solid_cases};

#[test]
fn every_case_agrees_with_both_backends() {
    let report = run(None, &matrix_cases().expect("bridge works")).expect("bridge works");
    let failed: Vec<_> = report.cases.iter().filter(|c| !c.pass).collect();
    assert!(failed.is_empty(), "outside tolerance: {failed:#?}");
    for backend in ["dolfinx", "skfem"] {
        let n = report.cases.iter().filter(|c| c.backend == backend && c.dim == 1).count();
        assert_eq!(n, 20, "{backend}: every 1D case");
        let traj = report.cases.iter().filter(|c| c.backend == backend && c.trajectory_max_abs_diff.is_some()).count();
        assert!(traj >= 12, "{backend}: trajectory cases ({traj})");
        let scalar_2d = report.cases.iter().filter(|c| c.backend == backend && c.dim == 2 && c.physics == "scalar");
        assert_eq!(scalar_2d.count(), cases_2d().len(), "{backend}: every 2D plate case");
        // The solids: triangle, quad and meshio triangle in 2D; tet, hex, meshio tet and meshio
        // hex in 3D; P2 straight and curved in both (crosscheck::p2_cases).
        for (dim, count) in [(2, 5), (3, 6)] {
            let elastic =
                report.cases.iter().filter(|c| c.backend == backend && c.dim == dim && c.physics == "elastic");
            assert_eq!(elastic.count(), count, "{backend}: every {dim}D elastic case");
        }
    }
    assert_eq!(report.versions.executable, "/usr/bin/python3");
}

#[test]
fn a_perturbed_weight_on_the_python_side_is_caught() {
    // One weight changed by 1e-6 on the Python side only: its mass matrix differs by h/3·1e-6 ≈ 6e-8
    // (far above the 1e-15 tolerance) and the trajectory drifts; every other case still passes.
    let tamper = Tamper { case: "m6_mod3_L1".into(), element: 3, delta: 1e-6 };
    let report = run(Some(&tamper), &[]).expect("bridge works");
    for c in &report.cases {
        if c.case == tamper.case {
            assert!(!c.pass, "{} must fail: {c:?}", c.backend);
            assert!(c.mass_max_abs_diff > 1e-8 && c.trajectory_max_abs_diff.unwrap() > 1e-10);
        } else {
            assert!(c.pass, "{c:?}");
        }
    }
    assert!(!report.all_pass());
}

#[test]
fn the_elastic_cases_test_both_lame_terms_and_catch_a_perturbed_weight() {
    // Both Lamé terms and ρ show (λ > 0, μ ≠ 1/2, ρ ≠ 1), the meshio cases are really
    // unstructured (jittered) and came through a file, and one weight changed by 1e-6 on the
    // Python side of the 3D meshio case makes both backends fail that case only.
    // mutation: crosscheck::jittered moving by 0.0 h -> fails with
    // "elastic_meshio_tri_5x4_mod3: 0 coordinates moved".
    let cases = solid_cases().expect("bridge works");
    for c in &cases {
        let Physics::Elastic(lame) = c.physics else { panic!("{}: not elastic", c.name) };
        assert!(lame.lambda > 0.0 && lame.mu != 0.5 && lame.density != 1.0, "{}: {lame:?}", c.name);
    }
    let meshio: Vec<_> = cases.iter().filter(|c| c.file.is_some()).collect();
    let grids = [
        Mesh::structured_2d(1.0, 0.8, 5, 4, Cell::Triangle).unwrap(),
        Mesh::structured_3d([1.0, 1.0, 1.0], [3, 2, 2], Cell::Tet).unwrap(),
        Mesh::structured_3d([1.0, 0.5, 0.75], [3, 2, 2], Cell::Hex).unwrap(),
    ];
    assert_eq!(meshio.len(), grids.len());
    for (c, grid) in meshio.iter().zip(&grids) {
        // Same cells as the grid, but moved interior vertices (and the file holds them).
        assert_eq!(c.mesh.cells, grid.cells, "{}", c.name);
        let moved = c.mesh.points.iter().zip(grid.flat_points()).filter(|(a, b)| *a != b).count();
        assert!(moved >= grid.dim, "{}: {moved} coordinates moved", c.name);
        assert!(!c.file.as_ref().unwrap().bytes.is_empty());
    }
    let tamper = Tamper { case: "elastic_meshio_tet_3x2x2_mod1".into(), element: 40, delta: 1e-6 };
    let report = run(Some(&tamper), &cases).expect("bridge works");
    for c in report.cases.iter().filter(|c| c.physics == "elastic") {
        // A 1e-6 weight change moves mass entries by ρ |c| 1e-6/10 ≈ 1e-9, far above the ~1e-15 tolerance.
        assert_eq!(c.pass, c.case != tamper.case, "{c:?}");
    }
}
