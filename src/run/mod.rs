//! Scenes run, for every geometry alike: the problem a scene poses ([`GeometrySpec::problem`],
//! built in the geometry's own folder), stepped by the one driver ([`crate::driver`]) with the
//! one set of observers ([`crate::observe`]). Nothing here names a geometry; nothing here does
//! I/O but the run folder of `massredist run` ([`run_scene_into`]), which streams into the
//! folder prepared before computing, through [`crate::output`].

use crate::driver::{DivergenceCriterion, Observer, integrate_watched};
use crate::fem::frames::FrameWriter;
use crate::observe::{Frame, FrameRecorder, SeriesRecorder, Summary, SummaryObserver};
use crate::output::{OutputDir, OutputError, SeriesWriter, commit_run};
use crate::problem::{Geometry, Problem};
use crate::scene::{AnyScene, Registered, Scene, SceneError};
use crate::schemes::{Scheme, SchemeError};
pub use crate::spec::{GeometrySpec, Totals};
use serde::Serialize;
use thiserror::Error;

/// A scene's problem with its scheme built (matrices assembled and factored), not yet stepped:
/// what `check` runs, so that a scene it accepts starts its run.
pub struct Setup<G: Geometry> {
    pub problem: Problem<G>,
    pub scheme: Box<dyn Scheme>,
}

/// Why a run failed: the scene cannot be set up (the input is at fault: exit code 2), the
/// scheme failed while stepping, or the output folder could not be written (exit code 1). A
/// divergence is not an error (it is in the [`Summary`]).
#[derive(Debug, Error)]
pub enum RunError {
    #[error(transparent)]
    Setup(SceneError),
    #[error(transparent)]
    Scheme(#[from] SchemeError),
    /// A problem built outside a scene (library users, `reproduce`) failed.
    #[error(transparent)]
    Problem(Box<dyn std::error::Error + Send + Sync>),
    #[error(transparent)]
    Output(#[from] OutputError),
}

impl RunError {
    /// Whether the input is at fault (the scene cannot be set up), rather than the computation.
    pub fn invalid_input(&self) -> bool {
        matches!(self, RunError::Setup(_))
    }

    /// A geometry's problem error.
    pub fn problem(e: impl std::error::Error + Send + Sync + 'static) -> Self {
        RunError::Problem(Box::new(e))
    }
}

/// The problem and scheme of a scene; a failure names the keys that shape the matrices.
pub fn setup<G: GeometrySpec + Registered>(scene: &Scene<G>) -> Result<Setup<G::System>, SceneError> {
    let error = |e: &dyn std::fmt::Display| SceneError::Setup { keys: G::SETUP_KEYS.into(), reason: e.to_string() };
    let problem = G::problem(scene).map_err(|e| error(&e))?;
    let scheme = problem.scheme_with(&scene.scheme, &scene.contact, scene.time.dt).map_err(|e| error(&e))?;
    Ok(Setup { problem, scheme })
}

/// Sets a scene up as `run` does (assembly, exact solution, factorisation), so a scene `check`
/// accepts starts its run, and times that set-up and the first few steps ([`Estimate`], with
/// the scheme's note: the stable limit of central differences).
pub fn check(scene: &AnyScene) -> Result<Estimate, SceneError> {
    crate::with_scene!(scene, s => estimate(s))
}

/// What `check` measured of a scene: the set-up's wall time, and the mean wall time of its
/// first steps (up to [`Estimate::PROBE_STEPS`] of them or [`Estimate::PROBE_SECONDS`]),
/// stepped with the run's summary (the exact L² error at every step where the scene asks for
/// it), from which [`Estimate::run_seconds`] extrapolates the run. What it covers is said with
/// it (issue 32, E14): a contact that starts after the probe (an impact) costs more per step
/// and is not in it ([`Estimate::touched`]); output (series, VTU) is not included.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    pub unknowns: usize,
    pub steps: usize,
    pub setup_seconds: f64,
    /// The mean step time over `probe_steps` (None if no step could be taken: the scheme
    /// failed at once).
    pub step_seconds: Option<f64>,
    pub probe_steps: usize,
    /// The scheme's note (the stable limit of central differences), if any.
    pub note: Option<String>,
    /// Whether a contact node touched during the probe (if not, steps in contact are not in
    /// the estimate).
    pub touched: bool,
    /// Whether the probe evaluated the exact L² error at each step, as the run's summary does.
    pub exact_error: bool,
}

impl Estimate {
    pub const PROBE_STEPS: usize = 16;
    pub const PROBE_SECONDS: f64 = 0.5;

    /// Set-up plus `steps` times the mean step.
    pub fn run_seconds(&self) -> Option<f64> {
        self.step_seconds.map(|s| self.setup_seconds + s * self.steps as f64)
    }
}

fn estimate<G: GeometrySpec + Registered>(scene: &Scene<G>) -> Result<Estimate, SceneError> {
    let start = std::time::Instant::now();
    let Setup { problem, mut scheme } = setup(scene)?;
    let setup_seconds = start.elapsed().as_secs_f64();
    let unknowns = G::totals(&problem.system).unknowns;
    let note = scheme.note();
    let (time, output) = (&scene.time, &scene.output);
    let mut summary = SummaryObserver::new(&problem, time.steps, time.dt, output.summary_l2);
    let exact_error = summary.needs().l2;
    let mut probe = Probe { started: std::time::Instant::now(), shown: 0, touched: false };
    let criterion = DivergenceCriterion { energy_factor: output.divergence_factor };
    let steps = Estimate::PROBE_STEPS.min(time.steps);
    // A scheme error or a divergence ends the probe: the steps shown before it are timed. A
    // factor refused when the run starts is a set-up failure, as in the run ([`set_up`]).
    let probed = integrate_watched(&problem, scheme.as_mut(), steps, &criterion, &mut [&mut summary, &mut probe]);
    if let Err(RunError::Setup(e)) = probed.map_err(set_up::<G>) {
        return Err(e);
    }
    let taken = probe.shown.saturating_sub(1);
    let step_seconds = (taken > 0).then(|| probe.started.elapsed().as_secs_f64() / taken as f64);
    let touched = probe.touched;
    Ok(Estimate {
        unknowns,
        steps: time.steps,
        setup_seconds,
        step_seconds,
        probe_steps: taken,
        note,
        touched,
        exact_error,
    })
}

/// `check`'s probe: counts the states shown (t_0 included), notes a contact, and halts the run
/// after [`Estimate::PROBE_SECONDS`].
struct Probe {
    started: std::time::Instant,
    shown: usize,
    touched: bool,
}

impl Observer for Probe {
    fn observe(&mut self, s: &crate::driver::Sample) {
        self.shown += 1;
        self.touched |= s.contact.touching;
    }

    fn halted(&self) -> bool {
        self.started.elapsed().as_secs_f64() >= Estimate::PROBE_SECONDS
    }
}

/// Runs a problem with its scheme, its summary and `observers` (series, frames, progress)
/// until `time.end` or a divergence (which is a result: it reaches the summary through
/// [`Observer::diverged`]).
fn run_observed<G: GeometrySpec + Registered>(
    scene: &Scene<G>,
    problem: &Problem<G::System>,
    scheme: &mut dyn Scheme,
    observers: &mut [&mut dyn Observer],
) -> Result<Summary, RunError> {
    let (time, output) = (&scene.time, &scene.output);
    let mut summary = SummaryObserver::new(problem, time.steps, time.dt, output.summary_l2);
    let mut all: Vec<&mut dyn Observer> = vec![&mut summary];
    for o in observers.iter_mut() {
        all.push(&mut **o);
    }
    let criterion = DivergenceCriterion { energy_factor: output.divergence_factor };
    let _ = integrate_watched(problem, scheme, time.steps, &criterion, &mut all).map_err(set_up::<G>)?;
    let mut summary = summary.finish();
    if let Some((limit, estimator)) = scheme.stable_limit() {
        (summary.stable_step, summary.stable_step_method) = (Some(limit), Some(estimator));
    }
    Ok(summary)
}

/// A factorisation that fails when the run starts (the divergence watch's `S_rr` or `M_mm`
/// refused by the memory limit) is a set-up failure naming the keys, as the scheme's own
/// factors are ([`setup`]); every other scheme error is the run's.
fn set_up<G: GeometrySpec>(e: SchemeError) -> RunError {
    match e {
        SchemeError::Linalg(l) => {
            RunError::Setup(SceneError::Setup { keys: G::SETUP_KEYS.into(), reason: l.to_string() })
        }
        other => RunError::Scheme(other),
    }
}

/// Everything a run of a scene produces, held in memory (the problem is kept for the VTU
/// writers and for reports).
#[derive(Debug)]
pub struct SceneRun<G: Geometry> {
    pub problem: Problem<G>,
    pub summary: Summary,
    pub series: SeriesRecorder,
    /// The states every `output.vtu_every` steps (None without VTU output).
    pub frames: Option<FrameRecorder>,
    /// The scheme's state when the run stopped, at the mesh nodes
    /// ([`crate::problem::GeometryView::nodal_values`]): the last state shown, or for a run that
    /// diverged on a non-finite state, that state.
    pub last: Frame,
}

/// Runs a scene: the summary always, plus the requested series and frames, held in memory (for
/// library users; `massredist run` streams them: [`run_scene_into`]), and `extra` observers. A
/// run that diverges (the driver's [`DivergenceCriterion`] with `output.divergence_factor`)
/// stops there and is still a result: `Summary::divergence` says where and why, the summary
/// and series hold the finite states.
pub fn run_scene<G: GeometrySpec + Registered>(
    scene: &Scene<G>,
    extra: &mut [&mut dyn Observer],
) -> Result<SceneRun<G::System>, RunError> {
    let Setup { problem, mut scheme } = setup(scene).map_err(RunError::Setup)?;
    let output = &scene.output;
    let rows = if output.series.is_empty() { 0 } else { scene.time.steps / output.every + 1 };
    let mut series = SeriesRecorder::new(output.series.clone(), output.every, rows);
    let mut frames = output.vtu_every.map(FrameRecorder::new);
    let mut observers: Vec<&mut dyn Observer> = vec![&mut series];
    if let Some(f) = frames.as_mut() {
        observers.push(f);
    }
    for o in extra.iter_mut() {
        observers.push(&mut **o);
    }
    let summary = run_observed(scene, &problem, scheme.as_mut(), &mut observers)?;
    drop(observers);
    let last = last_frame(&problem.system, scheme.as_ref());
    Ok(SceneRun { problem, summary, series, frames, last })
}

/// The scheme's current state at the mesh nodes.
fn last_frame<G: Geometry>(geometry: &G, scheme: &dyn Scheme) -> Frame {
    let state = scheme.state();
    let n = geometry.n_nodes() * geometry.components();
    let (mut u, mut v) = (vec![0.0; n], vec![0.0; n]);
    geometry.nodal_values(state.u, &mut u);
    geometry.nodal_values(state.v, &mut v);
    Frame { t: state.t, u, v, lambda: state.lambda.to_vec(), friction: scheme.friction().cloned() }
}

/// `massredist run`: runs a scene into the output folder `out` prepared before computing,
/// `series.csv` and the VTU frames (`vtu/frame_NNNNN.vtu`, `<collection>.pvd`) streamed into its
/// temporary folder as the run produces them (memory does not depend on the number of steps; a
/// write error such as a full disk halts the run at that step and fails it), then
/// `summary.json` and `scene.resolved.toml`, and commits it ([`OutputDir::commit`]). On an
/// error `out` is dropped, which removes the temporary folder and leaves the target as it was.
pub fn run_scene_into<G: GeometrySpec + Registered>(
    scene: &Scene<G>,
    out: OutputDir,
    extra: &mut [&mut dyn Observer],
) -> Result<Summary, RunError> {
    let Setup { problem, mut scheme } = setup(scene).map_err(RunError::Setup)?;
    let output = &scene.output;
    let fill = |e| out.fill_error(e);
    let mut series = match output.series.is_empty() {
        true => None,
        false => Some(SeriesWriter::create(out.staging(), output.series.clone(), output.every).map_err(fill)?),
    };
    let vtu = G::frames(&problem.system);
    let mut frames = match (output.vtu_every, vtu) {
        (Some(every), Some(g)) => Some(FrameWriter::create(out.staging(), g, every).map_err(fill)?),
        _ => None,
    };
    let mut observers: Vec<&mut dyn Observer> = Vec::with_capacity(extra.len() + 2);
    for o in extra.iter_mut() {
        observers.push(&mut **o);
    }
    if let Some(f) = frames.as_mut() {
        observers.push(f);
    }
    if let Some(s) = series.as_mut() {
        observers.push(s);
    }
    let summary = run_observed(scene, &problem, scheme.as_mut(), &mut observers)?;
    drop(observers);
    if let Some(s) = series {
        s.finish().map_err(fill)?;
    }
    if let Some(f) = frames {
        f.finish().map_err(fill)?;
    }
    commit_run(out, &summary_json(scene, &problem, &summary), &scene.resolved_toml())?;
    Ok(summary)
}

/// The `summary.json` of a run: the scene's identity, the geometry's keys
/// ([`GeometrySpec::summary_head`]) and the [`Summary`].
#[derive(Serialize)]
struct SummaryFile<'a, H: Serialize> {
    scheme: &'static str,
    mass: &'static str,
    /// Cells along x (the bar's `elements`).
    elements: usize,
    length: f64,
    end: f64,
    #[serde(flatten)]
    head: H,
    #[serde(flatten)]
    summary: &'a Summary,
}

/// `summary.json` text of a run of `problem`.
pub fn summary_json<G: GeometrySpec + Registered>(
    scene: &Scene<G>,
    problem: &Problem<G::System>,
    summary: &Summary,
) -> String {
    summary_json_of(scene, &G::totals(&problem.system), summary)
}

/// `summary.json` text from the totals of the system that ran (the engine's own).
pub fn summary_json_of<G: GeometrySpec + Registered>(scene: &Scene<G>, totals: &Totals, summary: &Summary) -> String {
    let file = SummaryFile {
        scheme: scene.scheme.name(),
        mass: scene.mass.name(),
        elements: scene.geometry.elements(),
        length: scene.geometry.length(),
        end: scene.time.end,
        head: G::summary_head(scene, totals),
        summary,
    };
    serde_json::to_string_pretty(&file).expect("summary serialises") + "\n"
}
