//! The Python exceptions: `SceneError` (a `ValueError`: the input is at fault, the CLI's exit
//! code 2) with the key it names in `.key`, and `RunError` (a `RuntimeError`: a scheme failed
//! while stepping).

use massredist::run::RunError as CoreRunError;
use massredist::scene::SceneError as CoreSceneError;
use pyo3::prelude::*;

pyo3::create_exception!(
    _core,
    SceneError,
    pyo3::exceptions::PyValueError,
    "A scene the CLI would refuse: the same message; `.key` is the key it names (None if none)."
);
pyo3::create_exception!(_core, RunError, pyo3::exceptions::PyRuntimeError, "A run failed while stepping.");

/// A `SceneError` with the message of the CLI and its key.
pub fn scene_error(py: Python<'_>, e: &CoreSceneError) -> PyErr {
    scene_error_msg(py, e.to_string(), e.key())
}

/// A `SceneError` for a scene built from a dict or changed by `Scene.replace`: the message
/// without the TOML positions and excerpt of the CLI's (that TOML is the package's own
/// serialisation, which the user never wrote: issue 32, "line 6, column 2" of a dict).
pub fn scene_error_unwritten(py: Python<'_>, e: &CoreSceneError) -> PyErr {
    scene_error_msg(py, without_toml_position(&e.to_string()), e.key())
}

/// `bar.elements: invalid type: … (line 2, column 12)\nTOML parse error at line 2 …` →
/// `bar.elements: invalid type: …`: the first line without its position; other messages as
/// they are.
fn without_toml_position(message: &str) -> String {
    let first = message.lines().next().unwrap_or_default();
    let is_position = |tail: &str| {
        tail.strip_prefix(" (line ").and_then(|t| t.strip_suffix(')')).is_some_and(|t| {
            t.split_once(", column ").is_some_and(|(l, c)| l.parse::<u64>().is_ok() && c.parse::<u64>().is_ok())
        })
    };
    match first.rfind(" (line ") {
        Some(i) if is_position(&first[i..]) => first[..i].to_string(),
        _ => message.to_string(),
    }
}

/// A `SceneError` from a message and a key (keys changed by `Scene.replace`).
pub fn scene_error_msg(py: Python<'_>, message: String, key: Option<String>) -> PyErr {
    let err = SceneError::new_err(message);
    // Setting an attribute on a fresh exception instance cannot fail but for memory.
    let _ = err.value(py).setattr("key", key);
    err
}

/// A run error: `SceneError` when the scene cannot be set up, `RunError` otherwise.
pub fn run_error(py: Python<'_>, e: &CoreRunError) -> PyErr {
    match e {
        CoreRunError::Setup(s) => scene_error(py, s),
        other => RunError::new_err(other.to_string()),
    }
}
