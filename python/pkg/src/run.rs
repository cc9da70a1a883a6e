//! `run`: the crate's `run::run_scene` (the CLI's step loop, divergence rule and summary) with
//! the GIL released while Rust steps, two observers of this module's own, and the results
//! handed to Python as numpy arrays.
//!
//! - [`Interrupt`] takes the GIL at most every [`SIGNAL_PERIOD`] to run Python's signal
//!   handlers (Ctrl-C raises `KeyboardInterrupt` there); an exception halts the run (the
//!   driver takes no further step) and is raised once `run_scene` returns. Nothing is written
//!   during the run; the VTU frames of a scene with `output.vtu` go into the folder the caller
//!   names, after it (removed again if writing fails), and without a folder such a scene is
//!   refused naming `output.vtu`.
//! - [`Callback`] calls a Python function every k steps with views of the state at the mesh
//!   nodes (read-only arrays refreshed in place).

use crate::errors::{run_error, scene_error_msg};
use crate::ops::{Meshed, put_mesh};
use crate::scene::Scene;
use massredist::driver::{Needs, Observer, Sample};
use massredist::fem::frames::{FrameWriter, VtuFrames};
use massredist::observe::Frame;
use massredist::observe::Status;
use massredist::problem::GeometryView;
use massredist::run::{GeometrySpec, run_scene, summary_json};
use massredist::scene::Registered;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How often a run looks for a pending signal: a Ctrl-C is seen within this time plus one step.
const SIGNAL_PERIOD: Duration = Duration::from_millis(20);
/// Steps between two reads of the clock (a read costs ~20 ns; a bar step about 100 ns).
const CLOCK_STEPS: usize = 16;

/// Runs Python's signal handlers every [`SIGNAL_PERIOD`] (module docs).
struct Interrupt {
    steps: usize,
    last: Instant,
    error: Option<PyErr>,
}

impl Observer for Interrupt {
    fn observe(&mut self, _: &Sample) {
        self.steps += 1;
        if !self.steps.is_multiple_of(CLOCK_STEPS) || self.last.elapsed() < SIGNAL_PERIOD {
            return;
        }
        self.last = Instant::now();
        if let Err(e) = Python::attach(|py| py.check_signals()) {
            self.error = Some(e);
        }
    }

    fn halted(&self) -> bool {
        self.error.is_some()
    }
}

/// Calls `f(n, t, u, v, reaction, energy)` every `every` steps: u and v at the mesh nodes
/// (n × components), the contact reactions λ_c in contact order; an exception halts the run.
///
/// The arrays are views of the run's state: the same three read-only numpy arrays at every
/// call, refreshed in place (the nodal values are written straight into numpy's memory, no
/// allocation per call). A caller who keeps a state copies it (`u.copy()`).
struct Callback<'a> {
    f: &'a Py<PyAny>,
    every: usize,
    error: Option<PyErr>,
    views: Option<Views>,
}

/// The three arrays a [`Callback`] hands out (see there).
struct Views {
    u: Py<PyArray2<f64>>,
    v: Py<PyArray2<f64>>,
    reaction: Py<PyArray1<f64>>,
}

impl Views {
    /// Zeroed arrays of the state's shapes, flagged read-only for Python.
    fn new(py: Python<'_>, shape: (usize, usize), contacts: usize) -> Self {
        let u = PyArray2::<f64>::zeros(py, [shape.0, shape.1], false);
        let v = PyArray2::<f64>::zeros(py, [shape.0, shape.1], false);
        let reaction = PyArray1::<f64>::zeros(py, contacts, false);
        // Only Python is refused writes: this module writes through `as_slice_mut`.
        let (u, v) = (u.readwrite().make_nonwriteable(), v.readwrite().make_nonwriteable());
        let reaction = reaction.readwrite().make_nonwriteable();
        Views {
            u: u.as_unbound().clone_ref(py),
            v: v.as_unbound().clone_ref(py),
            reaction: reaction.as_unbound().clone_ref(py),
        }
    }
}

impl Callback<'_> {
    fn call(&mut self, s: &Sample) -> PyResult<()> {
        let shape = (s.geometry.n_nodes(), s.geometry.components());
        Python::attach(|py| {
            let stale = self.views.as_ref().is_none_or(|w| w.reaction.bind(py).len() != s.state.lambda.len());
            if stale {
                self.views = Some(Views::new(py, shape, s.state.lambda.len()));
            }
            let w = self.views.as_ref().expect("set above");
            let (u, v, reaction) = (w.u.bind(py), w.v.bind(py), w.reaction.bind(py));
            // SAFETY: the arrays are C-contiguous and were allocated by `Views::new`; the GIL is
            // held, so no Python code reads them while they are written, and no Rust borrow of
            // them is alive (numpy's own borrow flags are not needed for that).
            unsafe {
                let (u, v) = (u.as_slice_mut().expect("contiguous"), v.as_slice_mut().expect("contiguous"));
                u.fill(0.0);
                v.fill(0.0);
                s.geometry.nodal_values(s.state.u, u);
                s.geometry.nodal_values(s.state.v, v);
                reaction.as_slice_mut().expect("contiguous").copy_from_slice(s.state.lambda);
            }
            self.f.call1(py, (s.state.n, s.state.t, u, v, reaction, s.energy))?;
            Ok(())
        })
    }
}

impl Observer for Callback<'_> {
    fn needs(&self) -> Needs {
        Needs { energy: true, ..Needs::default() }
    }

    fn every(&self) -> usize {
        self.every
    }

    fn observe(&mut self, s: &Sample) {
        if self.error.is_none()
            && let Err(e) = self.call(s)
        {
            self.error = Some(e);
        }
    }

    fn halted(&self) -> bool {
        self.error.is_some()
    }
}

/// Where a run's VTU frames go: `output.vtu` and `vtu_dir` must agree (issue 32: the frames
/// were silently dropped); the folder is created if missing, and one that holds frames already
/// is refused before the run (nothing the user wrote is overwritten).
fn frames_dir<G: GeometrySpec>(
    py: Python<'_>,
    scene: &massredist::scene::Scene<G>,
    vtu_dir: Option<&Path>,
) -> PyResult<Option<PathBuf>> {
    let key = Some("output.vtu".to_string());
    match (scene.output.vtu_every, vtu_dir) {
        (None, None) => Ok(None),
        (Some(_), None) => Err(scene_error_msg(
            py,
            "output.vtu = true: massredist.run keeps its results in memory and writes a scene's VTU frames only where you say: pass vtu_dir=FOLDER, or set output.vtu = false".into(),
            key,
        )),
        (None, Some(d)) => Err(scene_error_msg(
            py,
            format!("output.vtu: vtu_dir = {} was given, but the scene writes no frames: set output.vtu = true (and output.vtu_every)", d.display()),
            key,
        )),
        (Some(_), Some(d)) => {
            let collection = d.join("vtu");
            if collection.exists() {
                let msg = format!("{}: holds VTU frames already; give an empty or new folder", collection.display());
                return Err(pyo3::exceptions::PyFileExistsError::new_err(msg));
            }
            std::fs::create_dir_all(d)?;
            Ok(Some(d.to_path_buf()))
        }
    }
}

/// Writes the recorded frames as `massredist run` streams them (`vtu/frame_NNNNN.vtu` and the
/// `.pvd` collection); on an error what was written is removed.
fn write_frames(dir: &Path, geometry: &dyn VtuFrames, frames: &[Frame]) -> std::io::Result<()> {
    let written = (|| {
        let mut writer = FrameWriter::create(dir, geometry, 1)?;
        for f in frames {
            writer.write_recorded(f)?;
        }
        writer.finish()
    })();
    if written.is_err() {
        let _ = std::fs::remove_dir_all(dir.join("vtu"));
        let _ = std::fs::remove_file(dir.join(format!("{}.pvd", geometry.collection())));
    }
    written
}

/// A run of one geometry's scene (see [`run`]).
fn run_geometry<G>(
    py: Python<'_>,
    scene: &massredist::scene::Scene<G>,
    callback: Option<&Py<PyAny>>,
    every: usize,
    vtu_dir: Option<&Path>,
) -> PyResult<Py<PyDict>>
where
    G: GeometrySpec + Registered + Sync,
    G::System: Meshed + Send,
{
    let vtu_dir = frames_dir(py, scene, vtu_dir)?;
    let mut interrupt = Interrupt { steps: 0, last: Instant::now(), error: None };
    let result = py.detach(|| {
        let mut callback = callback.map(|f| Callback { f, every: every.max(1), error: None, views: None });
        let mut extra: Vec<&mut dyn Observer> = vec![&mut interrupt];
        if let Some(c) = callback.as_mut() {
            extra.push(c);
        }
        let run = run_scene(scene, &mut extra);
        (run, callback.and_then(|c| c.error))
    });
    let (run, callback_error) = result;
    if let Some(e) = interrupt.error.or(callback_error) {
        return Err(e);
    }
    let run = run.map_err(|e| run_error(py, &e))?;
    if let (Some(dir), Some(recorded), Some(geometry)) = (&vtu_dir, &run.frames, G::frames(&run.problem.system)) {
        py.detach(|| write_frames(dir, geometry, &recorded.frames))?;
    }
    let d = PyDict::new(py);
    let status = match run.summary.status {
        Status::Ok => "ok",
        Status::Diverged => "diverged",
    };
    d.set_item("status", status)?;
    d.set_item("summary_json", summary_json(scene, &run.problem, &run.summary))?;
    let names: Vec<&str> = run.series.columns.iter().map(|c| c.name()).collect();
    let width = run.series.width();
    let rows = run.series.rows.len() / width;
    d.set_item("columns", names)?;
    let table = Array2::from_shape_vec((rows, width), run.series.rows).expect("rows × width");
    d.set_item("series", table.into_pyarray(py))?;
    let geometry = &run.problem.system;
    let shape = (geometry.n_nodes(), geometry.components());
    d.set_item("t", run.last.t)?;
    d.set_item("u", Array2::from_shape_vec(shape, run.last.u).expect("n × components").into_pyarray(py))?;
    d.set_item("v", Array2::from_shape_vec(shape, run.last.v).expect("n × components").into_pyarray(py))?;
    d.set_item("reaction", PyArray1::from_vec(py, run.last.lambda))?;
    put_mesh(py, geometry, &d)?;
    Ok(d.unbind())
}

/// Runs a scene (module docs): a dict with `status`, `summary_json` (the CLI's
/// `summary.json` text), `columns` and `series` (rows: t, then one value per column), the
/// final state `t`, `u`, `v` (mesh nodes × components), `reaction` (contact order) and the
/// mesh. `callback(n, t, u, v, reaction, energy)` is called every `every` steps. The VTU
/// frames of a scene with `output.vtu` are written into `vtu_dir` ([`frames_dir`]).
#[pyfunction]
#[pyo3(signature = (scene, callback = None, every = 1, vtu_dir = None))]
pub fn run(
    py: Python<'_>,
    scene: &Scene,
    callback: Option<Py<PyAny>>,
    every: usize,
    vtu_dir: Option<PathBuf>,
) -> PyResult<Py<PyDict>> {
    let dir = vtu_dir.as_deref();
    massredist::with_scene!(&scene.any, s => run_geometry(py, s, callback.as_ref(), every, dir))
}
