//! Plate scenes: the problem of a `[plate]` scene and its run (the driver is
//! [`crate::driver`], the observers [`crate::observe`]). Nothing here does I/O.

use super::assembly::{PlateAssemblyError, PlateSystem};
use super::mesh::{CellKind, Mesh2d, MeshError};
use crate::driver::{DivergenceCriterion, Observer, integrate_watched};
use crate::exact::{Exact, ImpactingBar};
use crate::mass::MassKind;
use crate::observe::{FrameRecorder, SeriesRecorder, Summary, SummaryObserver};
use crate::schemes::SchemeError;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum PlateRunError {
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Assembly(#[from] PlateAssemblyError),
    #[error(transparent)]
    Scheme(#[from] SchemeError),
    #[error("the 1D reference run failed: {0}")]
    Reference(String),
}

/// Initial data of the plate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlateInitial {
    /// u⁰ = (L − x)/2, v⁰ = 0: the 1D benchmark extended constantly in y (exact solution known
    /// for f = 0: the 1D one).
    Paper,
    /// u⁰ = (L − x)/2 · (1 + ½ cos(π y/H)), v⁰ = 0: y-dependent (no exact solution). The
    /// edge x = 0 starts at heights 3/4 (y = 0) to 1/4 (y = H) above the obstacle, so its parts
    /// hit it at different times and the contact state varies along Γ_C. `∂_y u⁰ = 0` on
    /// y = 0, H (compatible with the Neumann condition) and u⁰ = 0 on x = L.
    Bump,
}

impl PlateInitial {
    pub fn name(self) -> &'static str {
        match self {
            PlateInitial::Paper => "paper",
            PlateInitial::Bump => "bump",
        }
    }

    /// `u⁰(x, y)` on the plate (0, L) × (0, H).
    pub fn displacement(self, length: f64, height: f64, x: f64, y: f64) -> f64 {
        let base = (length - x) / 2.0;
        match self {
            PlateInitial::Paper => base,
            PlateInitial::Bump => base * (1.0 + 0.5 * (std::f64::consts::PI * y / height).cos()),
        }
    }
}

/// The geometry and discretisation of a plate run.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateSpec {
    pub length: f64,
    pub height: f64,
    pub nx: usize,
    pub ny: usize,
    pub cells: CellKind,
    pub initial: PlateInitial,
    pub force: f64,
}

pub use crate::problem::PlateProblem;

impl PlateProblem {
    /// The structured plate of `spec`.
    pub fn new(spec: &PlateSpec, mass: &MassKind) -> Result<Self, PlateRunError> {
        let mesh = Mesh2d::structured(spec.length, spec.height, spec.nx, spec.ny, spec.cells)?;
        Self::from_mesh(mesh, mass, spec.initial, spec.force)
    }

    /// Any mesh of (0, L) × (y_min, y_min + H) (e.g. a triangle mesh read from a file with
    /// [`Mesh2d::from_arrays`]); the initial data use `y − y_min`.
    pub fn from_mesh(mesh: Mesh2d, mass: &MassKind, initial: PlateInitial, force: f64) -> Result<Self, PlateRunError> {
        let (l, h) = (mesh.length, mesh.height);
        let ymin = mesh.points.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        let plate = PlateSystem::new(mesh, mass, force)?;
        let u0 = plate.interpolate(|x, y| initial.displacement(l, h, x, y - ymin));
        let v0 = vec![0.0; u0.len()];
        let exact =
            (initial == PlateInitial::Paper && force == 0.0).then_some(Exact::Paper(ImpactingBar { length: l }));
        Ok(Self { system: plate, u0, v0, exact })
    }
}

/// Everything a plate scene run produces (the problem is kept for the VTU writer).
#[derive(Debug)]
pub struct PlateRun {
    pub problem: PlateProblem,
    pub summary: Summary,
    pub series: SeriesRecorder,
    pub frames: Option<FrameRecorder>,
}

/// Runs a plate scene: the summary always, plus the requested series and VTU frames. A run that
/// diverges stops there and is still a result (as [`crate::run::run_scene`]).
pub fn run_plate_scene(
    scene: &super::scene::PlateScene,
    extra: &mut [&mut dyn Observer],
) -> Result<PlateRun, PlateRunError> {
    let problem = match &scene.mesh_file {
        None => PlateProblem::new(&scene.plate, &scene.mass)?,
        Some(path) => {
            let mesh = read_mesh_file(path)?;
            PlateProblem::from_mesh(mesh, &scene.mass, scene.plate.initial, scene.plate.force)?
        }
    };
    let mut scheme = problem.scheme(&scene.scheme, scene.time.dt)?;
    let steps = scene.time.steps;
    let mut summary = SummaryObserver::new(&problem, steps, scene.time.dt, true);
    let mut series = SeriesRecorder::new(scene.output.series.clone(), scene.output.every, 0);
    let mut frames = scene.output.vtu_every.map(FrameRecorder::new);
    {
        let mut observers: Vec<&mut dyn Observer> = vec![&mut summary, &mut series];
        if let Some(f) = frames.as_mut() {
            observers.push(f);
        }
        for o in extra.iter_mut() {
            observers.push(&mut **o);
        }
        let criterion = DivergenceCriterion { energy_factor: scene.output.divergence_factor };
        // The outcome reaches the summary through `Observer::diverged`.
        let _ = integrate_watched(&problem, scheme.as_mut(), steps, &criterion, &mut observers)?;
    }
    Ok(PlateRun { problem, summary: summary.finish(), series, frames })
}

#[cfg(feature = "python")]
fn read_mesh_file(path: &std::path::Path) -> Result<Mesh2d, PlateRunError> {
    Ok(Mesh2d::read_file(path)?)
}

/// Unreachable in practice: scene validation already rejects `plate.mesh` without the feature.
#[cfg(not(feature = "python"))]
fn read_mesh_file(path: &std::path::Path) -> Result<Mesh2d, PlateRunError> {
    Err(super::mesh::MeshError::Arrays(format!("{}: mesh files need the `python` feature", path.display())).into())
}
