//! `massredist._core`: the massredist crate as a Python extension module (pyo3, abi3 for
//! CPython ≥ 3.11). The Python package `massredist` (python/pkg/python/massredist) wraps it;
//! its docstrings and stubs are the API's documentation.
//!
//! - [`scene`]: scenes from TOML text, a file or a dict, validated by the crate's own
//!   `AnyScene` (the CLI's checks and messages), changed key by key for sweeps.
//! - [`run`]: `run::run_scene` with the GIL released, an interrupt guard and an optional
//!   Python observer; the summary is the CLI's `summary.json` text.
//! - [`ops`]: the assembled operators, the mesh of a scene, and the exact bar solution.

mod errors;
mod ops;
mod run;
mod scene;

use pyo3::prelude::*;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // Load numpy's C API now: its first use imports numpy's Python code, where a pending
    // Ctrl-C would raise and rust-numpy would panic (found with the interrupt guard disabled:
    // the KeyboardInterrupt then fired inside the first array creation after a run).
    let _ = numpy::PyArray1::<f64>::zeros(py, 0, false);
    // What cannot fit in memory is refused (SceneError) as the CLI refuses it, never an abort
    // of the interpreter: the machine's limit, less what the process holds (the CLI's main).
    let _ = massredist::machine::install_memory_limit();
    m.add("SceneError", py.get_type::<errors::SceneError>())?;
    m.add("RunError", py.get_type::<errors::RunError>())?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<ops::ExactBar>()?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(scene::check, m)?)?;
    m.add_function(wrap_pyfunction!(ops::operators, m)?)?;
    m.add_function(wrap_pyfunction!(ops::exact, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
