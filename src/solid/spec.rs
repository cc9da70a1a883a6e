//! A solid's specification, [`SolidSpec`]: what the `[solid]` table of a scene validates into
//! (`crate::scene`'s solid table), and what the solid's problem is built from
//! (`super::problem`).
//!
//! ```toml
//! [solid]
//! dim = 2                  # 2 (plane strain) | 3
//! length = 1.0             # x: contact face x = 0, clamped face x = L
//! height = 1.0             # y
//! depth = 1.0              # z, dim = 3 only
//! nx = 20                  # >= 2
//! ny = 20                  # >= 1
//! nz = 20                  # >= 1, dim = 3 only
//! cells = "quad"           # dim 2: quad | triangle;  dim 3: hex | tet
//! lame_lambda = 0.0        # >= 0
//! lame_mu = 0.5            # > 0
//! density = 1.0            # > 0
//! gap = 0.0                # >= 0: u_x >= -gap on x = 0
//! lateral = "free"         # free | roller
//! force = [0.0, 0.0]       # constant body force, one number per component
//! initial = "paper"        # u = ((L-x)/2, 0[, 0]), v = 0; or per-component expressions in
//! # x, y[, z] and L, H[, D], pi:
//! # initial = { displacement = ["(1-x)/2", "0"], velocity = ["0", "0"] }
//! ```
//!
//! A body against a rigid plane adds an `[obstacle]` table and changes some keys
//! ([`BodySpec`], `crate::solid::body`):
//!
//! ```toml
//! [solid]
//! dim = 2
//! mesh = "disc.msh"        # or the structured box keys (its groups: xmin, xmax, ymin, ymax[, zmin, zmax])
//! force = ["0", "-0.1"]    # per unit volume: numbers or expressions in x, y[, z], t
//! initial = { displacement = ["0", "0"], velocity = ["0", "-1"] }   # default: at rest
//! clamped = "top"          # a group whose nodes are fixed; absent: a free body
//! # no gap, no lateral
//! [obstacle]
//! normal = [0.0, 1.0]      # from the plane into the body (normalised)
//! point = [0.0, 0.0]       # a point of the plane (default: the origin)
//! contact = "auto"         # or a group name
//! ```

use crate::expr::Expr;
use crate::fem::mesh::{Cell, Mesh, MeshError};
use crate::material::Lame;

/// The condition on the faces other than x = 0 and x = L.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Lateral {
    /// Traction-free.
    Free,
    /// u·n = 0 (the normal component eliminated), tangential traction-free.
    Roller,
}

impl Lateral {
    pub fn name(self) -> &'static str {
        match self {
            Lateral::Free => "free",
            Lateral::Roller => "roller",
        }
    }
}

/// The initial data of a solid.
#[derive(Debug, Clone, PartialEq)]
pub enum SolidInitial {
    /// u = ((L − x)/2, 0[, 0]), v = 0 (the paper's data as a plane wave).
    Paper,
    /// One expression per component (variables x, y[, z]; constants L, H[, D], pi).
    Fields { displacement: Vec<Expr>, velocity: Vec<Expr> },
}

impl SolidInitial {
    pub fn name(&self) -> &'static str {
        match self {
            SolidInitial::Paper => "paper",
            SolidInitial::Fields { .. } => "fields",
        }
    }

    /// Whether the data are a plane wave: u_x and v_x depend on x only, the other components 0.
    pub fn x_only(&self) -> bool {
        match self {
            SolidInitial::Paper => true,
            SolidInitial::Fields { displacement, velocity } => [displacement, velocity].iter().all(|f| {
                !f[0].depends_on("y") && !f[0].depends_on("z") && f[1..].iter().all(|e| e.is_constant() == Some(0.0))
            }),
        }
    }
}

/// A validated `[solid]` table (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct SolidSpec {
    pub dim: usize,
    /// `[L, H, D]` (D ignored in 2D).
    pub extent: [f64; 3],
    /// `[nx, ny, nz]` (nz ignored in 2D).
    pub cells_per_axis: [usize; 3],
    pub cells: Cell,
    pub lame: Lame,
    pub gap: f64,
    pub lateral: Lateral,
    /// Constant body force (entries beyond `dim` are 0).
    pub force: [f64; 3],
    pub initial: SolidInitial,
    /// The mesh file (read by meshio) that replaced the structured mesh; `extent` and `cells`
    /// then describe the file's mesh and `cells_per_axis` is `[0, 0, 0]`.
    pub mesh_file: Option<std::path::PathBuf>,
    /// The file's mesh, read once when the scene is validated (None: the structured mesh).
    pub mesh: Option<std::sync::Arc<Mesh>>,
    /// A body of any shape against a rigid plane (`[obstacle]`; module docs of
    /// [`super::body`]); None: the box, in contact on x = 0 and clamped on x = L.
    pub body: Option<BodySpec>,
}

/// Which nodes meet the obstacle.
#[derive(Debug, Clone, PartialEq)]
pub enum ContactSet {
    /// Every node of every boundary facet whose outward unit normal n_f has
    /// n_f · normal < −0.01 (GetFEM's rule).
    Auto,
    /// The nodes of a physical group of the mesh.
    Group(String),
}

/// The rigid plane `{x : normal · (x − point) = 0}`, the body on the side `normal` points to.
#[derive(Debug, Clone, PartialEq)]
pub struct Obstacle {
    /// Unit normal, pointing from the plane into the body (entries beyond `dim` are 0).
    pub normal: [f64; 3],
    /// A point of the plane (entries beyond `dim` are 0).
    pub point: [f64; 3],
    pub contact: ContactSet,
}

/// What a body scene adds to the solid: the obstacle, the clamped group, and the body force as
/// expressions in x, y[, z], t (force per unit volume).
#[derive(Debug, Clone, PartialEq)]
pub struct BodySpec {
    pub obstacle: Obstacle,
    /// The physical group whose nodes are fixed (None: a free body).
    pub clamped: Option<String>,
    /// One expression per component, variables x, y[, z], t.
    pub force: Vec<Expr>,
}

impl SolidSpec {
    /// The paper's bar as a solid: (0, 1)^d, λ = 0, μ = ½, ρ = 1, free lateral faces, the
    /// paper's data, Q1 cells (quad | hex).
    pub fn paper(dim: usize, n: [usize; 3]) -> Self {
        SolidSpec {
            dim,
            extent: [1.0, 1.0, 1.0],
            cells_per_axis: n,
            cells: if dim == 2 { Cell::Quad } else { Cell::Hex },
            lame: Lame::PAPER,
            gap: 0.0,
            lateral: Lateral::Free,
            force: [0.0; 3],
            initial: SolidInitial::Paper,
            mesh_file: None,
            mesh: None,
            body: None,
        }
    }

    /// The mesh: the file's, read with the scene, or the structured mesh of the spec (a body's
    /// with the groups of its faces, [`face_groups`]).
    pub fn mesh(&self) -> Result<Mesh, MeshError> {
        if let Some(m) = &self.mesh {
            return Ok(Mesh::clone(m));
        }
        let ([l, h, d], [nx, ny, nz]) = (self.extent, self.cells_per_axis);
        let mut mesh = match self.cells {
            Cell::Quad | Cell::Triangle | Cell::Triangle6 => Mesh::structured_2d(l, h, nx, ny, self.cells),
            Cell::Hex | Cell::Tet | Cell::Tet10 => Mesh::structured_3d([l, h, d], [nx, ny, nz], self.cells),
        }?;
        if self.body.is_some() {
            face_groups(&mut mesh);
        }
        Ok(mesh)
    }

    /// Whether the solution is a plane wave (module docs of [`crate::solid`]): x-only data, no
    /// force, and λ = 0 or roller lateral faces.
    pub fn is_plane_wave(&self) -> bool {
        self.body.is_none()
            && self.initial.x_only()
            && self.force.iter().all(|&f| f == 0.0)
            && (self.lame.lambda == 0.0 || self.lateral == Lateral::Roller)
    }
}

/// The groups of a structured box's faces, for bodies without a mesh file: "xmin", "xmax",
/// "ymin", "ymax" (and "zmin", "zmax" in 3D), each the nodes whose coordinate is exactly the
/// face's (structured meshes put them there).
pub fn face_groups(mesh: &mut Mesh) {
    for (axis, name) in ["x", "y", "z"].iter().enumerate().take(mesh.dim) {
        for (end, side) in [(0.0, "min"), (mesh.extent[axis], "max")] {
            let nodes = (0..mesh.n_nodes()).filter(|&v| mesh.points[v][axis] == end).collect();
            mesh.groups.insert(format!("{name}{side}"), nodes);
        }
    }
}
