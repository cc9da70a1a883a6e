//! Plate scenes: the problem of a `[plate]` scene and its run (the driver is
//! [`crate::driver`], the observers [`crate::observe`]). Nothing here does I/O but
//! [`run_plate_scene_into`] (through [`crate::output`] and [`crate::plate::vtu`]).

use super::RunFolderError;
use crate::characteristics::{Characteristics, CharacteristicsError, InitialData};
use crate::driver::Observer;
use crate::exact::{Exact, ImpactingBar, by_characteristics, paper_data};
use crate::fem::layers::cell_weights;
use crate::fem::{Mesh, MeshError};
use crate::mass::MassKind;
use crate::observe::Summary;
use crate::output::OutputDir;
use crate::plate::assembly::{PlateAssemblyError, PlateLoad, PlateSystem};
use crate::run::{Setup, setup_error};
use crate::scene::{Body, Force, PlateInitial, PlateScene, PlateSpec, SceneError};
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
    /// The scene's problem could not be set up (exit code 2: the input is at fault).
    #[error(transparent)]
    Setup(SceneError),
}

/// A plate problem.
pub type PlateProblem = crate::problem::Problem<PlateSystem>;

impl PlateProblem {
    /// The plate of `spec` (its validated mesh, or the structured one), with its exact solution
    /// where one is known: the paper's closed form, or a plane wave (`t_end`: how long the
    /// characteristics are traced).
    pub fn new(spec: &PlateSpec, mass: &MassKind) -> Result<Self, PlateRunError> {
        let mesh = Mesh::clone(spec.mesh()?.as_ref());
        Self::from_mesh(mesh, mass, &spec.initial, &spec.body)
    }

    /// [`PlateProblem::new`] with the plane-wave exact solution up to `t_end` where the data allow
    /// it and the closed form does not apply.
    pub fn with_plane_wave(spec: &PlateSpec, mass: &MassKind, t_end: f64) -> Result<Self, PlateRunError> {
        let mut problem = Self::new(spec, mass)?;
        if problem.exact.is_none() {
            problem.exact = plane_wave(spec, t_end)?.map(|c| Exact::General(std::sync::Arc::new(c)));
        }
        Ok(problem)
    }

    /// Any mesh of (0, L) × (y_min, y_min + H) (e.g. a triangle mesh read from a file with
    /// [`Mesh::from_arrays`]); the initial data use `y − y_min`.
    pub fn from_mesh(mesh: Mesh, mass: &MassKind, initial: &PlateInitial, body: &Body) -> Result<Self, PlateRunError> {
        let [l, h, _] = mesh.extent;
        let ymin = mesh.points.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        let weights = cell_weights(&mesh, mass).map_err(PlateAssemblyError::from)?;
        let field;
        let load = match &body.force {
            Force::Constant(f) => PlateLoad::Constant(*f),
            Force::Field(e) => {
                field = move |x: f64, y: f64| e.eval(&[x, y - ymin]);
                PlateLoad::Field(&field)
            }
            Force::Transient(_) => PlateLoad::Constant(0.0), // F(t) below
        };
        let mut plate = PlateSystem::assemble(mesh, weights, body.material, body.far_end, &load)?.with_gap(body.gap);
        if let Force::Transient(e) = &body.force {
            let forcing = transient_load(&plate, e, ymin)?;
            plate.system = plate.system.with_forcing(forcing);
        }
        let u0 = plate.interpolate(|x, y| initial.displacement(l, h, x, y - ymin));
        let v0 = plate.interpolate(|x, y| initial.velocity(x, y - ymin));
        let paper = *initial == PlateInitial::Paper && *body == Body::default();
        let exact = paper.then_some(Exact::Paper(ImpactingBar { length: l }));
        Ok(Self { system: plate, u0, v0, exact })
    }
}

/// `F(t) = M_w I_h f(·, t)` on the free nodes (the static field's load, [`PlateSystem::assemble`],
/// at each time), with `M_w` the weighted mass per unit density; its node values and row sums
/// live in a scratch buffer behind a mutex (no allocation per step).
fn transient_load(
    plate: &PlateSystem,
    e: &crate::expr::Expr,
    ymin: f64,
) -> Result<crate::system::Forcing, PlateAssemblyError> {
    let (mass_w, _) = crate::plate::assembly::assemble(&plate.mesh, &plate.weights)?;
    let (points, dofs, e) = (plate.mesh.points.clone(), plate.dofs.clone(), e.clone());
    let n = points.len();
    let scratch = std::sync::Mutex::new(vec![0.0; 2 * n]);
    let forcing = move |t: f64, out: &mut [f64]| {
        let mut guard = scratch.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let (f_nodes, rows) = guard.split_at_mut(n);
        for (f, p) in f_nodes.iter_mut().zip(&points) {
            *f = e.eval(&[p[0], p[1] - ymin, t]);
        }
        rows.fill(0.0);
        for (i, j, v) in crate::linalg::sparse::triplets(&mass_w) {
            rows[i] += v * f_nodes[j];
        }
        for (o, &v) in out.iter_mut().zip(&dofs) {
            *o = rows[v];
        }
    };
    Ok(crate::system::Forcing(std::sync::Arc::new(forcing)))
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

/// Everything a plate scene run produces (in memory).
pub type PlateRun = super::MeshRun<PlateSystem>;

/// The problem and scheme of a plate scene; a failure names the keys that shape the matrices.
pub fn setup(scene: &PlateScene) -> Result<Setup<PlateSystem>, SceneError> {
    let keys =
        "plate.length, plate.height, plate.nx, plate.ny, plate.density, plate.modulus, mass.*, scheme.*, time.dt";
    let problem = PlateProblem::with_plane_wave(&scene.geometry, &scene.mass, scene.time.end)
        .map_err(|e| setup_error(keys, e))?;
    let scheme = problem.scheme(&scene.scheme, scene.time.dt).map_err(|e| setup_error(keys, e))?;
    Ok(Setup { problem, scheme })
}

/// Runs a plate scene: the summary always, plus the requested series and VTU frames, held in
/// memory (for library users; `massredist run` streams them: [`run_plate_scene_into`]). A run
/// that diverges stops there and is still a result (as [`crate::run::run_scene`]).
pub fn run_plate_scene(scene: &PlateScene, extra: &mut [&mut dyn Observer]) -> Result<PlateRun, PlateRunError> {
    let setup = setup(scene).map_err(PlateRunError::Setup)?;
    Ok(super::run_in_memory(scene, setup, extra)?)
}

/// `massredist run` for a plate scene: as [`crate::run::run_scene_into`], with the VTU frames
/// streamed too (`vtu/frame_NNNNN.vtu` written when its step is observed, `plate.pvd` closed at
/// the end): memory does not depend on the number of steps.
pub fn run_plate_scene_into(
    scene: &PlateScene,
    out: OutputDir,
    extra: &mut [&mut dyn Observer],
) -> Result<Summary, RunFolderError<PlateRunError>> {
    let setup = setup(scene).map_err(|e| RunFolderError::Run(PlateRunError::Setup(e)))?;
    let json = |problem: &PlateProblem, summary: &Summary| summary_json(scene, problem, summary);
    super::run_frames_into(scene, setup, out, extra, json, PlateRunError::Scheme)
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
    let p = &scene.geometry;
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
