//! Plate scenes: the problem of a `[plate]` scene and its run (the driver is
//! [`crate::driver`], the observers [`crate::observe`]). Nothing here does I/O but
//! [`run_plate_scene_into`] (through [`crate::output`] and [`crate::plate::vtu`]).

use super::RunFolderError;
use crate::characteristics::{Characteristics, CharacteristicsError, InitialData};
use crate::driver::{DivergenceCriterion, Observer, integrate_watched};
use crate::exact::{Exact, ImpactingBar, by_characteristics, paper_data};
use crate::mass::MassKind;
use crate::observe::{FrameRecorder, SeriesRecorder, Summary, SummaryObserver};
use crate::output::{OutputDir, commit_run};
use crate::plate::assembly::{PlateAssemblyError, PlateLoad, PlateSystem};
use crate::plate::layers::cell_weights;
use crate::plate::mesh::{Mesh2d, MeshError};
use crate::plate::scene::{PlateInitial, PlateScene, PlateSpec};
use crate::plate::vtu::FrameWriter;
use crate::scene::{Body, Force};
use crate::schemes::SchemeError;
use serde::Serialize;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum PlateRunError {
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Assembly(#[from] PlateAssemblyError),
    #[error(transparent)]
    Scheme(#[from] SchemeError),
    #[error("the plane-wave exact solution of this scene: {0}")]
    Exact(CharacteristicsError),
    #[error("the 1D reference run failed: {0}")]
    Reference(String),
}

/// A plate problem.
pub type PlateProblem = crate::problem::Problem<PlateSystem>;

impl PlateProblem {
    /// The structured plate of `spec`.
    pub fn new(spec: &PlateSpec, mass: &MassKind) -> Result<Self, PlateRunError> {
        let mesh = Mesh2d::structured(spec.length, spec.height, spec.nx, spec.ny, spec.cells)?;
        Self::from_mesh(mesh, mass, &spec.initial, &spec.body)
    }

    /// Any mesh of (0, L) × (y_min, y_min + H) (e.g. a triangle mesh read from a file with
    /// [`Mesh2d::from_arrays`]); the initial data use `y − y_min`.
    pub fn from_mesh(
        mesh: Mesh2d,
        mass: &MassKind,
        initial: &PlateInitial,
        body: &Body,
    ) -> Result<Self, PlateRunError> {
        let (l, h) = (mesh.length, mesh.height);
        let ymin = mesh.points.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        let weights = cell_weights(&mesh, mass).map_err(PlateAssemblyError::from)?;
        let field;
        let load = match &body.force {
            Force::Constant(f) => PlateLoad::Constant(*f),
            Force::Field(e) => {
                field = move |x: f64, y: f64| e.eval(&[x, y - ymin]);
                PlateLoad::Field(&field)
            }
        };
        let plate = PlateSystem::assemble(mesh, weights, body.material, body.far_end, &load)?.with_gap(body.gap);
        let u0 = plate.interpolate(|x, y| initial.displacement(l, h, x, y - ymin));
        let v0 = plate.interpolate(|x, y| initial.velocity(x, y - ymin));
        let paper = *initial == PlateInitial::Paper && *body == Body::default();
        let exact = paper.then_some(Exact::Paper(ImpactingBar { length: l }));
        Ok(Self { system: plate, u0, v0, exact })
    }
}

/// The plane-wave solution of a plate with y-independent data and no force: the bar's solution
/// by characteristics, extended in y (None otherwise).
fn plane_wave(spec: &PlateSpec, t_end: f64) -> Result<Option<Characteristics>, PlateRunError> {
    let b = &spec.body;
    if !spec.initial.y_independent() || b.force.constant() != Some(0.0) {
        return Ok(None);
    }
    let exact = |data| by_characteristics(spec.length, b.material, b.far_end, b.gap, data, t_end);
    let (x, u, v) = paper_data(spec.length);
    let solution = match &spec.initial {
        PlateInitial::Fields { displacement, velocity } => {
            let (u, v) = (|x: f64| displacement.eval(&[x, 0.0]), |x: f64| velocity.eval(&[x, 0.0]));
            exact(InitialData::Smooth { u: &u, v: &v })
        }
        _ => exact(InitialData::PiecewiseLinear { x: &x, u: &u, v: &v }),
    };
    Ok(Some(solution.map_err(PlateRunError::Exact)?))
}

/// Everything a plate scene run produces (the problem is kept for the VTU writer).
#[derive(Debug)]
pub struct PlateRun {
    pub problem: PlateProblem,
    pub summary: Summary,
    pub series: SeriesRecorder,
    pub frames: Option<FrameRecorder>,
}

impl PlateProblem {
    /// The problem of a plate scene: its structured mesh or mesh file, and the closed-form or
    /// plane-wave exact solution where there is one.
    pub fn from_plate_scene(scene: &PlateScene) -> Result<Self, PlateRunError> {
        let mut problem = match &scene.mesh_file {
            None => PlateProblem::new(&scene.plate, &scene.mass)?,
            Some(path) => {
                let mesh = read_mesh_file(path)?;
                PlateProblem::from_mesh(mesh, &scene.mass, &scene.plate.initial, &scene.plate.body)?
            }
        };
        if problem.exact.is_none() {
            problem.exact = plane_wave(&scene.plate, scene.time.end)?.map(|c| Exact::General(std::sync::Arc::new(c)));
        }
        Ok(problem)
    }
}

/// Runs a plate scene: the summary always, plus the requested series and VTU frames, held in
/// memory (for library users; `massredist run` streams them: [`run_plate_scene_into`]). A run
/// that diverges stops there and is still a result (as [`crate::run::run_scene`]).
pub fn run_plate_scene(scene: &PlateScene, extra: &mut [&mut dyn Observer]) -> Result<PlateRun, PlateRunError> {
    let problem = PlateProblem::from_plate_scene(scene)?;
    let mut series = SeriesRecorder::new(scene.output.series.clone(), scene.output.every, 0);
    let mut frames = scene.output.vtu_every.map(FrameRecorder::new);
    let mut observers: Vec<&mut dyn Observer> = vec![&mut series];
    if let Some(f) = frames.as_mut() {
        observers.push(f);
    }
    for o in extra.iter_mut() {
        observers.push(&mut **o);
    }
    let summary = run_observed(scene, &problem, &mut observers)?;
    Ok(PlateRun { problem, summary, series, frames })
}

/// `massredist run` for a plate scene: as [`crate::run::run_scene_into`], with the VTU frames
/// streamed too (`vtu/frame_NNNNN.vtu` written when its step is observed, `plate.pvd` closed at
/// the end): memory does not depend on the number of steps.
pub fn run_plate_scene_into(
    scene: &PlateScene,
    out: OutputDir,
    extra: &mut [&mut dyn Observer],
) -> Result<Summary, RunFolderError<PlateRunError>> {
    let problem = PlateProblem::from_plate_scene(scene).map_err(RunFolderError::Run)?;
    let create = |k| FrameWriter::create(out.staging(), &problem.system, k).map_err(|e| out.fill_error(e));
    let mut frames = scene.output.vtu_every.map(create).transpose()?;
    let mut observers: Vec<&mut dyn Observer> = Vec::with_capacity(extra.len() + 1);
    for o in extra.iter_mut() {
        observers.push(&mut **o);
    }
    if let Some(f) = frames.as_mut() {
        observers.push(f);
    }
    let run = |obs: &mut [&mut dyn Observer]| run_observed(scene, &problem, obs);
    let summary = super::stream_series(&out, &scene.output, &mut observers, run)?;
    drop(observers);
    if let Some(f) = frames {
        f.finish().map_err(|e| out.fill_error(e))?;
    }
    commit_run(out, &summary_json(scene, &problem, &summary), &scene.resolved_toml())?;
    Ok(summary)
}

/// Runs a plate problem with its summary and `observers` (series and frames among them).
fn run_observed(
    scene: &PlateScene,
    problem: &PlateProblem,
    observers: &mut [&mut dyn Observer],
) -> Result<Summary, PlateRunError> {
    let mut scheme = problem.scheme(&scene.scheme, scene.time.dt)?;
    let steps = scene.time.steps;
    let mut summary = SummaryObserver::new(problem, steps, scene.time.dt, scene.output.summary_l2);
    let mut all: Vec<&mut dyn Observer> = vec![&mut summary];
    for o in observers.iter_mut() {
        all.push(&mut **o);
    }
    let criterion = DivergenceCriterion { energy_factor: scene.output.divergence_factor };
    // The outcome reaches the summary through `Observer::diverged`.
    let _ = integrate_watched(problem, scheme.as_mut(), steps, &criterion, &mut all)?;
    Ok(summary.finish())
}

#[cfg(feature = "python")]
fn read_mesh_file(path: &std::path::Path) -> Result<Mesh2d, PlateRunError> {
    Ok(Mesh2d::read_file(path)?)
}

/// Unreachable in practice: scene validation already rejects `plate.mesh` without the feature.
#[cfg(not(feature = "python"))]
fn read_mesh_file(path: &std::path::Path) -> Result<Mesh2d, PlateRunError> {
    Err(crate::plate::mesh::MeshError::Arrays(format!("{}: mesh files need the `python` feature", path.display()))
        .into())
}

#[derive(Serialize)]
struct PlateSummaryFile<'a> {
    scheme: &'a str,
    mass: &'a str,
    /// Cells along x (the bar's `elements`).
    elements: usize,
    length: f64,
    end: f64,
    height: f64,
    nx: usize,
    ny: usize,
    cells: &'a str,
    initial: &'a str,
    total_mass: f64,
    #[serde(flatten)]
    summary: &'a Summary,
}

/// `summary.json` text.
pub fn summary_json(scene: &PlateScene, problem: &PlateProblem, summary: &Summary) -> String {
    let p = &scene.plate;
    let file = PlateSummaryFile {
        scheme: scene.scheme.name(),
        mass: scene.mass.name(),
        elements: p.nx,
        length: p.length,
        end: scene.time.end,
        height: p.height,
        nx: p.nx,
        ny: p.ny,
        cells: p.cells.name(),
        initial: p.initial.name(),
        total_mass: problem.system.total_mass(),
        summary,
    };
    serde_json::to_string_pretty(&file).expect("summary serialises") + "\n"
}
