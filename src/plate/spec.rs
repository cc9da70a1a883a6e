//! A plate's specification, [`PlateSpec`]: what the `[plate]` table of a scene validates into
//! (its table parser, `super::table`), and what the plate's problem is built from
//! (`super::problem`).

use crate::expr::Expr;
use crate::fem::{Cell, Mesh, MeshError};
use crate::medium::Medium;
use std::sync::Arc;

/// Initial data of the plate.
#[derive(Debug, Clone, PartialEq)]
pub enum PlateInitial {
    /// u⁰ = (L − x)/2, v⁰ = 0: the 1D benchmark extended constantly in y (exact solution known
    /// for f = 0: the 1D one).
    Paper,
    /// u⁰ = (L − x)/2 · (1 + ½ cos(π y/H)), v⁰ = 0: y-dependent (no exact solution). The
    /// edge x = 0 starts at heights 3/4 (y = 0) to 1/4 (y = H) above the obstacle, so its parts
    /// hit it at different times and the contact state varies along Γ_C. `∂_y u⁰ = 0` on
    /// y = 0, H (compatible with the Neumann condition) and u⁰ = 0 on x = L.
    Bump,
    /// u⁰(x, y), v⁰(x, y) as expressions (in x, y, L, H, pi), interpolated at every node.
    Fields { displacement: Expr, velocity: Expr },
}

impl PlateInitial {
    pub fn name(&self) -> &'static str {
        match self {
            PlateInitial::Paper => "paper",
            PlateInitial::Bump => "bump",
            PlateInitial::Fields { .. } => "expressions",
        }
    }

    /// `u⁰(x, y)` on the plate (0, L) × (0, H).
    pub fn displacement(&self, length: f64, height: f64, x: f64, y: f64) -> f64 {
        let base = (length - x) / 2.0;
        match self {
            PlateInitial::Paper => base,
            PlateInitial::Bump => base * (1.0 + 0.5 * (std::f64::consts::PI * y / height).cos()),
            PlateInitial::Fields { displacement, .. } => displacement.eval(&[x, y]),
        }
    }

    /// Whether the data are constant in y (so that, without force, the solution is a plane
    /// wave: the bar's solution by characteristics extended in y).
    pub fn y_independent(&self) -> bool {
        match self {
            PlateInitial::Paper => true,
            PlateInitial::Bump => false,
            PlateInitial::Fields { displacement, velocity } => {
                !displacement.depends_on("y") && !velocity.depends_on("y")
            }
        }
    }

    /// `v⁰(x, y)` (0 for the named data).
    pub fn velocity(&self, x: f64, y: f64) -> f64 {
        match self {
            PlateInitial::Fields { velocity, .. } => velocity.eval(&[x, y]),
            _ => 0.0,
        }
    }
}

/// The geometry and discretisation of a plate run.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateSpec {
    pub length: f64,
    pub height: f64,
    /// Cells along x and y of a structured mesh (0 for a mesh file).
    pub nx: usize,
    pub ny: usize,
    pub cells: Cell,
    pub initial: PlateInitial,
    /// Material, far end (x = L), gap and force.
    pub medium: Medium,
    /// The mesh file (read by meshio) that replaced the structured mesh; `length`, `height` and
    /// `cells` then describe the file's mesh.
    pub mesh_file: Option<std::path::PathBuf>,
    /// The mesh, built or read once when the scene is validated (None: the structured mesh of
    /// `nx`, `ny`, `cells`, built with the problem).
    pub mesh: Option<Arc<Mesh>>,
}

impl PlateSpec {
    /// The structured plate (0, L) × (0, H) with nx × ny cells (its mesh built with the problem).
    pub fn structured(length: f64, height: f64, nx: usize, ny: usize, cells: Cell, initial: PlateInitial) -> Self {
        PlateSpec { length, height, nx, ny, cells, initial, medium: Medium::default(), mesh_file: None, mesh: None }
    }

    /// The mesh: the one validated with the scene, or the structured one of the spec.
    pub fn mesh(&self) -> Result<Arc<Mesh>, MeshError> {
        match &self.mesh {
            Some(m) => Ok(m.clone()),
            None => Ok(Arc::new(Mesh::structured_2d(self.length, self.height, self.nx, self.ny, self.cells)?)),
        }
    }

    /// Whether the paper's closed form is this plate's exact solution (its data on its body).
    pub fn has_paper_solution(&self) -> bool {
        self.initial == PlateInitial::Paper && self.medium == Medium::default()
    }

    /// Whether the plate's solution is a plane wave (y-independent data, no force): the bar's
    /// solution by characteristics extended in y.
    pub fn has_plane_wave(&self) -> bool {
        self.initial.y_independent() && self.medium.force.constant() == Some(0.0)
    }
}
