//! The lumped weighted mass of a solid for the explicit schemes (issue 20): one value per
//! node, the same for every vector component (the mass is `δ_ij` times a scalar mass),
//! computed over **all** nodes before any component is eliminated.
//!
//! ```text
//! P1, Q1:  m_a = Σ_c w_c ρ Σ_b ∫_c φ_a φ_b = Σ_c w_c ρ ∫_c φ_a          (row sums),
//! P2:      m_a = Σ_c w_c ρ |c| M^c_aa / Σ_b M^c_bb                      (HRZ diagonal scaling),
//! ```
//!
//! The row sums of a P2 mass vanish at the triangle's vertices (∫ φ_a = 0) and are negative at
//! the tetrahedron's (−|c|/20), so P2 takes the diagonal scaling of Hinton, Rock and
//! Zienkiewicz (Earthquake Eng. Struct. Dyn. 4, 1976): each cell's mass `w_c ρ |c|` shared in
//! proportion to its consistent diagonal, positive at every node. Both keep the total mass of
//! every cell, so `Σ_a m_a = ρ Σ_c w_c |c|` (= [`super::SolidSystem::total_mass`]). A node all of
//! whose cells weigh 0 (the contact layer of mod1–mod3, and P2's edge nodes inside it) gets
//! `m_a = 0` exactly: it is massless (quasi-static) in central differences.

use super::assembly::SolidSystem;
use crate::fem::Mesh;
use crate::mass::ContactDirections;

/// `m_a` per mesh node (module docs) for cell weights `weights` and density `density`.
pub fn node_masses(mesh: &Mesh, weights: &[f64], density: f64) -> Vec<f64> {
    let mut m = vec![0.0; mesh.n_nodes()];
    let hrz = mesh.kind.is_quadratic();
    for (c, &w) in weights.iter().enumerate() {
        if w == 0.0 {
            continue;
        }
        let e = mesh.integrals(c);
        let v = mesh.cell(c);
        let k = v.len();
        let share: Vec<f64> = if hrz {
            let diag: f64 = (0..k).map(|a| e.mass[a][a]).sum();
            let total: f64 = (0..k).flat_map(|a| (0..k).map(move |b| (a, b))).map(|(a, b)| e.mass[a][b]).sum();
            (0..k).map(|a| total * e.mass[a][a] / diag).collect()
        } else {
            (0..k).map(|a| e.mass[a][..k].iter().sum()).collect()
        };
        for (a, s) in share.into_iter().enumerate() {
            m[v[a]] += density * w * s;
        }
    }
    m
}

/// The lumped mass `M_L` on the free unknowns `dofs`: `m_a` of the unknown's node (module
/// docs), the tangential components' of the standard mass under `mass.contact_directions =
/// "normal"`.
pub fn lumped_on(
    mesh: &Mesh,
    weights: &[f64],
    directions: ContactDirections,
    density: f64,
    dofs: &[usize],
) -> Vec<f64> {
    let d = mesh.dim;
    let m = node_masses(mesh, weights, density);
    let standard = match directions {
        ContactDirections::All => None,
        ContactDirections::Normal => Some(node_masses(mesh, &vec![1.0; mesh.n_cells()], density)),
    };
    dofs.iter()
        .map(|&g| match &standard {
            Some(s) if g % d > 0 => s[g / d],
            _ => m[g / d],
        })
        .collect()
}

/// The reports' lumped masses per node: `Σ_c ρ w_c Σ_a ∫_c φ_a φ_b` (component 0's weight),
/// the tangential components' (`w^(1)`) and the unweighted, ρ = 1 one, cell by cell.
pub(super) fn frame_lumps(mesh: &Mesh, weights: &[f64], directions: ContactDirections, density: f64) -> [Vec<f64>; 3] {
    let n_nodes = mesh.n_nodes();
    let (mut lumped, mut lumped_tangential, mut lumped_unit) =
        (vec![0.0; n_nodes], vec![0.0; n_nodes], vec![0.0; n_nodes]);
    for (c, &w) in weights.iter().enumerate() {
        let e = mesh.integrals(c);
        let v = mesh.cell(c);
        for a in 0..v.len() {
            for (b, &vb) in v.iter().enumerate() {
                let m = e.mass[a][b];
                lumped[vb] += density * w * m;
                lumped_tangential[vb] += density * directions.weight(1, w) * m;
                lumped_unit[vb] += m;
            }
        }
    }
    [lumped, lumped_tangential, lumped_unit]
}

impl SolidSystem {
    /// The lumped mass `M_L` on the free unknowns ([`lumped_on`]; a lean system's is its mass
    /// matrix's diagonal, [`SolidSystem::assemble_explicit`]).
    pub fn lumped_mass(&self) -> Vec<f64> {
        if self.lean.is_some() {
            use crate::linalg::SymMatrix;
            return (0..self.dofs.len()).map(|i| self.system.mass.diag(i)).collect();
        }
        lumped_on(&self.mesh, &self.weights, self.directions, self.lame.density, &self.dofs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::Cell;

    /// Total mass kept and every node positive, for each kind on a unit square/cube with
    /// weight 1: Σ m_a = ρ|Ω| (to round-off of a sum of n values) and min m_a > 0 (P2's row
    /// sums would give 0 at the triangle's vertices: mutation `hrz = false` -> the P2 triangle
    /// fails the positivity assertion).
    #[test]
    fn lumped_mass_keeps_the_total_and_is_positive() {
        let quad = |m: Mesh, p2: bool| if p2 { m.quadratic().unwrap() } else { m };
        for (kind, p2) in [(Cell::Triangle, false), (Cell::Quad, false), (Cell::Triangle, true)] {
            let mesh = quad(Mesh::structured_2d(1.0, 1.0, 3, 3, kind).unwrap(), p2);
            let m = node_masses(&mesh, &vec![1.0; mesh.n_cells()], 2.0);
            assert!((m.iter().sum::<f64>() - 2.0).abs() <= 1e-14 * m.len() as f64, "{kind:?}");
            assert!(m.iter().all(|&x| x > 0.0), "{kind:?}: {m:?}");
        }
        for (kind, p2) in [(Cell::Tet, false), (Cell::Hex, false), (Cell::Tet, true)] {
            let mesh = quad(Mesh::structured_3d([1.0; 3], [2, 2, 2], kind).unwrap(), p2);
            let m = node_masses(&mesh, &vec![1.0; mesh.n_cells()], 2.0);
            assert!((m.iter().sum::<f64>() - 2.0).abs() <= 1e-14 * m.len() as f64, "{kind:?}");
            assert!(m.iter().all(|&x| x > 0.0), "{kind:?}");
        }
    }
}
