//! The contact system of a body against a curved obstacle (issue 30; [`super::surface`]): the
//! unknowns of each contact node in its own frame R_i (first column n_i, [`super::body::rotation`]),
//! so that component 0 of a contact node is its normal displacement with the bound
//! `u'_0 ≥ −g_i`; every other node in the world frame (R = I), except under
//! `mass.contact_directions = "normal"` a node of a cell with a weight ≠ 1, whose frame is
//! that of the obstacle's normal at the node (its normal component takes the weights).
//!
//! With the world element blocks `m^c_ab = ∫_c φ_a φ_b` and `S^c_ab` (d × d, as in
//! [`super::assembly::assemble`]), each cell adds, in the frames,
//!
//! ```text
//! M'_ab += ρ m^c_ab D_a R_aᵀ R_b D_b,    D = diag(√w_c^(0), …, √w_c^(d−1))   (w^(i) as in
//!                                                                            ContactDirections),
//! S'_ab += R_aᵀ S^c_ab R_b,              M¹'_ab += m^c_ab R_aᵀ R_b   (ρ = 1, unweighted),
//! ```
//!
//! symmetric and positive semi-definite cell by cell (M' = Dᵀ Tᵀ (m^c ⊗ I) T D with T the
//! block-diagonal frames); with one frame for all nodes it is the plane's system
//! ([`super::body_system`]) written in that frame. A diagonal block of a node (R_aᵀ R_a = I)
//! takes `w^(i)` itself, not `√w^(i)²`. The load is `F_a = R_aᵀ Σ_b m_ab f(X_b)` and the
//! momentum `P = Σ_b L_b v_b`, `L_b = Σ_a R_a M'_ab` (the consistent mass's `1ᵀ M V`).

use super::assembly::{Free, Matrices, Parts, SolidAssemblyError, SolidSystem};
use super::body::{BodyContact, BodyFrame, BodySpec, Frames, rotation};
use crate::fem::Mesh;
use crate::linalg::sparse;
use crate::mass::ContactDirections;
use crate::material::Lame;
use std::sync::Arc;

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// `R_aᵀ R_b` (the identity, exactly, for one frame).
fn relative(ra: &[[f64; 3]; 3], rb: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    if ra == rb {
        return IDENTITY;
    }
    let mut q = [[0.0; 3]; 3];
    for (i, row) in q.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (0..3).map(|k| ra[k][i] * rb[k][j]).sum();
        }
    }
    q
}

impl SolidSystem {
    /// A body against a curved obstacle (module docs).
    pub(super) fn assemble_curved(
        mesh: Arc<Mesh>,
        (weights, directions): (Vec<f64>, ContactDirections),
        lame: Lame,
        body: &BodySpec,
        contact: &BodyContact,
    ) -> Result<Self, SolidAssemblyError> {
        let d = mesh.dim;
        let n_nodes = mesh.n_nodes();
        let mut frames = vec![IDENTITY; n_nodes];
        if directions == ContactDirections::Normal {
            let level = body.obstacle.surface.level(d);
            for (c, &w) in weights.iter().enumerate() {
                if w == 1.0 {
                    continue;
                }
                for &v in mesh.cell(c) {
                    if frames[v] != IDENTITY || contact.contact[v] {
                        continue;
                    }
                    let p = mesh.points[v];
                    let Some((_, n)) = level.gap_normal(p) else {
                        let at = p[..d].iter().map(|x| crate::numfmt::fmt_f64(*x)).collect::<Vec<_>>().join(", ");
                        let grad = level.at(p).1[..d].iter().map(|x| crate::numfmt::fmt_f64(*x)).collect::<Vec<_>>();
                        let grad = format!("[{}]", grad.join(", "));
                        let shape = body.obstacle.surface.name();
                        return Err(super::body::BodyError::NoNormal { node: v, at, grad, shape }.into());
                    };
                    frames[v] = rotation(n, d);
                }
            }
        }
        for (&v, &n) in contact.nodes.iter().zip(&contact.normals) {
            frames[v] = rotation(n, d);
        }
        let m = frame_matrices(&mesh, &weights, directions, &lame, &frames)?;
        let (mass_all, stiff_all, unit_all, momentum) = (m.mass_all, m.stiff_all, m.unit_all, m.momentum);
        let (lumped, lumped_tangential, lumped_unit) = (m.lumped, m.lumped_tangential, m.lumped_unit);
        let free = Free::new(&mesh, |g| contact.clamped[g / d]);
        let scalar_unit = m.scalar_unit;
        let frames = Frames::Nodes(frames);
        let forces = vec![(0, body.force.clone())];
        let (load, forcing) =
            super::body_system::body_load(&mesh, &free, frames.clone(), forces, scalar_unit, Default::default());
        let contact_area = contact.areas.iter().sum();
        let volume = lumped_unit.iter().sum();
        let coupling = Default::default();
        let frame =
            BodyFrame { frames, momentum, lumped, lumped_tangential, lumped_unit, volume, contact_area, coupling };
        let matrices = Matrices::All { mass: mass_all, stiffness: stiff_all, unit: unit_all };
        let parts = Parts { matrices, load, forcing, frame: Some(frame), contact_area };
        Self::on_free(mesh, (weights, directions), lame, super::Lateral::Free, free, parts, contact)
    }
}

/// What [`frame_matrices`] assembles (full indices `node·d + c`, in the frames).
pub(super) struct FrameMatrices {
    pub mass_all: sparse::SpMat,
    pub stiff_all: sparse::SpMat,
    pub unit_all: sparse::SpMat,
    /// `L_b = Σ_a R_a M'_ab` per node.
    pub momentum: Vec<[[f64; 3]; 3]>,
    pub lumped: Vec<f64>,
    pub lumped_tangential: Vec<f64>,
    pub lumped_unit: Vec<f64>,
    /// The scalar unit-mass triplets (node a, node b, ∫ φ_a φ_b) of the load.
    pub scalar_unit: Vec<(usize, usize, f64)>,
}

/// M', S', M¹' and the momentum rows of `mesh` with one frame per node (module docs).
pub(super) fn frame_matrices(
    mesh: &Mesh,
    weights: &[f64],
    directions: ContactDirections,
    lame: &Lame,
    frames: &[[[f64; 3]; 3]],
) -> Result<FrameMatrices, sparse::SparseError> {
    let (d, n_nodes) = (mesh.dim, mesh.n_nodes());
    let k = mesh.kind.verts();
    let (mut tm, mut ts, mut tu) = (Vec::new(), Vec::new(), Vec::new());
    let (mut lumped, mut lumped_tangential, mut lumped_unit) =
        (vec![0.0; n_nodes], vec![0.0; n_nodes], vec![0.0; n_nodes]);
    for (c, &w) in weights.iter().enumerate() {
        let e = mesh.integrals(c);
        let v = mesh.cell(c);
        let scale: Vec<f64> = (0..d).map(|i| directions.weight(i, w).sqrt()).collect();
        for a in 0..k {
            for b in 0..k {
                let (ra, rb) = (&frames[v[a]], &frames[v[b]]);
                let q = relative(ra, rb);
                let m = e.mass[a][b];
                lumped[v[b]] += lame.density * w * m;
                lumped_tangential[v[b]] += lame.density * directions.weight(1, w) * m;
                lumped_unit[v[b]] += m;
                // The world stiffness block (`columns::stiffness_block`).
                let s = super::columns::stiffness_block(&e, lame, a, b, d);
                let world = *ra == IDENTITY && *rb == IDENTITY;
                for i in 0..d {
                    for j in 0..d {
                        let (row, col) = (v[a] * d + i, v[b] * d + j);
                        if q == IDENTITY {
                            if i == j {
                                tm.push((row, col, lame.density * directions.weight(i, w) * m));
                                tu.push((row, col, m));
                            }
                        } else {
                            tm.push((row, col, lame.density * m * scale[i] * q[i][j] * scale[j]));
                            tu.push((row, col, m * q[i][j]));
                        }
                        if world {
                            ts.push((row, col, s[i][j]));
                            continue;
                        }
                        // (R_aᵀ S R_b)_ij = Σ_kl R_a[k][i] S_kl R_b[l][j].
                        let mut x = 0.0;
                        for kk in 0..d {
                            for l in 0..d {
                                x += ra[kk][i] * s[kk][l] * rb[l][j];
                            }
                        }
                        ts.push((row, col, x));
                    }
                }
            }
        }
    }
    let n = n_nodes * d;
    let mass_all = sparse::from_triplets(n, &tm, "mass")?;
    let stiff_all = sparse::from_triplets(n, &ts, "stiffness")?;
    let unit_all = sparse::from_triplets(n, &tu, "mass")?;
    drop((tm, ts, tu));
    let mut momentum = vec![[[0.0; 3]; 3]; n_nodes];
    for (row, col, x) in sparse::triplets(&mass_all) {
        let (a, i, b, j) = (row / d, row % d, col / d, col % d);
        for kk in 0..d {
            momentum[b][kk][j] += frames[a][kk][i] * x;
        }
    }
    let mut scalar_unit = Vec::new();
    for c in 0..mesh.n_cells() {
        let e = mesh.integrals(c);
        let v = mesh.cell(c);
        for a in 0..k {
            for b in 0..k {
                scalar_unit.push((v[a], v[b], e.mass[a][b]));
            }
        }
    }
    Ok(FrameMatrices { mass_all, stiff_all, unit_all, momentum, lumped, lumped_tangential, lumped_unit, scalar_unit })
}
