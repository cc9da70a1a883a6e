//! The problem a plate scene poses ([`PlateSpec`] → [`PlateProblem`]: the assembled plate, the
//! interpolated initial data, and the paper's closed form or the plane wave where it applies),
//! and the plate's place in the one run path ([`GeometrySpec`]).

use super::assembly::{PlateAssemblyError, PlateLoad, PlateSystem};
use super::spec::{PlateInitial, PlateSpec};
use crate::characteristics::{Characteristics, CharacteristicsError, InitialData};
use crate::exact::{Exact, ImpactingBar, by_characteristics, paper_data};
use crate::fem::frames::VtuFrames;
use crate::fem::layers::cell_weights;
use crate::fem::{Mesh, MeshError};
use crate::mass::MassKind;
use crate::medium::{Force, Medium};
use crate::spec::Scene;
use crate::spec::{GeometrySpec, Totals};
use serde::Serialize;
use thiserror::Error;

/// Why a plate problem cannot be built.
#[derive(Debug, Error)]
pub enum PlateError {
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Assembly(#[from] PlateAssemblyError),
    #[error("the plane-wave exact solution of this scene: {0}")]
    Exact(CharacteristicsError),
}

/// A plate problem.
pub type PlateProblem = crate::problem::Problem<PlateSystem>;

impl PlateProblem {
    /// The plate of `spec` (its validated mesh, or the structured one), with its exact solution
    /// where one is known: the paper's closed form, or a plane wave (`t_end`: how long the
    /// characteristics are traced).
    pub fn new(spec: &PlateSpec, mass: &MassKind) -> Result<Self, PlateError> {
        let mesh = Mesh::clone(spec.mesh()?.as_ref());
        Self::from_mesh(mesh, mass, &spec.initial, &spec.medium)
    }

    /// [`PlateProblem::new`] with the plane-wave exact solution up to `t_end` where the data allow
    /// it and the closed form does not apply ([`PlateSpec::exact`]).
    pub fn with_plane_wave(spec: &PlateSpec, mass: &MassKind, t_end: f64) -> Result<Self, PlateError> {
        let mut problem = Self::new(spec, mass)?;
        problem.exact = spec.exact(t_end)?;
        Ok(problem)
    }

    /// Any mesh of (0, L) × (y_min, y_min + H) (e.g. a triangle mesh read from a file with
    /// [`Mesh::from_arrays`]); the initial data use `y − y_min`.
    pub fn from_mesh(mesh: Mesh, mass: &MassKind, initial: &PlateInitial, medium: &Medium) -> Result<Self, PlateError> {
        let [l, h, _] = mesh.extent;
        let ymin = mesh.points.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        let weights = cell_weights(&mesh, mass).map_err(PlateAssemblyError::from)?;
        let field;
        let load = match &medium.force {
            Force::Constant(f) => PlateLoad::Constant(*f),
            Force::Field(e) => {
                field = move |x: f64, y: f64| e.eval(&[x, y - ymin]);
                PlateLoad::Field(&field)
            }
            Force::Transient(_) => PlateLoad::Constant(0.0), // F(t) below
        };
        let mut plate =
            PlateSystem::assemble(mesh, weights, medium.material, medium.far_end, &load)?.with_gap(medium.gap);
        if let Force::Transient(e) = &medium.force {
            let forcing = transient_load(&plate, e, ymin)?;
            plate.system = plate.system.with_forcing(forcing);
        }
        let u0 = plate.interpolate(|x, y| initial.displacement(l, h, x, y - ymin));
        let v0 = plate.interpolate(|x, y| initial.velocity(x, y - ymin));
        let paper = *initial == PlateInitial::Paper && *medium == Medium::default();
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

impl PlateSpec {
    /// The exact solution up to `t_end` (None if none is known): the paper's closed form for its
    /// data on its body, else the plane wave where the data allow it. The Rust run and the
    /// FEniCSx engine's observers both take it from here.
    pub fn exact(&self, t_end: f64) -> Result<Option<Exact>, PlateError> {
        if self.has_paper_solution() {
            return Ok(Some(Exact::Paper(ImpactingBar { length: self.length })));
        }
        Ok(plane_wave(self, t_end)?.map(|c| Exact::General(std::sync::Arc::new(c))))
    }
}

/// The plane-wave solution of a plate with y-independent data and no force: the bar's solution
/// by characteristics, extended in y (None otherwise).
fn plane_wave(spec: &PlateSpec, t_end: f64) -> Result<Option<Characteristics>, PlateError> {
    let b = &spec.medium;
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
    Ok(Some(solution.map_err(PlateError::Exact)?))
}

/// The plate keys of `summary.json`.
#[derive(Serialize)]
pub struct PlateHead {
    height: f64,
    nx: usize,
    ny: usize,
    cells: &'static str,
    initial: &'static str,
    total_mass: f64,
}

impl GeometrySpec for PlateSpec {
    type System = PlateSystem;
    type Error = PlateError;
    type Head = PlateHead;
    const SETUP_KEYS: &'static str =
        "plate.length, plate.height, plate.nx, plate.ny, plate.density, plate.modulus, mass.*, scheme.*, time.dt";

    fn elements(&self) -> usize {
        self.nx
    }

    fn problem(scene: &Scene<Self>) -> Result<PlateProblem, PlateError> {
        PlateProblem::with_plane_wave(&scene.geometry, &scene.mass, scene.time.exact_end())
    }

    fn summary_head(scene: &Scene<Self>, totals: &Totals) -> PlateHead {
        let p = &scene.geometry;
        PlateHead {
            height: p.height,
            nx: p.nx,
            ny: p.ny,
            cells: p.cells.name(),
            initial: p.initial.name(),
            total_mass: totals.total_mass,
        }
    }

    fn totals(system: &PlateSystem) -> Totals {
        Totals { total_mass: system.total_mass(), unknowns: system.system.n() }
    }

    fn frames(system: &PlateSystem) -> Option<&dyn VtuFrames> {
        Some(system)
    }
}
