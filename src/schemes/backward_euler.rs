//! Backward Euler with a contact law (paper eq. (4.5), "theta method3"; the law's λ: exact
//! Signorini by default, penalty or Nitsche, [`crate::contact::StepLaw`]).
//!
//! ```text
//! U^{n+1} = Uⁿ + Δt V^{n+1},   V^{n+1} = Vⁿ + Δt A^{n+1},
//! M A^{n+1} + S U^{n+1} = F − Σ_c λ_c^{n+1} e_c,   0 ≤ u_c^{n+1} − lb_c ⊥ λ_c^{n+1} ≤ 0.
//! ```
//!
//! Eliminating V and A: `(M + Δt² S) U^{n+1} = M (Uⁿ + Δt Vⁿ) + Δt² (F − Σ λ_c e_c)`, solved
//! for the contact by the law's step (σ = Δt²). First order, and with exact contact the energy
//! E = ½VᵀMV + ½UᵀSU − UᵀF never increases: testing the equation with V^{n+1}
//! gives, with `δ = V^{n+1} − Vⁿ`, `ΔU = U^{n+1} − Uⁿ`,
//! `ΔE = −½ δᵀMδ − ½ ΔUᵀSΔU + Σ_c λ_c^{n+1} (u_cⁿ − lb_c) ≤ 0`
//! (`λ^{n+1} ⊥ u^{n+1} − lb`, λ ≤ 0 and uⁿ ≥ lb).
//!
//! A step is three passes: right-hand side, solve with contact, one update pass (V^{n+1}, next
//! predictor U^{n+1} + Δt V^{n+1}).

use super::{SchemeError, StateView, check_finite, check_range, contact_err};
use crate::contact::law::ContactLaw;
use crate::contact::{Backend, StepLaw};
use crate::system::ContactSystem;

#[derive(Debug)]
pub struct BackwardEuler<A: Backend> {
    dt: f64,
    mass: A,
    /// S, kept for the energy of a law with a force (None for the exact law).
    stiffness: Option<A>,
    load: Vec<f64>,
    /// A time-dependent load: `load` is refreshed to F(t_{n+1}) at each step.
    forcing: Option<crate::system::Forcing>,
    lower: Vec<f64>,
    law: Box<dyn StepLaw>,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    lambda: Vec<f64>,
    /// Uⁿ + Δt Vⁿ for the next step.
    pred: Vec<f64>,
    rhs: Vec<f64>,
    pivots: usize,
}

impl<A: Backend> BackwardEuler<A> {
    pub const NAME: &'static str = super::SchemeSpec::BackwardEuler.name();

    /// Backward Euler with exact contact.
    pub fn new(system: &ContactSystem<A>, dt: f64, u0: Vec<f64>, v0: Vec<f64>) -> Result<Self, SchemeError> {
        Self::with_law(system, &ContactLaw::Exact, dt, u0, v0)
    }

    /// Backward Euler with the contact law `law` (λ⁰ of the data for a law with a force).
    pub fn with_law(
        system: &ContactSystem<A>,
        law: &ContactLaw,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let name = "M + Δt² S";
        let k = system.mass.combine(1.0, &system.stiffness, dt * dt, name)?;
        let mut law = law.step_law(system, &k, name, dt * dt, dt)?;
        law.start(&u0);
        let mut lambda = vec![0.0; system.contact.len()];
        law.lambda_of(&u0, &system.lower, &mut lambda);
        let stiffness = law.has_force().then(|| system.stiffness.clone());
        let pred = u0.iter().zip(&v0).map(|(u, v)| u + dt * v).collect();
        Ok(Self {
            dt,
            mass: system.mass.clone(),
            stiffness,
            load: system.load.clone(),
            forcing: system.forcing.clone(),
            lower: system.lower.clone(),
            law,
            n: 0,
            rhs: vec![0.0; u0.len()],
            u: u0,
            v: v0,
            lambda,
            pred,
            pivots: 0,
        })
    }

    /// `½V·MV + ½U·SU − F·U` plus the law's energy, for a law with one; None for the exact law.
    pub fn energy(&self) -> Option<f64> {
        let (stiffness, law) = (self.stiffness.as_ref()?, self.law.energy(&self.u, &self.lower)?);
        let work: f64 = self.u.iter().zip(&self.load).map(|(u, f)| u * f).sum();
        Some(0.5 * self.mass.quad_form(&self.v) + 0.5 * stiffness.quad_form(&self.u) - work + law)
    }
}

impl<A: Backend> super::Scheme for BackwardEuler<A> {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: &self.lambda }
    }

    fn pivots(&self) -> usize {
        self.pivots
    }

    fn friction(&self) -> Option<&crate::contact::friction::FrictionRecord> {
        self.law.friction()
    }

    fn energy(&self) -> Option<f64> {
        BackwardEuler::energy(self)
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let dt = self.dt;
        let sigma = dt * dt;
        let (step, time) = (self.n + 1, (self.n + 1) as f64 * dt);
        if let Some(f) = &self.forcing {
            (f.0)(time, &mut self.load); // implicit: the equation is written at t_{n+1}
        }
        self.mass.mul_add_into(&self.pred, sigma, &self.load, &mut self.rhs);
        self.pivots = self.law.solve(&mut self.rhs, &self.lower, &mut self.lambda).map_err(contact_err(step, time))?;
        let m = self.u.len();
        let (u, v, pred) = (&mut self.u[..m], &mut self.v[..m], &mut self.pred[..m]);
        let x = &self.rhs[..m];
        for i in 0..m {
            let u_new = x[i];
            let v_new = (u_new - u[i]) / dt;
            u[i] = u_new;
            v[i] = v_new;
            pred[i] = u_new + dt * v_new;
        }
        self.n = step;
        check_finite(&self.u, &self.lambda, A::SOLVE_SPREADS_NAN, step, time)
    }
}
