//! Linear elasticity on a [`Mesh`] of dimension d = 2 (plane strain) or 3: the weighted vector
//! mass, the elasticity stiffness and the load, and the contact system on the free unknowns.
//!
//! ```text
//! M_(a,i),(b,j) = δ_ij ρ Σ_c w_c ∫_c φ_a φ_b,
//! S_(a,i),(b,j) = ∫_Ω λ ∂_i φ_a ∂_j φ_b + μ (δ_ij ∇φ_a·∇φ_b + ∂_j φ_a ∂_i φ_b)
//!               (= ∫ λ div u div v + 2μ ε(u):ε(v) with u = φ_b e_j, v = φ_a e_i),
//! F_(a,i) = f_i ∫_Ω w_h φ_a      (a constant body force f, weighted as for bars and plates).
//! ```
//!
//! **Unknowns are interleaved per node**: the full index of component i of node a is
//! `a·d + i`. [`SolidSystem`] keeps the full indices that are not eliminated, in increasing
//! order (`dofs`): all components on the clamped face x = L are eliminated, and with
//! `lateral = roller` the normal component on the lateral faces (u_y on y = 0, H; u_z on
//! z = 0, D). The contact unknowns are the x-components of the nodes on x = 0, in node order
//! (the first is the node at the lowest y and z), with the bound u_x ≥ −gap.
//!
//! One weight per cell ([`crate::fem::layers`]): with `mass.contact_directions = "all"` every
//! component of a contact-face node is massless under mod1/mod2/mod3. The tangential ones are
//! then free quasi-static unknowns, which the schemes handle as massless unknowns without a
//! contact condition (`crate::schemes::hybrid`). With `"normal"` only component 0 (the normal
//! one, in the obstacle's frame) takes the weights, the others the standard mass
//! ([`ContactDirections`]):
//!
//! ```text
//! M_(a,i),(b,j) = δ_ij ρ Σ_c w_c^(i) ∫_c φ_a φ_b,   w_c^(0) = w_c,  w_c^(i≥1) = 1.
//! ```

use super::body::BodyContact;
use super::dof_map::DofMap;
use super::spec::Support;
use crate::fem::Mesh;
use crate::fem::layers::LayerMassError;
use crate::linalg::sparse::{self, SpMat, SparseError};
use crate::mass::ContactDirections;
use crate::system::{ContactSystem, Forcing};
use std::sync::{Arc, OnceLock};
use thiserror::Error;

pub use super::spec::Lateral;
pub use crate::material::Lame;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolidAssemblyError {
    #[error(transparent)]
    Mass(#[from] LayerMassError),
    #[error(transparent)]
    Sparse(#[from] SparseError),
    #[error("solid.force = {0:?}: must be finite")]
    Force([f64; 3]),
    #[error(transparent)]
    Body(#[from] super::body::BodyError),
    #[error(transparent)]
    Bodies(#[from] super::bodies::BodiesError),
}

/// The weighted vector mass (with ρ) and the stiffness over all nodes and components (full
/// indices `a·d + i`, no boundary condition): the matrices dolfinx and scikit-fem assemble.
pub fn assemble(mesh: &Mesh, weights: &[f64], lame: &Lame) -> Result<(SpMat, SpMat), SparseError> {
    assemble_directed(mesh, weights, ContactDirections::All, lame)
}

/// [`assemble`] with the weights on the components `directions` names (module docs; the
/// mesh's first axis is the obstacle's normal).
pub fn assemble_directed(
    mesh: &Mesh,
    weights: &[f64],
    directions: ContactDirections,
    lame: &Lame,
) -> Result<(SpMat, SpMat), SparseError> {
    assert_eq!(weights.len(), mesh.n_cells(), "one weight per cell");
    let d = mesh.dim;
    let k = mesh.kind.verts();
    let mut tm = Vec::with_capacity(mesh.n_cells() * k * k * d);
    let mut ts = Vec::with_capacity(mesh.n_cells() * k * k * d * d);
    for (c, &w) in weights.iter().enumerate() {
        let e = mesh.integrals(c);
        let v = mesh.cell(c);
        for a in 0..k {
            for b in 0..k {
                for i in 0..d {
                    tm.push((v[a] * d + i, v[b] * d + i, lame.density * directions.weight(i, w) * e.mass[a][b]));
                }
                for i in 0..d {
                    for j in 0..d {
                        ts.push((v[a] * d + i, v[b] * d + j, super::columns::stiffness_entry(&e, lame, a, b, i, j)));
                    }
                }
            }
        }
    }
    let n = mesh.n_nodes() * d;
    Ok((sparse::from_triplets(n, &tm, "mass")?, sparse::from_triplets(n, &ts, "stiffness")?))
}

/// The unknowns that are not eliminated: free unknown → full index `node·d + component`
/// (increasing), and back.
pub(super) struct Free {
    pub dofs: Vec<usize>,
    pub dof_of: DofMap,
}

impl Free {
    pub fn new(mesh: &Mesh, eliminated: impl Fn(usize) -> bool) -> Self {
        let n = mesh.n_nodes() * mesh.dim;
        let dofs: Vec<usize> = (0..n).filter(|&g| !eliminated(g)).collect();
        let dof_of = DofMap::new(n, &dofs);
        Free { dofs, dof_of }
    }

    /// The free unknowns of a box (`Support::Face`) after its force and cell weights are
    /// checked: all components eliminated on the clamped face, and the normal one on the
    /// lateral faces under `lateral = roller`.
    pub fn of_box(
        mesh: &Mesh,
        weights: &[f64],
        lateral: Lateral,
        force: [f64; 3],
        contact: &BodyContact,
    ) -> Result<Self, SolidAssemblyError> {
        if force.iter().any(|f| !f.is_finite()) {
            return Err(SolidAssemblyError::Force(force));
        }
        crate::fem::layers::validate_weights(mesh, weights)?;
        let d = mesh.dim;
        Ok(Free::new(mesh, |g: usize| {
            let (node, comp) = (g / d, g % d);
            contact.clamped[node] || (lateral == Lateral::Roller && comp >= 1 && mesh.on_lateral(node, comp))
        }))
    }
}

/// What a support assembles: its matrices, the load on the free unknowns (F(0) if it depends
/// on time, with its `forcing`), a body's frame, and `|Γ_C|`.
pub(super) struct Parts {
    pub matrices: Matrices,
    pub load: Vec<f64>,
    pub forcing: Option<Forcing>,
    pub frame: Option<super::body::BodyFrame>,
    pub contact_area: f64,
}

/// The weighted mass, the stiffness and the unit mass of a support.
pub(super) enum Matrices {
    /// Over all full indices (a body's, in its frames): their principal submatrices on the free
    /// unknowns are taken.
    All { mass: SpMat, stiffness: SpMat, unit: SpMat },
    /// Already on the free unknowns (the box's, assembled there by [`super::columns`]); the unit
    /// mass is assembled when first asked for ([`SolidSystem::mass_unit`]).
    Free { mass: SpMat, stiffness: SpMat },
}

/// Central differences' stiffness on a run's lean system ([`super::lean`]), shared by the
/// schemes built on it.
#[derive(Debug, Clone)]
pub struct LeanStiffness {
    /// The box's stencil or the assembled matrix in row-run form (which
    /// [`crate::linalg::Operator::is_matrix_free`] tells apart).
    pub operator: Arc<dyn crate::linalg::Operator>,
    /// The unit mass (ρ = 1) as a stencil, for the L² norms (None: assembled when first asked
    /// for, [`SolidSystem::mass_unit`]).
    pub unit_mass: Option<Arc<dyn crate::linalg::Operator>>,
    /// The divergence watch's `E_F`, made once ([`SolidSystem::lean_load_energy`]).
    pub load_energy: OnceLock<f64>,
    /// `S_rr` is singular (a body that keeps a rigid motion, [`super::body::BodyContact::keeps_rigid_motion`]): no `E_F`, the watch takes the
    /// free-flight scale.
    pub singular: bool,
}

/// The solid on its free unknowns: mesh, weights, material, the contact system and what the
/// reports need (module docs for the layout).
#[derive(Debug, Clone)]
pub struct SolidSystem {
    pub mesh: Arc<Mesh>,
    /// The cell weights of the normal component (of every component under `all`).
    pub weights: Vec<f64>,
    /// Which components take `weights` (the others the standard mass).
    pub directions: ContactDirections,
    pub lame: Lame,
    pub lateral: Lateral,
    /// Free unknown → full index `node·d + component`.
    pub dofs: Vec<usize>,
    /// Full index → free unknown (None where eliminated).
    pub dof_of: DofMap,
    pub system: ContactSystem<SpMat>,
    /// The unweighted vector mass with ρ = 1 on the free unknowns (for L² norms): a body's set
    /// when it is built, the box's assembled when first asked for ([`SolidSystem::mass_unit`]).
    mass_unit: OnceLock<SpMat>,
    /// The mesh nodes that meet the obstacle (contact order).
    pub contact_nodes: Vec<usize>,
    /// `∫_{Γ_C} φ_c` per contact node (its share of the face area; they sum to |Γ_C|).
    pub contact_areas: Vec<f64>,
    /// `|Γ_C|`: the box's face x = 0 (`Mesh::face_area`), a body's `Σ_i a_i`.
    pub contact_area: f64,
    /// A body against a plane: its frame and lumped masses (None: the box, whose frame is the
    /// world's; [`super::body_system`]). Unknowns are then components in the frame.
    pub frame: Option<super::body::BodyFrame>,
    /// Several bodies: the layout of their pairs' and bodies' reports (`super::report`).
    pub bodies: Option<super::bodies::BodiesLayout>,
    /// Central differences' lean system ([`SolidSystem::assemble_explicit`]): the stiffness as
    /// an operator, the system's own holding only the rows and columns of the massless
    /// unknowns. None: the system's stiffness is whole.
    pub(super) lean: Option<LeanStiffness>,
}

impl SolidSystem {
    /// Assembles M, S, F on the free unknowns of `support` on `mesh` with validated cell
    /// `weights` and the contact set of the support (`contact`): the box's load is the constant
    /// force weighted as the mass (module docs), a body's the interpolated force per unit volume
    /// in its frame ([`super::body_system`]).
    pub fn assemble(
        mesh: Arc<Mesh>,
        weights: Vec<f64>,
        directions: ContactDirections,
        lame: Lame,
        support: &Support,
        contact: &BodyContact,
    ) -> Result<Self, SolidAssemblyError> {
        match support {
            Support::Face { gap: _, lateral, force } => {
                let free = Free::of_box(&mesh, &weights, *lateral, *force, contact)?;
                let d = mesh.dim;
                // Straight into compressed columns (`super::columns`): no triplets. The weighted
                // mass over all full indices first, for the load's row sums, then its free part.
                let all = DofMap::identity(mesh.n_nodes() * d);
                let mass_all = super::columns::mass(&mesh, &weights, directions, lame.density, &all, all.len());
                drop(all);
                // F_(a,i) = f_i ∫ w_h φ_a = f_i Σ_b M_(a,i),(b,i) / ρ (the basis sums to 1).
                let mut row_sums = vec![0.0; mesh.n_nodes() * d];
                for (i, _, v) in sparse::triplets(&mass_all) {
                    row_sums[i] += v;
                }
                let load = free.dofs.iter().map(|&g| force[g % d] * row_sums[g] / lame.density).collect();
                drop(row_sums);
                let mass = sparse::principal(&mass_all, &free.dofs, "mass")?;
                drop(mass_all);
                let stiffness = super::columns::stiffness(&mesh, &lame, &free.dof_of, free.dofs.len());
                let contact_area = mesh.face_area();
                let matrices = Matrices::Free { mass, stiffness };
                let parts = Parts { matrices, load, forcing: None, frame: None, contact_area };
                Self::on_free(mesh, (weights, directions), lame, *lateral, free, parts, contact)
            }
            Support::Plane(body) => Self::assemble_body(mesh, (weights, directions), lame, body, contact, None),
            // `mesh` and `contact` are the joined bodies' (`SolidSpec::built`): joined again here.
            Support::Bodies(bodies) => {
                let joined = bodies.join()?;
                Self::assemble_bodies(weights, lame, bodies, &joined)
            }
        }
    }

    /// The system on the free unknowns from the assembled parts (contact unknowns: component 0
    /// of the contact nodes, bounded below by `0 − g_i`).
    pub(super) fn on_free(
        mesh: Arc<Mesh>,
        (weights, directions): (Vec<f64>, ContactDirections),
        lame: Lame,
        lateral: Lateral,
        free: Free,
        parts: Parts,
        contact: &BodyContact,
    ) -> Result<Self, SolidAssemblyError> {
        let Free { dofs, dof_of } = free;
        let d = mesh.dim;
        let (mass, stiffness, mass_unit) = match parts.matrices {
            Matrices::All { mass, stiffness, unit } => {
                // Each whole matrix gives way to its free part before the next is copied, and a
                // body without a clamped node keeps its matrices (all its unknowns are free).
                let free = |a: SpMat, name| {
                    if dofs.len() == a.nrows() { Ok(a) } else { sparse::principal(&a, &dofs, name) }
                };
                (free(mass, "mass")?, free(stiffness, "stiffness")?, OnceLock::from(free(unit, "mass")?))
            }
            Matrices::Free { mass, stiffness } => (mass, stiffness, OnceLock::new()),
        };
        let unknowns =
            contact.nodes.iter().map(|&v| dof_of.get(v * d).expect("contact nodes are not clamped")).collect();
        let mut system = ContactSystem::new(mass, stiffness, parts.load, unknowns, 0.0);
        // Components 1.. of the contact nodes in the obstacle's frame (the box's: the world's),
        // and the world directions of those axes, R e_k: one list for a global frame, each
        // node's own under per-node frames (node i's axis k at i (d − 1) + k − 1).
        let axis = |r: &[[f64; 3]; 3], k: usize| {
            let mut e = [0.0; 3];
            e[k] = 1.0;
            super::body::from_frame(r, e)
        };
        let per_node = parts.frame.as_ref().and_then(|f| match &f.frames {
            super::body::Frames::Nodes(r) => Some(r),
            super::body::Frames::Global(_) => None,
        });
        let axes = match per_node {
            Some(r) => contact.nodes.iter().flat_map(|&v| (1..d).map(move |k| axis(&r[v], k))).collect(),
            None => (1..d)
                .map(|k| {
                    let mut e = [0.0; 3];
                    e[k] = 1.0;
                    parts.frame.as_ref().map_or(e, |f| axis(f.frames.of(0), k))
                })
                .collect(),
        };
        let offset = |slot: usize| if per_node.is_some() { slot * (d - 1) } else { 0 };
        system.tangential = Some(crate::system::Tangential {
            unknowns: contact.nodes.iter().map(|&v| (1..d).filter_map(|i| dof_of.get(v * d + i)).collect()).collect(),
            components: contact
                .nodes
                .iter()
                .enumerate()
                .map(|(slot, &v)| (1..d).filter(|&i| dof_of.is_free(v * d + i)).map(|i| offset(slot) + i - 1).collect())
                .collect(),
            areas: contact.areas.clone(),
            axes,
        });
        // 0 − g, not −g: no −0.0 bound (the box's 0 − gap).
        system.lower = contact.gaps.iter().map(|&g| 0.0 - g).collect();
        if let Some(forcing) = parts.forcing {
            system = system.with_forcing(forcing);
        }
        let contact_area = parts.contact_area;
        Ok(Self {
            mesh,
            weights,
            directions,
            lame,
            lateral,
            dofs,
            dof_of,
            system,
            mass_unit,
            contact_nodes: contact.nodes.clone(),
            contact_areas: contact.areas.clone(),
            contact_area,
            frame: parts.frame,
            bodies: None,
            lean: None,
        })
    }

    /// The unweighted vector mass with ρ = 1 on the free unknowns (for L² norms): a body's
    /// built with it, the box's assembled on first use (a run without an exact solution never
    /// holds it).
    pub fn mass_unit(&self) -> &SpMat {
        self.mass_unit.get_or_init(|| {
            let ones = vec![1.0; self.mesh.n_cells()];
            super::columns::mass(&self.mesh, &ones, ContactDirections::All, 1.0, &self.dof_of, self.dofs.len())
        })
    }

    /// `xᵀ M_1 x` with the unit mass ([`Self::mass_unit`]; a lean box's stencil of it,
    /// [`super::lean`]).
    pub fn unit_quad_form(&self, x: &[f64]) -> f64 {
        match self.lean.as_ref().and_then(|l| l.unit_mass.as_ref()) {
            Some(m) => m.quad_form(x),
            None => sparse::quad_form(self.mass_unit(), x),
        }
    }

    /// The nodal interpolant of a vector field g(x) (component i of g at `x`, world
    /// components) on the free unknowns (a body's: in its frame, Rᵀ g).
    pub fn interpolate(&self, g: impl Fn(usize, [f64; 3]) -> f64) -> Vec<f64> {
        self.interpolate_nodes(|_, i, p| g(i, p))
    }

    /// [`SolidSystem::interpolate`] of a field that also depends on the node, `g(node, i, x)`
    /// (several bodies: each its own data), mapped to the pairs' variables z = T⁻¹ u'.
    pub fn interpolate_nodes(&self, g: impl Fn(usize, usize, [f64; 3]) -> f64) -> Vec<f64> {
        let d = self.mesh.dim;
        let Some(frame) = &self.frame else {
            return self.dofs.iter().map(|&k| g(k / d, k % d, self.mesh.points[k / d])).collect();
        };
        let at = |node: usize| {
            let p = self.mesh.points[node];
            let mut w = [0.0; 3];
            for (i, x) in w[..d].iter_mut().enumerate() {
                *x = g(node, i, p);
            }
            super::body::to_frame(frame.frames.of(node), w)
        };
        let mut z: Vec<f64> = self.dofs.iter().map(|&k| at(k / d)[k % d]).collect();
        frame.coupling.unapply(&mut z);
        z
    }

    /// The free unknowns in the frames, u' = T z (the pairs' change of variables; z itself for
    /// one body).
    pub fn in_frames<'a>(&self, z: &'a [f64]) -> std::borrow::Cow<'a, [f64]> {
        match &self.frame {
            Some(f) if !f.coupling.is_empty() => {
                let mut u = z.to_vec();
                f.coupling.apply(&mut u);
                std::borrow::Cow::Owned(u)
            }
            _ => std::borrow::Cow::Borrowed(z),
        }
    }

    /// Total mass `Σ_c w_c ρ |c| = ∫ ρ w_h` (of the normal component; of every component
    /// under `mass.contact_directions = "all"`).
    pub fn total_mass(&self) -> f64 {
        self.lame.density * crate::fem::layers::total_mass(&self.mesh, &self.weights)
    }

    /// Values on all full indices (0 where eliminated), interleaved `node·d + component`
    /// (a body's rotated back to world components, R u').
    pub fn to_nodes(&self, u: &[f64], out: &mut [f64]) {
        let u = self.in_frames(u);
        for (g, k) in self.dof_of.iter().enumerate() {
            out[g] = k.map_or(0.0, |k| u[k]);
        }
        if let Some(frame) = &self.frame {
            let d = self.mesh.dim;
            for (k, node) in out.chunks_mut(d).enumerate() {
                let mut w = [0.0; 3];
                w[..d].copy_from_slice(node);
                node.copy_from_slice(&super::body::from_frame(frame.frames.of(k), w)[..d]);
            }
        }
    }
}
