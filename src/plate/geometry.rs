//! The plate as a [`Geometry`] of the one driver: contact means over Γ_C, the exact L² norms of
//! [`super::norms`], nodal values for VTU.

use super::assembly::PlateSystem;
use crate::exact::Exact;
use crate::problem::{Geometry, GeometryView};
use crate::system::ContactSystem;

impl GeometryView for PlateSystem {
    fn name(&self) -> &'static str {
        "plate"
    }

    fn dim(&self) -> usize {
        2
    }

    fn h(&self) -> f64 {
        self.mesh.h()
    }

    fn length(&self) -> f64 {
        self.mesh.extent[0]
    }

    fn section(&self) -> f64 {
        self.mesh.extent[1]
    }

    fn contact_measure(&self) -> f64 {
        self.contact_length()
    }

    fn contact(&self) -> &[usize] {
        &self.system.contact
    }

    fn contact_mean(&self, u: &[f64]) -> f64 {
        PlateSystem::contact_mean(self, u)
    }

    /// The paper's closed form, split at its kinks ([`crate::plate::norms::l2_error`]); a plane
    /// wave by characteristics, integrated in x by its own rule
    /// ([`crate::plate::norms::l2_error_plane_wave`]).
    fn l2_error(&self, u: &[f64], exact: &Exact, t: f64) -> f64 {
        match exact {
            Exact::Paper(e) => crate::plate::norms::l2_error(self, u, e, t),
            Exact::General(c) => crate::plate::norms::l2_error_plane_wave(self, u, c, t),
        }
    }

    fn interp_norm(&self, exact: &Exact, t: f64, scratch: &mut Vec<f64>) -> f64 {
        scratch.resize(self.dofs.len(), 0.0);
        for (e, &v) in scratch.iter_mut().zip(&self.dofs) {
            *e = exact.u(self.mesh.points[v][0], t);
        }
        crate::plate::norms::l2_norm(self, scratch)
    }

    fn y_variation(&self, u: &[f64]) -> f64 {
        self.base.iter().enumerate().filter_map(|(d, b)| b.map(|b| (u[d] - u[b]).abs())).fold(0.0, f64::max)
    }

    fn n_nodes(&self) -> usize {
        self.mesh.n_nodes()
    }

    fn nodal_values(&self, u: &[f64], out: &mut [f64]) {
        self.to_nodes(u, out)
    }
}

impl Geometry for PlateSystem {
    type Matrix = crate::linalg::sparse::SpMat;

    fn force_key(&self) -> &'static str {
        "plate.force"
    }

    fn system(&self) -> &ContactSystem<Self::Matrix> {
        &self.system
    }

    fn lumped_mass(&self) -> Option<Vec<f64>> {
        Some(self.lumped.clone())
    }
}
