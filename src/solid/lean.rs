//! The explicit scheme's system of a box or a body at scale (issues 20 and 31): what
//! central differences need and nothing else, in memory linear in the unknowns with a small
//! constant: the lumped mass [`super::lumped::node_masses`] as the [`ContactSystem`]'s mass
//! matrix (a diagonal; no consistent mass is formed), the load `F_(a,i) = f_i ∫ w_h φ_a`, and the
//! stiffness as one operator: the box's stencil ([`BoxStencil`], matrix-free), the cell-by-cell
//! kernel of any other mesh ([`CellKernel`], matrix-free; `auto` takes one of the two), or with
//! `scheme.operator = "assembled"` the assembled matrix in row-run form. The system's own stiffness holds only the rows and columns of the
//! massless unknowns ([`super::columns::stiffness_touching`], bit for bit the assembled
//! entries): all that the contact layer's quasi-static rows and the laws read (none for the
//! standard mass).
//!
//! Two entries:
//! - **a scene's run** ([`SolidSystem::assemble_explicit`], issue 31, item 0): every box scene
//!   and every body against a rigid obstacle stepped by central differences (not Nitsche, whose term
//!   reads a massive contact row). Its L² norms take the unit mass as a stencil where the box
//!   has one (else it is assembled when first asked for), and its divergence watch's `E_F`
//!   comes from conjugate gradients on the operator ([`SolidSystem::lean_load_energy`]) instead
//!   of a factorisation (a body that keeps a rigid motion, unclamped or clamped at too few nodes, has none: its `S_rr` is singular, and
//!   the watch takes the free-flight scale). A body's system is made in
//!   [`SolidSystem::assemble_body`]'s lean branch: its load and reports from its whole masses,
//!   which are dropped before its stiffness is made: the kernel in the plane's frame, or with
//!   `assembled` the matrix assembled in that frame (bit for bit the whole system's, so that its
//!   run is the whole system's run bit for bit: `tests/lean_run.rs`); a body against a curved
//!   obstacle in `SolidSystem::curved_lean` (each contact node in its own frame; with
//!   `assembled` the frame matrices' entries in compressed columns, bit for bit as well);
//!   several bodies are set up whole;
//! - **the benches** ([`SolidSpec::explicit_box`], [`SolidSpec::explicit_box_matrix_free`]),
//!   which step the system themselves (P1/Q1 boxes: the load from the lumped mass over ρ).
//!
//! At 10⁶ unknowns: about 170 bytes per unknown matrix-free, 1.6 kB assembled
//! (`bench --explicit-scaling`); a tetra10 body of 10⁶ unknowns 1.2 kB with the kernel, 1.6 kB
//! assembled (its set-up's whole masses are the peak); of 2·10⁵ unknowns: 1.7 kB against a plane or a
//! cylinder (`tests/lean_run.rs`).

use super::assembly::{Free, LeanStiffness, Matrices, Parts, SolidAssemblyError, SolidSystem};
use super::body::{BodyContact, Frames};
use super::dof_map::DofMap;
use super::kernel::CellKernel;
use super::spec::{SolidInitial, SolidSpec, Support};
use super::stencil::BoxStencil;
use crate::fem::Mesh;
use crate::linalg::Operator;
use crate::linalg::sparse::{self, RunMat, SpMat};
use crate::mass::{ContactDirections, MassKind};
use crate::material::Lame;
use crate::schemes::StiffnessOperator;
use crate::system::ContactSystem;
use std::sync::{Arc, OnceLock};

/// Relative residual at which [`SolidSystem::lean_load_energy`]'s conjugate gradients stop.
/// `E_F` only sets the divergence watch's scale (a factor 10⁶ above it by default); the
/// functional at the iterate misses it by `½ r_kᵀ K⁻¹ r_k ≤ κ tol² E_F`, far inside that factor.
pub const LOAD_ENERGY_TOL: f64 = 1e-6;

/// The lean stiffness of an assembled matrix: `k` in row-run form (its values moved, its row
/// indices dropped), E_F still to make.
pub(super) fn assembled(k: SpMat) -> Result<LeanStiffness, SolidAssemblyError> {
    let n = k.nrows();
    let runs = RunMat::from_owned(k).map_err(|_| sparse::SparseError::Structure {
        matrix: "stiffness",
        detail: format!("{n} unknowns: the row-run form holds at most {} rows", u32::MAX),
    })?;
    Ok(LeanStiffness { operator: Arc::new(runs), unit_mass: None, load_energy: OnceLock::new(), singular: false })
}

/// A lean stiffness operator without a stencil as `choice` says: the cell-by-cell kernel on
/// the world mesh ([`CellKernel`]; a body's in its `frames`, a box's in none) for `auto` and
/// `matrix-free`, the matrix `assemble` makes (in the frames, compressed columns) in row-run
/// form for `assembled`.
pub(super) fn cell_operator(
    choice: StiffnessOperator,
    (mesh, lame): (&Arc<Mesh>, Lame),
    dof_of: &DofMap,
    frames: Option<Frames>,
    assemble: impl FnOnce() -> SpMat,
) -> Result<LeanStiffness, SolidAssemblyError> {
    match choice {
        StiffnessOperator::Auto | StiffnessOperator::MatrixFree => Ok(LeanStiffness {
            operator: Arc::new(CellKernel::new(Arc::clone(mesh), lame, dof_of, frames)),
            unit_mass: None,
            load_energy: OnceLock::new(),
            singular: false,
        }),
        StiffnessOperator::Assembled => assembled(assemble()),
    }
}

/// The diagonal mass matrix of the lumped masses `m`.
pub(super) fn diagonal(m: &[f64]) -> Result<SpMat, SolidAssemblyError> {
    let diag: Vec<(usize, usize, f64)> = m.iter().enumerate().map(|(i, &m)| (i, i, m)).collect();
    Ok(sparse::from_triplets(m.len(), &diag, "mass")?)
}

impl SolidSystem {
    /// The lean system of a box (`Support::Face`) for central differences (module docs): the
    /// lumped mass as a diagonal mass, the load `f_i Σ_c w_c^(i) ∫_c φ_a` cell by cell, the
    /// stiffness as `choice` says (`auto` and `matrix-free`: the stencil where the box has one,
    /// else the kernel; `assembled`: the row-run matrix), and of the stiffness matrix only the massless
    /// unknowns' rows and columns. A body (against a plane or a curved obstacle) is set up
    /// lean by [`SolidSystem::assemble_body`]; several bodies are assembled whole
    /// ([`SolidSystem::assemble`]).
    pub fn assemble_explicit(
        (mesh, contact): (Arc<Mesh>, &BodyContact),
        (weights, directions): (Vec<f64>, ContactDirections),
        lame: Lame,
        support: &Support,
        choice: StiffnessOperator,
    ) -> Result<Self, SolidAssemblyError> {
        let Support::Face { lateral, force, .. } = *support else {
            return match support {
                Support::Plane(body) => {
                    Self::assemble_body(mesh, (weights, directions), lame, body, contact, Some(choice))
                }
                _ => Self::assemble(mesh, weights, directions, lame, support, contact),
            };
        };
        let free = Free::of_box(&mesh, &weights, lateral, force, contact)?;
        let n = free.dofs.len();
        let lumped = super::lumped::lumped_on(&mesh, &weights, directions, lame.density, &free.dofs);
        let massless: Vec<bool> = lumped.iter().map(|&m| m <= 0.0).collect();
        let flags = || free.dof_of.flags();
        let stencil = match choice {
            StiffnessOperator::Assembled => None,
            StiffnessOperator::Auto | StiffnessOperator::MatrixFree => BoxStencil::new(&mesh, &lame, flags()),
        };
        let lean = match stencil {
            Some(s) => LeanStiffness {
                operator: Arc::new(s),
                unit_mass: BoxStencil::unit_mass(&mesh, flags()).map(|m| Arc::new(m) as Arc<dyn Operator>),
                load_energy: OnceLock::new(),
                singular: false,
            },
            None => cell_operator(choice, (&mesh, lame), &free.dof_of, None, || {
                super::columns::stiffness(&mesh, &lame, &free.dof_of, n)
            })?,
        };
        let stiffness = super::columns::stiffness_touching(&mesh, &lame, &free.dof_of, n, &massless);
        let load = box_load(&mesh, &weights, directions, force, &free.dofs);
        let mass = diagonal(&lumped)?;
        let parts = Parts {
            matrices: Matrices::Free { mass, stiffness },
            load,
            forcing: None,
            frame: None,
            contact_area: mesh.face_area(),
        };
        let mut system = Self::on_free(mesh, (weights, directions), lame, lateral, free, parts, contact)?;
        system.lean = Some(lean);
        // E_F now, while no scheme holds its vectors: its conjugate gradients' five vectors
        // are then not on top of them (issue 31: the run's peak memory under a body force).
        let _ = system.lean_load_energy();
        Ok(system)
    }

    /// The divergence watch's `E_F = ½ F_rᵀ K_rr⁻¹ F_r = max_x (F_rᵀx − ½ xᵀK_rr x)` (r: the
    /// unknowns but the contact ones) of a lean system: that functional at conjugate gradients'
    /// iterate on its operator, from 0 to [`LOAD_ENERGY_TOL`] relative residual (at most n
    /// iterations), below `E_F` by `½ r_kᵀ K_rr⁻¹ r_k`; computed once (the lean set-up asks
    /// first). None for a system that is whole (the driver factors `K_rr`) or whose `K_rr` is
    /// singular (a body that keeps a rigid motion).
    pub fn lean_load_energy(&self) -> Option<f64> {
        let lean = self.lean.as_ref().filter(|l| !l.singular)?;
        Some(*lean.load_energy.get_or_init(|| self.conjugate_load_energy(lean.operator.as_ref(), &self.system.load)))
    }

    /// `max_x (fᵀx − ½ xᵀK_rr x)` at conjugate gradients' iterate ([`Self::lean_load_energy`]
    /// for the load `f`).
    pub(super) fn conjugate_load_energy(&self, op: &dyn Operator, f: &[f64]) -> f64 {
        let s = &self.system;
        if f.iter().all(|&f| f == 0.0) {
            // b = 0: the functional's maximum is 0 (no vectors made).
            return 0.0;
        }
        let mut b = f.to_vec();
        for &c in &s.contact {
            b[c] = 0.0;
        }
        let x = conjugate_gradients(op, &s.contact, &b);
        let work: f64 = b.iter().zip(&x).map(|(b, x)| b * x).sum();
        work - 0.5 * op.quad_form(&x)
    }
}

/// x ≈ A_rr⁻¹ b by conjugate gradients from 0 (the rows and columns `held` removed: b is 0
/// there, and so are x and each product's entries there), to [`LOAD_ENERGY_TOL`] relative
/// residual or n iterations.
fn conjugate_gradients(a: &dyn Operator, held: &[usize], b: &[f64]) -> Vec<f64> {
    let n = a.n();
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
    let bb = dot(b, b);
    if bb == 0.0 {
        return vec![0.0; n];
    }
    let (mut x, mut r, mut p, mut q) = (vec![0.0; n], b.to_vec(), b.to_vec(), vec![0.0; n]);
    let mut rr = bb;
    for _ in 0..n {
        a.apply(&p, &mut q);
        for &c in held {
            q[c] = 0.0;
        }
        let alpha = rr / dot(&p, &q);
        x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
        r.iter_mut().zip(&q).for_each(|(r, q)| *r -= alpha * q);
        let next = dot(&r, &r);
        if next <= LOAD_ENERGY_TOL * LOAD_ENERGY_TOL * bb {
            break;
        }
        let beta = next / rr;
        p.iter_mut().zip(&r).for_each(|(p, r)| *p = r + beta * *p);
        rr = next;
    }
    x
}

/// The box's load on the free unknowns `dofs`: `F_(a,i) = f_i Σ_c w_c^(i) Σ_b ∫_c φ_a φ_b`
/// (the row sums of the weighted mass over ρ, as [`SolidSystem::assemble`] takes them, cell by
/// cell without the matrix; zero without force).
fn box_load(mesh: &Mesh, weights: &[f64], directions: ContactDirections, force: [f64; 3], dofs: &[usize]) -> Vec<f64> {
    let d = mesh.dim;
    if force.iter().all(|&f| f == 0.0) {
        return vec![0.0; dofs.len()];
    }
    let mut sums = vec![0.0; mesh.n_nodes() * d];
    for (c, &w) in weights.iter().enumerate() {
        let e = mesh.integrals(c);
        let v = mesh.cell(c);
        for (a, &node) in v.iter().enumerate() {
            let row: f64 = e.mass[a][..v.len()].iter().sum();
            for (i, sum) in sums[node * d..(node + 1) * d].iter_mut().enumerate() {
                *sum += directions.weight(i, w) * row;
            }
        }
    }
    dofs.iter().map(|&g| force[g % d] * sums[g]).collect()
}

/// The system of central differences on a box with its lumped mass and initial data.
#[derive(Debug)]
pub struct ExplicitBox {
    pub system: ContactSystem<SpMat>,
    pub lumped: Vec<f64>,
    pub u0: Vec<f64>,
    pub v0: Vec<f64>,
}

impl SolidSpec {
    /// The box of this spec (no `[obstacle]`, P1/Q1) for central differences (module docs).
    pub fn explicit_box(&self, mass: &MassKind) -> Result<ExplicitBox, super::SolidError> {
        self.explicit_box_with(mass, false).map(|(b, _)| b)
    }

    /// [`Self::explicit_box`] with the stiffness matrix-free (Q1 boxes: [`BoxStencil`]): the
    /// system's stiffness holds only the rows and columns of the massless unknowns
    /// ([`super::columns::stiffness_touching`]: what the contact layer's quasi-static rows
    /// read; empty for the standard mass), to be stepped by
    /// [`crate::schemes::CentralDifference::with_operator`] with the stencil returned. No
    /// global matrix is assembled.
    pub fn explicit_box_matrix_free(&self, mass: &MassKind) -> Result<(ExplicitBox, BoxStencil), super::SolidError> {
        let (b, op) = self.explicit_box_with(mass, true)?;
        Ok((b, op.ok_or(super::SolidError::NotABox)?))
    }

    fn explicit_box_with(
        &self,
        mass: &MassKind,
        matrix_free: bool,
    ) -> Result<(ExplicitBox, Option<BoxStencil>), super::SolidError> {
        let Support::Face { gap, lateral, force } = self.support else {
            return Err(super::SolidError::NotABox);
        };
        let built = self.built()?;
        let mesh = &built.mesh;
        let weights = self.weights(&built, mass)?;
        let d = mesh.dim;
        let Free { dofs, dof_of } = Free::of_box(mesh, &weights, lateral, force, &built.contact)?;
        let n = dofs.len();
        let nodes = super::lumped::node_masses(mesh, &weights, self.lame.density);
        let lumped: Vec<f64> = dofs.iter().map(|&g| nodes[g / d]).collect();
        let (stiffness, stencil) = if matrix_free {
            let massless: Vec<bool> = lumped.iter().map(|&m| m <= 0.0).collect();
            let free = dof_of.flags();
            let stencil = BoxStencil::new(mesh, &self.lame, free).ok_or(super::SolidError::NotABox)?;
            (super::columns::stiffness_touching(mesh, &self.lame, &dof_of, n, &massless), Some(stencil))
        } else {
            (super::columns::stiffness(mesh, &self.lame, &dof_of, n), None)
        };
        let load = dofs.iter().map(|&g| force[g % d] * nodes[g / d] / self.lame.density).collect();
        let mass_matrix = diagonal(&lumped)?;
        let contact = built.contact.nodes.iter().filter_map(|&v| dof_of.get(v * d)).collect();
        let system = ContactSystem::new(mass_matrix, stiffness, load, contact, gap);
        let l = self.extent[0];
        let at = |f: &dyn Fn(usize, &[f64; 3]) -> f64| dofs.iter().map(|&g| f(g % d, &mesh.points[g / d])).collect();
        let (u0, v0) = match &self.initial {
            SolidInitial::Paper => (at(&|i, p| if i == 0 { (l - p[0]) / 2.0 } else { 0.0 }), vec![0.0; n]),
            SolidInitial::Fields { displacement, velocity } => {
                (at(&|i, p| displacement[i].eval(&p[..d])), at(&|i, p| velocity[i].eval(&p[..d])))
            }
        };
        Ok((ExplicitBox { system, lumped, u0, v0 }, stencil))
    }
}
