//! `massredist crosscheck`: the Rust assembly and time stepping against FEniCSx (dolfinx) and
//! scikit-fem, through the pyo3 bridge (feature `python`).
//!
//! Per case and backend: `max |M_rust − M_py|` and `max |S_rust − S_py|` over all vertices (no
//! boundary condition), and for trajectory cases the max over steps and free nodes of
//! `|U_rust − U_py|` and of `|λ_rust − λ_py|`, where the Python side assembles with the backend
//! and steps with the independent numpy steppers of `python/stepper.py`.
//!
//! Tolerances (round-off scaled by size):
//! - matrices: `16 n ε · max|entry|` with n the number of vertices — both sides round the vertex
//!   coordinates (x_i = L i/m vs i·h) and sum up to two element contributions per entry, so
//!   entries may differ by a few ulps times n in relative terms;
//! - trajectories: `1e-10` on U (values ≤ L/2) over 300 steps of Δt = 0.01, and `1e-10/h` on λ
//!   (λ = min(u_1, 0)/h amplifies U's rounding by 1/h). Both sides solve the same discrete
//!   equations; their rounding differs by O(ε) per step and grows at most linearly for w_0 = 0
//!   masses. The standard mass is chaotic after impact (the issue measured a 1e-13 change of the
//!   data changing u_0 at t = 30 by 16%), so it is compared on its pre-impact part only.
//! - the hybrid scheme's contact column at n = 0: the Python stepper reports (u_1⁰)⁺ there, this
//!   crate the interpolant u(0) (its stated convention); row n = 0 of the contact node is skipped.

use crate::bar::assembly::{Bar, full_matrices};
use crate::bridge::{self, Backend, BridgeError, Csr};
use crate::linalg::tridiag::SymTridiag;
use crate::mass::MassKind;
use crate::run::{Observer, Problem, Sample, integrate};
use crate::scene::{Formulation, SchemeSpec};
use serde::Serialize;

/// One line of the report.
#[derive(Debug, Clone, Serialize)]
pub struct CaseReport {
    pub backend: &'static str,
    pub dim: usize,
    pub case: String,
    pub mass_max_abs_diff: f64,
    pub stiffness_max_abs_diff: f64,
    pub trajectory_max_abs_diff: Option<f64>,
    pub lambda_max_abs_diff: Option<f64>,
    pub mass_tolerance: f64,
    pub stiffness_tolerance: f64,
    pub trajectory_tolerance: Option<f64>,
    pub pass: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub cases: Vec<CaseReport>,
    pub versions: bridge::Versions,
}

impl Report {
    pub fn all_pass(&self) -> bool {
        self.cases.iter().all(|c| c.pass)
    }
}

/// A deliberate discrepancy for tests: the weight of `element` sent to Python in case `case` is
/// changed by `delta` (the Rust side keeps the true weights). The report must then fail.
#[derive(Debug, Clone)]
pub struct Tamper {
    pub case: String,
    pub element: usize,
    pub delta: f64,
}

/// A 2D case supplied by the plate module: vertices (x, y), cells, weights and the Rust matrices.
pub struct Case2d {
    pub name: String,
    pub points: Vec<f64>,
    pub cells: Vec<usize>,
    pub verts_per_cell: usize,
    pub weights: Vec<f64>,
    /// Dense Rust mass and stiffness over all vertices, row-major n×n.
    pub mass: Vec<f64>,
    pub stiffness: Vec<f64>,
}

fn seeded_weights(m: usize, seed: u64) -> Vec<f64> {
    // xorshift64: a fixed, documented sequence of weights in [0.5, 2], w_0 = 0.
    let mut s = seed;
    (0..m)
        .map(|j| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            if j == 0 { 0.0 } else { 0.5 + 1.5 * (s % 1_000_000) as f64 / 1_000_000.0 }
        })
        .collect()
}

/// The 1D cases: (name, length, m, mass).
pub fn cases_1d() -> Vec<(String, f64, usize, MassKind)> {
    let mut v = Vec::new();
    for (l, ms) in [(1.0, &[2usize, 6, 37][..]), (2.5, &[6][..])] {
        for &m in ms {
            let masses = [
                MassKind::Standard,
                MassKind::Mod1,
                MassKind::Mod2,
                MassKind::Mod3,
                MassKind::Custom(seeded_weights(m, 0x5eed + m as u64)),
            ];
            for mass in masses {
                v.push((format!("m{m}_{}_L{l}", mass.name()), l, m, mass));
            }
        }
    }
    v
}

fn max_diff_tridiag(a: &SymTridiag, b: &Csr) -> f64 {
    let n = a.len();
    let mut d: f64 = 0.0;
    for i in 0..n {
        for j in 0..n {
            d = d.max((a.get(i, j) - b.get(i, j)).abs());
        }
    }
    d
}

fn max_diff_dense(a: &[f64], b: &Csr) -> f64 {
    let n = b.nrows;
    let mut d: f64 = 0.0;
    for i in 0..n {
        for j in 0..n {
            d = d.max((a[i * n + j] - b.get(i, j)).abs());
        }
    }
    d
}

fn max_abs(a: impl Iterator<Item = f64>) -> f64 {
    a.fold(0.0, |m, x| m.max(x.abs()))
}

#[derive(Default)]
struct Keep(Vec<(Vec<f64>, f64)>);

impl Observer for Keep {
    fn observe(&mut self, s: &Sample) {
        self.0.push((s.state.u.to_vec(), s.state.lambda[0]));
    }
}

/// (max |ΔU|, max |Δλ|) between the Rust and Python trajectories of a 1D case.
fn trajectory_diff(
    backend: Backend,
    l: f64,
    m: usize,
    weights: &[f64],
    py_weights: &[f64],
    scheme: &str,
    steps: usize,
) -> Result<(f64, f64), BridgeError> {
    let dt = 0.01;
    let problem = Problem::benchmark(l, m, &MassKind::Custom(weights.to_vec())).expect("valid case");
    let spec = match scheme {
        "hybrid" => SchemeSpec::Hybrid,
        _ => SchemeSpec::CrankNicolson { formulation: Formulation::Full },
    };
    let mut s = problem.scheme(&spec, dt).expect("scheme builds");
    let mut keep = Keep::default();
    integrate(&problem, s.as_mut(), steps, &mut [&mut keep]).expect("run succeeds");
    let (u_py, lam_py) = bridge::trajectory_1d(backend, l, m, py_weights, scheme, dt, steps)?;
    let (mut du, mut dl): (f64, f64) = (0.0, 0.0);
    for (n, ((u, lam), (up, lp))) in keep.0.iter().zip(u_py.iter().zip(&lam_py)).enumerate() {
        let first = usize::from(n == 0 && scheme == "hybrid");
        du = du.max(max_abs(u[first..].iter().zip(&up[first..]).map(|(a, b)| a - b)));
        dl = dl.max((lam - lp).abs());
    }
    Ok((du, dl))
}

/// Runs every case against both backends. `cases_2d` comes from the plate module (may be empty).
pub fn run(tamper: Option<&Tamper>, cases_2d: &[Case2d]) -> Result<Report, BridgeError> {
    let versions = bridge::versions()?;
    let mut cases = Vec::new();
    for (name, l, m, mass) in cases_1d() {
        let weights = mass.weights(m).expect("valid case");
        let mut py_weights = weights.clone();
        if let Some(t) = tamper.filter(|t| t.case == name) {
            py_weights[t.element] += t.delta;
        }
        let bar = Bar { length: l, elements: m };
        let (mr, sr) = full_matrices(&bar, &weights);
        let points: Vec<f64> = (0..=m).map(|i| bar.x(i)).collect();
        let cells: Vec<usize> = (0..m).flat_map(|j| [j, j + 1]).collect();
        let eps_n = 16.0 * (m + 1) as f64 * f64::EPSILON;
        let (mass_tol, stiff_tol) =
            (eps_n * max_abs(mr.diag.iter().copied()), eps_n * max_abs(sr.diag.iter().copied()));
        for backend in Backend::ALL {
            let (mp, sp) = bridge::assemble(backend, &points, 1, &cells, 2, &py_weights)?;
            let (dm, ds) = (max_diff_tridiag(&mr, &mp), max_diff_tridiag(&sr, &sp));
            let mut pass = dm <= mass_tol && ds <= stiff_tol;
            // Trajectories: w_0 = 0 masses over 300 steps (CN and hybrid); the standard mass
            // with CN before its first impact (t < 0.9 L).
            let runs: Vec<(&str, usize)> = match (&mass, m) {
                (_, 2) => vec![],
                (MassKind::Standard, _) => vec![("crank-nicolson", (90.0 * l) as usize)],
                _ => vec![("crank-nicolson", 300), ("hybrid", 300)],
            };
            let (mut du, mut dl, mut traj_tol) = (None::<f64>, None::<f64>, None);
            for (scheme, steps) in runs {
                let (a, b) = trajectory_diff(backend, l, m, &weights, &py_weights, scheme, steps)?;
                du = Some(du.unwrap_or(0.0).max(a));
                dl = Some(dl.unwrap_or(0.0).max(b));
                traj_tol = Some(1e-10);
                pass &= a <= 1e-10 && b <= 1e-10 / bar.h();
            }
            cases.push(CaseReport {
                backend: backend.name(),
                dim: 1,
                case: name.clone(),
                mass_max_abs_diff: dm,
                stiffness_max_abs_diff: ds,
                trajectory_max_abs_diff: du,
                lambda_max_abs_diff: dl,
                mass_tolerance: mass_tol,
                stiffness_tolerance: stiff_tol,
                trajectory_tolerance: traj_tol,
                pass,
            });
        }
    }
    for c in cases_2d {
        let n = c.points.len() / 2;
        let mut py_weights = c.weights.clone();
        if let Some(t) = tamper.filter(|t| t.case == c.name) {
            py_weights[t.element] += t.delta;
        }
        // 2D entries sum up to 6 (triangles) or 4 (quads) cell contributions per entry.
        let eps_n = 16.0 * n as f64 * f64::EPSILON;
        let (mass_tol, stiff_tol) =
            (eps_n * max_abs(c.mass.iter().copied()), eps_n * max_abs(c.stiffness.iter().copied()));
        for backend in Backend::ALL {
            let (mp, sp) = bridge::assemble(backend, &c.points, 2, &c.cells, c.verts_per_cell, &py_weights)?;
            let (dm, ds) = (max_diff_dense(&c.mass, &mp), max_diff_dense(&c.stiffness, &sp));
            cases.push(CaseReport {
                backend: backend.name(),
                dim: 2,
                case: c.name.clone(),
                mass_max_abs_diff: dm,
                stiffness_max_abs_diff: ds,
                trajectory_max_abs_diff: None,
                lambda_max_abs_diff: None,
                mass_tolerance: mass_tol,
                stiffness_tolerance: stiff_tol,
                trajectory_tolerance: None,
                pass: dm <= mass_tol && ds <= stiff_tol,
            });
        }
    }
    Ok(Report { cases, versions })
}

/// The report as a fixed-width table.
pub fn table(report: &Report) -> String {
    let mut s = format!(
        "{:<8} {:>3} {:<26} {:>10} {:>10} {:>10} {:>10}  {}\n",
        "backend", "dim", "case", "|ΔM|max", "|ΔS|max", "|ΔU|max", "|Δλ|max", "status"
    );
    let opt = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.2e}"));
    for c in &report.cases {
        s.push_str(&format!(
            "{:<8} {:>3} {:<26} {:>10.2e} {:>10.2e} {:>10} {:>10}  {}\n",
            c.backend,
            c.dim,
            c.case,
            c.mass_max_abs_diff,
            c.stiffness_max_abs_diff,
            opt(c.trajectory_max_abs_diff),
            opt(c.lambda_max_abs_diff),
            if c.pass { "ok" } else { "FAIL" }
        ));
    }
    let v = &report.versions;
    s.push_str(&format!(
        "python {} ({}), dolfinx {}, scikit-fem {}, numpy {}\n",
        v.python, v.executable, v.dolfinx, v.skfem, v.numpy
    ));
    s
}

/// The 2D cases: structured triangle (P1) and quadrilateral (Q1) meshes with the 2D mass
/// redistributions of `plate::layers` and seeded random per-cell weights, plus the gmsh fixture
/// mesh read through meshio. Panics only on a bug in these fixed, valid cases.
pub fn cases_2d() -> Vec<Case2d> {
    use crate::linalg::sparse::to_dense;
    use crate::plate::{CellKind, Mesh2d, assemble, layers::cell_weights};
    let structured = |l: f64, h: f64, nx: usize, ny: usize, kind: CellKind| {
        Mesh2d::structured(l, h, nx, ny, kind).expect("valid structured mesh")
    };
    let mut meshes: Vec<(String, Mesh2d, MassKind)> = vec![
        ("tri_4x3_mod3".into(), structured(1.0, 1.0, 4, 3, CellKind::Triangle), MassKind::Mod3),
        ("quad_3x3_L2_mod2".into(), structured(2.0, 1.0, 3, 3, CellKind::Quad), MassKind::Mod2),
        ("quad_5x4_standard".into(), structured(1.0, 1.0, 5, 4, CellKind::Quad), MassKind::Standard),
    ];
    let tri = structured(1.0, 0.5, 6, 5, CellKind::Triangle);
    let random = MassKind::Custom(seeded_weights(tri.n_cells(), 0x2d).iter().map(|w| w + 0.5).collect());
    meshes.push(("tri_6x5_custom".into(), tri, random));
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes/square_4x3_tri.msh");
    if let Ok(mesh) = Mesh2d::read_file(&file) {
        meshes.push(("gmsh_square_4x3_tri_mod1".into(), mesh, MassKind::Mod1));
    }
    meshes
        .into_iter()
        .map(|(name, mesh, mass)| {
            let weights = cell_weights(&mesh, &mass).expect("valid weights");
            let (m, s) = assemble(&mesh, &weights).expect("assembly succeeds");
            let flat = |a: Vec<Vec<f64>>| a.into_iter().flatten().collect::<Vec<f64>>();
            Case2d {
                name,
                points: mesh.points_flat(),
                cells: mesh.cells.clone(),
                verts_per_cell: mesh.kind.verts(),
                weights,
                mass: flat(to_dense(&m)),
                stiffness: flat(to_dense(&s)),
            }
        })
        .collect()
}
