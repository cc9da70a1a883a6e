//! The FEniCSx engine as a process: `massredist run SCENE --engine fenicsx --ranks N --out DIR`
//! for plate and solid scenes (issue 12). The engine streams, Rust observes.
//!
//! The scene is validated exactly as for a Rust run (`crate::scene::AnyScene::from_file`: keys,
//! mesh, cell weights, schemes), what the engine cannot run is refused ([`document`]), the
//! resolved scene with every value written out is written as JSON into the output folder's
//! temporary sibling ([`document::EngineScene`]), and
//!
//! ```text
//! mpirun -n N /usr/bin/python3 python/fenicsx_engine.py DIR.tmp/scene.engine.json DIR.tmp
//! ```
//!
//! steps it with dolfinx and PETSc (python/engine/: its own mesh, the weighted mass as a DG0
//! weight field, each implicit step a bound-constrained QP solved by SNES `vinewtonrsls`, its own
//! exact solution and L² error). Rank 0 streams every state's diagnostics ([`stream`]: energy,
//! u0, means, contact force and pressure, L² error, y-variation, contact extremes, solver
//! iterations) to this process, whose observers write `series.csv` and `summary.json` exactly as
//! for a Rust run ([`crate::observe::SummaryObserver`], [`crate::output::SeriesWriter`], the
//! geometry's own `summary_json`) and whose divergence rule ([`DivergenceWatch`]) answers each
//! state with `go` or `stop`. The engine itself writes `engine.json` (ranks, solver, tolerances,
//! timings, complementarity record) and `fields.xdmf`/`.h5` (displacement and velocity, a time
//! series at `output.vtu_every`, else the last state) into the temporary folder; this module then
//! commits it like every run folder ([`crate::output::commit_run`]: the marker, the rename).
//! Exit status of the engine: 0 ok, 3 stopped (diverged; folder written), 2 an input it cannot
//! run, anything else a failure; it must agree with what the stream said.
//!
//! Nothing here needs the `python` feature: the engine is a separate process. The programs can be
//! replaced through the environment: `MASSREDIST_MPIRUN` (default `mpirun`; e.g. a cluster's
//! launcher), `MASSREDIST_PYTHON` (default `/usr/bin/python3`, Debian's, which sees dolfinx) and
//! `MASSREDIST_ENGINE` (the entry point, default `python/fenicsx_engine.py` of this source tree).

pub mod body;
pub mod document;
pub mod stream;

use crate::driver::{DivergenceCriterion, DivergenceWatch, Observer};
use crate::exact::Exact;
use crate::observe::{Summary, SummaryObserver};
use crate::output::{OutputDir, SeriesWriter, commit_run};
use crate::scene::{PlateSpec, Scene};
use crate::solid::SolidSpec;
use std::path::{Path, PathBuf};
use std::process::Command;
use stream::{Head, Message, StreamedGeometry};
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
    #[error("the fenicsx engine ({ranks} ranks) failed ({status})")]
    Failed { ranks: usize, status: String },
    #[error("writing the run folder: {0}")]
    Output(std::io::Error),
    /// The engine's stream broke the protocol ([`stream`]).
    #[error("the fenicsx engine's stream: {0}")]
    Protocol(String),
    /// The engine ended before its first record (the launcher, or the engine's set-up, failed).
    #[error("the fenicsx engine ended before its first record")]
    Ended,
    /// The launcher cannot start that many processes here.
    #[error(
        "--ranks {ranks}: `{launcher} -n {ranks}` cannot start {ranks} processes here (not enough slots; this machine has {processors} processor(s), and Open MPI gives one slot per core unless a hostfile or the scheduler grants more); choose --ranks {processors} or fewer"
    )]
    Ranks { ranks: usize, launcher: String, processors: usize },
}

impl EngineError {
    /// True when nothing was computed: an invalid scene or a missing dependency (exit code 2 of
    /// `massredist run`), as opposed to a failure while computing or writing (exit code 1).
    pub fn is_invalid(&self) -> bool {
        matches!(self, EngineError::Scene(_) | EngineError::Missing { .. } | EngineError::Ranks { .. })
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
pub trait EngineGeometry: crate::run::GeometrySpec + crate::scene::Registered {
    /// Why the engine cannot run this geometry (None if it can).
    fn engine_refusal(&self) -> Option<String>;
    /// The geometry as the engine reads it ([`document`]), or why the engine cannot run it.
    fn document(&self) -> Result<document::GeometryDoc, String>;
    /// The exact solution up to `t_end` that a Rust run of this scene compares with (None if
    /// none is known); the error names the scene's data.
    fn exact(&self, t_end: f64) -> Result<Option<Exact>, String>;
    /// The measures the observers read, with the engine's own mesh size.
    fn streamed(&self, head: &Head) -> StreamedGeometry;
    /// Data the engine reads besides the scene (`body.json` of a body, [`body`]), and the
    /// measures `[|Γ_C|, L, h]` the observers then read; None for the other geometries.
    fn engine_data(&self, _mass: &crate::mass::MassKind, _t_end: f64) -> Result<Option<(String, [f64; 3])>, String> {
        Ok(None)
    }
}

impl EngineGeometry for PlateSpec {
    fn engine_refusal(&self) -> Option<String> {
        self.mesh_file.as_ref().map(|_| "plate.mesh: the fenicsx engine runs structured plates only (for now)".into())
    }

    fn document(&self) -> Result<document::GeometryDoc, String> {
        document::plate(self)
    }

    fn exact(&self, t_end: f64) -> Result<Option<Exact>, String> {
        PlateSpec::exact(self, t_end).map_err(|e| e.to_string())
    }

    fn streamed(&self, head: &Head) -> StreamedGeometry {
        StreamedGeometry {
            name: "plate",
            dim: 2,
            h: head.h,
            length: self.length,
            section: self.height,
            integrates: true,
            is_body: false,
            tangential: false,
            body: None,
        }
    }
}

/// Solids: structured boxes of every cell kind (a box from a `solid.mesh` file not yet), and
/// bodies against an axis plane ([`body`]).
impl EngineGeometry for SolidSpec {
    fn engine_refusal(&self) -> Option<String> {
        if self.support.bodies().is_some() {
            return Some(
                "[[solid]]: the fenicsx engine runs one body (several bodies in contact run on the native engine)"
                    .into(),
            );
        }
        if self.support.body().is_some() {
            return body::refusal(self);
        }
        let structured = matches!(self.source, crate::solid::MeshSource::Box);
        (!structured).then(|| "solid.mesh: the fenicsx engine runs structured solids only (for now)".into())
    }

    fn document(&self) -> Result<document::GeometryDoc, String> {
        Ok(document::solid(self))
    }

    fn exact(&self, t_end: f64) -> Result<Option<Exact>, String> {
        SolidSpec::exact(self, t_end).map_err(|e| e.to_string())
    }

    /// The exact L² error on structured tensor cells (quad, hex) only, as
    /// `crate::solid::geometry`'s `integrates`.
    fn streamed(&self, head: &Head) -> StreamedGeometry {
        let [l, h, d] = self.extent;
        StreamedGeometry {
            name: "solid",
            dim: self.dim,
            h: head.h,
            length: l,
            section: if self.dim == 3 { h * d } else { h },
            integrates: self.cells.is_tensor(),
            is_body: self.support.body().is_some(),
            tangential: true,
            body: None,
        }
    }

    fn engine_data(&self, mass: &crate::mass::MassKind, t_end: f64) -> Result<Option<(String, [f64; 3])>, String> {
        body::data(self, mass, t_end)
    }
}

/// What the engine cannot run (the refusals of [`document::document`], each naming its key).
pub fn validate<G: EngineGeometry>(scene: &Scene<G>) -> Result<(), EngineError> {
    document::document(scene).map(drop)
}

/// Runs `scene` with the engine on `ranks` MPI ranks and writes the run folder `out` (module
/// docs), prepared before anything is computed ([`OutputDir::prepare`]): the engine streams its
/// states ([`stream`]); this process's observers write `series.csv` and `summary.json` as for a
/// Rust run and its divergence rule stops the engine; then the folder is committed.
pub fn run<G: EngineGeometry>(scene: &Scene<G>, out: OutputDir, ranks: usize) -> Result<EngineOutcome, EngineError> {
    let doc = document::document(scene)?;
    let exact = scene.geometry.exact(scene.time.exact_end()).map_err(EngineError::Scene)?;
    check_available()?;
    let staging = out.staging().to_path_buf();
    let scene_file = staging.join(document::FILE);
    std::fs::write(&scene_file, document::to_json(&doc)).map_err(EngineError::Output)?;
    let data = scene.geometry.engine_data(&scene.mass, scene.time.end).map_err(EngineError::Scene)?;
    if let Some((json, _)) = &data {
        std::fs::write(staging.join("body.json"), json).map_err(EngineError::Output)?;
    }
    let mut child = Engine::start(ranks, &scene_file, &staging)?;
    let consumed = consume(scene, exact.as_ref(), data.map(|d| d.1), &staging, &mut child);
    let status = child.finish()?;
    if let (Err(EngineError::Ended), false) = (&consumed, status.success()) {
        return Err(too_many_ranks(ranks).unwrap_or(EngineError::Failed { ranks, status: status.to_string() }));
    }
    let (head, summary) = consumed?;
    let diverged = summary.divergence.is_some();
    match (status.code(), diverged) {
        (Some(0), false) | (Some(3), true) => {}
        _ => return Err(EngineError::Failed { ranks, status: status.to_string() }),
    }
    // `summary.json`: the keys of the Rust run (the same code), with the engine's own totals.
    let totals = crate::run::Totals { total_mass: head.total_mass, unknowns: head.unknowns };
    let json = crate::run::summary_json_of(scene, &totals, &summary);
    commit_run(out, &json, &scene.resolved_toml()).map_err(|e| EngineError::Output(std::io::Error::other(e)))?;
    Ok(if diverged { EngineOutcome::Diverged } else { EngineOutcome::Completed })
}

/// Reads the engine's records until it ends, shows them to the summary and the series writer,
/// replies to each state ([`stream::Reply`]); returns the head and the summary. A state after
/// a reply other than `go` breaks the protocol.
fn consume<G: EngineGeometry>(
    scene: &Scene<G>,
    exact: Option<&Exact>,
    body: Option<[f64; 3]>,
    staging: &Path,
    child: &mut Engine,
) -> Result<(Head, Summary), EngineError> {
    let broken = |e: String| EngineError::Protocol(e);
    let head = match child.next()? {
        Some(Message::Head(h)) => h,
        Some(other) => return Err(broken(format!("the engine's first record is {other:?}, not its head"))),
        // The engine ended before its problem was set up (its message is on stderr).
        None => return Err(EngineError::Ended),
    };
    let mut geometry = scene.geometry.streamed(&head);
    // A body: its contact area, extent and mesh size as the Rust run reads them.
    if let Some([section, length, h]) = body {
        (geometry.section, geometry.length, geometry.h) = (section, length, h);
    }
    let o = &scene.output;
    let mut summary = SummaryObserver::of_view(&geometry, exact, scene.time.steps, scene.time.dt, o.summary_l2);
    let mut series = match o.series.is_empty() {
        true => None,
        false => Some(SeriesWriter::create(staging, o.series.clone(), o.every).map_err(EngineError::Output)?),
    };
    let watch = DivergenceWatch::new(&DivergenceCriterion { energy_factor: o.divergence_factor }, head.load_energy);
    let mut all: Vec<&mut dyn Observer> = vec![&mut summary];
    if let Some(s) = series.as_mut() {
        all.push(s);
    }
    let mut observed = stream::Observed::new(&mut all, watch, &geometry, exact);
    let mut stopped: Option<usize> = None;
    loop {
        match (child.next()?, stopped) {
            (Some(Message::Sample(r)), Some(at)) => {
                return Err(broken(format!("the engine sent state {} after it was told to stop at state {at}", r.n)));
            }
            (Some(Message::Sample(r)), None) => {
                let reply = observed.show(&r);
                child.reply(reply);
                stopped = (reply != stream::Reply::Go).then_some(r.n);
            }
            (Some(Message::NonFinite { n, t }), _) => observed.non_finite(n, t),
            (Some(Message::Head(_)), _) => return Err(broken("a second head record".into())),
            (None, _) => break,
        }
    }
    observed.finish();
    if let Some(s) = series {
        s.finish().map_err(EngineError::Output)?;
    }
    Ok((head, summary.finish()))
}

/// `mpirun -n RANKS` with the environment every engine launch gets.
fn launcher(ranks: usize) -> Command {
    let mut cmd = Command::new(program("MASSREDIST_MPIRUN", "mpirun"));
    cmd.arg("-n").arg(ranks.to_string());
    // Ranks that wait in a collective yield the core (this machine, and any oversubscribed
    // one, has fewer cores than busy processes); a cluster sets its own MCA parameters.
    if std::env::var_os("OMPI_MCA_mpi_yield_when_idle").is_none() {
        cmd.env("OMPI_MCA_mpi_yield_when_idle", "1");
    }
    if running_as_root() {
        cmd.env("OMPI_ALLOW_RUN_AS_ROOT", "1").env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    }
    cmd
}

/// After an engine that ended before its first record: whether the launcher refuses `ranks`
/// processes for want of slots (probed with `true` in their place; Open MPI says "not enough
/// slots"). Costs nothing on a run that starts.
fn too_many_ranks(ranks: usize) -> Option<EngineError> {
    let probe = launcher(ranks).arg("true").stdin(std::process::Stdio::null()).output().ok()?;
    let said = String::from_utf8_lossy(&probe.stderr).to_lowercase() + &String::from_utf8_lossy(&probe.stdout);
    (!probe.status.success() && said.contains("slots")).then(|| EngineError::Ranks {
        ranks,
        launcher: program("MASSREDIST_MPIRUN", "mpirun"),
        processors: std::thread::available_parallelism().map_or(1, |n| n.get()),
    })
}

/// The engine's process: `mpirun -n N python fenicsx_engine.py SCENE DIR` with its standard
/// output read line by line ([`stream::parse`]) and its standard input for the replies.
struct Engine {
    child: std::process::Child,
    /// The engine's process group, to which massredist forwards SIGTERM, SIGINT and SIGHUP.
    _group: crate::output::ChildGroup,
    lines: std::io::Lines<std::io::BufReader<std::process::ChildStdout>>,
    replies: Option<std::process::ChildStdin>,
}

impl Engine {
    fn start(ranks: usize, scene_file: &Path, dir: &Path) -> Result<Engine, EngineError> {
        use std::io::BufRead;
        let mut cmd = launcher(ranks);
        cmd.arg(program("MASSREDIST_PYTHON", "/usr/bin/python3"));
        cmd.arg(entry_point()).arg(scene_file).arg(dir);
        cmd.stdin(std::process::Stdio::piped()).stdout(std::process::Stdio::piped());
        // Its own process group, so that a signal to massredist reaches mpirun and its ranks
        // through the signal thread (src/output/staging.rs), which then removes the folder.
        std::os::unix::process::CommandExt::process_group(&mut cmd, 0);
        let mut child = cmd.spawn().map_err(EngineError::Output)?;
        let _group = crate::output::ChildGroup::register(child.id());
        let stdout = child.stdout.take().expect("stdout is piped");
        let replies = child.stdin.take();
        Ok(Engine { child, _group, lines: std::io::BufReader::new(stdout).lines(), replies })
    }

    /// The next record (None at the end of the engine's output); other lines go to stderr.
    fn next(&mut self) -> Result<Option<Message>, EngineError> {
        for line in self.lines.by_ref() {
            let line = line.map_err(EngineError::Output)?;
            match stream::parse(&line) {
                Some(m) => return m.map(Some).map_err(EngineError::Protocol),
                None => eprintln!("{line}"),
            }
        }
        Ok(None)
    }

    /// The reply to a state (the engine waits for it after each one).
    fn reply(&mut self, reply: stream::Reply) {
        use std::io::Write;
        let Some(w) = self.replies.as_mut() else { return };
        // A closed pipe: the engine has ended (its status says how).
        if w.write_all(reply.line()).and_then(|()| w.flush()).is_err() {
            self.replies = None;
        }
    }

    /// Closes the replies and waits for the engine's end (draining what it still prints).
    fn finish(mut self) -> Result<std::process::ExitStatus, EngineError> {
        self.replies = None;
        while let Some(line) = self.lines.next() {
            match line {
                Ok(l) if stream::parse(&l).is_none() => eprintln!("{l}"),
                _ => {}
            }
        }
        self.child.wait().map_err(EngineError::Output)
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
