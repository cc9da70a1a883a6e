//! The bridge to FEniCSx (dolfinx 0.5) and scikit-fem: independent assembly of the weighted
//! mass and stiffness matrices of the paper's section 3 and independent numpy steppers for the
//! 1D benchmark (section 4.2.1, Crank–Nicolson; section 5, the hybrid scheme (P^hyb)).
//! Section numbers follow the paper's LaTeX source.
//!
//! Compiled only with the feature `python`. The Python code lives in `python/` (small pure
//! functions, see `python/crosscheck/fem_dolfinx.py`, `python/crosscheck/fem_skfem.py`, `python/crosscheck/stepper.py`); this
//! module calls them through the solver's interpreter start-up (`massredist::python`, which also
//! reads and writes meshes through meshio). `bash python/install-deps.sh` installs what it needs.

use std::path::Path;

use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use massredist::material::Lame;
pub use massredist::python::{MeshArrays, PythonError as BridgeError, module_version, read_mesh_blocks, write_mesh};
use massredist::python::{SOLID_CELLS, attach, check_mesh, mesh_args, startup};

/// The FEM library that assembles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    /// FEniCSx: dolfinx 0.5.2 (Debian's python3-dolfinx-real).
    Dolfinx,
    /// scikit-fem 12.0.2 (in `.pydeps`).
    Skfem,
}

impl Backend {
    /// Both backends.
    pub const ALL: [Backend; 2] = [Backend::Dolfinx, Backend::Skfem];

    /// `"dolfinx"` or `"skfem"`, as used by `python/crosscheck/crosscheck.py` and the fixture files.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Dolfinx => "dolfinx",
            Backend::Skfem => "skfem",
        }
    }

    fn module(self) -> &'static str {
        match self {
            Backend::Dolfinx => "fem_dolfinx",
            Backend::Skfem => "fem_skfem",
        }
    }
}

/// Versions of the embedded interpreter and the libraries it uses.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Versions {
    /// `sys.executable`; `/usr/bin/python3` when start-up went as intended.
    pub executable: String,
    /// `platform.python_version()`.
    pub python: String,
    pub dolfinx: String,
    pub skfem: String,
    pub numpy: String,
}

/// A square sparse matrix in compressed sparse row form, column indices sorted within each row.
///
/// Row `i` holds the entries `data[k]` at columns `indices[k]` for
/// `k in indptr[i]..indptr[i + 1]`. The pattern is the one the backend assembled: dolfinx keeps
/// structural zeros, scikit-fem drops them, so compare values (`get`, `to_dense`), not patterns.
#[derive(Debug, Clone, PartialEq)]
pub struct Csr {
    pub nrows: usize,
    pub indptr: Vec<usize>,
    pub indices: Vec<usize>,
    pub data: Vec<f64>,
}

impl Csr {
    /// The entry (i, j), 0 where the pattern has none.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let row = self.indptr[i]..self.indptr[i + 1];
        match self.indices[row.clone()].binary_search(&j) {
            Ok(k) => self.data[row.start + k],
            Err(_) => 0.0,
        }
    }

    /// The dense `nrows × nrows` matrix, row by row.
    pub fn to_dense(&self) -> Vec<Vec<f64>> {
        let mut dense = vec![vec![0.0; self.nrows]; self.nrows];
        for (i, row) in dense.iter_mut().enumerate() {
            for k in self.indptr[i]..self.indptr[i + 1] {
                row[self.indices[k]] += self.data[k];
            }
        }
        dense
    }
}

/// The versions of Python, dolfinx, scikit-fem and numpy (starts the interpreter if needed).
pub fn versions() -> Result<Versions, BridgeError> {
    let s = startup()?;
    Ok(Versions {
        executable: s.executable.clone(),
        python: s.python.clone(),
        dolfinx: s.dolfinx.clone()?,
        skfem: s.skfem.clone()?,
        numpy: s.numpy.clone(),
    })
}

/// Weighted mass and stiffness matrices assembled by `backend` (paper section 3):
///
/// M_ij = ∫ w φ_i φ_j dx,  S_ij = ∫ ∇φ_i · ∇φ_j dx,
///
/// with P1 elements on intervals and triangles and Q1 on quadrilaterals, `w` constant on each
/// cell. In 1D on a uniform mesh this gives M_00 = h w_0/3, M_ii = h (w_{i−1} + w_i)/3,
/// M_{i,i+1} = h w_i/6, S = (1/h) tridiag(−1, 2, −1) with S_00 = 1/h.
///
/// `points` holds `gdim` coordinates per vertex (gdim 1 or 2), `cells` holds `verts_per_cell`
/// vertex indices per cell (2: intervals, 3: triangles, 4: quadrilaterals counter-clockwise),
/// `weights` one value per cell. Every vertex must belong to a cell. The matrices cover all
/// vertices in input order, with no boundary condition applied. Returns `(mass, stiffness)`.
pub fn assemble(
    backend: Backend,
    points: &[f64],
    gdim: usize,
    cells: &[usize],
    verts_per_cell: usize,
    weights: &[f64],
) -> Result<(Csr, Csr), BridgeError> {
    let (n, ncells) = check_mesh(points, gdim, cells, verts_per_cell, weights, &[(1, 2), (2, 3), (2, 4)])?;
    backend_ready(backend)?;
    attach(|py| {
        let args = mesh_args(py, points, gdim, cells, verts_per_cell, weights, (n, ncells))?;
        let out = py.import(backend.module())?.call_method1("assemble", args)?;
        Ok((csr(&out.get_item("mass")?, n)?, csr(&out.get_item("stiffness")?, n)?))
    })
}

/// The elastic solid's weighted vector mass and stiffness assembled by `backend`, the matrices
/// of [`massredist::solid::assembly::assemble`]:
///
/// M_(a,i),(b,j) = δ_ij ρ ∫ w φ_a φ_b,   S = ∫ σ(u) : ε(v),  σ = λ tr ε(u) I + 2μ ε(u)
///
/// (plane strain in 2D), P1 on triangles and tetrahedra, Q1 on quadrilaterals (counter-clockwise)
/// and hexahedra (VTK order), `w` constant on each cell. Rows and columns are interleaved per
/// vertex, `vertex·gdim + component`, over all vertices in input order (no boundary condition).
/// dolfinx: `VectorFunctionSpace`, `ufl.sym(ufl.grad(u))`; scikit-fem: `ElementVector`,
/// `skfem.models.elasticity.linear_elasticity` (`python/fem_*.py::assemble_elastic`).
pub fn assemble_elastic(
    backend: Backend,
    mesh: &MeshArrays,
    weights: &[f64],
    lame: &Lame,
) -> Result<(Csr, Csr), BridgeError> {
    let MeshArrays { points, dim: gdim, cells, verts_per_cell } = mesh;
    let (points, gdim, cells, verts_per_cell) = (points.as_slice(), *gdim, cells.as_slice(), *verts_per_cell);
    let (n, ncells) = check_mesh(points, gdim, cells, verts_per_cell, weights, &SOLID_CELLS)?;
    backend_ready(backend)?;
    attach(|py| {
        let (p, c, w) = mesh_args(py, points, gdim, cells, verts_per_cell, weights, (n, ncells))?;
        let args = (p, c, w, lame.lambda, lame.mu, lame.density);
        let out = py.import(backend.module())?.call_method1("assemble_elastic", args)?;
        Ok((csr(&out.get_item("mass")?, n * gdim)?, csr(&out.get_item("stiffness")?, n * gdim)?))
    })
}

/// [`assemble_elastic`] on the mesh of a file, which the Python side reads itself through meshio
/// (`python/crosscheck/crosscheck.py::assemble_elastic_file`, through `python/crosscheck/mesh_io.py::read_cells`): `weights` one per
/// cell in the file's order. The matrices have `vertices·dim` rows in the file's vertex order.
pub fn assemble_elastic_file(
    backend: Backend,
    path: &Path,
    weights: &[f64],
    lame: &Lame,
) -> Result<(Csr, Csr), BridgeError> {
    backend_ready(backend)?;
    attach(|py| {
        let path = path.to_string_lossy().into_owned();
        let args = (backend.name(), path, PyArray1::from_slice(py, weights), lame.lambda, lame.mu, lame.density);
        let out = py.import("crosscheck")?.call_method1("assemble_elastic_file", args)?;
        let n: usize = out.get_item("n")?.extract()?;
        Ok((csr(&out.get_item("mass")?, n)?, csr(&out.get_item("stiffness")?, n)?))
    })
}

/// The 1D benchmark of section 4 (bar (0, L), m uniform elements, h = L/m, element j with weight
/// `weights[j]`, u0(x) = (L − x)/2, v0 = 0, F = 0), assembled by `backend` on the m free nodes
/// (vertex m is Dirichlet) and run by the independent numpy steppers of `python/crosscheck/stepper.py`:
///
/// - `"crank-nicolson"`: Newmark (β, γ) = (1/4, 1/2), eq. (4.3), with 0 ≤ u_0 ⊥ λ ≤ 0 solved
///   exactly each step; λ^0 = 0; for w_0 = 0 the contact acceleration A_0 is kept at 0;
/// - `"hybrid"`: (P^hyb) of section 5 on nodes 1..m−1 (needs w_0 = 0) with M_r = h M*,
///   S_r = S*/h, each step solved exactly on its linear piece; the contact node is
///   u_0 = (u_1)^+ (eq. (3.3), also at n = 0) and λ = min(u_1, 0)/h from the contact row.
///
/// Returns `(U, λ)`: `U[n]` the m free nodal values at t_n = n dt, n = 0..=steps, and `λ[n]`.
pub fn trajectory_1d(
    backend: Backend,
    length: f64,
    m: usize,
    weights: &[f64],
    scheme: &str,
    dt: f64,
    steps: usize,
) -> Result<(Vec<Vec<f64>>, Vec<f64>), BridgeError> {
    if !matches!(scheme, "crank-nicolson" | "hybrid") {
        return invalid(format!("scheme {scheme:?}; allowed: \"crank-nicolson\", \"hybrid\""));
    }
    let valid = m >= 2 && weights.len() == m && length > 0.0 && dt > 0.0;
    if !valid {
        return invalid(format!(
            "need m >= 2 (got {m}), m weights (got {}), L > 0 (got {length}), dt > 0 (got {dt})",
            weights.len()
        ));
    }
    backend_ready(backend)?;
    attach(|py| {
        let weights = PyArray1::from_slice(py, weights);
        let args = (backend.name(), length, m, weights, scheme, dt, steps);
        let out = py.import("crosscheck")?.call_method1("trajectory_1d", args)?;
        let (u, lam): (PyReadonlyArray2<f64>, PyReadonlyArray1<f64>) = out.extract()?;
        let u = u.as_array().rows().into_iter().map(|row| row.to_vec()).collect();
        Ok((u, lam.as_array().to_vec()))
    })
}

/// Fails with the start-up error of `backend`'s library, if any.
fn backend_ready(backend: Backend) -> Result<(), BridgeError> {
    let s = startup()?;
    let found = match backend {
        Backend::Dolfinx => &s.dolfinx,
        Backend::Skfem => &s.skfem,
    };
    found.as_ref().map(|_| ()).map_err(Clone::clone)
}

/// A `(indptr, indices, data)` tuple of int64, int64, float64 arrays as a [`Csr`] with n rows.
fn csr(triplets: &Bound<'_, PyAny>, n: usize) -> PyResult<Csr> {
    let (indptr, indices, data): (PyReadonlyArray1<i64>, PyReadonlyArray1<i64>, PyReadonlyArray1<f64>) =
        triplets.extract()?;
    let to_usize = |a: &PyReadonlyArray1<i64>| a.as_array().iter().map(|&v| v as usize).collect::<Vec<_>>();
    let out = Csr { nrows: n, indptr: to_usize(&indptr), indices: to_usize(&indices), data: data.as_array().to_vec() };
    if out.indptr.len() != n + 1 || out.indices.len() != out.data.len() || out.indptr[n] != out.data.len() {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "malformed CSR from Python: {} row pointers for {n} rows, {} indices, {} values",
            out.indptr.len(),
            out.indices.len(),
            out.data.len()
        )));
    }
    Ok(out)
}

fn invalid<T>(reason: String) -> Result<T, BridgeError> {
    Err(BridgeError::InvalidInput { reason })
}
