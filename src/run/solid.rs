//! Solid scenes: the problem of a `[solid]` scene ([`crate::solid::SolidSpec::problem`]) and its
//! run, by the same driver, observers and streaming run folder as plates
//! ([`super::run_frames_into`]). Nothing here does I/O but [`run_solid_scene_into`].

use super::{RunFolderError, Setup, setup_error};
use crate::driver::Observer;
use crate::observe::Summary;
use crate::output::OutputDir;
use crate::scene::{SceneError, SolidScene};
use crate::schemes::SchemeError;
use crate::solid::SolidSystem;
use crate::solid::spec::SolidError;
use serde::Serialize;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum SolidRunError {
    #[error(transparent)]
    Solid(#[from] SolidError),
    #[error(transparent)]
    Scheme(#[from] SchemeError),
    /// The scene's problem could not be set up (exit code 2: the input is at fault).
    #[error(transparent)]
    Setup(SceneError),
}

/// A solid problem.
pub type SolidProblem = crate::problem::Problem<SolidSystem>;

/// The problem and scheme of a solid scene; a failure names the keys that shape the matrices.
pub fn setup(scene: &SolidScene) -> Result<Setup<SolidSystem>, SceneError> {
    let keys = "solid.*, mass.*, scheme.*, time.dt";
    let problem = scene.geometry.problem(&scene.mass, scene.time.end).map_err(|e| setup_error(keys, e))?;
    let scheme = problem.scheme(&scene.scheme, scene.time.dt).map_err(|e| setup_error(keys, e))?;
    Ok(Setup { problem, scheme })
}

/// Everything a solid scene run produces (in memory; [`crate::solid::vtu::write_frames`] writes
/// its frames).
pub type SolidRun = super::MeshRun<SolidSystem>;

/// Runs a solid scene in memory (for library users; `massredist run` streams:
/// [`run_solid_scene_into`]). A run that diverges stops there and is still a result.
pub fn run_solid_scene(scene: &SolidScene, extra: &mut [&mut dyn Observer]) -> Result<SolidRun, SolidRunError> {
    let setup = setup(scene).map_err(SolidRunError::Setup)?;
    Ok(super::run_in_memory(scene, setup, extra)?)
}

/// `massredist run` for a solid scene: `series.csv`, the VTU frames (`vtu/frame_NNNNN.vtu`,
/// `solid.pvd`) streamed, then `summary.json` and `scene.resolved.toml`.
pub fn run_solid_scene_into(
    scene: &SolidScene,
    out: OutputDir,
    extra: &mut [&mut dyn Observer],
) -> Result<Summary, RunFolderError<SolidRunError>> {
    let setup = setup(scene).map_err(|e| RunFolderError::Run(SolidRunError::Setup(e)))?;
    let json = |problem: &SolidProblem, summary: &Summary| summary_json(scene, problem, summary);
    super::run_frames_into(scene, setup, out, extra, json, SolidRunError::Scheme)
}

#[derive(Serialize)]
struct SolidSummaryFile<'a> {
    scheme: &'a str,
    mass: &'a str,
    /// Cells along x (the bar's `elements`).
    elements: usize,
    length: f64,
    end: f64,
    dim: usize,
    height: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    depth: Option<f64>,
    nx: usize,
    ny: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    nz: Option<usize>,
    cells: &'a str,
    lateral: &'a str,
    lame_lambda: f64,
    lame_mu: f64,
    density: f64,
    gap: f64,
    initial: &'a str,
    /// `∫ ρ w_h` (per component).
    total_mass: f64,
    /// Unknowns (free components).
    unknowns: usize,
    #[serde(flatten)]
    summary: &'a Summary,
}

/// `summary.json` text: the plate keys and the solid's (module docs of [`crate::scene`]'s
/// `[solid]`), then the [`Summary`].
pub fn summary_json(scene: &SolidScene, problem: &SolidProblem, summary: &Summary) -> String {
    summary_json_of(scene, problem.system.total_mass(), problem.system.dofs.len(), summary)
}

/// [`summary_json`] with `∫ ρ w_h` and the unknowns given (an engine run's own).
pub fn summary_json_of(scene: &SolidScene, total_mass: f64, unknowns: usize, summary: &Summary) -> String {
    let s = &scene.geometry;
    let three = s.dim == 3;
    let file = SolidSummaryFile {
        scheme: scene.scheme.name(),
        mass: scene.mass.name(),
        elements: s.cells_per_axis[0],
        length: s.extent[0],
        end: scene.time.end,
        dim: s.dim,
        height: s.extent[1],
        depth: three.then_some(s.extent[2]),
        nx: s.cells_per_axis[0],
        ny: s.cells_per_axis[1],
        nz: three.then_some(s.cells_per_axis[2]),
        cells: s.cells.name(),
        lateral: s.lateral.name(),
        lame_lambda: s.lame.lambda,
        lame_mu: s.lame.mu,
        density: s.lame.density,
        gap: s.gap,
        initial: s.initial.name(),
        total_mass,
        unknowns,
        summary,
    };
    serde_json::to_string_pretty(&file).expect("summary serialises") + "\n"
}
