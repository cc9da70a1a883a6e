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
use super::body_system::UnitMass;
use super::dof_map::DofMap;
use crate::fem::Mesh;
use crate::linalg::sparse;
use crate::mass::ContactDirections;
use crate::material::Lame;
use crate::schemes::StiffnessOperator;
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
        explicit: Option<StiffnessOperator>,
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
        if let Some(choice) = explicit {
            return Self::curved_lean(mesh, (weights, directions), lame, (body, contact), frames, choice);
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

impl SolidSystem {
    /// Central differences' lean system of a body against a curved obstacle ([`super::lean`]):
    /// the entries of [`frame_matrices`] in compressed columns ([`super::columns::assemble_on`]
    /// with the blocks of [`mass_block`] and [`stiffness_in_frames`], the same sums in the same
    /// order: bit for bit), and of them only what the run reads, each dropped before the next is
    /// made: the weighted mass `M'` for the momentum rows `L_b`; the stiffness as the row-run
    /// operator and its massless rows and columns; then the load from each cell's unit mass
    /// ([`UnitMass`], kept through the run when the force depends on time). The
    /// lumped mass is the diagonal (frame-free: [`super::lumped`]). No element triplets and no
    /// unit mass `M¹'` (a body has no L² error).
    fn curved_lean(
        mesh: Arc<Mesh>,
        (weights, directions): (Vec<f64>, ContactDirections),
        lame: Lame,
        (body, contact): (&BodySpec, &BodyContact),
        frames: Vec<[[f64; 3]; 3]>,
        choice: StiffnessOperator,
    ) -> Result<Self, SolidAssemblyError> {
        use super::columns::assemble_on;
        let d = mesh.dim;
        // Nodes a and b couple in every component pair where their frames differ (the
        // triplets' `q != IDENTITY`, the same per pair in every cell).
        let full = |a: usize, b: usize| relative(&frames[a], &frames[b]) != IDENTITY;
        let momentum = {
            let all = DofMap::identity(mesh.n_nodes() * d);
            let mass_all = assemble_on(&mesh, &all, all.len(), full, None, |c, e, a, b| {
                let v = mesh.cell(c);
                let q = relative(&frames[v[a]], &frames[v[b]]);
                mass_block(e.mass[a][b], weights[c], directions, lame.density, &q, d)
            });
            momentum_rows(&mass_all, &frames, d)
        };
        let [lumped, lumped_tangential, lumped_unit] =
            super::lumped::frame_lumps(&mesh, &weights, directions, lame.density);
        let free = Free::new(&mesh, |g| contact.clamped[g / d]);
        let n = free.dofs.len();
        let lumped_free = super::lumped::lumped_on(&mesh, &weights, directions, lame.density, &free.dofs);
        let massless: Vec<bool> = lumped_free.iter().map(|&m| m <= 0.0).collect();
        let block = |c: usize, e: &crate::fem::element::CellIntegrals, a: usize, b: usize| {
            let v = mesh.cell(c);
            stiffness_in_frames(super::columns::stiffness_block(e, &lame, a, b, d), &frames[v[a]], &frames[v[b]], d)
        };
        let stiffness = super::columns::touching(&mesh, &free.dof_of, n, &massless, block);
        drop(massless);
        let operator = super::lean::cell_operator(
            choice,
            (&mesh, lame),
            &free.dof_of,
            Some(Frames::Nodes(frames.clone())),
            || assemble_on(&mesh, &free.dof_of, n, |_, _| true, None, block),
        )?;
        // The load after the stiffness: a force that depends on time keeps its unit mass through
        // the run, and it is then not on top of the stiffness's assembly (the set-up's peak).
        let forces = vec![(0, body.force.clone())];
        let (load, forcing) = super::body_system::body_load(
            &mesh,
            &free,
            Frames::Nodes(frames.clone()),
            forces,
            UnitMass::of(&mesh),
            Default::default(),
        );
        let mass = super::lean::diagonal(&lumped_free)?;
        drop(lumped_free);
        let contact_area = contact.areas.iter().sum();
        let volume = lumped_unit.iter().sum();
        let frame = BodyFrame {
            frames: Frames::Nodes(frames),
            momentum,
            lumped,
            lumped_tangential,
            lumped_unit,
            volume,
            contact_area,
            coupling: Default::default(),
        };
        let parts =
            Parts { matrices: Matrices::Free { mass, stiffness }, load, forcing, frame: Some(frame), contact_area };
        Self::lean_body(mesh, (weights, directions), lame, free, parts, contact, operator)
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
    /// The scalar unit mass of the load, cell by cell.
    pub scalar_unit: UnitMass,
}

/// The block `M'_ab` of one cell (module docs) for `m = ∫_c φ_a φ_b`, cell weight `w` and
/// `q = R_aᵀ R_b`: only its diagonal where `q` is the identity (`ρ w^(i) m`).
fn mass_block(
    m: f64,
    w: f64,
    directions: ContactDirections,
    density: f64,
    q: &[[f64; 3]; 3],
    d: usize,
) -> [[f64; 3]; 3] {
    let mut x = [[0.0; 3]; 3];
    if *q == IDENTITY {
        for (i, row) in x.iter_mut().enumerate().take(d) {
            row[i] = density * directions.weight(i, w) * m;
        }
        return x;
    }
    let scale: Vec<f64> = (0..d).map(|i| directions.weight(i, w).sqrt()).collect();
    for (i, row) in x.iter_mut().enumerate().take(d) {
        for (j, y) in row.iter_mut().enumerate().take(d) {
            *y = density * m * scale[i] * q[i][j] * scale[j];
        }
    }
    x
}

/// `R_aᵀ S R_b` of the world block `s` ([`super::columns::stiffness_block`]): `s` itself where
/// both frames are the world's.
fn stiffness_in_frames(s: [[f64; 3]; 3], ra: &[[f64; 3]; 3], rb: &[[f64; 3]; 3], d: usize) -> [[f64; 3]; 3] {
    if *ra == IDENTITY && *rb == IDENTITY {
        return s;
    }
    let mut x = [[0.0; 3]; 3];
    for (i, row) in x.iter_mut().enumerate().take(d) {
        for (j, y) in row.iter_mut().enumerate().take(d) {
            // (R_aᵀ S R_b)_ij = Σ_kl R_a[k][i] S_kl R_b[l][j].
            let mut sum = 0.0;
            for kk in 0..d {
                for l in 0..d {
                    sum += ra[kk][i] * s[kk][l] * rb[l][j];
                }
            }
            *y = sum;
        }
    }
    x
}

/// M', S', M¹' and the momentum rows of `mesh` with one frame per node (module docs), from
/// element triplets: the whole system's (every scheme but central differences, whose lean
/// system is [`SolidSystem::curved_lean`]'s, the same entries in compressed columns).
pub(super) fn frame_matrices(
    mesh: &Arc<Mesh>,
    weights: &[f64],
    directions: ContactDirections,
    lame: &Lame,
    frames: &[[[f64; 3]; 3]],
) -> Result<FrameMatrices, sparse::SparseError> {
    let (d, n_nodes) = (mesh.dim, mesh.n_nodes());
    let k = mesh.kind.verts();
    let (mut tm, mut ts, mut tu) = (Vec::new(), Vec::new(), Vec::new());
    for (c, &w) in weights.iter().enumerate() {
        let e = mesh.integrals(c);
        let v = mesh.cell(c);
        for a in 0..k {
            for b in 0..k {
                let (ra, rb) = (&frames[v[a]], &frames[v[b]]);
                let q = relative(ra, rb);
                let m = e.mass[a][b];
                let mass = mass_block(m, w, directions, lame.density, &q, d);
                let unit = mass_block(m, 1.0, ContactDirections::All, 1.0, &q, d);
                let s = stiffness_in_frames(super::columns::stiffness_block(&e, lame, a, b, d), ra, rb, d);
                for i in 0..d {
                    for j in 0..d {
                        let (row, col) = (v[a] * d + i, v[b] * d + j);
                        if q != IDENTITY || i == j {
                            tm.push((row, col, mass[i][j]));
                            tu.push((row, col, unit[i][j]));
                        }
                        ts.push((row, col, s[i][j]));
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
    let momentum = momentum_rows(&mass_all, frames, d);
    let [lumped, lumped_tangential, lumped_unit] = super::lumped::frame_lumps(mesh, weights, directions, lame.density);
    let scalar_unit = UnitMass::of(mesh);
    Ok(FrameMatrices { mass_all, stiff_all, unit_all, momentum, lumped, lumped_tangential, lumped_unit, scalar_unit })
}

/// `L_b = Σ_a R_a M'_ab` per node from the whole `M'` (full indices), its entries in column
/// order.
fn momentum_rows(mass_all: &sparse::SpMat, frames: &[[[f64; 3]; 3]], d: usize) -> Vec<[[f64; 3]; 3]> {
    let mut momentum = vec![[[0.0; 3]; 3]; frames.len()];
    for (row, col, x) in sparse::triplets(mass_all) {
        let (a, i, b, j) = (row / d, row % d, col / d, col % d);
        for kk in 0..d {
            momentum[b][kk][j] += frames[a][kk][i] * x;
        }
    }
    momentum
}
