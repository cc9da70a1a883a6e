//! Weighted mass and stiffness matrices on 2D meshes (paper §3 in 2D), and the discrete
//! contact system on the free nodes.
//!
//! ```text
//! M_ij = Σ_c w_c ∫_c φ_i φ_j,     S_ij = ∫_Ω ∇φ_i · ∇φ_j,     F_i = f ∫_Ω w_h φ_i = f (M 1)_i.
//! ```
//!
//! The element integrals are the ones of every mesh ([`crate::fem::element::CellIntegrals`], as
//! for solids): `∫_c φ_a φ_b` and `∫_c ∇φ_a·∇φ_b`, exact for P1 triangles and for Q1 on the
//! axis-aligned rectangles every plate mesh has. On a rectangle they are the tensor products
//! `M = (a/6)[[2,1],[1,2]] ⊗ (b/6)[[2,1],[1,2]]` and `S = K_x ⊗ M_y + M_x ⊗ K_y` with
//! `K = (1/len)[[1,−1],[−1,1]]`; on a structured mesh the global matrices are the same tensor
//! products, so with x-only weights the y-independent fields reduce to the 1D problem.
//!
//! The matrices cover all vertices in mesh order without boundary condition ([`assemble`],
//! for cross-checks against dolfinx and scikit-fem); [`PlateSystem`] removes the Dirichlet
//! nodes x = L and keeps the contact nodes x = 0 as unknowns (Signorini rows).

use crate::fem::Mesh;
use crate::fem::layers::{LayerMassError, cell_weights};
use crate::linalg::sparse::{self, SpMat, SparseError};
use crate::mass::MassKind;
use crate::material::{FarEnd, Material};
use crate::system::ContactSystem;

/// The body force of a plate.
pub enum PlateLoad<'a> {
    Constant(f64),
    /// f(x, y), time-independent.
    Field(&'a dyn Fn(f64, f64) -> f64),
}
use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum PlateAssemblyError {
    #[error(transparent)]
    Mass(#[from] LayerMassError),
    #[error(transparent)]
    Sparse(#[from] SparseError),
    #[error("plate.force = {0}: must be finite")]
    Force(f64),
}

/// Weighted mass and stiffness matrices over all vertices, in mesh order, no boundary
/// condition (the matrices dolfinx and scikit-fem assemble). `weights` has one entry per cell.
pub fn assemble(mesh: &Mesh, weights: &[f64]) -> Result<(SpMat, SpMat), SparseError> {
    assert_eq!(weights.len(), mesh.n_cells(), "one weight per cell");
    let k = mesh.kind.verts();
    let mut pos = Vec::with_capacity(mesh.n_cells() * k * k);
    let mut vm = Vec::with_capacity(mesh.n_cells() * k * k);
    let mut vs = Vec::with_capacity(mesh.n_cells() * k * k);
    for (c, &w) in weights.iter().enumerate() {
        let e = mesh.integrals(c);
        let v = mesh.cell(c);
        for p in 0..k {
            for q in 0..k {
                pos.push((v[p], v[q]));
                vm.push(w * e.mass[p][q]);
                vs.push(e.stiffness(p, q));
            }
        }
    }
    // One pattern for both matrices (the same positions).
    let pattern = sparse::Pattern::new(mesh.n_nodes(), pos.into_iter(), "mass")?;
    Ok((pattern.assemble(&vm), pattern.assemble(&vs)))
}

/// The plate problem on the free nodes (all but x = L): the mesh, its cell weights, the contact
/// system, and what is needed to report on Γ_C.
#[derive(Debug, Clone)]
pub struct PlateSystem {
    pub mesh: Mesh,
    pub weights: Vec<f64>,
    /// Free unknown → mesh node.
    pub dofs: Vec<usize>,
    /// Mesh node → free unknown (None on Γ_D).
    pub node_dof: Vec<Option<usize>>,
    pub system: ContactSystem<SpMat>,
    /// The lumped mass on the unknowns: row sums of ρ M_w over all nodes, taken before the
    /// Dirichlet nodes are removed (explicit schemes).
    pub lumped: Vec<f64>,
    /// The unweighted mass matrix on the free nodes (for L² norms).
    pub mass_unit: SpMat,
    /// For each free unknown, the free unknown at the same x on the lowest y (for the
    /// y-variation of a solution; exact coordinates, so structured meshes only).
    pub base: Vec<Option<usize>>,
    /// `∫_{Γ_C} φ_c dy` for each contact unknown (trace weights: the mean of u on Γ_C is
    /// `Σ_c ℓ_c u_c / |Γ_C|`, exact for the piecewise-linear trace).
    pub contact_lengths: Vec<f64>,
    /// The cells over each interval of the distinct vertex abscissae, built by the first L²
    /// error against a plane wave ([`crate::plate::norms::l2_error_plane_wave`]).
    pub columns: std::sync::OnceLock<crate::fem::columns::Columns>,
    /// The Q1 cells as the exact L² pass reads them, built by its first call
    /// ([`crate::plate::cells::QuadCells`]).
    pub quad_cells: std::sync::OnceLock<super::cells::QuadCells>,
}

impl PlateSystem {
    /// Assembles M, S, F on the free nodes for a mass redistribution and a constant body force.
    /// Contact unknowns are ordered by increasing y (the first one is the node at y = 0 on a
    /// structured mesh).
    pub fn new(mesh: Mesh, mass: &MassKind, force: f64) -> Result<Self, PlateAssemblyError> {
        let weights = cell_weights(&mesh, mass)?;
        Self::from_weights(mesh, weights, force)
    }

    /// Assembly from validated cell weights (ρ = E = 1, clamped at x = L, constant force).
    pub fn from_weights(mesh: Mesh, weights: Vec<f64>, force: f64) -> Result<Self, PlateAssemblyError> {
        Self::assemble(mesh, weights, Material::UNIT, FarEnd::Clamped, &PlateLoad::Constant(force))
    }

    /// The general plate: mass `ρ ∫ w_h u v`, stiffness `E ∫ ∇u·∇v`, the nodes of x = L
    /// eliminated when clamped and kept (natural condition) when free, and the load
    /// `F_i = ∫ f w_h φ_i`: for a constant f exactly `f (M 1)_i`, for f(x, y) with f
    /// interpolated at the nodes, `F = M I_h f` (exact for f in the finite element space).
    pub fn assemble(
        mesh: Mesh,
        weights: Vec<f64>,
        material: Material,
        far_end: FarEnd,
        force: &PlateLoad,
    ) -> Result<Self, PlateAssemblyError> {
        if let PlateLoad::Constant(f) = force
            && !f.is_finite()
        {
            return Err(PlateAssemblyError::Force(*f));
        }
        let (mut mass_all, mut stiff_all) = assemble(&mesh, &weights)?;
        if material != Material::UNIT {
            mass_all = sparse::combine(&mass_all, material.density, &mass_all, 0.0, "mass")?;
            stiff_all = sparse::combine(&stiff_all, material.modulus, &stiff_all, 0.0, "stiffness")?;
        }
        let (unit_all, _) = assemble(&mesh, &vec![1.0; mesh.n_cells()])?;
        let eliminated = |v: usize| far_end == FarEnd::Clamped && mesh.on_dirichlet(v);
        let dofs: Vec<usize> = (0..mesh.n_nodes()).filter(|&v| !eliminated(v)).collect();
        let mut node_dof = vec![None; mesh.n_nodes()];
        for (d, &v) in dofs.iter().enumerate() {
            node_dof[v] = Some(d);
        }
        // Constant f: F_i = f ∫ w_h φ_i = f Σ_j M_ij (the basis functions sum to 1); a field:
        // F_i = Σ_j M_ij f(x_j). The weighted mass is per unit density here.
        let f_nodes: Vec<f64> = match force {
            PlateLoad::Constant(_) => vec![1.0; mesh.n_nodes()],
            PlateLoad::Field(f) => mesh.points.iter().map(|p| f(p[0], p[1])).collect(),
        };
        let scale = match force {
            PlateLoad::Constant(f) => *f / material.density,
            PlateLoad::Field(_) => 1.0 / material.density,
        };
        let mut row_sums = vec![0.0; mesh.n_nodes()];
        let mut lumped_all = vec![0.0; mesh.n_nodes()];
        for (i, j, v) in sparse::triplets(&mass_all) {
            row_sums[i] += v * f_nodes[j];
            lumped_all[i] += v;
        }
        let lumped: Vec<f64> = dofs.iter().map(|&v| lumped_all[v]).collect();
        let load: Vec<f64> = dofs.iter().map(|&v| scale * row_sums[v]).collect();
        let mass = sparse::principal(&mass_all, &dofs, "mass")?;
        let stiffness = sparse::principal(&stiff_all, &dofs, "stiffness")?;
        let mass_unit = sparse::principal(&unit_all, &dofs, "mass")?;
        let mut contact_nodes: Vec<usize> = (0..mesh.n_nodes()).filter(|&v| mesh.on_contact(v)).collect();
        contact_nodes.sort_by(|&a, &b| mesh.points[a][1].total_cmp(&mesh.points[b][1]));
        let contact: Vec<usize> = contact_nodes.iter().map(|&v| node_dof[v].expect("x = 0 is not x = L")).collect();
        let mut contact_lengths = vec![0.0; contact.len()];
        let mut slots = vec![None; mesh.n_nodes()];
        for (k, &v) in contact_nodes.iter().enumerate() {
            slots[v] = Some(k);
        }
        let slot = |v: usize| slots[v];
        for c in 0..mesh.n_cells() {
            let cell = mesh.cell(c);
            for a in 0..cell.len() {
                let (p, q) = (cell[a], cell[(a + 1) % cell.len()]);
                if let (Some(i), Some(j)) = (slot(p), slot(q)) {
                    let len = (mesh.points[p][1] - mesh.points[q][1]).abs();
                    contact_lengths[i] += len / 2.0;
                    contact_lengths[j] += len / 2.0;
                }
            }
        }
        let system = ContactSystem::new(mass, stiffness, load, contact, 0.0);
        let ymin = dofs.iter().map(|&v| mesh.points[v][1]).fold(f64::INFINITY, f64::min);
        let bottom: std::collections::HashMap<u64, usize> = dofs
            .iter()
            .enumerate()
            .filter(|(_, v)| mesh.points[**v][1] == ymin)
            .map(|(d, &v)| (mesh.points[v][0].to_bits(), d))
            .collect();
        let base = dofs.iter().map(|&v| bottom.get(&mesh.points[v][0].to_bits()).copied()).collect();
        let (columns, quad_cells) = Default::default();
        Ok(Self {
            mesh,
            weights,
            dofs,
            node_dof,
            system,
            lumped,
            mass_unit,
            base,
            contact_lengths,
            columns,
            quad_cells,
        })
    }

    /// The same system with the obstacle at `u_c = −gap` on every contact node (gap ≥ 0).
    pub fn with_gap(mut self, gap: f64) -> Self {
        self.system.lower = vec![0.0 - gap; self.system.contact.len()];
        self
    }

    /// Nodal interpolant of g(x, y) on the free nodes.
    pub fn interpolate(&self, g: impl Fn(f64, f64) -> f64) -> Vec<f64> {
        self.dofs.iter().map(|&v| g(self.mesh.points[v][0], self.mesh.points[v][1])).collect()
    }

    /// Values at all mesh nodes (0 on Γ_D) from values on the free nodes.
    pub fn to_nodes(&self, u: &[f64], out: &mut [f64]) {
        for (v, d) in self.node_dof.iter().enumerate() {
            out[v] = d.map_or(0.0, |d| u[d]);
        }
    }

    /// `|Γ_C|`, the length of the contact boundary.
    pub fn contact_length(&self) -> f64 {
        self.contact_lengths.iter().sum()
    }

    /// Mean of u on Γ_C: `Σ_c ℓ_c u_c / |Γ_C|`.
    pub fn contact_mean(&self, u: &[f64]) -> f64 {
        let s: f64 = self.system.contact.iter().zip(&self.contact_lengths).map(|(&c, l)| l * u[c]).sum();
        s / self.contact_length()
    }

    /// Total mass `1ᵀ M_full 1 = ∫ w_h`.
    pub fn total_mass(&self) -> f64 {
        crate::fem::layers::total_mass(&self.mesh, &self.weights)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn q1_matrices_are_tensor_products_of_the_1d_ones() {
        // On a structured mesh, M = Mx^w ⊗ My and S = Kx ⊗ My + Mx ⊗ Ky (x-only weights).
        let (nx, ny, l, h) = (4, 3, 1.0, 0.6);
        let mesh = Mesh::structured_2d(l, h, nx, ny, crate::fem::Cell::Quad).unwrap();
        let w = cell_weights(&mesh, &MassKind::Mod3).unwrap();
        let (m, s) = assemble(&mesh, &w).unwrap();
        let w1 = MassKind::Mod3.weights(nx).unwrap();
        let bar = |len: f64, n: usize, w: &[f64]| {
            let d = len / n as f64;
            let mut mm = vec![vec![0.0; n + 1]; n + 1];
            let mut kk = vec![vec![0.0; n + 1]; n + 1];
            for e in 0..n {
                for (p, q) in [(e, e), (e, e + 1), (e + 1, e), (e + 1, e + 1)] {
                    mm[p][q] += w[e] * d * if p == q { 2.0 } else { 1.0 } / 6.0;
                    kk[p][q] += if p == q { 1.0 } else { -1.0 } / d;
                }
            }
            (mm, kk)
        };
        let (mxw, _) = bar(l, nx, &w1);
        let (mx, kx) = bar(l, nx, &vec![1.0; nx]);
        let (my, ky) = bar(h, ny, &vec![1.0; ny]);
        let node = |i: usize, j: usize| j * (nx + 1) + i;
        for (i, j) in (0..=nx).flat_map(|i| (0..=ny).map(move |j| (i, j))) {
            for (p, q) in (0..=nx).flat_map(|p| (0..=ny).map(move |q| (p, q))) {
                let (a, b) = (node(i, j), node(p, q));
                let me = mxw[i][p] * my[j][q];
                let se = kx[i][p] * my[j][q] + mx[i][p] * ky[j][q];
                // Sums of up to 4 element contributions of size ≤ 1/h²: a few ulps of that.
                assert!((sparse::get(&m, a, b) - me).abs() <= 16.0 * f64::EPSILON, "M[{a},{b}]");
                assert!((sparse::get(&s, a, b) - se).abs() <= 16.0 * f64::EPSILON * 100.0, "S[{a},{b}]");
            }
        }
    }
}
