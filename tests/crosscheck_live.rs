//! Live cross-check against dolfinx and scikit-fem through the pyo3 bridge (feature `python`;
//! `bash python/install-deps.sh` installs what it needs).
#![cfg(feature = "python")]

use massredist::crosscheck::{Tamper, cases_2d, run};

#[test]
fn every_case_agrees_with_both_backends() {
    let report = run(None, &cases_2d()).expect("bridge works");
    let failed: Vec<_> = report.cases.iter().filter(|c| !c.pass).collect();
    assert!(failed.is_empty(), "outside tolerance: {failed:#?}");
    for backend in ["dolfinx", "skfem"] {
        let n = report.cases.iter().filter(|c| c.backend == backend && c.dim == 1).count();
        assert_eq!(n, 20, "{backend}: every 1D case");
        let traj = report.cases.iter().filter(|c| c.backend == backend && c.trajectory_max_abs_diff.is_some()).count();
        assert!(traj >= 12, "{backend}: trajectory cases ({traj})");
        let two_d = report.cases.iter().filter(|c| c.backend == backend && c.dim == 2).count();
        assert_eq!(two_d, cases_2d().len(), "{backend}: every 2D case");
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
