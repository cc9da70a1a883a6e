//! The explicit scheme's system of a box at scale (issue 20, explicit at scale): what central
//! differences need and nothing else, in memory linear in the unknowns with a small constant
//! (the benches' set-up): the stiffness straight into compressed columns
//! ([`super::columns::stiffness`]), the lumped mass [`super::lumped::node_masses`] as the
//! [`ContactSystem`]'s mass matrix (a diagonal; no consistent mass is formed), and the load
//! `F_(a,i) = f_i ∫ w_h φ_a` (P1/Q1: the lumped mass over ρ; a P2 box has no structured mesh).
//! Matrix-free ([`SolidSpec::explicit_box_matrix_free`], issue 31): the box's stencil, and of
//! the stiffness only the rows and columns of the massless unknowns (none for the standard
//! mass): about 170 bytes per unknown at 10⁶ unknowns (`bench --explicit-scaling`).

use super::assembly::{Free, SolidAssemblyError};
use super::spec::{Lateral, SolidInitial, SolidSpec, Support};
use super::stencil::BoxStencil;
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
        let eliminated = |g: usize| {
            let (node, comp) = (g / d, g % d);
            built.contact.clamped[node] || (lateral == Lateral::Roller && comp >= 1 && mesh.on_lateral(node, comp))
        };
        let Free { dofs, dof_of } = Free::new(mesh, eliminated);
        let n = dofs.len();
        let nodes = super::lumped::node_masses(mesh, &weights, self.lame.density);
        let lumped: Vec<f64> = dofs.iter().map(|&g| nodes[g / d]).collect();
        let (stiffness, stencil) = if matrix_free {
            let massless: Vec<bool> = lumped.iter().map(|&m| m <= 0.0).collect();
            let free = dof_of.iter().map(Option::is_some).collect();
            let stencil = BoxStencil::new(mesh, &self.lame, free).ok_or(super::SolidError::NotABox)?;
            (super::columns::stiffness_touching(mesh, &self.lame, &dof_of, n, &massless), Some(stencil))
        } else {
            (super::columns::stiffness(mesh, &self.lame, &dof_of, n), None)
        };
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
        Ok((ExplicitBox { system, lumped, u0, v0 }, stencil))
    }
}
