//! Scenes run: the problem a scene poses, built for its geometry, stepped by the one driver
//! ([`crate::driver`]) with the one set of observers ([`crate::observe`]). One file per geometry
//! (as the schemes have one file per method). Nothing here does I/O but the run folders of
//! `massredist run` ([`run_scene_into`], [`plate::run_plate_scene_into`]), which stream into the
//! folder prepared before computing, through [`crate::output`].

pub mod bar;
pub mod plate;
pub mod solid;

pub use bar::*;

/// A scene's problem with its scheme built (matrices assembled and factored), not yet stepped:
/// what `check` runs, so that a scene it accepts starts its run.
pub struct Setup<G: crate::problem::Geometry = crate::bar::assembly::BarSystem> {
    pub problem: Problem<G>,
    pub scheme: Box<dyn crate::schemes::Scheme>,
}

/// A setup failure as a scene error naming `keys`.
pub(crate) fn setup_error(keys: &str, e: impl std::fmt::Display) -> crate::scene::SceneError {
    crate::scene::SceneError::Setup { keys: keys.to_string(), reason: e.to_string() }
}

/// A run's failure, and whether the input is at fault (the scene cannot be set up: exit code 2)
/// rather than the computation (exit code 1).
pub trait RunFailure: std::error::Error {
    fn invalid_input(&self) -> bool;
}

impl RunFailure for RunError {
    fn invalid_input(&self) -> bool {
        matches!(self, RunError::Setup(_))
    }
}

impl RunFailure for plate::PlateRunError {
    fn invalid_input(&self) -> bool {
        matches!(self, plate::PlateRunError::Setup(_))
    }
}

impl RunFailure for solid::SolidRunError {
    fn invalid_input(&self) -> bool {
        matches!(self, solid::SolidRunError::Setup(_))
    }
}

/// Sets a scene up as `run` does (assembly, exact solution, factorisation) without stepping:
/// `check` calls it, so a scene `check` accepts starts its run.
pub fn check(scene: &crate::scene::AnyScene) -> Result<(), crate::scene::SceneError> {
    match scene {
        crate::scene::AnyScene::Bar(s) => bar::setup(s).map(|_| ()),
        crate::scene::AnyScene::Plate(s) => plate::setup(s).map(|_| ()),
        crate::scene::AnyScene::Solid(s) => solid::setup(s).map(|_| ()),
    }
}

use crate::fem::frames::{FrameWriter, VtuFrames};
use crate::output::{OutputDir, OutputError, SeriesWriter, commit_run};
use crate::problem::Geometry;
use crate::scene::{OutputSpec, SceneGeometry, TimeSpec};
use crate::schemes::{Scheme, SchemeError};

/// Why a run into an output folder failed: computing (`Run`, the geometry's error), or writing
/// (`Output`). Either way the temporary folder is removed and the target left as it was.
#[derive(Debug, thiserror::Error)]
pub enum RunFolderError<E: std::error::Error> {
    #[error(transparent)]
    Run(E),
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// The part of a run into a folder every geometry shares: `series.csv` (if any column) streamed
/// into `out`'s temporary folder by a [`SeriesWriter`] while `run` steps with it and `extra` as
/// observers; a write error (disk full) halts the run at that step and fails it.
fn stream_series<E: std::error::Error>(
    out: &OutputDir,
    spec: &OutputSpec,
    extra: &mut [&mut dyn Observer],
    run: impl FnOnce(&mut [&mut dyn Observer]) -> Result<Summary, E>,
) -> Result<Summary, RunFolderError<E>> {
    let mut series = match spec.series.is_empty() {
        true => None,
        false => {
            Some(SeriesWriter::create(out.staging(), spec.series.clone(), spec.every).map_err(|e| out.fill_error(e))?)
        }
    };
    let mut observers: Vec<&mut dyn Observer> = Vec::with_capacity(extra.len() + 1);
    for o in extra.iter_mut() {
        observers.push(&mut **o);
    }
    if let Some(s) = series.as_mut() {
        observers.push(s);
    }
    let summary = run(&mut observers).map_err(RunFolderError::Run)?;
    if let Some(s) = series {
        s.finish().map_err(|e| out.fill_error(e))?;
    }
    Ok(summary)
}

/// Runs a problem with its scheme, its summary and `observers` (series, frames, progress)
/// until `time.end` or a divergence (which is a result: it reaches the summary through
/// [`Observer::diverged`]).
pub(crate) fn run_observed<G: Geometry>(
    problem: &Problem<G>,
    mut scheme: Box<dyn Scheme>,
    time: &TimeSpec,
    output: &OutputSpec,
    observers: &mut [&mut dyn Observer],
) -> Result<Summary, SchemeError> {
    let mut summary = SummaryObserver::new(problem, time.steps, time.dt, output.summary_l2);
    let mut all: Vec<&mut dyn Observer> = vec![&mut summary];
    for o in observers.iter_mut() {
        all.push(&mut **o);
    }
    let criterion = DivergenceCriterion { energy_factor: output.divergence_factor };
    let _ = integrate_watched(problem, scheme.as_mut(), time.steps, &criterion, &mut all)?;
    Ok(summary.finish())
}

/// Everything a run of a plate or solid scene produces, held in memory (the problem is kept for
/// the VTU writers).
#[derive(Debug)]
pub struct MeshRun<G: Geometry> {
    pub problem: Problem<G>,
    pub summary: Summary,
    pub series: crate::observe::SeriesRecorder,
    pub frames: Option<crate::observe::FrameRecorder>,
}

/// Runs a set-up scene with the requested series and VTU frames recorded in memory, and
/// `extra` observers (for library users; `massredist run` streams: [`run_frames_into`]). A run
/// that diverges stops there and is still a result.
pub(crate) fn run_in_memory<G: Geometry, S: SceneGeometry>(
    scene: &crate::scene::Scene<S>,
    setup: Setup<G>,
    extra: &mut [&mut dyn Observer],
) -> Result<MeshRun<G>, SchemeError> {
    let Setup { problem, scheme } = setup;
    let mut series = crate::observe::SeriesRecorder::new(scene.output.series.clone(), scene.output.every, 0);
    let mut frames = scene.output.vtu_every.map(crate::observe::FrameRecorder::new);
    let mut observers: Vec<&mut dyn Observer> = vec![&mut series];
    if let Some(f) = frames.as_mut() {
        observers.push(f);
    }
    for o in extra.iter_mut() {
        observers.push(&mut **o);
    }
    let summary = run_observed(&problem, scheme, &scene.time, &scene.output, &mut observers)?;
    Ok(MeshRun { problem, summary, series, frames })
}

/// `massredist run` for a geometry with VTU frames (plates, solids): `series.csv` and the
/// frames streamed into `out`'s temporary folder while the set-up problem steps, then
/// `summary.json` (from `summary_json`) and the resolved scene written and the folder
/// committed. Memory does not depend on the number of steps.
pub(crate) fn run_frames_into<G: Geometry + VtuFrames, S: SceneGeometry, E: std::error::Error>(
    scene: &crate::scene::Scene<S>,
    setup: Setup<G>,
    out: OutputDir,
    extra: &mut [&mut dyn Observer],
    summary_json: impl FnOnce(&Problem<G>, &Summary) -> String,
    error: impl Fn(SchemeError) -> E,
) -> Result<Summary, RunFolderError<E>> {
    let Setup { problem, scheme } = setup;
    let create = |k| FrameWriter::create(out.staging(), &problem.system, k).map_err(|e| out.fill_error(e));
    let mut frames = scene.output.vtu_every.map(create).transpose()?;
    let mut observers: Vec<&mut dyn Observer> = Vec::with_capacity(extra.len() + 1);
    for o in extra.iter_mut() {
        observers.push(&mut **o);
    }
    if let Some(f) = frames.as_mut() {
        observers.push(f);
    }
    let run =
        |obs: &mut [&mut dyn Observer]| run_observed(&problem, scheme, &scene.time, &scene.output, obs).map_err(&error);
    let summary = stream_series(&out, &scene.output, &mut observers, run)?;
    drop(observers);
    if let Some(f) = frames {
        f.finish().map_err(|e| out.fill_error(e))?;
    }
    commit_run(out, &summary_json(&problem, &summary), &scene.resolved_toml())?;
    Ok(summary)
}
