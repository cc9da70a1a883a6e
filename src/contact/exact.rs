//! The exact law: the Signorini condition `0 ≤ u_c − lb_c ⊥ λ_c ≤ 0` itself.
//!
//! - Implicit step ([`ExactStep`]): the back-end's exact solver of `K U = r − σ Σ λ_c e_c`
//!   ([`super::OneNode`] for a bar, [`super::Schur`] for many nodes).
//! - Central differences ([`ExactExplicit`]): on massive contact nodes the forward-increment
//!   Lagrange multiplier (Carpenter, Taylor, Katona, IJNME 32, 1991: with `ũ_c = u_cⁿ +
//!   Δt v_c + κΔt² a_c` the contact-free prediction, `λ_c = min(0, (ũ_c − lb_c) m_c/(κΔt²))`, κ = 1,
//!   ½ at n = 0); on massless ones the quasi-static rows solved exactly ([`super::layer::Layer`]:
//!   the contact and free massless unknowns of the layer with a sparse factor, issue 31).

use super::layer::Layer;
use super::lcp::LcpError;
use super::{ContactSolver, ExplicitLaw, Massive, StepLaw};
use crate::linalg::{LinalgError, SymMatrix};
use crate::system::ContactSystem;

/// The exact implicit step: the back-end's solver with the scheme's σ.
#[derive(Debug)]
pub struct ExactStep<S: ContactSolver> {
    pub solver: S,
    pub sigma: f64,
}

impl<S: ContactSolver> StepLaw for ExactStep<S> {
    fn solve(&mut self, rhs: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError> {
        self.solver.solve(rhs, lower, self.sigma, lambda)
    }

    fn reciprocal_sigma(&self) -> bool {
        true
    }
}

/// The contact unknowns of central differences split by their lumped mass: the massive ones
/// `(slot in contact order, unknown)`, and the massless ones (slots, unknowns) with the free
/// massless unknowns (massless, not contact: a contact layer's).
#[derive(Debug, Clone)]
pub struct Split {
    pub massive: Vec<(usize, usize)>,
    pub slots: Vec<usize>,
    pub massless: Vec<usize>,
    pub free: Vec<usize>,
    /// The bounds of the massless contact unknowns.
    pub lower: Vec<f64>,
}

impl Split {
    pub fn new<A>(system: &ContactSystem<A>, lumped: &[f64]) -> Self {
        let contact = &system.contact;
        let mut is_contact = vec![false; lumped.len()];
        contact.iter().for_each(|&c| is_contact[c] = true);
        let massive = contact.iter().enumerate().filter(|&(_, &c)| lumped[c] > 0.0).map(|(s, &c)| (s, c)).collect();
        let slots: Vec<usize> = (0..contact.len()).filter(|&s| lumped[contact[s]] <= 0.0).collect();
        let massless = slots.iter().map(|&s| contact[s]).collect();
        let free = (0..lumped.len()).filter(|&i| lumped[i] <= 0.0 && !is_contact[i]).collect();
        let lower = slots.iter().map(|&s| system.lower[s]).collect();
        Self { massive, slots, massless, free, lower }
    }
}

/// A law's quasi-static map of the massless unknowns (the exact [`Layer`], the penalty's
/// `super::penalty::PenaltyQuasiStatic`).
pub trait QuasiRows: std::fmt::Debug + Send {
    /// Takes the entries of a new load vector.
    fn set_load(&mut self, load: &[f64]);
    /// Overwrites the massless entries of `u` and writes the multipliers; returns the pivots.
    fn apply(&mut self, u: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError>;
}

impl QuasiRows for Layer {
    fn set_load(&mut self, load: &[f64]) {
        Layer::set_load(self, load)
    }

    fn apply(&mut self, u: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError> {
        Layer::apply(self, u, lower, lambda)
    }
}

/// The massless contact unknowns of central differences under a law's map Φ (None without
/// massless unknowns), with their slots in contact order.
#[derive(Debug)]
pub struct MasslessRows<Q: QuasiRows> {
    phi: Option<Q>,
    slots: Vec<usize>,
    lower: Vec<f64>,
    lambda: Vec<f64>,
}

impl<Q: QuasiRows> MasslessRows<Q> {
    pub fn new(split: &Split, phi: Option<Q>) -> Self {
        let (slots, lower) = (split.slots.clone(), split.lower.clone());
        Self { phi, lambda: vec![0.0; slots.len()], slots, lower }
    }

    /// Φ at the current time (`forced`: the load depends on t); writes the λ of the massless
    /// contact unknowns into `lambda` (contact order).
    pub fn solve(&mut self, u: &mut [f64], load: &[f64], forced: bool, lambda: &mut [f64]) -> Result<usize, LcpError> {
        let Some(phi) = &mut self.phi else { return Ok(0) };
        if forced {
            phi.set_load(load);
        }
        let pivots = phi.apply(u, &self.lower, &mut self.lambda)?;
        for (&k, &l) in self.slots.iter().zip(&self.lambda) {
            lambda[k] = l;
        }
        Ok(pivots)
    }
}

/// The exact law in central differences (module docs).
#[derive(Debug)]
pub struct ExactExplicit {
    massive: Vec<(usize, usize)>,
    lower: Vec<f64>,
    massless: MasslessRows<Layer>,
}

impl ExactExplicit {
    pub fn new<A: SymMatrix>(system: &ContactSystem<A>, lumped: &[f64]) -> Result<Self, LinalgError> {
        let split = Split::new(system, lumped);
        let any_massless = lumped.iter().any(|&m| m <= 0.0);
        let phi = if any_massless {
            Some(Layer::new(&system.stiffness, &system.load, &split.massless, &split.free)?)
        } else {
            None
        };
        let massless = MasslessRows::new(&split, phi);
        Ok(Self { massive: split.massive, lower: system.lower.clone(), massless })
    }
}

impl ExplicitLaw for ExactExplicit {
    fn massive(&mut self, s: Massive<'_>) {
        let dt2 = s.kappa * s.dt * s.dt;
        for &(k, c) in &self.massive {
            let predicted = s.u[c] + s.dt * s.v[c] + dt2 * s.a[c];
            let l = ((predicted - self.lower[k]) * s.lumped[c] / dt2).min(0.0);
            s.lambda[k] = l;
            s.a[c] -= l * s.inv_mass[c];
        }
    }

    fn quasi_static(
        &mut self,
        u: &mut [f64],
        load: &[f64],
        forced: bool,
        lambda: &mut [f64],
    ) -> Result<usize, LcpError> {
        self.massless.solve(u, load, forced, lambda)
    }
}
