//! The contact system of a body against a rigid plane ([`super::body`] for the definitions):
//! assembled in the frame X' = Rᵀ X whose first axis is the plane's normal, so that the contact
//! unknown of a node is component 0 with the bound `u'_0 ≥ −g_i`.
//!
//! ```text
//! M_(a,i),(b,j) = δ_ij ρ Σ_c w_c ∫_c φ_a φ_b          (weighted, w from the contact layers),
//! S as for the box (isotropic: the same in any orthonormal frame),
//! F_(a,i)(t) = Σ_b (∫_Ω φ_a φ_b) f'_i(X_b, t),  f' = Rᵀ f,
//! ```
//!
//! the load of the nodal interpolant of the force per unit volume, `∫_Ω I_h f · v`: neither
//! multiplied by ρ nor weighted (exact for f affine in x on P1 and Q1 parallelogram cells, in
//! particular for gravity). All components of the clamped nodes are eliminated; no other node
//! is constrained (a free body has none).
//!
//! What the reports need, over all nodes (clamped rows included, where V = 0):
//! `P_k = 1ᵀ M V_k = Σ_b m_b,k v_b,k` with `m_b,k = Σ_a M_(a,k),(b,k)` (the weighted lumped mass
//! of component k: the tangential ones standard under `mass.contact_directions = "normal"`), and the
//! mean displacement `ū_k = Σ_b m¹_b u_b,k / |Ω|` with the unweighted, ρ = 1 lumped mass m¹
//! (both computed in the frame and rotated back by R).

use super::assembly::{Free, Matrices, Parts, SolidAssemblyError, SolidSystem};
pub use super::body::BodyFrame;
use super::body::{BodyContact, BodySpec, Frames, from_frame, rotation, to_frame};
use super::columns;
use super::dof_map::DofMap;
use crate::expr::Expr;
use crate::fem::Mesh;
use crate::linalg::sparse;
use crate::mass::ContactDirections;
use crate::material::Lame;
use crate::schemes::StiffnessOperator;
use crate::system::Forcing;
use std::sync::Arc;

/// The scalar unit mass `∫ φ_a φ_b` a body's load is taken with ([`body_load`]).
pub(super) enum UnitMass {
    /// Entries (node a, node b, ∫ φ_a φ_b), summed in their order (the implicit schemes'
    /// system against a plane, from its assembled unit mass); node numbers in 32 bits, 16 bytes
    /// an entry (a mesh of 2³² nodes is far beyond the memory validation admits).
    Pairs(Vec<(u32, u32, f64)>),
    /// Each cell's k × k element matrix `∫_c φ_a φ_b`, row by row, cells in the mesh's order:
    /// the sums of the cells' triplets in their order (cell, a, b). Computed from the mesh
    /// where it is read (`stored` None: a force constant in time reads it once, at set-up, and
    /// nothing is kept: issue 31's peak memory), or stored, 8 bytes an entry (a force that
    /// depends on time reads it at every step: [`body_load`] stores it then). Either gives the
    /// same bits. A curved obstacle's, several bodies' and central differences' lean load.
    Cells { mesh: Arc<Mesh>, stored: Option<Vec<f64>> },
}

impl UnitMass {
    /// The unit mass of `mesh`'s cells, computed where it is read.
    pub(super) fn of(mesh: &Arc<Mesh>) -> Self {
        UnitMass::Cells { mesh: Arc::clone(mesh), stored: None }
    }

    /// Calls `f(a, b, ∫ φ_a φ_b)` for every entry, in the order of the sums.
    fn for_each(&self, mut f: impl FnMut(usize, usize, f64)) {
        let (mesh, stored) = match self {
            UnitMass::Pairs(p) => return p.iter().for_each(|&(a, b, m)| f(a as usize, b as usize, m)),
            UnitMass::Cells { mesh, stored } => (mesh, stored),
        };
        let k = mesh.kind.verts();
        let mut emit = |c: usize, block: &[f64]| {
            let v = mesh.cell(c);
            for (a, row) in block.chunks_exact(k).enumerate() {
                for (&vb, &m) in v.iter().zip(row) {
                    f(v[a], vb, m);
                }
            }
        };
        match stored {
            Some(m) => m.chunks_exact(k * k).enumerate().for_each(|(c, block)| emit(c, block)),
            None => {
                let mut block = Vec::with_capacity(k * k);
                for c in 0..mesh.n_cells() {
                    block.clear();
                    cell_unit_mass(mesh, c, &mut block);
                    emit(c, &block);
                }
            }
        }
    }

    /// The cells' matrices computed once and kept (pairs as they are).
    fn stored(self) -> Self {
        let UnitMass::Cells { mesh, stored: None } = self else { return self };
        let k = mesh.kind.verts();
        let mut unit = Vec::with_capacity(mesh.n_cells() * k * k);
        (0..mesh.n_cells()).for_each(|c| cell_unit_mass(&mesh, c, &mut unit));
        UnitMass::Cells { mesh, stored: Some(unit) }
    }
}

/// Appends cell c's `∫_c φ_a φ_b`, row by row, to `out`.
fn cell_unit_mass(mesh: &Mesh, c: usize, out: &mut Vec<f64>) {
    let k = mesh.kind.verts();
    let e = mesh.integrals(c);
    for row in &e.mass[..k] {
        out.extend_from_slice(&row[..k]);
    }
}

/// The load `F(t)` on the free unknowns (module docs): the scalar unit mass, the free index of
/// (a, i), the rotation and the force expressions.
struct BodyLoad {
    unit: UnitMass,
    dof_of: DofMap,
    frames: Frames,
    /// The force of the nodes from each first node on (one body: one entry, node 0).
    force: Vec<(usize, Vec<Expr>)>,
    points: Vec<[f64; 3]>,
    dim: usize,
}

impl BodyLoad {
    /// F(t) into `out` (free unknowns).
    fn at(&self, t: f64, out: &mut [f64]) {
        let d = self.dim;
        let mut args = [0.0; 4];
        let world = |v: usize, args: &mut [f64; 4]| {
            let p = &self.points[v];
            args[..d].copy_from_slice(&p[..d]);
            args[d] = t;
            let mut w = [0.0; 3];
            let force = &self.force[self.force.partition_point(|(first, _)| *first <= v) - 1].1;
            for (k, e) in force.iter().enumerate() {
                w[k] = e.eval(&args[..d + 1]);
            }
            w
        };
        out.fill(0.0);
        let Frames::Global(rot) = &self.frames else {
            // Per-node frames: F_a = R_aᵀ Σ_b (∫ φ_a φ_b) f(X_b).
            let f: Vec<[f64; 3]> = (0..self.points.len()).map(|v| world(v, &mut args)).collect();
            let mut sum = vec![[0.0; 3]; self.points.len()];
            self.unit.for_each(|a, b, m| {
                for i in 0..d {
                    sum[a][i] += m * f[b][i];
                }
            });
            for (a, s) in sum.iter().enumerate() {
                let s = to_frame(self.frames.of(a), *s);
                for (i, si) in s[..d].iter().enumerate() {
                    if let Some(k) = self.dof_of.get(a * d + i) {
                        out[k] = *si;
                    }
                }
            }
            return;
        };
        let f: Vec<[f64; 3]> = (0..self.points.len()).map(|v| to_frame(rot, world(v, &mut args))).collect();
        self.unit.for_each(|a, b, m| {
            for (i, fb) in f[b][..d].iter().enumerate() {
                if let Some(k) = self.dof_of.get(a * d + i) {
                    out[k] += m * fb;
                }
            }
        });
    }
}

/// The load F(0) on the free unknowns and, if the force depends on t, its forcing (module
/// docs): `unit` the scalar unit-mass triplets (node a, node b, ∫ φ_a φ_b), `force` the
/// expressions of the nodes from each first node on (one body: `[(0, its force)]`), `coupling`
/// the pairs' Tᵀ on the free unknowns (`super::pair`; empty for one body).
pub(super) fn body_load(
    mesh: &Mesh,
    free: &Free,
    frames: Frames,
    force: Vec<(usize, Vec<Expr>)>,
    unit: UnitMass,
    coupling: super::coupling::Coupling,
) -> (Vec<f64>, Option<Forcing>) {
    let transient = force.iter().flat_map(|f| &f.1).any(|e| e.depends_on("t"));
    let unit = if transient { unit.stored() } else { unit };
    let load =
        BodyLoad { unit, dof_of: free.dof_of.clone(), frames, force, points: mesh.points.clone(), dim: mesh.dim };
    let mut f0 = vec![0.0; free.dofs.len()];
    load.at(0.0, &mut f0);
    coupling.transpose_apply(&mut f0);
    let forcing = transient.then(|| {
        Forcing(Arc::new(move |t, out: &mut [f64]| {
            load.at(t, out);
            coupling.transpose_apply(out);
        }))
    });
    (f0, forcing)
}

/// The reports' lumped masses per node (component 0's weighted, the tangential components',
/// the unweighted ρ = 1 one: module docs) and the scalar unit mass of the load, as row sums and
/// entries of a body's whole weighted mass `mass_all` and unit mass `unit_all` (full indices, in
/// the plane's frame): the implicit schemes' system, which holds both.
fn whole_lumps(mass_all: &sparse::SpMat, unit_all: &sparse::SpMat, d: usize) -> ([Vec<f64>; 3], UnitMass) {
    let n_nodes = mass_all.ncols() / d;
    let (mut lumped, mut lumped_unit) = (vec![0.0; n_nodes], vec![0.0; n_nodes]);
    let mut lumped_tangential = vec![0.0; n_nodes];
    for (i, j, v) in sparse::triplets(mass_all) {
        if i % d == 0 && j % d == 0 {
            lumped[j / d] += v;
        } else if i % d == 1 && j % d == 1 {
            lumped_tangential[j / d] += v;
        }
    }
    // Node numbers in 32 bits: the mesh's points alone would take 96 GB at 2³² nodes.
    let node = |g: usize| u32::try_from(g / d).expect("fewer than 2³² nodes (the memory validation)");
    let scalar_unit: Vec<(u32, u32, f64)> = sparse::triplets(unit_all)
        .filter(|(i, j, _)| i % d == 0 && j % d == 0)
        .map(|(i, j, v)| (node(i), node(j), v))
        .collect();
    for &(_, b, v) in &scalar_unit {
        lumped_unit[b as usize] += v;
    }
    ([lumped, lumped_tangential, lumped_unit], UnitMass::Pairs(scalar_unit))
}

/// A body's frame against a plane (rotation `rot`) from its reports' lumped masses `lumps`
/// ([`whole_lumps`], or cell by cell for central differences' lean system), with the load F(0)
/// and its forcing from the scalar unit mass `unit`.
fn body_frame(
    mesh: &Mesh,
    free: &Free,
    rot: [[f64; 3]; 3],
    (body, contact): (&BodySpec, &BodyContact),
    [lumped, lumped_tangential, lumped_unit]: [Vec<f64>; 3],
    unit: UnitMass,
) -> (BodyFrame, Vec<f64>, Option<Forcing>) {
    let forces = vec![(0, body.force.clone())];
    let (f0, forcing) = body_load(mesh, free, Frames::Global(rot), forces, unit, Default::default());
    let contact_area = contact.areas.iter().sum();
    let volume = lumped_unit.iter().sum();
    let frame = BodyFrame {
        frames: Frames::Global(rot),
        momentum: Vec::new(),
        lumped,
        lumped_tangential,
        volume,
        lumped_unit,
        contact_area,
        coupling: Default::default(),
    };
    (frame, f0, forcing)
}

impl SolidSystem {
    /// Assembles a body (module docs) on `mesh` (world coordinates) with validated cell
    /// `weights` and its contact data: with `explicit`, central differences' lean system
    /// ([`super::lean`]: the lumped mass as the mass matrix, the stiffness as one operator in
    /// row-run form, the system's own stiffness only the massless unknowns' rows and columns),
    /// else the whole one; a curved obstacle's in the nodes' frames ([`Self::assemble_curved`]).
    pub(super) fn assemble_body(
        mesh: Arc<Mesh>,
        (weights, directions): (Vec<f64>, crate::mass::ContactDirections),
        lame: Lame,
        body: &BodySpec,
        contact: &BodyContact,
        explicit: Option<StiffnessOperator>,
    ) -> Result<Self, SolidAssemblyError> {
        let d = mesh.dim;
        let Some(normal) = body.obstacle.plane_normal() else {
            return Self::assemble_curved(mesh, (weights, directions), lame, body, contact, explicit);
        };
        let rot = rotation(normal, d);
        let mut frame_mesh = Mesh::clone(&mesh);
        for p in frame_mesh.points.iter_mut() {
            *p = to_frame(&rot, *p);
        }
        let free = Free::new(&mesh, |g| contact.clamped[g / d]);
        let Some(choice) = explicit else {
            // Straight into compressed columns over all full indices (`super::columns`: the
            // triplet assembly's matrices bit for bit, without its element triplets, about 22 kB
            // a tetra10 cell per matrix).
            let all = DofMap::identity(mesh.n_nodes() * d);
            let mass_all = columns::mass(&frame_mesh, &weights, directions, lame.density, &all, all.len());
            let ones = vec![1.0; mesh.n_cells()];
            let unit_all = columns::mass(&frame_mesh, &ones, ContactDirections::All, 1.0, &all, all.len());
            drop(ones);
            let (lumps, unit) = whole_lumps(&mass_all, &unit_all, d);
            let (frame, f0, forcing) = body_frame(&mesh, &free, rot, (body, contact), lumps, unit);
            let contact_area = frame.contact_area;
            let stiff_all = columns::stiffness(&frame_mesh, &lame, &all, all.len());
            drop((frame_mesh, all));
            let matrices = Matrices::All { mass: mass_all, stiffness: stiff_all, unit: unit_all };
            let parts = Parts { matrices, load: f0, forcing, frame: Some(frame), contact_area };
            return Self::on_free(mesh, (weights, directions), lame, super::Lateral::Free, free, parts, contact);
        };
        // The lean system holds no whole mass (issue 31's peak memory): the reports' lumped
        // masses summed cell by cell and the load from each cell's unit mass (computed where it
        // is read), as against a curved obstacle. These are the whole system's sums in another
        // order: equal to round-off, not bit for bit (`tests/lean_run.rs`).
        let lumps = super::lumped::frame_lumps(&mesh, &weights, directions, lame.density);
        let (frame, f0, forcing) = body_frame(&mesh, &free, rot, (body, contact), lumps, UnitMass::of(&mesh));
        let contact_area = frame.contact_area;
        let n = free.dofs.len();
        let lumped = super::lumped::lumped_on(&mesh, &weights, directions, lame.density, &free.dofs);
        let massless: Vec<bool> = lumped.iter().map(|&m| m <= 0.0).collect();
        let stiffness = columns::stiffness_touching(&frame_mesh, &lame, &free.dof_of, n, &massless);
        drop(massless);
        let operator =
            super::lean::cell_operator(choice, (&mesh, lame), &free.dof_of, Some(Frames::Global(rot)), || {
                columns::stiffness(&frame_mesh, &lame, &free.dof_of, n)
            })?;
        drop(frame_mesh);
        let mass = super::lean::diagonal(&lumped)?;
        drop(lumped);
        let matrices = Matrices::Free { mass, stiffness };
        let parts = Parts { matrices, load: f0, forcing, frame: Some(frame), contact_area };
        Self::lean_body(mesh, (weights, directions), lame, free, parts, contact, operator)
    }

    /// A lean body's system from its parts and operator (its plane's or its curved obstacle's
    /// set-up): a body that keeps a rigid motion (no clamped node, or too few) has a singular
    /// `S_rr`, and its watch takes the free-flight scale (as for the whole system, whose factor
    /// of `S_rr` fails) without conjugate gradients towards an unbounded `E_F`; any other gets
    /// `E_F` now, before a scheme holds its vectors.
    pub(super) fn lean_body(
        mesh: Arc<Mesh>,
        (weights, directions): (Vec<f64>, ContactDirections),
        lame: Lame,
        free: Free,
        parts: Parts,
        contact: &BodyContact,
        operator: super::assembly::LeanStiffness,
    ) -> Result<Self, SolidAssemblyError> {
        let singular = contact.keeps_rigid_motion(&mesh.points, mesh.dim);
        let mut system = Self::on_free(mesh, (weights, directions), lame, super::Lateral::Free, free, parts, contact)?;
        system.lean = Some(super::assembly::LeanStiffness { singular, ..operator });
        let _ = system.lean_load_energy();
        Ok(system)
    }

    /// Momentum `P = 1ᵀ M V` and mean displacement `ū` (module docs), world components.
    pub fn moments(&self, u: &[f64], v: &[f64]) -> Option<([f64; 3], [f64; 3])> {
        let frame = self.frame.as_ref()?;
        let (u, v) = (self.in_frames(u), self.in_frames(v));
        let d = self.mesh.dim;
        let rot = match &frame.frames {
            Frames::Global(rot) => rot,
            Frames::Nodes(_) => return Some(self.moments_in(&u, &v, 0..self.mesh.n_nodes(), frame.volume)),
        };
        let (mut p, mut m) = ([0.0; 3], [0.0; 3]);
        for (k, &g) in self.dofs.iter().enumerate() {
            let (node, comp) = (g / d, g % d);
            let m_b = if comp == 0 { frame.lumped[node] } else { frame.lumped_tangential[node] };
            p[comp] += m_b * v[k];
            m[comp] += frame.lumped_unit[node] * u[k];
        }
        Some((from_frame(rot, p), from_frame(rot, m.map(|x| x / frame.volume))))
    }

    /// Per-node frames: the momentum `P = Σ_b L_b v'_b` and mean displacement
    /// `ū = Σ_b m¹_b R_b u'_b / volume` of the nodes `nodes` (a body of several: its own, as the
    /// bodies share no cell), from the values in the frames u', v'.
    pub fn moments_in(&self, u: &[f64], v: &[f64], nodes: std::ops::Range<usize>, volume: f64) -> ([f64; 3], [f64; 3]) {
        let Some(frame) = self.frame.as_ref() else { return ([f64::NAN; 3], [f64::NAN; 3]) };
        let d = self.mesh.dim;
        let (mut p, mut m) = ([0.0; 3], [0.0; 3]);
        let first = self.dofs.partition_point(|&g| g < nodes.start * d);
        for (k, &g) in self.dofs.iter().enumerate().skip(first) {
            let (node, comp) = (g / d, g % d);
            if node >= nodes.end {
                break;
            }
            let (l, r) = (&frame.momentum[node], frame.frames.of(node));
            for a in 0..d {
                p[a] += l[a][comp] * v[k];
                m[a] += frame.lumped_unit[node] * r[a][comp] * u[k];
            }
        }
        (p, m.map(|x| x / volume))
    }
}
