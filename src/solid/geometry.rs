//! The solid as a [`Geometry`] of the one driver: contact means over Γ_C, the vector L² norms
//! against the plane wave, nodal values for output.
//!
//! - `u0`: the plain mean of u_x over the contact-face nodes (each node once); `contact_mean`
//!   (the series' `u_mean`): `∫_{Γ_C} u_{h,x} / |Γ_C|`, as for plates;
//! - `contact_measure` = `section` = `|Γ_C|` (H in 2D, H·D in 3D; a body's contact area
//!   `Σ_i a_i`), so the driver's pressure is the total contact reaction divided by it; for a
//!   body `u0` and `u_mean` are the means of the normal displacement u_n;
//! - `l2_error`: `‖u_h − u‖_{L²(Ω)^d}` against the plane wave `u = (u¹ᴰ(x, t), 0[, 0])`. The
//!   transverse components are the quadratic form of the unit mass (exact). For u_x on a
//!   structured Q1 mesh, u_h restricted to a line (y, z) fixed is the P1 function of x with the
//!   multilinear interpolation of the nodal values; `∫ (u_h − u)² dx` along it (the 1D exact
//!   error, split at the kinks: [`crate::bar::norms::l2_error`] or
//!   `Characteristics::l2_error_p1`) is a polynomial of degree ≤ 2 in each of y, z, so the
//!   2 (× 2)-point Gauss rule across each transverse cell integrates it exactly. Simplex meshes:
//!   not offered (NaN, [`GeometryView::integrates`] false);
//! - `nodal_values`: [`GeometryView::components`] = d values per node, interleaved
//!   `node·d + component` (0 where eliminated).

use super::assembly::SolidSystem;
use crate::bar::assembly::Bar;
use crate::column::Column;
use crate::exact::Exact;
use crate::problem::{Geometry, GeometryView, OwnSummary};
use crate::schemes::StiffnessOperator;
use crate::system::ContactSystem;

impl SolidSystem {
    /// The plain mean of u_x over the contact nodes (each node once): the reported `u0`.
    pub fn contact_node_mean(&self, u: &[f64]) -> f64 {
        let c = &self.system.contact;
        c.iter().map(|&i| u[i]).sum::<f64>() / c.len() as f64
    }

    /// The mean of u_x over Γ_C, `Σ_c a_c u_c / |Γ_C|` with `a_c = ∫_{Γ_C} φ_c`: the reported
    /// `u_mean` (as for plates).
    pub fn contact_mean(&self, u: &[f64]) -> f64 {
        let s: f64 = self.system.contact.iter().zip(&self.contact_areas).map(|(&c, a)| a * u[c]).sum();
        s / self.contact_area()
    }

    /// `|Γ_C|`: the box's face x = 0, or a body's contact area `Σ_i a_i`.
    pub fn contact_area(&self) -> f64 {
        self.contact_area
    }

    /// `∫_Ω (u_{h,x} − u(x, t))² ` on a structured Q1 mesh (module docs); NaN otherwise.
    fn x_error_squared(&self, u: &[f64], exact: &Exact, t: f64) -> f64 {
        let (mesh, d) = (&self.mesh, self.mesh.dim);
        let Some([nx, ny, nz]) = mesh.grid.filter(|_| mesh.kind.is_tensor()) else {
            return f64::NAN;
        };
        let nz = if d == 2 { 1 } else { nz };
        let node = |i: usize, j: usize, k: usize| (k * (ny + 1) + j) * (nx + 1) + i;
        let ux = |v: usize| self.dof_of.get(v * d).map_or(0.0, |k| u[k]);
        let xs: Vec<f64> = (0..=nx).map(|i| mesh.points[i][0]).collect();
        let bar = Bar { length: mesh.extent[0], elements: nx };
        let g = [0.5 - 0.5 / 3f64.sqrt(), 0.5 + 0.5 / 3f64.sqrt()];
        let (gz_count, layers) = if d == 2 { (1, 1) } else { (2, 2) };
        let mut line = vec![0.0; nx + 1];
        let mut sum = 0.0;
        for k in 0..nz {
            for j in 0..ny {
                let hy = mesh.points[node(0, j + 1, 0)][1] - mesh.points[node(0, j, 0)][1];
                let hz = if d == 2 { 1.0 } else { mesh.points[node(0, 0, k + 1)][2] - mesh.points[node(0, 0, k)][2] };
                for gy in g {
                    for &gz in &g[..gz_count] {
                        for (i, l) in line.iter_mut().enumerate() {
                            let mut s = 0.0;
                            for b in 0..2 {
                                let wy = if b == 1 { gy } else { 1.0 - gy };
                                for c in 0..layers {
                                    let wz = if d == 2 {
                                        1.0
                                    } else if c == 1 {
                                        gz
                                    } else {
                                        1.0 - gz
                                    };
                                    s += wy * wz * ux(node(i, j + b, k + c));
                                }
                            }
                            *l = s;
                        }
                        let e = match exact {
                            Exact::Paper(p) => crate::bar::norms::l2_error(&bar, &line[..nx], p, t),
                            Exact::General(c) => c.l2_error_p1(&xs, &line, t),
                        };
                        sum += 0.5 * hy * if d == 2 { 1.0 } else { 0.5 * hz } * e * e;
                    }
                }
            }
        }
        sum
    }
}

impl GeometryView for SolidSystem {
    fn name(&self) -> &'static str {
        "solid"
    }

    fn has_tangential(&self) -> bool {
        true
    }

    fn dim(&self) -> usize {
        self.mesh.dim
    }

    fn h(&self) -> f64 {
        self.mesh.h()
    }

    fn length(&self) -> f64 {
        self.mesh.extent[0]
    }

    fn section(&self) -> f64 {
        self.contact_area()
    }

    fn contact_measure(&self) -> f64 {
        self.contact_area()
    }

    fn contact(&self) -> &[usize] {
        &self.system.contact
    }

    fn contact_mean(&self, u: &[f64]) -> f64 {
        SolidSystem::contact_mean(self, u)
    }

    fn u0(&self, u: &[f64]) -> f64 {
        self.contact_node_mean(u)
    }

    /// Module docs: exact on structured Q1 meshes, NaN on simplices.
    fn l2_error(&self, u: &[f64], exact: &Exact, t: f64) -> f64 {
        let ex = self.x_error_squared(u, exact, t);
        let d = self.mesh.dim;
        let transverse: Vec<f64> = u.iter().zip(&self.dofs).map(|(&x, &g)| if g % d == 0 { 0.0 } else { x }).collect();
        let et = self.unit_quad_form(&transverse);
        (ex + et.max(0.0)).sqrt()
    }

    fn integrates(&self, _exact: &Exact) -> bool {
        self.mesh.kind.is_tensor() && self.mesh.grid.is_some()
    }

    fn interp_norm(&self, exact: &Exact, t: f64, scratch: &mut Vec<f64>) -> f64 {
        let d = self.mesh.dim;
        scratch.resize(self.dofs.len(), 0.0);
        for (e, &g) in scratch.iter_mut().zip(&self.dofs) {
            *e = if g % d == 0 { exact.u(self.mesh.points[g / d][0], t) } else { 0.0 };
        }
        self.unit_quad_form(scratch).max(0.0).sqrt()
    }

    /// The largest departure from a plane wave: `max |u_x(x, y, z) − u_x(x, y_0, z_0)|` and the
    /// largest transverse component, on structured meshes (0 otherwise).
    fn y_variation(&self, u: &[f64]) -> f64 {
        let (d, n1) = (self.mesh.dim, self.mesh.grid.map_or(0, |g| g[0] + 1));
        if n1 == 0 || self.frame.is_some() {
            return 0.0;
        }
        let mut worst: f64 = 0.0;
        for (&x, &g) in u.iter().zip(&self.dofs) {
            let (node, comp) = (g / d, g % d);
            let dev = if comp == 0 { self.dof_of.get((node % n1) * d).map_or(x, |b| x - u[b]) } else { x };
            worst = worst.max(dev.abs());
        }
        worst
    }

    fn n_nodes(&self) -> usize {
        self.mesh.n_nodes()
    }

    fn components(&self) -> usize {
        self.mesh.dim
    }

    fn nodal_values(&self, u: &[f64], out: &mut [f64]) {
        self.to_nodes(u, out)
    }

    /// A body's reactions, distances, momentum and mean displacement ([`super::report`]);
    /// none for the box.
    fn own_columns(&self) -> &[Column] {
        match (&self.bodies, &self.frame) {
            (Some(layout), _) => &layout.columns,
            (None, Some(_)) => &super::report::COLUMNS,
            (None, None) => &[],
        }
    }

    fn own_values(&self, u: &[f64], v: &[f64], lambda: &[f64], out: &mut [f64]) {
        self.report(u, v, lambda, out)
    }

    fn own_summary(&self) -> Option<Box<dyn OwnSummary>> {
        let keys = match &self.bodies {
            Some(layout) => super::report::BodyKeys::of_bodies(self.mesh.dim, layout.clone()),
            None => super::report::BodyKeys::new(self.mesh.dim),
        };
        self.frame.as_ref().map(|_| Box::new(keys) as Box<dyn OwnSummary>)
    }
}

impl Geometry for SolidSystem {
    type Matrix = crate::linalg::sparse::SpMat;

    fn force_key(&self) -> &'static str {
        "solid.force"
    }

    fn system(&self) -> &ContactSystem<Self::Matrix> {
        &self.system
    }

    /// Row sums (P1, Q1) or HRZ (P2) of the weighted mass over all nodes, per component
    /// ([`super::lumped`]).
    fn lumped_mass(&self) -> Option<Vec<f64>> {
        Some(SolidSystem::lumped_mass(self))
    }

    /// A lean system's operator ([`super::lean`]), else the structured Q1 box's stencil
    /// ([`super::stencil`]) unless `choice` is `assembled`.
    fn stiffness_operator(&self, choice: StiffnessOperator) -> Option<Box<dyn crate::linalg::Operator>> {
        if let Some(lean) = &self.lean {
            let allowed = lean.operator.is_matrix_free() || choice != StiffnessOperator::MatrixFree;
            return allowed
                .then(|| Box::new(std::sync::Arc::clone(&lean.operator)) as Box<dyn crate::linalg::Operator>);
        }
        match choice {
            StiffnessOperator::Assembled => None,
            StiffnessOperator::Auto | StiffnessOperator::MatrixFree => {
                super::stencil::BoxStencil::of_system(self).map(|s| Box::new(s) as Box<dyn crate::linalg::Operator>)
            }
        }
    }

    fn load_energy(&self) -> crate::problem::LoadEnergy {
        use crate::problem::LoadEnergy;
        match (&self.lean, self.lean_load_energy()) {
            (None, _) => LoadEnergy::Factor,
            (Some(_), Some(e)) => LoadEnergy::Known(e),
            (Some(_), None) => LoadEnergy::FreeFlight,
        }
    }

    fn load_energy_of(&self, f: &[f64]) -> crate::problem::LoadEnergy {
        use crate::problem::LoadEnergy;
        match self.lean.as_ref() {
            None => LoadEnergy::Factor,
            Some(l) if l.singular => LoadEnergy::FreeFlight,
            Some(l) => LoadEnergy::Known(self.conjugate_load_energy(l.operator.as_ref(), f)),
        }
    }
}
