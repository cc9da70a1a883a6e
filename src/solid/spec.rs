//! A solid's specification, [`SolidSpec`]: what the `[solid]` table of a scene validates into
//! (its table parser, `super::table`), and what the solid's problem is built from
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

use super::body::{BodyContact, BodyError};
pub use super::body::{BodySpec, ContactSet, Obstacle};
use crate::expr::Expr;
use crate::fem::layers::{LayerMassError, cell_weights_of};
use crate::fem::mesh::{Cell, Mesh, MeshError};
use crate::mass::MassKind;
use crate::material::Lame;
use std::sync::{Arc, Mutex};

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

/// Where a solid's mesh comes from.
#[derive(Debug, Clone)]
pub enum MeshSource {
    /// The box generator: (0, L) × (0, H) [× (0, D)] of [`SolidSpec::extent`] in
    /// [`SolidSpec::cells_per_axis`] cells of kind [`SolidSpec::cells`], its faces grouped
    /// ([`face_groups`]).
    Box,
    /// A mesh file (the path resolved against the scene's folder), read once when the scene is
    /// validated.
    File { path: std::path::PathBuf, mesh: Arc<Mesh> },
    /// Arrays the caller passed with the scene (the Python package's `mesh=`), checked as a
    /// file's when the scene is validated; the scene names them `mesh = "<arrays>"`.
    Arrays(Arc<Mesh>),
}

impl PartialEq for MeshSource {
    /// Meshes read or given are the same source when they are the same mesh (the same object,
    /// or equal).
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (MeshSource::Box, MeshSource::Box) => true,
            (MeshSource::File { path: a, mesh: m }, MeshSource::File { path: b, mesh: n }) => {
                a == b && (Arc::ptr_eq(m, n) || m == n)
            }
            (MeshSource::Arrays(m), MeshSource::Arrays(n)) => Arc::ptr_eq(m, n) || m == n,
            _ => false,
        }
    }
}

impl MeshSource {
    /// The mesh read or given (None: generated).
    pub fn given(&self) -> Option<&Arc<Mesh>> {
        match self {
            MeshSource::Box => None,
            MeshSource::File { mesh, .. } | MeshSource::Arrays(mesh) => Some(mesh),
        }
    }

    /// The file's path (None: generated or given as arrays).
    pub fn path(&self) -> Option<&std::path::Path> {
        match self {
            MeshSource::File { path, .. } => Some(path),
            _ => None,
        }
    }
}

/// Where the solid meets its rigid obstacle, where it is held, and the force on it.
#[derive(Debug, Clone, PartialEq)]
pub enum Support {
    /// The box of a scene without `[obstacle]`: its face x = 0 against the plane x = −gap
    /// (normal e_x; each node of the face starts at the distance `gap`), clamped on the face
    /// x = L, the lateral faces free or on rollers, and a constant force f weighted as the
    /// mass, `F_(a,i) = f_i ∫ w_h φ_a` (`super::assembly`).
    Face { gap: f64, lateral: Lateral, force: [f64; 3] },
    /// A body of any shape against the plane of `[obstacle]` ([`BodySpec`], `super::body`).
    Plane(BodySpec),
    /// Several bodies (`[[solid]]`) in contact through their pairs (`[[pair]]`,
    /// `super::bodies`); the spec's mesh is the bodies' joined mesh.
    Bodies(super::bodies::Bodies),
}

impl Support {
    /// The paper's box: no gap, free lateral faces, no force.
    pub const PAPER: Support = Support::Face { gap: 0.0, lateral: Lateral::Free, force: [0.0; 3] };

    /// The obstacle's initial distance to the face x = 0 (a body's plane is placed by
    /// `obstacle.point`: 0).
    pub fn gap(&self) -> f64 {
        match self {
            Support::Face { gap, .. } => *gap,
            Support::Plane(_) | Support::Bodies(_) => 0.0,
        }
    }

    /// The lateral faces' condition (a body's boundary is free but where clamped).
    pub fn lateral(&self) -> Lateral {
        match self {
            Support::Face { lateral, .. } => *lateral,
            Support::Plane(_) | Support::Bodies(_) => Lateral::Free,
        }
    }

    /// The body of `[obstacle]` (None: the box).
    pub fn body(&self) -> Option<&BodySpec> {
        match self {
            Support::Face { .. } | Support::Bodies(_) => None,
            Support::Plane(b) => Some(b),
        }
    }

    /// The bodies of `[[solid]]` (None: one body or the box).
    pub fn bodies(&self) -> Option<&super::bodies::Bodies> {
        match self {
            Support::Bodies(b) => Some(b),
            _ => None,
        }
    }

    /// Whether the solid reports as a body (its contact force, distances, momentum): one body
    /// against an obstacle, or several bodies.
    pub fn is_body(&self) -> bool {
        !matches!(self, Support::Face { .. })
    }
}

/// A validated `[solid]` table (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct SolidSpec {
    pub dim: usize,
    /// `[L, H, D]` (D ignored in 2D): the generated box's, or the extent of the mesh read.
    pub extent: [f64; 3],
    /// `[nx, ny, nz]` (nz ignored in 2D; `[0, 0, 0]` for a mesh read or given).
    pub cells_per_axis: [usize; 3],
    pub cells: Cell,
    pub lame: Lame,
    pub initial: SolidInitial,
    /// Where the mesh comes from.
    pub source: MeshSource,
    /// Where the solid meets its obstacle and is held, and the force on it.
    pub support: Support,
    /// The mesh and contact set, built once ([`SolidSpec::built`]).
    pub cache: BuildCache,
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
            initial: SolidInitial::Paper,
            source: MeshSource::Box,
            support: Support::PAPER,
            cache: BuildCache::default(),
        }
    }

    /// The mesh and contact set of this spec, built on the first call and kept (a scene builds
    /// them once, when it is validated, and its run uses them); a spec changed since is built
    /// again ([`BuildCache`]).
    pub fn built(&self) -> Result<Arc<Built>, BuildError> {
        self.cache.get(self)
    }

    /// The mesh: the one read or given, or the generated box with the groups of its faces
    /// ([`face_groups`]).
    pub fn mesh(&self) -> Result<Arc<Mesh>, MeshError> {
        if let Some(m) = self.source.given() {
            return Ok(Arc::clone(m));
        }
        let ([l, h, d], [nx, ny, nz]) = (self.extent, self.cells_per_axis);
        let mut mesh = match self.cells {
            Cell::Quad | Cell::Triangle | Cell::Triangle6 => Mesh::structured_2d(l, h, nx, ny, self.cells),
            Cell::Hex | Cell::Tet | Cell::Tet10 => Mesh::structured_3d([l, h, d], [nx, ny, nz], self.cells),
        }?;
        face_groups(&mut mesh);
        Ok(Arc::new(mesh))
    }

    /// Whether the solution is a plane wave (module docs of [`crate::solid`]): the box, x-only
    /// data, no force, and λ = 0 or roller lateral faces.
    pub fn is_plane_wave(&self) -> bool {
        let Support::Face { lateral, force, .. } = self.support else { return false };
        self.initial.x_only()
            && force.iter().all(|&f| f == 0.0)
            && (self.lame.lambda == 0.0 || lateral == Lateral::Roller)
    }
}

/// Why a spec's mesh or contact set cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BuildError {
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Body(#[from] BodyError),
    #[error(transparent)]
    Bodies(#[from] super::bodies::BodiesError),
}

/// What [`SolidSpec::built`] builds: the mesh and its contact set, and the cell weights of the
/// last mass redistribution asked for ([`Built::weights`]).
#[derive(Debug)]
pub struct Built {
    pub mesh: Arc<Mesh>,
    pub contact: BodyContact,
    /// Several bodies: the joined mesh's bodies and pairs (None: one body).
    pub joined: Option<(super::bodies::Bodies, super::bodies::Joined)>,
    weights: Mutex<Option<(MassKind, Vec<f64>)>>,
}

impl Built {
    /// The cell weights of `mass` on this mesh, its contact layer the cells holding a contact
    /// node ([`crate::fem::layers`]), validated; computed once per mass (a scene's validation
    /// learns w_0 from them, its run assembles them).
    pub fn weights(&self, mass: &MassKind) -> Result<Vec<f64>, LayerMassError> {
        let mut slot = self.weights.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some((m, w)) = slot.as_ref()
            && m == mass
        {
            return Ok(w.clone());
        }
        let c = &self.contact;
        let w = match &self.joined {
            Some((bodies, joined)) => bodies.weights(joined, mass)?,
            None => cell_weights_of(&self.mesh, mass, &c.contact, &c.clamped)?,
        };
        *slot = Some((mass.clone(), w.clone()));
        Ok(w)
    }
}

/// The spec's inputs that the mesh and the contact set depend on.
#[derive(Debug, Clone, PartialEq)]
struct BuildKey {
    dim: usize,
    extent: [f64; 3],
    cells_per_axis: [usize; 3],
    cells: Cell,
    source: MeshSource,
    support: Support,
}

impl BuildKey {
    fn of(s: &SolidSpec) -> Self {
        let (dim, extent, cells_per_axis, cells) = (s.dim, s.extent, s.cells_per_axis, s.cells);
        BuildKey { dim, extent, cells_per_axis, cells, source: s.source.clone(), support: s.support.clone() }
    }
}

/// The mesh and contact set of a spec, kept with the inputs they were built from: a spec whose
/// fields changed since (library users and tests edit specs) is built again. Shared between
/// clones of the spec; not part of its value (two specs are equal whatever their caches hold).
#[derive(Debug, Clone, Default)]
pub struct BuildCache(Arc<Mutex<Option<(BuildKey, Arc<Built>)>>>);

impl PartialEq for BuildCache {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl BuildCache {
    fn get(&self, spec: &SolidSpec) -> Result<Arc<Built>, BuildError> {
        let key = BuildKey::of(spec);
        let mut slot = self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some((k, built)) = slot.as_ref()
            && *k == key
        {
            return Ok(Arc::clone(built));
        }
        let (mesh, contact, joined) = match &spec.support {
            Support::Bodies(bodies) => {
                let j = bodies.join()?;
                (Arc::clone(&j.mesh), j.contact.clone(), Some((bodies.clone(), j)))
            }
            support => {
                let mesh = spec.mesh()?;
                let contact = match support {
                    Support::Plane(body) => super::body::contact(&mesh, body)?,
                    _ => super::body::face_contact(&mesh, spec.support.gap()),
                };
                (mesh, contact, None)
            }
        };
        let built = Arc::new(Built { mesh, contact, joined, weights: Mutex::new(None) });
        *slot = Some((key, Arc::clone(&built)));
        Ok(built)
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
