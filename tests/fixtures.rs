//! The Rust assembly and integrators against the stored dolfinx / scikit-fem fixtures
//! (`python/scripts/gen_fixtures.py`; provenance in `fixtures/provenance.json`). No Python needed.

mod common;

use massredist::bar::BarProblem;
use massredist::bar::assembly::{Bar, full_matrices};
use massredist::mass::MassKind;
use massredist::scene::{Formulation, SchemeSpec};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn dir(sub: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures").join(sub)
}

fn read(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

/// Dense n×n from the fixture's CSR.
fn dense(csr: &Value) -> Vec<Vec<f64>> {
    let n = csr["nrows"].as_u64().unwrap() as usize;
    let (ptr, idx, data) = (f64s(&csr["indptr"]), f64s(&csr["indices"]), f64s(&csr["data"]));
    let mut a = vec![vec![0.0; n]; n];
    for i in 0..n {
        for k in ptr[i] as usize..ptr[i + 1] as usize {
            a[i][idx[k] as usize] += data[k];
        }
    }
    a
}

#[test]
fn one_d_matrices_match_dolfinx_and_scikit_fem() {
    let mut count = 0;
    for entry in std::fs::read_dir(dir("matrices")).unwrap() {
        let path = entry.unwrap().path();
        let f = read(&path);
        if f["dim"] != 1 {
            continue;
        }
        let points: Vec<f64> = f["points"].as_array().unwrap().iter().map(|p| p[0].as_f64().unwrap()).collect();
        let weights = f64s(&f["weights"]);
        let m = weights.len();
        let bar = Bar { length: *points.last().unwrap(), elements: m };
        let (mr, sr) = full_matrices(&bar, &weights);
        let (mp, sp) = (dense(&f["mass"]), dense(&f["stiffness"]));
        // Same tolerance as `massredist crosscheck`: 16 n ε times the largest entry (both sides
        // round the vertex coordinates differently).
        let eps_n = 16.0 * (m + 1) as f64 * f64::EPSILON;
        let (tm, ts) = (eps_n * mr.diag.iter().fold(0.0f64, |a, b| a.max(*b)), eps_n * sr.diag[1]);
        for i in 0..=m {
            for j in 0..=m {
                assert!(
                    approx::relative_eq!(mr.get(i, j), mp[i][j], epsilon = tm, max_relative = 0.0),
                    "{}: M[{i}][{j}]",
                    path.display()
                );
                assert!(
                    approx::relative_eq!(sr.get(i, j), sp[i][j], epsilon = ts, max_relative = 0.0),
                    "{}: S[{i}][{j}]",
                    path.display()
                );
            }
        }
        count += 1;
    }
    assert!(count >= 26, "all 1D fixtures read ({count})");
}

#[test]
fn trajectories_match_the_independent_python_steppers() {
    let mut count = 0;
    for entry in std::fs::read_dir(dir("trajectories")).unwrap() {
        let path = entry.unwrap().path();
        let f = read(&path);
        let (l, m) = (f["L"].as_f64().unwrap(), f["m"].as_u64().unwrap() as usize);
        let (dt, steps, every) = (
            f["dt"].as_f64().unwrap(),
            f["steps"].as_u64().unwrap() as usize,
            f["record_every"].as_u64().unwrap() as usize,
        );
        let problem = BarProblem::benchmark(l, m, &MassKind::Custom(f64s(&f["weights"]))).unwrap();
        let scheme = f["scheme"].as_str().unwrap();
        let spec = match scheme {
            "hybrid" => SchemeSpec::Hybrid,
            "crank-nicolson" => SchemeSpec::CrankNicolson { formulation: Formulation::Full },
            other => panic!("unknown scheme {other}"),
        };
        let ours = common::trajectory(&problem, &spec, dt, steps);
        let (u, lam) = (f["U"].as_array().unwrap(), f64s(&f["lam"]));
        for (k, row) in u.iter().enumerate() {
            let n = k * every;
            let row = f64s(row);
            // The hybrid stepper reports (u_1⁰)⁺ at the contact node at n = 0, this crate the
            // interpolant u(0) (see src/crosscheck.rs); skip that single entry.
            let first = usize::from(n == 0 && scheme == "hybrid");
            let du = common::max_abs_diff(&ours[n].u[first..], &row[first..]);
            // Same tolerance as `massredist crosscheck`: 1e-10 on U, 1e-10/h on λ.
            assert!(du <= 1e-10, "{}: n={n} |ΔU| = {du:e}", path.display());
            assert!(
                approx::relative_eq!(ours[n].lambda, lam[k], epsilon = 1e-10 * m as f64 / l, max_relative = 0.0),
                "{}: n={n} λ",
                path.display()
            );
        }
        count += 1;
    }
    assert_eq!(count, 6, "all trajectory fixtures read");
}
