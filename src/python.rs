//! The embedded Python interpreter and meshio: the solver's one door to Python (compiled only
//! with the feature `python`). It reads mesh files through meshio ([`read_mesh_blocks`], used by
//! [`crate::mesh_file`]) and writes and reads meshes and frames ([`write_mesh`],
//! [`read_point_data`]); the study's bridge to FEniCSx and scikit-fem
//! (`study/src/bridge.rs`) starts the interpreter through [`startup`] and [`attach`].
//!
//! Start-up is deterministic and happens once per process ([`OnceLock`]), in the first call of any
//! function here:
//! - the interpreter is Debian's `/usr/bin/python3` whatever `PATH` says (`Py_SetProgramName`
//!   before it starts; otherwise a pyenv or venv first on `PATH` supplies the standard library);
//! - `OMPI_MCA_ess_singleton_isolated=1` is set before mpi4py loads (no `orted` daemon);
//! - `<crate>/python` and `<crate>/.pydeps` (or `$MASSREDIST_PYDEPS`) go first on `sys.path`;
//! - log records below WARNING are disabled (the dolfinx JIT's compiler lines; raising the root
//!   logger's level is not enough, distutils lowers it again while compiling);
//! - dolfinx is imported in that same first attach, on the thread that started the interpreter:
//!   importing it first on another thread that later detaches and re-attaches makes the next
//!   mesh creation hang for ever. After that, calls from any number of threads are safe (the GIL
//!   serialises them).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2};
use pyo3::exceptions::PyModuleNotFoundError;
use pyo3::prelude::*;

/// The interpreter we embed: Debian's, which sees `python3-dolfinx-real`.
pub const PYTHON_EXECUTABLE: &std::ffi::CStr = c"/usr/bin/python3";

/// What to do when a Python module is missing.
const INSTALL_HINT: &str = "run `bash python/install-deps.sh` (as root) to install dolfinx, \
                            meshio, h5py and scikit-fem";

/// Errors of the embedded interpreter.
#[derive(Debug, Clone, thiserror::Error)]
pub enum PythonError {
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

/// The Python module imported first, on the thread that starts the interpreter (see the module
/// documentation): the dolfinx assembler of `python/crosscheck/fem_dolfinx.py`.
const FIRST_IMPORT: &str = "fem_dolfinx";

/// `(dim, nodes per cell)` of triangles, quadrilaterals, tetrahedra, hexahedra, triangle6 and
/// tetra10.
pub const SOLID_CELLS: [(usize, usize); 6] = [(2, 3), (2, 4), (3, 4), (3, 8), (2, 6), (3, 10)];

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
pub fn check_mesh(
    points: &[f64],
    gdim: usize,
    cells: &[usize],
    verts_per_cell: usize,
    weights: &[f64],
    allowed: &[(usize, usize)],
) -> Result<(usize, usize), PythonError> {
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
pub fn mesh_args<'py>(
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

/// Writes a mesh with meshio (`python/crosscheck/mesh_io.py::write_mesh`; `.msh` as gmsh 2.2 ASCII, else
/// by the extension, e.g. `.vtu`): triangles, quadrilaterals, tetrahedra or hexahedra by `dim`
/// and `verts_per_cell`.
pub fn write_mesh(path: &Path, mesh: &MeshArrays) -> Result<(), PythonError> {
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
pub fn read_point_data(path: &Path, name: &str) -> Result<(Vec<f64>, Vec<f64>, usize), PythonError> {
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
/// ([`crate::mesh_file`]) picks and checks the cells.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshBlocks {
    /// `columns` coordinates per point (meshio pads 2D files to 3 for most formats).
    pub points: Vec<f64>,
    pub columns: usize,
    /// `(meshio cell type, vertex indices as the file gives them, vertices per cell)`.
    pub blocks: Vec<(String, Vec<i64>, usize)>,
}

/// The points and cell blocks of a file as meshio reads it ([`MeshBlocks`]).
pub fn read_mesh_blocks(path: &Path) -> Result<MeshBlocks, PythonError> {
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
pub fn read_cell_blocks(path: &Path) -> Result<(Vec<f64>, Vec<(String, Vec<usize>)>), PythonError> {
    let m = read_mesh_blocks(path)?;
    let mut blocks = Vec::with_capacity(m.blocks.len());
    for (t, c, _) in m.blocks {
        let c = c.into_iter().map(usize::try_from).collect::<Result<Vec<usize>, _>>();
        let c =
            c.map_err(|_| PythonError::InvalidInput { reason: format!("a negative vertex index in the {t} cells") })?;
        blocks.push((t, c));
    }
    Ok((m.points, blocks))
}

/// Imports `module` in the embedded interpreter and returns its `__version__` (empty if it has
/// none). A module that is not installed gives [`PythonError::MissingModule`].
pub fn module_version(module: &str) -> Result<String, PythonError> {
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
pub struct Startup {
    pub executable: String,
    pub python: String,
    pub numpy: String,
    pub dolfinx: Result<String, PythonError>,
    pub skfem: Result<String, PythonError>,
}

/// Starts the interpreter once per process (see the module documentation).
pub fn startup() -> Result<&'static Startup, PythonError> {
    static STARTUP: OnceLock<Result<Startup, PythonError>> = OnceLock::new();
    STARTUP
        .get_or_init(|| {
            set_program_name();
            Python::attach(|py| {
                let (executable, python) = prepare(py).map_err(|err| python_error(py, err))?;
                let version = |module: &str| -> Result<String, PythonError> {
                    let found = py.import(module).and_then(|m| m.getattr("__version__"));
                    found.and_then(|v| v.extract()).map_err(|err| python_error(py, err))
                };
                // fem_dolfinx imports dolfinx, basix, ufl and mpi4py: here, and only here first.
                let dolfinx =
                    py.import(FIRST_IMPORT).map_err(|err| python_error(py, err)).and_then(|_| version("dolfinx"));
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

/// `<crate>/python` and the scikit-fem target folder, in `sys.path` order.
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

/// Runs `f` attached to the interpreter, turning a Python exception into a [`PythonError`].
pub fn attach<T>(f: impl for<'py> FnOnce(Python<'py>) -> PyResult<T>) -> Result<T, PythonError> {
    Python::attach(|py| f(py).map_err(|err| python_error(py, err)))
}

/// `ModuleNotFoundError` becomes [`PythonError::MissingModule`], anything else
/// [`PythonError::Python`] with the formatted traceback.
pub fn python_error(py: Python<'_>, err: PyErr) -> PythonError {
    if err.is_instance_of::<PyModuleNotFoundError>(py) {
        let name = err.value(py).getattr("name").and_then(|n| n.extract::<String>());
        return PythonError::MissingModule {
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
    PythonError::Python { traceback: formatted.map_or_else(|_| err.to_string(), |l| l.concat()) }
}

fn invalid<T>(reason: String) -> Result<T, PythonError> {
    Err(PythonError::InvalidInput { reason })
}
