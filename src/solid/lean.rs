//! The explicit scheme's system of a box at scale (issue 20, explicit at scale): what central
//! differences need and nothing else, in memory linear in the unknowns with a small constant.
//!
//! [`super::SolidSystem::assemble`] builds the weighted and the unit consistent masses and the
//! stiffness over all nodes from element triplets (about 23 kB of triplets per hexahedron), then
//! their principal submatrices: what the implicit schemes and the reports need. Here the
//! stiffness is assembled straight into its compressed columns on the free unknowns (the
//! pattern from the node graph: unknown (a, i) couples to (b, j) when nodes a and b share a
//! cell), the lumped mass is [`super::lumped::node_masses`] and the mass matrix of the
//! [`ContactSystem`] is that diagonal; no consistent mass is formed. Each entry receives its
//! cell contributions in increasing cell order, computed by the same expression as
//! [`super::assembly::assemble`], so the stiffness equals the triplet-assembled one bit for bit
//! (`tests/central_solid.rs`). The load is the box's `F_(a,i) = f_i ∫ w_h φ_a` (P1/Q1: the
//! lumped mass over ρ; a P2 box has no structured mesh).

use super::assembly::{Free, SolidAssemblyError};
use super::spec::{Lateral, SolidInitial, SolidSpec, Support};
use crate::fem::Mesh;
use crate::linalg::sparse::{self, SpMat};
use crate::mass::MassKind;
use crate::system::ContactSystem;

/// The system of central differences on a box with its lumped mass and initial data.
#[derive(Debug)]
pub struct ExplicitBox {
    pub system: ContactSystem<SpMat>,
    pub lumped: Vec<f64>,
    pub u0: Vec<f64>,
    pub v0: Vec<f64>,
}

/// The stiffness on the free unknowns (`dof_of`: full index → free index) in compressed
/// columns, assembled cell by cell without triplets (module docs).
pub fn stiffness(mesh: &Mesh, lame: &crate::material::Lame, dof_of: &[Option<usize>], n: usize) -> SpMat {
    let d = mesh.dim;
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); mesh.n_nodes()];
    for c in 0..mesh.n_cells() {
        let v = mesh.cell(c);
        for &a in v {
            adj[a].extend_from_slice(v);
        }
    }
    adj.iter_mut().for_each(|l| {
        l.sort_unstable();
        l.dedup();
    });
    // Column (a, i) holds rows (b, j) for b adjacent to a, j free, in increasing free index.
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::new();
    for g in (0..mesh.n_nodes() * d).filter(|&g| dof_of[g].is_some()) {
        row_idx.extend(adj[g / d].iter().flat_map(|&b| (0..d).filter_map(move |j| dof_of[b * d + j])));
        col_ptr.push(row_idx.len());
    }
    drop(adj);
    let mut val = vec![0.0; row_idx.len()];
    for c in 0..mesh.n_cells() {
        let e = mesh.integrals(c);
        let v = mesh.cell(c);
        for a in 0..v.len() {
            for b in 0..v.len() {
                for i in 0..d {
                    let Some(col) = dof_of[v[a] * d + i] else { continue };
                    let rows = &row_idx[col_ptr[col]..col_ptr[col + 1]];
                    for j in 0..d {
                        let Some(row) = dof_of[v[b] * d + j] else { continue };
                        // The expression of `assembly::assemble` (bit-identical sums).
                        let mut s = 0.0;
                        for q in 0..e.nq {
                            let (ga, gb) = (&e.grads[q][a], &e.grads[q][b]);
                            let delta = if i == j { e.grad_dot(q, a, b) } else { 0.0 };
                            s += e.weights[q] * (lame.lambda * ga[i] * gb[j] + lame.mu * (delta + ga[j] * gb[i]));
                        }
                        let k = rows.binary_search(&row).expect("the pattern holds every cell pair");
                        val[col_ptr[col] + k] += s;
                    }
                }
            }
        }
    }
    sparse::from_csc(n, col_ptr, row_idx, val)
}

impl SolidSpec {
    /// The box of this spec (no `[obstacle]`, P1/Q1) for central differences (module docs).
    pub fn explicit_box(&self, mass: &MassKind) -> Result<ExplicitBox, super::SolidError> {
        let Support::Face { gap, lateral, force } = self.support else {
            return Err(super::SolidError::NotABox);
        };
        let built = self.built()?;
        let mesh = &built.mesh;
        let weights = self.weights(&built, mass)?;
        let d = mesh.dim;
        let eliminated = |g: usize| {
            let (node, comp) = (g / d, g % d);
            built.contact.clamped[node] || (lateral == Lateral::Roller && comp >= 1 && mesh.on_lateral(node, comp))
        };
        let Free { dofs, dof_of } = Free::new(mesh, eliminated);
        let n = dofs.len();
        let stiffness = stiffness(mesh, &self.lame, &dof_of, n);
        let nodes = super::lumped::node_masses(mesh, &weights, self.lame.density);
        let lumped: Vec<f64> = dofs.iter().map(|&g| nodes[g / d]).collect();
        let load = dofs.iter().map(|&g| force[g % d] * nodes[g / d] / self.lame.density).collect();
        let diag: Vec<(usize, usize, f64)> = lumped.iter().enumerate().map(|(i, &m)| (i, i, m)).collect();
        let mass_matrix = sparse::from_triplets(n, &diag, "mass").map_err(SolidAssemblyError::from)?;
        let contact = built.contact.nodes.iter().filter_map(|&v| dof_of[v * d]).collect();
        let system = ContactSystem::new(mass_matrix, stiffness, load, contact, gap);
        let l = self.extent[0];
        let at = |f: &dyn Fn(usize, &[f64; 3]) -> f64| dofs.iter().map(|&g| f(g % d, &mesh.points[g / d])).collect();
        let (u0, v0) = match &self.initial {
            SolidInitial::Paper => (at(&|i, p| if i == 0 { (l - p[0]) / 2.0 } else { 0.0 }), vec![0.0; n]),
            SolidInitial::Fields { displacement, velocity } => {
                (at(&|i, p| displacement[i].eval(&p[..d])), at(&|i, p| velocity[i].eval(&p[..d])))
            }
        };
        Ok(ExplicitBox { system, lumped, u0, v0 })
    }
}
