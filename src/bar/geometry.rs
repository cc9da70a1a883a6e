//! The bar as a [`Geometry`] of the one driver: its contact node u_0, its exact L² norms
//! ([`super::norms`]), its fast per-step diagnostics (one-pass tridiagonal kernels) and its
//! one-node contact system (Paoli–Schatzman and the reduced formulation need it).

use super::assembly::BarSystem;
use super::norms::Energy;
use crate::exact::Exact;
use crate::problem::{Diagnostics, Geometry, GeometryView};
use crate::schemes::OneNodeContact;
use crate::system::ContactSystem;

impl BarSystem {
    /// Its one-node contact system ([`OneNodeContact`]).
    pub fn one_node(&self) -> OneNodeContact<'_> {
        OneNodeContact { system: &self.system, h: self.h(), w0: self.weights[0] }
    }
}

impl GeometryView for BarSystem {
    fn name(&self) -> &'static str {
        "bar"
    }

    fn dim(&self) -> usize {
        1
    }

    fn h(&self) -> f64 {
        self.bar.h()
    }

    fn length(&self) -> f64 {
        self.bar.length
    }

    fn section(&self) -> f64 {
        1.0
    }

    fn contact_measure(&self) -> f64 {
        1.0
    }

    fn contact(&self) -> &[usize] {
        &self.system.contact
    }

    fn contact_mean(&self, u: &[f64]) -> f64 {
        u[0]
    }

    /// The paper's closed form is integrated split at its kinks ([`super::norms::l2_error`]);
    /// the general solution by its own exact cell rule (`Characteristics::l2_error_p1`).
    fn l2_error(&self, u: &[f64], exact: &Exact, t: f64) -> f64 {
        match exact {
            Exact::Paper(e) => super::norms::l2_error(&self.bar, u, e, t),
            Exact::General(c) => {
                let nodes: Vec<f64> = (0..=self.m()).map(|i| self.bar.x(i)).collect();
                let mut values = u.to_vec();
                values.resize(self.m() + 1, 0.0); // u_m = 0 when clamped
                c.l2_error_p1(&nodes, &values, t)
            }
        }
    }

    fn interp_norm(&self, exact: &Exact, t: f64, scratch: &mut Vec<f64>) -> f64 {
        scratch.resize(self.n(), 0.0);
        for (i, e) in scratch.iter_mut().enumerate() {
            *e = exact.u(self.bar.x(i), t);
        }
        super::norms::l2_norm_p1(&self.bar, scratch)
    }

    fn n_nodes(&self) -> usize {
        self.m() + 1
    }

    fn nodal_values(&self, u: &[f64], out: &mut [f64]) {
        out[..u.len()].copy_from_slice(u);
        out[u.len()..].fill(0.0);
    }
}

impl Geometry for BarSystem {
    type Matrix = crate::linalg::tridiag::SymTridiag;

    fn force_key(&self) -> &'static str {
        "bar.force"
    }

    fn system(&self) -> &ContactSystem<Self::Matrix> {
        &self.system
    }

    fn one_node(&self) -> Option<OneNodeContact<'_>> {
        Some(BarSystem::one_node(self))
    }

    fn lumped_mass(&self) -> Option<Vec<f64>> {
        Some(self.lumped.clone())
    }

    fn diagnostics(&self) -> Box<dyn Diagnostics + '_> {
        let s = &self.system;
        let unloaded = s.forcing.is_none() && s.load.iter().all(|&f| f == 0.0);
        Box::new(BarDiagnostics {
            bar: self,
            kernel: Energy::new(&s.mass, &s.stiffness),
            unloaded,
            load: Vec::new(),
            interp: Vec::new(),
            nodes: (0..=self.m()).map(|i| self.bar.x(i)).collect(),
            values: Vec::new(),
        })
    }
}

/// The bar's one-pass diagnostics ([`super::norms`]): the energy in one pass instead of three,
/// the closed-form L² error and interpolant norm together, without per-node phase searches.
/// They agree with the general ones to round-off.
struct BarDiagnostics<'b> {
    bar: &'b BarSystem,
    kernel: Energy,
    /// The load is 0 (its work term is skipped).
    unloaded: bool,
    /// F(t) of a time-dependent load.
    load: Vec<f64>,
    /// The exact solution at the nodes.
    interp: Vec<f64>,
    /// The node coordinates, and the nodal values (u_m = 0 when clamped) for the general exact
    /// solution's L² error.
    nodes: Vec<f64>,
    values: Vec<f64>,
}

impl Diagnostics for BarDiagnostics<'_> {
    fn energy(&mut self, u: &[f64], v: &[f64], t: f64) -> f64 {
        let s = &self.bar.system;
        let load = if s.forcing.is_some() {
            self.load.resize(s.n(), 0.0);
            s.load_at(t, &mut self.load);
            Some(&self.load[..])
        } else {
            (!self.unloaded).then_some(&s.load[..])
        };
        self.kernel.energy(&s.mass, &s.stiffness, load, u, v)
    }

    fn l2(&mut self, u: &[f64], exact: &Exact, t: f64) -> (f64, f64) {
        match exact {
            Exact::Paper(e) => {
                super::norms::l2_error_and_interp_norm(&self.bar.bar, u, e, t, &self.nodes, &mut self.interp)
            }
            Exact::General(c) => {
                self.values.clear();
                self.values.extend_from_slice(u);
                self.values.resize(self.nodes.len(), 0.0); // u_m = 0 when clamped
                (c.l2_error_p1(&self.nodes, &self.values, t), self.bar.interp_norm(exact, t, &mut self.interp))
            }
        }
    }
}
