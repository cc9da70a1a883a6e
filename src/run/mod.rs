//! Scenes run: the problem a scene poses, built for its geometry, stepped by the one driver
//! ([`crate::driver`]) with the one set of observers ([`crate::observe`]). One file per geometry
//! (as the schemes have one file per method). Nothing here does I/O but the run folders of
//! `massredist run` ([`run_scene_into`], [`plate::run_plate_scene_into`]), which stream into the
//! folder prepared before computing, through [`crate::output`].

pub mod bar;
pub mod plate;

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

/// Sets a scene up as `run` does (assembly, exact solution, factorisation) without stepping:
/// `check` calls it, so a scene `check` accepts starts its run.
pub fn check(scene: &crate::scene::AnyScene) -> Result<(), crate::scene::SceneError> {
    match scene {
        crate::scene::AnyScene::Bar(s) => bar::setup(s).map(|_| ()),
        crate::scene::AnyScene::Plate(s) => plate::setup(s).map(|_| ()),
    }
}

use crate::output::{OutputDir, OutputError, SeriesWriter};
use crate::scene::OutputSpec;

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
