//! Newmark(β, γ) with a contact law (paper eq. (4.4), with `−Σ_c λ_c e_c`; the law's λ:
//! exact Signorini by default, penalty or Nitsche, [`crate::contact::StepLaw`]).
//!
//! ```text
//! U^{n+1} = Uⁿ + Δt Vⁿ + (½ − β) Δt² Aⁿ + β Δt² A^{n+1}
//! V^{n+1} = Vⁿ + (1 − γ) Δt Aⁿ + γ Δt A^{n+1}
//! M A^{n+1} + S U^{n+1} = F − Σ_c λ_c^{n+1} e_c,     0 ≤ u_c^{n+1} − lb_c ⊥ λ_c^{n+1} ≤ 0
//! ```
//!
//! Eliminating A^{n+1} = (U^{n+1} − Ũ)/(β Δt²) with the predictor
//! `Ũ = Uⁿ + Δt Vⁿ + (½ − β) Δt² Aⁿ` gives `(M + β Δt² S) U^{n+1} = M Ũ + β Δt² (F − Σ λ_c e_c)`,
//! solved exactly for the contact by the back-end's [`ContactSolver`] (σ = β Δt²).
//! Crank–Nicolson is (β, γ) = (1/4, 1/2): second order and energy conserving without contact.
//! With massless contact nodes their rows are the quasi-static Signorini rows
//! `(S U)_C = F_C − λ`; in 1D (w_0 = 0) the contact row reads `(u_0 − u_1)/h = −λ`, whose
//! complementarity solution is `u_0 = u_1⁺` (paper eq. (3.2)).
//!
//! A step is three passes over the unknowns: the right-hand side `M Ũ + σ F`, the solve with
//! contact, and one update pass that forms A^{n+1}, V^{n+1} and the next predictor Ũ.

use super::{Beta, Gamma, SchemeError, SchemeSpec, StateView, check_finite, check_range, contact_err};
use crate::contact::law::ContactLaw;
use crate::contact::{Backend, StepLaw};
use crate::system::ContactSystem;

#[derive(Debug)]
pub struct Newmark<A: Backend> {
    beta: f64,
    gamma: f64,
    dt: f64,
    mass: A,
    /// S, kept for the energy of a law with a force (None for the exact law).
    stiffness: Option<A>,
    load: Vec<f64>,
    /// A time-dependent load: `load` is refreshed to F(t_{n+1}) at each step.
    forcing: Option<crate::system::Forcing>,
    lower: Vec<f64>,
    /// Massless unknowns and their displacement at the start of the step.
    massless: Vec<usize>,
    massless_old: Vec<f64>,
    law: Box<dyn StepLaw>,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: Vec<f64>,
    /// The predictor Ũ of the next step (kept up to date by the update pass).
    pred: Vec<f64>,
    rhs: Vec<f64>,
    pivots: usize,
}

impl<A: Backend> Newmark<A> {
    pub const NAME: &'static str = SchemeSpec::NEWMARK.name();

    /// Newmark(β, γ) with exact contact ([`Beta`], [`Gamma`]: in range by their type;
    /// unconditionally stable without contact for γ ≥ ½ and β ≥ (½ + γ)²/4).
    pub fn new(
        system: &ContactSystem<A>,
        beta: Beta,
        gamma: Gamma,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        Self::with_law(system, &ContactLaw::Exact, beta, gamma, dt, u0, v0)
    }

    /// Newmark(β, γ) with the contact law `law`.
    pub fn with_law(
        system: &ContactSystem<A>,
        law: &ContactLaw,
        beta: Beta,
        gamma: Gamma,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        let (beta, gamma) = (beta.get(), gamma.get());
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let name = "M + β Δt² S";
        let k = system.mass.combine(1.0, &system.stiffness, beta * dt * dt, name)?;
        let mut law = law.step_law(system, &k, name, beta * dt * dt, dt)?;
        law.start(&u0);
        let mut lambda = vec![0.0; system.contact.len()];
        let (a, stiffness) = if law.has_force() {
            // A⁰ with the law's force of the data (the penalty's: 0 unless they penetrate).
            let mut with_force = system.clone();
            law.add_force(&u0, &system.lower, -1.0, &mut with_force.load);
            law.lambda_of(&u0, &system.lower, &mut lambda);
            (with_force.initial_acceleration(&u0)?, Some(system.stiffness.clone()))
        } else {
            (system.initial_acceleration(&u0)?, None)
        };
        let c = (0.5 - beta) * dt * dt;
        let pred = (0..u0.len()).map(|i| u0[i] + dt * v0[i] + c * a[i]).collect();
        let massless: Vec<usize> = (0..system.n()).filter(|&i| system.massless[i]).collect();
        Ok(Self {
            beta,
            gamma,
            dt,
            mass: system.mass.clone(),
            stiffness,
            load: system.load.clone(),
            forcing: system.forcing.clone(),
            lower: system.lower.clone(),
            massless_old: vec![0.0; massless.len()],
            massless,
            law,
            n: 0,
            rhs: vec![0.0; u0.len()],
            u: u0,
            v: v0,
            a,
            lambda,
            pred,
            pivots: 0,
        })
    }

    /// Crank–Nicolson, Newmark(1/4, 1/2).
    pub fn crank_nicolson(system: &ContactSystem<A>, dt: f64, u0: Vec<f64>, v0: Vec<f64>) -> Result<Self, SchemeError> {
        Self::new(system, Beta::DEFAULT, Gamma::DEFAULT, dt, u0, v0)
    }

    /// The acceleration Aⁿ.
    pub fn acceleration(&self) -> &[f64] {
        &self.a
    }

    /// `½V·MV + ½U·SU − F·U` plus the law's energy (F of the last step's time), for a law with
    /// one (penalty springs, Nitsche's θΦ); None for the exact law (the run computes the
    /// system's).
    pub fn energy(&self) -> Option<f64> {
        let (stiffness, law) = (self.stiffness.as_ref()?, self.law.energy(&self.u, &self.lower)?);
        let work: f64 = self.u.iter().zip(&self.load).map(|(u, f)| u * f).sum();
        Some(0.5 * self.mass.quad_form(&self.v) + 0.5 * stiffness.quad_form(&self.u) - work + law)
    }
}

impl<A: Backend> super::Scheme for Newmark<A> {
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
        Newmark::energy(self)
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let (dt, beta, gamma) = (self.dt, self.beta, self.gamma);
        let sigma = beta * dt * dt;
        let c = (0.5 - beta) * dt * dt;
        let (step, time) = (self.n + 1, (self.n + 1) as f64 * dt);
        if let Some(f) = &self.forcing {
            (f.0)(time, &mut self.load); // the equation of motion is written at t_{n+1}
        }
        self.mass.mul_add_into(&self.pred, sigma, &self.load, &mut self.rhs);
        for (old, &i) in self.massless_old.iter_mut().zip(&self.massless) {
            *old = self.u[i];
        }
        self.pivots = self.law.solve(&mut self.rhs, &self.lower, &mut self.lambda).map_err(contact_err(step, time))?;
        let inv_sigma = 1.0 / sigma;
        let reciprocal = self.law.reciprocal_sigma();
        let m = self.u.len();
        let (u, v, a, pred) = (&mut self.u[..m], &mut self.v[..m], &mut self.a[..m], &mut self.pred[..m]);
        let x = &self.rhs[..m];
        for i in 0..m {
            let u_new = x[i];
            // (The two forms differ by one rounding: StepLaw::reciprocal_sigma.)
            let a_new = if reciprocal { (u_new - pred[i]) * inv_sigma } else { (u_new - pred[i]) / sigma };
            let v_new = v[i] + dt * ((1.0 - gamma) * a[i] + gamma * a_new);
            u[i] = u_new;
            v[i] = v_new;
            a[i] = a_new;
            pred[i] = u_new + dt * v_new + c * a_new;
        }
        for (&old, &i) in self.massless_old.iter().zip(&self.massless) {
            // Quasi-static unknown: its a and v enter no equation (module docs of `schemes`).
            a[i] = 0.0;
            v[i] = (u[i] - old) / dt;
            pred[i] = u[i] + dt * v[i];
        }
        self.n = step;
        check_finite(&self.u, &self.lambda, A::SOLVE_SPREADS_NAN, step, time)
    }
}
