//! The contact system of several bodies ([`super::bodies`], [`super::pair`]): the joined mesh
//! assembled with one frame per node (`super::curved`'s [`frame_matrices`]: a pair's
//! first-group node i in the frame R_i whose first column is ν_i, every other node in the
//! world's), then the pairs' change of variables u' = T z applied by congruence,
//!
//! ```text
//! M_z = Tᵀ M' T,   S_z = Tᵀ S' T,   M¹_z = Tᵀ M¹' T,   F_z = Tᵀ F',
//! ```
//!
//! so that the contact unknown of node i is w_i = d_i − g_i with the bound w_i ≥ −g_i. The
//! momentum rows L_b = Σ_a R_a M'_ab are those of M' (P = Σ_b L_b v'_b with v' = T v_z), and the
//! reports map z back to u' = T z ([`super::body::BodyFrame::coupling`]).

use super::assembly::{Free, Matrices, Parts, SolidAssemblyError, SolidSystem};
use super::bodies::{Bodies, Joined};
use super::body::{BodyFrame, Frames, rotation};
use super::coupling::Coupling;
use super::curved::frame_matrices;
use super::report::{BodiesLayout, dotted_columns};
use crate::linalg::sparse;
use crate::mass::ContactDirections;
use crate::material::Lame;

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

impl SolidSystem {
    /// Several bodies in contact (module docs), with validated cell `weights` (each body's own,
    /// [`Bodies::weights`]); the masses take the weights in every direction.
    pub(super) fn assemble_bodies(
        weights: Vec<f64>,
        lame: Lame,
        bodies: &Bodies,
        joined: &Joined,
    ) -> Result<Self, SolidAssemblyError> {
        let mesh = std::sync::Arc::clone(&joined.mesh);
        let (d, n_nodes) = (mesh.dim, mesh.n_nodes());
        let contact = &joined.contact;
        let mut frames = vec![IDENTITY; n_nodes];
        for (&v, &n) in contact.nodes.iter().zip(&contact.normals) {
            frames[v] = rotation(n, d);
        }
        let directions = ContactDirections::All;
        let m = frame_matrices(&mesh, &weights, directions, &lame, &frames)?;
        let frames = Frames::Nodes(frames);
        let nodes = joined
            .pairs
            .iter()
            .flat_map(|p| p.nodes.iter().zip(&p.normals).zip(&p.masters).map(|((&i, &nv), m)| (i, nv, m.as_slice())));
        let full = Coupling::new(nodes, |k| *frames.of(k), d);
        let n = n_nodes * d;
        let congruent =
            |a: &sparse::SpMat, name| sparse::from_triplets(n, &full.congruence(n, sparse::triplets(a)), name);
        let mass_all = congruent(&m.mass_all, "mass")?;
        let stiff_all = congruent(&m.stiff_all, "stiffness")?;
        let unit_all = congruent(&m.unit_all, "mass")?;
        let free = Free::new(&mesh, |g| contact.clamped[g / d]);
        let coupling = full.on_free(&free.dof_of);
        let forces = bodies.bodies.iter().zip(&joined.node0).map(|(b, &first)| (first, b.force.clone())).collect();
        let (load, forcing) =
            super::body_system::body_load(&mesh, &free, frames.clone(), forces, m.scalar_unit, coupling.clone());
        let contact_area = contact.areas.iter().sum();
        let volume = m.lumped_unit.iter().sum();
        let m_volumes: Vec<f64> = joined.node0.windows(2).map(|w| m.lumped_unit[w[0]..w[1]].iter().sum()).collect();
        let frame = BodyFrame {
            frames,
            momentum: m.momentum,
            lumped: m.lumped,
            lumped_tangential: m.lumped_tangential,
            lumped_unit: m.lumped_unit,
            volume,
            contact_area,
            coupling,
        };
        let matrices = Matrices::All { mass: mass_all, stiffness: stiff_all, unit: unit_all };
        let parts = Parts { matrices, load, forcing, frame: Some(frame), contact_area };
        let mut system = Self::on_free(mesh, (weights, directions), lame, super::Lateral::Free, free, parts, contact)?;
        system.bodies = Some(layout(bodies, joined, &m_volumes));
        Ok(system)
    }
}

/// The layout of the bodies' reports (`super::report`): names, slots, first nodes, volumes.
pub fn layout(bodies: &Bodies, joined: &Joined, volumes: &[f64]) -> BodiesLayout {
    let pairs: Vec<String> = bodies.pairs.iter().map(|p| p.name.clone()).collect();
    let names: Vec<String> = bodies.bodies.iter().map(|b| b.name.clone()).collect();
    let dotted = dotted_columns(&pairs, &names, joined.mesh.dim);
    let columns = super::report::COLUMNS.iter().copied().chain(dotted).collect();
    BodiesLayout {
        pairs,
        bodies: names,
        slots: joined.slots.clone(),
        node0: joined.node0.clone(),
        volumes: volumes.to_vec(),
        columns,
    }
}
