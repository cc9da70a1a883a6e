//! The bridge to FEniCSx (dolfinx 0.5) and scikit-fem: independent assembly of the weighted
//! mass and stiffness matrices of the paper's section 3 and independent numpy steppers for the
//! 1D benchmark (section 4.2.1, Crank–Nicolson; section 5, the hybrid scheme (P^hyb)).
//! Section numbers follow the paper's LaTeX source.
//!
//! Compiled only with the feature `python`. The Python code lives in `python/crosscheck/` (small pure
//! functions, see `python/crosscheck/fem_dolfinx.py`, `python/crosscheck/fem_skfem.py`, `python/crosscheck/stepper.py`); this
//! module is the one place that starts the interpreter. `bash python/install-deps.sh` installs
//! what it needs.
//!
//! Start-up is deterministic and happens once per process ([`OnceLock`]), in the first call of any
//! function here:
//! - the interpreter is Debian's `/usr/bin/python3` whatever `PATH` says (`Py_SetProgramName`
//!   before it starts; otherwise a pyenv or venv first on `PATH` supplies the standard library);
//! - `OMPI_MCA_ess_singleton_isolated=1` is set before mpi4py loads (no `orted` daemon);
//! - `<crate>/python/crosscheck` and `<crate>/.pydeps` (or `$MASSREDIST_PYDEPS`) go first on `sys.path`;
//! - log records below WARNING are disabled (the dolfinx JIT's compiler lines; raising the root
//!   logger's level is not enough, distutils lowers it again while compiling);
//! - dolfinx is imported in that same first attach, on the thread that started the interpreter:
//!   importing it first on another thread that later detaches and re-attaches makes the next
//!   mesh creation hang for ever. After that, calls from any number of threads are safe (the GIL
//!   serialises them).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::PyModuleNotFoundError;
use pyo3::prelude::*;

use crate::material::Lame;

/// The interpreter we embed: Debian's, which sees `python3-dolfinx-real`.
pub const PYTHON_EXECUTABLE: &std::ffi::CStr = c"/usr/bin/python3";

/// What to do when a Python module is missing.
const INSTALL_HINT: &str = "run `bash python/install-deps.sh` (as root) to install dolfinx, \
                            meshio, h5py and scikit-fem";

/// Errors of the bridge.
#[derive(Debug, Clone, thiserror::Error)]
pub enum BridgeError {
    /// Python raised; `traceback` is the formatted traceback (`traceback.format_exception`).
    #[error("Python raised an exception:\n{traceback}")]
    Python { traceback: String },
    /// A module could not be imported (`ModuleNotFoundError`).
    #[error("Python module `{module}` is not installed: {hint}")]
    MissingModule { module: String, hint: String },
    /// The arguments are inconsistent; checked before Python is called.
    #[error("invalid input: {reason}")]
    InvalidInput { reason: String },
}

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
/// of [`crate::solid::assembly::assemble`]:
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

/// `(dim, nodes per cell)` of triangles, quadrilaterals, tetrahedra, hexahedra, triangle6 and
/// tetra10.
const SOLID_CELLS: [(usize, usize); 6] = [(2, 3), (2, 4), (3, 4), (3, 8), (2, 6), (3, 10)];

/// A mesh as flat arrays: `dim` coordinates per vertex, `verts_per_cell` vertex indices per cell.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshArrays {
    pub points: Vec<f64>,
    pub dim: usize,
    pub cells: Vec<usize>,
    pub verts_per_cell: usize,
}

impl MeshArrays {
    /// The arrays of a mesh (`dim` coordinates per vertex).
    pub fn of(mesh: &crate::fem::Mesh) -> Self {
        MeshArrays {
            points: mesh.flat_points(),
            dim: mesh.dim,
            cells: mesh.cells.clone(),
            verts_per_cell: mesh.kind.verts(),
        }
    }
}

/// Validates a mesh given as arrays; returns `(vertices, cells)`. `allowed` lists the
/// `(gdim, verts_per_cell)` pairs the caller's Python function accepts.
fn check_mesh(
    points: &[f64],
    gdim: usize,
    cells: &[usize],
    verts_per_cell: usize,
    weights: &[f64],
    allowed: &[(usize, usize)],
) -> Result<(usize, usize), BridgeError> {
    if !allowed.contains(&(gdim, verts_per_cell)) {
        return invalid(format!("gdim {gdim} with {verts_per_cell} vertices per cell; allowed: {allowed:?}"));
    }
    if !points.len().is_multiple_of(gdim) || !cells.len().is_multiple_of(verts_per_cell) {
        return invalid(format!(
            "{} coordinates are not a multiple of gdim {gdim}, or {} cell entries not a multiple \
             of {verts_per_cell}",
            points.len(),
            cells.len()
        ));
    }
    let (n, ncells) = (points.len() / gdim, cells.len() / verts_per_cell);
    if weights.len() != ncells {
        return invalid(format!("{} weights for {ncells} cells (need one per cell)", weights.len()));
    }
    if let Some(&v) = cells.iter().find(|&&v| v >= n) {
        return invalid(format!("cell vertex {v} out of range 0..{n}"));
    }
    Ok((n, ncells))
}

/// The numpy arrays `(points (n, gdim), cells (ncells, verts_per_cell) int64, weights)`.
#[allow(clippy::type_complexity)] // three numpy arrays, named in the doc line
fn mesh_args<'py>(
    py: Python<'py>,
    points: &[f64],
    gdim: usize,
    cells: &[usize],
    verts_per_cell: usize,
    weights: &[f64],
    (n, ncells): (usize, usize),
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyArray1<f64>>)> {
    let points = PyArray1::from_slice(py, points).reshape([n, gdim])?.into_any();
    let cells: Vec<i64> = cells.iter().map(|&v| v as i64).collect();
    let cells = PyArray1::from_vec(py, cells).reshape([ncells, verts_per_cell])?.into_any();
    Ok((points, cells, PyArray1::from_slice(py, weights)))
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

/// Writes a mesh with meshio (`python/crosscheck/mesh_io.py::write_mesh`; `.msh` as gmsh 2.2 ASCII, else
/// by the extension, e.g. `.vtu`): triangles, quadrilaterals, tetrahedra or hexahedra by `dim`
/// and `verts_per_cell`.
pub fn write_mesh(path: &Path, mesh: &MeshArrays) -> Result<(), BridgeError> {
    let (n, ncells) = check_mesh(
        &mesh.points,
        mesh.dim,
        &mesh.cells,
        mesh.verts_per_cell,
        &vec![0.0; mesh.cells.len() / mesh.verts_per_cell.max(1)],
        &SOLID_CELLS,
    )?;
    startup()?;
    attach(|py| {
        let (points, cells, _) =
            mesh_args(py, &mesh.points, mesh.dim, &mesh.cells, mesh.verts_per_cell, &[], (n, ncells))?;
        let path = path.to_string_lossy().into_owned();
        py.import("mesh_io")?.call_method1("write_mesh", (path, points, cells))?;
        Ok(())
    })
}

/// The points (x, y, z per point) and one point-data array (`components` values per point) of a
/// file read by meshio (`python/crosscheck/mesh_io.py::read_point_data`), e.g. a `.vtu` frame.
pub fn read_point_data(path: &Path, name: &str) -> Result<(Vec<f64>, Vec<f64>, usize), BridgeError> {
    startup()?;
    attach(|py| {
        let path = path.to_string_lossy().into_owned();
        let out = py.import("mesh_io")?.call_method1("read_point_data", (path, name))?;
        let (points, data): (PyReadonlyArray2<f64>, PyReadonlyArray2<f64>) = out.extract()?;
        let components = data.as_array().ncols();
        Ok((points.as_array().iter().copied().collect(), data.as_array().iter().copied().collect(), components))
    })
}

/// A mesh file as meshio reads it (`python/crosscheck/mesh_io.py::read_cell_blocks`; gmsh `.msh` with
/// `file_format="gmsh"`), nothing dropped or checked: the scene's edge
/// ([`crate::scene::mesh_file`]) picks and checks the cells.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshBlocks {
    /// `columns` coordinates per point (meshio pads 2D files to 3 for most formats).
    pub points: Vec<f64>,
    pub columns: usize,
    /// `(meshio cell type, vertex indices as the file gives them, vertices per cell)`.
    pub blocks: Vec<(String, Vec<i64>, usize)>,
}

/// The points and cell blocks of a file as meshio reads it ([`MeshBlocks`]).
pub fn read_mesh_blocks(path: &Path) -> Result<MeshBlocks, BridgeError> {
    startup()?;
    attach(|py| {
        let path = path.to_string_lossy().into_owned();
        let out = py.import("mesh_io")?.call_method1("read_cell_blocks", (path,))?;
        let (points, blocks): (PyReadonlyArray2<f64>, Vec<(String, PyReadonlyArray2<i64>)>) = out.extract()?;
        let blocks = blocks
            .into_iter()
            .map(|(t, c)| (t, c.as_array().iter().copied().collect(), c.as_array().ncols()))
            .collect();
        let columns = points.as_array().ncols();
        Ok(MeshBlocks { points: points.as_array().iter().copied().collect(), columns, blocks })
    })
}

/// The points (x, y, z per point) and the cell blocks `(meshio cell type, flat vertex indices)`
/// of a file as meshio reads it, nothing dropped: for checking the files we write (a negative
/// index is an error).
#[allow(clippy::type_complexity)] // points and a list of blocks, named in the doc line
pub fn read_cell_blocks(path: &Path) -> Result<(Vec<f64>, Vec<(String, Vec<usize>)>), BridgeError> {
    let m = read_mesh_blocks(path)?;
    let mut blocks = Vec::with_capacity(m.blocks.len());
    for (t, c, _) in m.blocks {
        let c = c.into_iter().map(usize::try_from).collect::<Result<Vec<usize>, _>>();
        let c =
            c.map_err(|_| BridgeError::InvalidInput { reason: format!("a negative vertex index in the {t} cells") })?;
        blocks.push((t, c));
    }
    Ok((m.points, blocks))
}

/// Imports `module` in the embedded interpreter and returns its `__version__` (empty if it has
/// none). A module that is not installed gives [`BridgeError::MissingModule`].
pub fn module_version(module: &str) -> Result<String, BridgeError> {
    startup()?;
    attach(|py| {
        let module = py.import(module)?;
        match module.getattr("__version__") {
            Ok(version) => Ok(version.str()?.to_string()),
            Err(_) => Ok(String::new()),
        }
    })
}

/// What the one-time start-up found.
struct Startup {
    executable: String,
    python: String,
    numpy: String,
    dolfinx: Result<String, BridgeError>,
    skfem: Result<String, BridgeError>,
}

/// Starts the interpreter once per process (see the module documentation).
fn startup() -> Result<&'static Startup, BridgeError> {
    static STARTUP: OnceLock<Result<Startup, BridgeError>> = OnceLock::new();
    STARTUP
        .get_or_init(|| {
            set_program_name();
            Python::attach(|py| {
                let (executable, python) = prepare(py).map_err(|err| python_error(py, err))?;
                let version = |module: &str| -> Result<String, BridgeError> {
                    let found = py.import(module).and_then(|m| m.getattr("__version__"));
                    found.and_then(|v| v.extract()).map_err(|err| python_error(py, err))
                };
                // fem_dolfinx imports dolfinx, basix, ufl and mpi4py: here, and only here first.
                let dolfinx = py
                    .import(Backend::Dolfinx.module())
                    .map_err(|err| python_error(py, err))
                    .and_then(|_| version("dolfinx"));
                Ok(Startup { executable, python, numpy: version("numpy")?, dolfinx, skfem: version("skfem") })
            })
        })
        .as_ref()
        .map_err(Clone::clone)
}

/// Environment, `sys.path` and logging set-up; returns `(sys.executable, Python version)`.
fn prepare(py: Python<'_>) -> PyResult<(String, String)> {
    let os = py.import("os")?;
    os.getattr("environ")?.set_item("OMPI_MCA_ess_singleton_isolated", "1")?;
    let sys = py.import("sys")?;
    let path = sys.getattr("path")?;
    for (i, dir) in python_dirs().iter().enumerate() {
        path.call_method1("insert", (i, dir.to_string_lossy().into_owned()))?;
    }
    let logging = py.import("logging")?;
    logging.call_method1("disable", (logging.getattr("INFO")?,))?;
    let python = py.import("platform")?.call_method0("python_version")?.extract()?;
    Ok((sys.getattr("executable")?.extract()?, python))
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

/// `<crate>/python/crosscheck` and the scikit-fem target folder, in `sys.path` order.
fn python_dirs() -> [PathBuf; 2] {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let pydeps = std::env::var_os("MASSREDIST_PYDEPS").map_or_else(|| root.join(".pydeps"), PathBuf::from);
    [root.join("python").join("crosscheck"), pydeps]
}

/// Makes the interpreter `/usr/bin/python3` (sys.executable, sys.prefix) whatever `PATH` holds.
#[allow(deprecated)] // Py_SetProgramName: deprecated in 3.11 for PyConfig, still honoured
fn set_program_name() {
    // SAFETY: both calls are allowed before Py_Initialize (Python docs, "Before Python
    // Initialization"); we only make them while the interpreter is not running, inside the
    // OnceLock initialiser (one thread). The decoded string is never freed: Python keeps the
    // pointer for the life of the process.
    unsafe {
        if pyo3::ffi::Py_IsInitialized() == 0 {
            let name = pyo3::ffi::Py_DecodeLocale(PYTHON_EXECUTABLE.as_ptr(), std::ptr::null_mut());
            if !name.is_null() {
                pyo3::ffi::Py_SetProgramName(name);
            }
        }
    }
}

/// Runs `f` attached to the interpreter, turning a Python exception into a [`BridgeError`].
fn attach<T>(f: impl for<'py> FnOnce(Python<'py>) -> PyResult<T>) -> Result<T, BridgeError> {
    Python::attach(|py| f(py).map_err(|err| python_error(py, err)))
}

/// `ModuleNotFoundError` becomes [`BridgeError::MissingModule`], anything else
/// [`BridgeError::Python`] with the formatted traceback.
fn python_error(py: Python<'_>, err: PyErr) -> BridgeError {
    if err.is_instance_of::<PyModuleNotFoundError>(py) {
        let name = err.value(py).getattr("name").and_then(|n| n.extract::<String>());
        return BridgeError::MissingModule {
            module: name.unwrap_or_else(|_| err.to_string()),
            hint: INSTALL_HINT.to_string(),
        };
    }
    let formatted = py
        .import("traceback")
        .and_then(|tb| {
            // Python 3.11 keeps the traceback apart from the exception value: pass all three.
            tb.call_method1("format_exception", (err.get_type(py), err.value(py), err.traceback(py)))
        })
        .and_then(|lines| lines.extract::<Vec<String>>());
    BridgeError::Python { traceback: formatted.map_or_else(|_| err.to_string(), |l| l.concat()) }
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
