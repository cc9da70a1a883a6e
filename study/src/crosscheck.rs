//! `massredist crosscheck`: the Rust assembly and time stepping against FEniCSx (dolfinx) and
//! scikit-fem, through the pyo3 bridge (feature `python`).
//!
//! Per case and backend: `max |M_rust − M_py|` and `max |S_rust − S_py|` over all vertices (no
//! boundary condition; for elastic solids over all vertices and components, rows interleaved
//! `vertex·d + component`, [`massredist::solid::assembly::assemble`]), and for trajectory cases the max over steps and free nodes of
//! `|U_rust − U_py|` and of `|λ_rust − λ_py|`, where the Python side assembles with the backend
//! and steps with the independent numpy steppers of `python/crosscheck/stepper.py`.
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
//! - elastic matrices: `8 ε · max|entry| · r` with r the largest number of non-zero entries in a
//!   row of the Rust stiffness (at most 2·9 in 2D, 3·27 in 3D): an entry is a sum over the cells around an
//!   edge of quadrature sums whose terms are each bounded by `max|entry|`-sized products, computed
//!   in different orders by the three codes (the 2D scalar cases keep their `16 n ε` bound);
//! - the hybrid scheme's contact column at n = 0: the Python stepper reports (u_1⁰)⁺ there, this
//!   crate the interpolant u(0) (its stated convention); row n = 0 of the contact node is skipped.

use crate::bridge::{self, Backend, BridgeError, Csr, MeshArrays};
use massredist::bar::BarProblem;
use massredist::bar::assembly::{Bar, full_matrices};
use massredist::driver::{Observer, Sample, integrate};
use massredist::linalg::tridiag::SymTridiag;
use massredist::mass::MassKind;
use massredist::scene::{Formulation, SchemeSpec};
use massredist::solid::Lame;
use serde::Serialize;

#[path = "crosscheck_p2.rs"]
mod p2;
pub use p2::p2_cases;

/// One line of the report.
#[derive(Debug, Clone, Serialize)]
pub struct CaseReport {
    pub backend: &'static str,
    pub dim: usize,
    /// `"scalar"` (bars, plates) or `"elastic"` (solids).
    pub physics: &'static str,
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

/// What a matrix case assembles: the plate's scalar M and S, or the solid's vector mass and
/// elasticity stiffness with these Lamé coefficients and density.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Physics {
    Scalar,
    Elastic(Lame),
}

impl Physics {
    pub fn name(self) -> &'static str {
        match self {
            Physics::Scalar => "scalar",
            Physics::Elastic(_) => "elastic",
        }
    }
}

/// A mesh file as written and read back through meshio on the Rust side: the Python side reads
/// the same bytes (written again to a temporary file with this extension) through meshio.
#[derive(Debug, Clone)]
pub struct MeshFile {
    /// `"msh"` (gmsh 2.2) or `"vtu"`.
    pub extension: &'static str,
    pub bytes: Vec<u8>,
}

/// A 2D or 3D matrix case: the mesh, the weights, what is assembled and the Rust matrices.
pub struct MatrixCase {
    pub name: String,
    pub mesh: MeshArrays,
    pub weights: Vec<f64>,
    pub physics: Physics,
    /// Set for the meshio cases: the Python side reads the mesh from this file, not the arrays.
    pub file: Option<MeshFile>,
    /// Dense Rust mass and stiffness over all unknowns (vertices, times d if elastic),
    /// row-major.
    pub mass: Vec<f64>,
    pub stiffness: Vec<f64>,
}

pub(crate) fn seeded_weights(m: usize, seed: u64) -> Vec<f64> {
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

/// max |a − b| entrywise (a dense row-major n×n, n = b's rows); ∞ if the sizes differ.
fn max_diff_dense(a: &[f64], b: &Csr) -> f64 {
    let n = b.nrows;
    if a.len() != n * n {
        return f64::INFINITY;
    }
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
    let problem = BarProblem::benchmark(l, m, &MassKind::Custom(weights.to_vec())).expect("valid case");
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

/// Runs every case against both backends: the 1D cases, then `matrix_cases` ([`matrix_cases`],
/// may be empty).
pub fn run(tamper: Option<&Tamper>, matrix_cases: &[MatrixCase]) -> Result<Report, BridgeError> {
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
                physics: "scalar",
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
    for c in matrix_cases {
        let mut py_weights = c.weights.clone();
        if let Some(t) = tamper.filter(|t| t.case == c.name) {
            py_weights[t.element] += t.delta;
        }
        let (mass_tol, stiff_tol) = tolerances(c);
        for backend in Backend::ALL {
            let (mp, sp) = python_matrices(backend, c, &py_weights)?;
            let (dm, ds) = (max_diff_dense(&c.mass, &mp), max_diff_dense(&c.stiffness, &sp));
            cases.push(CaseReport {
                backend: backend.name(),
                dim: c.mesh.dim,
                physics: c.physics.name(),
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
    cases.extend(getfem::case_reports()); // GetFEM as a live peer (src/crosscheck_getfem.rs)
    Ok(Report { cases, versions })
}

/// The report as a fixed-width table.
pub fn table(report: &Report) -> String {
    let mut s = format!(
        "{:<8} {:>3} {:<36} {:>10} {:>10} {:>10} {:>10}  {}\n",
        "backend", "dim", "case", "|ΔM|max", "|ΔS|max", "|ΔU|max", "|Δλ|max", "status"
    );
    let opt = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.2e}"));
    for c in &report.cases {
        s.push_str(&format!(
            "{:<8} {:>3} {:<36} {:>10.2e} {:>10.2e} {:>10} {:>10}  {}\n",
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
/// redistributions of `fem::layers` and seeded random per-cell weights, plus the gmsh fixture
/// mesh read through meshio. Panics only on a bug in these fixed, valid cases.
pub fn cases_2d() -> Vec<MatrixCase> {
    use massredist::fem::{Cell, Mesh, layers::cell_weights};
    use massredist::linalg::sparse::to_dense;
    use massredist::plate::assemble;
    let structured = |l: f64, h: f64, nx: usize, ny: usize, kind: Cell| {
        Mesh::structured_2d(l, h, nx, ny, kind).expect("valid structured mesh")
    };
    let mut meshes: Vec<(String, Mesh, MassKind)> = vec![
        ("tri_4x3_mod3".into(), structured(1.0, 1.0, 4, 3, Cell::Triangle), MassKind::Mod3),
        ("quad_3x3_L2_mod2".into(), structured(2.0, 1.0, 3, 3, Cell::Quad), MassKind::Mod2),
        ("quad_5x4_standard".into(), structured(1.0, 1.0, 5, 4, Cell::Quad), MassKind::Standard),
    ];
    let tri = structured(1.0, 0.5, 6, 5, Cell::Triangle);
    let random = MassKind::Custom(seeded_weights(tri.n_cells(), 0x2d).iter().map(|w| w + 0.5).collect());
    meshes.push(("tri_6x5_custom".into(), tri, random));
    let file = crate::repo::root().join("fixtures/meshes/square_4x3_tri.msh");
    if let Ok(mesh) = massredist::scene::mesh_file::read("plate.mesh", &file) {
        meshes.push(("gmsh_square_4x3_tri_mod1".into(), mesh, MassKind::Mod1));
    }
    meshes
        .into_iter()
        .map(|(name, mesh, mass)| {
            let weights = cell_weights(&mesh, &mass).expect("valid weights");
            let (m, s) = assemble(&mesh, &weights).expect("assembly succeeds");
            let flat = |a: Vec<Vec<f64>>| a.into_iter().flatten().collect::<Vec<f64>>();
            MatrixCase {
                name,
                mesh: MeshArrays::of(&mesh),
                weights,
                physics: Physics::Scalar,
                file: None,
                mass: flat(to_dense(&m)),
                stiffness: flat(to_dense(&s)),
            }
        })
        .collect()
}

/// The (mass, stiffness) tolerances of a matrix case (module docs).
fn tolerances(c: &MatrixCase) -> (f64, f64) {
    let abs_max = |a: &[f64]| max_abs(a.iter().copied());
    let eps_n = match c.physics {
        // 2D scalar entries sum up to 6 (triangles) or 4 (quads) cell contributions per entry.
        Physics::Scalar => 16.0 * (c.mesh.points.len() / c.mesh.dim) as f64 * f64::EPSILON,
        // 8 ε times the entries per row (module docs).
        Physics::Elastic(_) => 8.0 * f64::EPSILON * max_row_entries(&c.stiffness, c.mass.len().isqrt()) as f64,
    };
    (eps_n * abs_max(&c.mass), eps_n * abs_max(&c.stiffness))
}

/// The largest number of non-zero entries in a row of a dense row-major n×n matrix.
fn max_row_entries(a: &[f64], n: usize) -> usize {
    a.chunks(n.max(1)).map(|row| row.iter().filter(|x| **x != 0.0).count()).max().unwrap_or(0)
}

/// The backend's matrices of a case: from the arrays, or from the case's mesh file (written to
/// a temporary file for the Python side to read through meshio, removed afterwards).
fn python_matrices(backend: Backend, c: &MatrixCase, py_weights: &[f64]) -> Result<(Csr, Csr), BridgeError> {
    let m = &c.mesh;
    match (c.physics, &c.file) {
        (Physics::Scalar, _) => bridge::assemble(backend, &m.points, m.dim, &m.cells, m.verts_per_cell, py_weights),
        (Physics::Elastic(lame), None) => bridge::assemble_elastic(backend, m, py_weights, &lame),
        (Physics::Elastic(lame), Some(file)) => {
            let path = scratch_path(&c.name, file.extension);
            std::fs::write(&path, &file.bytes)
                .map_err(|e| BridgeError::InvalidInput { reason: format!("{}: {e}", path.display()) })?;
            let out = bridge::assemble_elastic_file(backend, &path, py_weights, &lame);
            let _ = std::fs::remove_file(&path);
            out
        }
    }
}

/// A fresh path in the system's temporary folder (unique per process and call).
fn scratch_path(name: &str, extension: &str) -> std::path::PathBuf {
    static COUNTER: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    std::env::temp_dir().join(format!("massredist-crosscheck-{}-{k}-{name}.{extension}", std::process::id()))
}

/// Every matrix case of `massredist crosscheck`: the plate's ([`cases_2d`]), the solid's
/// ([`solid_cases`]) and the P2 bodies' ([`p2_cases`]).
pub fn matrix_cases() -> Result<Vec<MatrixCase>, BridgeError> {
    let mut cases = cases_2d();
    cases.extend(solid_cases()?);
    cases.extend(p2_cases());
    Ok(cases)
}

/// The material of the elastic cases: λ > 0 and μ ≠ ½ so that both Lamé terms and ρ ≠ 1 show.
pub const SOLID_LAME: Lame = Lame { lambda: 0.8, mu: 0.3, density: 1.7 };

/// The elastic solid cases: structured triangle, quadrilateral, tetrahedron and hexahedron meshes
/// of boxes with unequal sides, cell-layer masses (mod1–3) and seeded random per-cell weights, and
/// three meshio cases: jittered triangle (gmsh `.msh`), tetrahedron (`.vtu`) and hexahedron
/// (non-uniform grid, gmsh `.msh`) meshes written with meshio and read back on both sides
/// ([`massredist::scene::mesh_file::read`] here: the pure-Rust gmsh reader for `.msh`, meshio for
/// `.vtu`; `python/crosscheck/crosscheck.py::assemble_elastic_file` there, through meshio). Fails only if the bridge does (writing
/// the files); panics only on a bug in these fixed, valid cases.
pub fn solid_cases() -> Result<Vec<MatrixCase>, BridgeError> {
    use massredist::fem::layers::cell_weights;
    use massredist::fem::{Cell, Mesh};
    let random = |mesh: &Mesh, seed: u64| {
        MassKind::Custom(seeded_weights(mesh.n_cells(), seed).iter().map(|w| w + 0.5).collect())
    };
    let tri = Mesh::structured_2d(1.0, 0.75, 4, 3, Cell::Triangle).expect("valid mesh");
    let quad = Mesh::structured_2d(2.0, 1.0, 3, 3, Cell::Quad).expect("valid mesh");
    let tet = Mesh::structured_3d([1.0, 0.75, 0.5], [3, 2, 2], Cell::Tet).expect("valid mesh");
    let hex = Mesh::structured_3d([1.5, 0.5, 0.75], [3, 2, 2], Cell::Hex).expect("valid mesh");
    let (quad_mass, hex_mass) = (random(&quad, 0x50_11d), random(&hex, 0x4e_c5));
    let mut meshes: Vec<(String, Mesh, MassKind, Option<MeshFile>)> = vec![
        ("elastic_tri_4x3_mod3".into(), tri, MassKind::Mod3, None),
        ("elastic_quad_3x3_L2_custom".into(), quad, quad_mass, None),
        ("elastic_tet_3x2x2_mod2".into(), tet, MassKind::Mod2, None),
        ("elastic_hex_3x2x2_custom".into(), hex, hex_mass, None),
    ];
    for (name, mesh, extension, mass) in [
        ("elastic_meshio_tri_5x4_mod3", Mesh::structured_2d(1.0, 0.8, 5, 4, Cell::Triangle), "msh", MassKind::Mod3),
        (
            "elastic_meshio_tet_3x2x2_mod1",
            Mesh::structured_3d([1.0, 1.0, 1.0], [3, 2, 2], Cell::Tet),
            "vtu",
            MassKind::Mod1,
        ),
        (
            "elastic_meshio_hex_3x2x2_mod3",
            Mesh::structured_3d([1.0, 0.5, 0.75], [3, 2, 2], Cell::Hex),
            "msh",
            MassKind::Mod3,
        ),
    ] {
        let (mesh, file) = written_and_read_back(&jittered(mesh.expect("valid mesh")), name, extension)?;
        meshes.push((name.into(), mesh, mass, Some(file)));
    }
    let lame = SOLID_LAME;
    Ok(meshes
        .into_iter()
        .map(|(name, mesh, mass, file)| {
            let weights = cell_weights(&mesh, &mass).expect("valid weights");
            let (m, s) = massredist::solid::assembly::assemble(&mesh, &weights, &lame).expect("assembly succeeds");
            let flat = |a: Vec<Vec<f64>>| a.into_iter().flatten().collect::<Vec<f64>>();
            MatrixCase {
                name,
                mesh: MeshArrays::of(&mesh),
                weights,
                physics: Physics::Elastic(lame),
                file,
                mass: flat(massredist::linalg::sparse::to_dense(&m)),
                stiffness: flat(massredist::linalg::sparse::to_dense(&s)),
            }
        })
        .collect())
}

/// The mesh with its interior vertices moved by up to 0.15 h per coordinate (seeded xorshift), so
/// that the meshio cases are unstructured; boundary vertices stay on the box's faces. A 0.15 h
/// move keeps every triangle and Kuhn tetrahedron positively sized (their heights are ≥ h/√3).
/// Hexahedra must stay boxes: there each interior grid plane t moves as a whole, by
/// 0.15 h sin(7 t/h) (a non-uniform grid).
pub(crate) fn jittered(mut mesh: massredist::fem::Mesh) -> massredist::fem::Mesh {
    let h = mesh.h();
    if mesh.kind.is_tensor() {
        let ext = mesh.extent;
        for p in &mut mesh.points {
            for (x, e) in p.iter_mut().zip(ext) {
                if *x > 0.0 && *x < e {
                    *x += 0.15 * h * (7.0 * *x / h).sin();
                }
            }
        }
        return mesh;
    }
    let mut s: u64 = 0x3e5_1a7_u64.wrapping_add(mesh.n_nodes() as u64);
    let (ext, d) = (mesh.extent, mesh.dim);
    for p in &mut mesh.points {
        let interior = (0..d).all(|k| p[k] > 0.0 && p[k] < ext[k]);
        for x in p.iter_mut().take(d) {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            if interior {
                *x += 0.15 * h * ((s % 2001) as f64 / 1000.0 - 1.0);
            }
        }
    }
    mesh
}

/// Writes `mesh` with meshio to a temporary `.{extension}` file and reads it back through meshio
/// ([`massredist::scene::mesh_file::read`]); returns the mesh read and the file's bytes.
fn written_and_read_back(
    mesh: &massredist::fem::Mesh,
    name: &str,
    extension: &'static str,
) -> Result<(massredist::fem::Mesh, MeshFile), BridgeError> {
    let path = scratch_path(name, extension);
    let read = bridge::write_mesh(&path, &MeshArrays::of(mesh)).and_then(|()| {
        let back = massredist::scene::mesh_file::read("solid.mesh", &path)
            .map_err(|e| BridgeError::InvalidInput { reason: format!("reading back {}: {e}", path.display()) })?;
        let bytes = std::fs::read(&path).map_err(|e| BridgeError::InvalidInput { reason: e.to_string() })?;
        Ok((back, MeshFile { extension, bytes }))
    });
    let _ = std::fs::remove_file(&path);
    read
}

/// GetFEM as a live peer (issue 19, item 6): src/crosscheck_getfem.rs.
#[path = "crosscheck_getfem.rs"]
pub mod getfem;
