//! The FEniCSx engine as a process: `massredist run SCENE --engine fenicsx --ranks N --out DIR`
//! for plate and solid scenes (issue 12).
//!
//! The scene is validated exactly as for a Rust run (`crate::scene::AnyScene::from_file`: keys,
//! mesh, cell weights, schemes), its resolved form is written into the output folder's temporary sibling, and
//!
//! ```text
//! mpirun -n N /usr/bin/python3 python/fenicsx_engine.py DIR.tmp/scene.resolved.toml DIR.tmp --staged
//! ```
//!
//! steps it with dolfinx and PETSc (python/engine/: the weighted mass as a DG0 weight field, each
//! implicit step a bound-constrained QP solved by SNES `vinewtonrsls`). The engine writes
//! series.csv, summary.json (the columns and keys of the Rust run), engine.json (ranks, solver,
//! tolerances, timings, complementarity record) and fields.xdmf/.h5 into the temporary folder;
//! this module then commits it like every run folder ([`crate::output::OutputDir::commit`]:
//! the marker, the rename). Exit status of the engine: 0 ok, 3 diverged (folder written), 2 an
//! input it cannot run, anything else a failure.
//!
//! Nothing here needs the `python` feature: the engine is a separate process. The programs can be
//! replaced through the environment: `MASSREDIST_MPIRUN` (default `mpirun`; e.g. a cluster's
//! launcher), `MASSREDIST_PYTHON` (default `/usr/bin/python3`, Debian's, which sees dolfinx) and
//! `MASSREDIST_ENGINE` (the entry point, default `python/fenicsx_engine.py` of this source tree).

use crate::output::OutputDir;
use crate::scene::{PlateSpec, Scene, SceneGeometry};
use crate::solid::SolidSpec;
use std::path::{Path, PathBuf};
use std::process::Command;
use thiserror::Error;

/// The command that installs what the engine needs.
pub const INSTALL: &str = "bash python/install-deps.sh";

#[derive(Debug, Error)]
pub enum EngineError {
    /// The scene cannot be run (as a Rust run would refuse it), or not by the engine.
    #[error("{0}")]
    Scene(String),
    /// A program or Python module the engine needs is missing.
    #[error("the fenicsx engine needs {what}, which is not available ({detail}); install it with `{INSTALL}`")]
    Missing { what: &'static str, detail: String },
    /// The engine ran and failed (its own message is on stderr above).
    #[error("the fenicsx engine ({ranks} ranks) failed with exit status {status}")]
    Failed { ranks: usize, status: String },
    #[error("writing the run folder: {0}")]
    Output(std::io::Error),
}

impl EngineError {
    /// True when nothing was computed: an invalid scene or a missing dependency (exit code 2 of
    /// `massredist run`), as opposed to a failure while computing or writing (exit code 1).
    pub fn is_invalid(&self) -> bool {
        matches!(self, EngineError::Scene(_) | EngineError::Missing { .. })
    }
}

/// How an engine run ended (its folder is written in both cases).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EngineOutcome {
    Completed,
    /// The run diverged (status "diverged" in summary.json), as a Rust run's exit code 3.
    Diverged,
}

fn program(var: &str, default: &str) -> String {
    std::env::var(var).ok().filter(|s| !s.is_empty()).unwrap_or_else(|| default.to_string())
}

/// The engine's entry point (`MASSREDIST_ENGINE`, else python/fenicsx_engine.py of this tree).
pub fn entry_point() -> PathBuf {
    std::env::var_os("MASSREDIST_ENGINE")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("python").join("fenicsx_engine.py"))
}

/// Whether this process runs as root (Open MPI then refuses to start without its two
/// `OMPI_ALLOW_RUN_AS_ROOT*` variables).
fn running_as_root() -> bool {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata("/proc/self").is_ok_and(|m| m.uid() == 0)
}

/// Checks that the launcher, the interpreter with dolfinx/petsc4py/mpi4py, and the entry point
/// are there; the error names what is missing and the install command.
pub fn check_available() -> Result<(), EngineError> {
    let mpirun = program("MASSREDIST_MPIRUN", "mpirun");
    let python = program("MASSREDIST_PYTHON", "/usr/bin/python3");
    match Command::new(&mpirun).arg("--version").output() {
        Ok(o) if o.status.success() => {}
        Ok(o) => {
            return Err(EngineError::Missing { what: "mpirun", detail: format!("`{mpirun} --version`: {}", o.status) });
        }
        Err(e) => return Err(EngineError::Missing { what: "mpirun", detail: format!("`{mpirun}`: {e}") }),
    }
    let probe = Command::new(&python)
        .args(["-c", "import dolfinx, petsc4py, mpi4py"])
        .env("OMPI_MCA_ess_singleton_isolated", "1")
        .output();
    match probe {
        Ok(o) if o.status.success() => {}
        Ok(o) => {
            let err = String::from_utf8_lossy(&o.stderr);
            let last = err.lines().last().unwrap_or("").to_string();
            return Err(EngineError::Missing {
                what: "dolfinx (with petsc4py and mpi4py)",
                detail: format!("{python}: {last}"),
            });
        }
        Err(e) => return Err(EngineError::Missing { what: "Debian's python3", detail: format!("`{python}`: {e}") }),
    }
    let entry = entry_point();
    if !entry.is_file() {
        return Err(EngineError::Missing {
            what: "the engine's entry point",
            detail: format!("{} is not a file", entry.display()),
        });
    }
    Ok(())
}

/// The geometries the engine runs (plates and solids; bars are 1D and serial), and what of them
/// it cannot run yet. Everything a Rust run refuses (keys, mesh, cell weights, bar-only schemes)
/// the validated scene has already refused (`crate::scene::validate_sections`).
pub trait EngineGeometry: SceneGeometry {
    /// Why the engine cannot run this geometry (None if it can).
    fn engine_refusal(&self) -> Option<String>;
}

impl EngineGeometry for PlateSpec {
    fn engine_refusal(&self) -> Option<String> {
        self.mesh_file.as_ref().map(|_| "plate.mesh: the fenicsx engine runs structured plates only (for now)".into())
    }
}

/// Solids: structured meshes of every cell kind; `solid.mesh` files not yet.
impl EngineGeometry for SolidSpec {
    fn engine_refusal(&self) -> Option<String> {
        self.mesh_file.as_ref().map(|_| "solid.mesh: the fenicsx engine runs structured solids only (for now)".into())
    }
}

/// What the engine cannot run yet ([`EngineGeometry::engine_refusal`]).
pub fn validate<G: EngineGeometry>(scene: &Scene<G>) -> Result<(), EngineError> {
    scene.geometry.engine_refusal().map_or(Ok(()), |m| Err(EngineError::Scene(m)))
}

/// Runs `scene` with the engine on `ranks` MPI ranks and writes the run folder `out` (module
/// docs), prepared before anything is computed ([`OutputDir::prepare`]).
pub fn run<G: EngineGeometry>(scene: &Scene<G>, out: OutputDir, ranks: usize) -> Result<EngineOutcome, EngineError> {
    validate(scene)?;
    check_available()?;
    let mut outcome = EngineOutcome::Completed;
    let mut failure = None;
    let written = out.commit(|tmp| {
        let resolved = tmp.join("scene.resolved.toml");
        std::fs::write(&resolved, scene.resolved_toml())?;
        let mut cmd = Command::new(program("MASSREDIST_MPIRUN", "mpirun"));
        cmd.arg("-n").arg(ranks.to_string()).arg(program("MASSREDIST_PYTHON", "/usr/bin/python3"));
        cmd.arg(entry_point()).arg(&resolved).arg(tmp).arg("--staged");
        // Ranks that wait in a collective yield the core (this machine, and any oversubscribed
        // one, has fewer cores than busy processes); a cluster sets its own MCA parameters.
        if std::env::var_os("OMPI_MCA_mpi_yield_when_idle").is_none() {
            cmd.env("OMPI_MCA_mpi_yield_when_idle", "1");
        }
        if running_as_root() {
            cmd.env("OMPI_ALLOW_RUN_AS_ROOT", "1").env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
        }
        let status = cmd.status()?;
        match status.code() {
            Some(0) => Ok(()),
            Some(3) => {
                outcome = EngineOutcome::Diverged;
                Ok(())
            }
            _ => {
                failure = Some(EngineError::Failed { ranks, status: status.to_string() });
                Err(std::io::Error::other("the engine failed"))
            }
        }
    });
    match (written, failure) {
        (_, Some(f)) => Err(f),
        (Err(e), None) => Err(EngineError::Output(std::io::Error::other(e))),
        (Ok(()), None) => Ok(outcome),
    }
}

/// The line `massredist run` prints after an engine run (as after a Rust run), from the folder's
/// summary.json and engine.json.
pub fn report(out: &Path) -> String {
    let read = |name: &str| -> serde_json::Value {
        std::fs::read_to_string(out.join(name)).ok().and_then(|t| serde_json::from_str(&t).ok()).unwrap_or_default()
    };
    let (s, e) = (read("summary.json"), read("engine.json"));
    let num = |v: &serde_json::Value| v.as_f64().map_or("n/a".to_string(), |x| format!("{x:.4e}"));
    format!(
        "{}: {} steps in {:.3} s on {} MPI rank(s) (fenicsx engine: {}), L∞(L²) error {}, energy {} -> {}",
        out.display(),
        e["steps_taken"],
        e["step_seconds"].as_f64().unwrap_or(f64::NAN),
        e["ranks"],
        e["solver"].as_str().unwrap_or("?"),
        num(&s["linf_l2_error"]),
        s["energy_initial"],
        s["energy_final"]
    )
}
