//! Newmark(β, γ) on the full m-unknown system with exact contact (paper eq. (4.4)).
//!
//! ```text
//! U^{n+1} = Uⁿ + Δt Vⁿ + (½ − β) Δt² Aⁿ + β Δt² A^{n+1}
//! V^{n+1} = Vⁿ + (1 − γ) Δt Aⁿ + γ Δt A^{n+1}
//! M A^{n+1} + S U^{n+1} = F − λ^{n+1} e_0,     0 ≤ u_0^{n+1} ⊥ λ^{n+1} ≤ 0
//! ```
//!
//! Eliminating A^{n+1} = (U^{n+1} − Ũ)/(β Δt²) with the predictor
//! `Ũ = Uⁿ + Δt Vⁿ + (½ − β) Δt² Aⁿ` gives `(M + β Δt² S) U^{n+1} = M Ũ + β Δt² (F − λ e_0)`,
//! solved exactly for the contact by `contact_multiplier` (schemes/mod.rs) (σ = β Δt²). Crank–Nicolson is
//! (β, γ) = (1/4, 1/2): second order and energy conserving without contact. With w_0 = 0 the
//! contact row reads `(u_0 − u_1)/h = −λ`, whose complementarity solution is `u_0 = u_1⁺`
//! (paper eq. (3.2)).

//!
//! A step is three passes over the nodes: the right-hand side `M Ũ + σ F` (one vectorised
//! pass), the two-sided solve `U* = K⁻¹(M Ũ + σ F)` ([`TwistedFactor`]: two independent
//! substitution chains), and one update pass that applies the contact correction `−σ λ z`
//! (`z = K⁻¹ e_0`) and forms A^{n+1}, V^{n+1} and the next predictor Ũ.

use super::{SchemeError, StateView, check_finite, check_range, contact_multiplier, factor_err, initial_acceleration};
use crate::assembly::System;
use crate::tridiag::{SymTridiag, TwistedFactor};

#[derive(Debug, Clone)]
pub struct Newmark {
    beta: f64,
    gamma: f64,
    dt: f64,
    mass: SymTridiag,
    load: Vec<f64>,
    massless_contact: bool,
    factor: TwistedFactor,
    /// z = K⁻¹ e_0, the response to a unit contact force.
    response: Vec<f64>,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: f64,
    /// The predictor Ũ of the next step (kept up to date by the update pass).
    pred: Vec<f64>,
    rhs: Vec<f64>,
}

impl Newmark {
    pub const NAME: &'static str = "newmark";

    /// Newmark(β, γ) with 0 < β ≤ 1 and 0 ≤ γ ≤ 1 (unconditionally stable without contact for
    /// γ ≥ ½ and β ≥ (½ + γ)²/4).
    pub fn new(
        system: &System,
        beta: f64,
        gamma: f64,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        check_range(Self::NAME, "beta", beta, beta > 0.0 && beta <= 1.0, "(0, 1]")?;
        check_range(Self::NAME, "gamma", gamma, (0.0..=1.0).contains(&gamma), "[0, 1]")?;
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let k = system.mass.combine(1.0, &system.stiffness, beta * dt * dt);
        let factor = k.factor_twisted().map_err(factor_err("M + β Δt² S"))?;
        let response = factor.unit_response(0);
        let a = initial_acceleration(system, &u0)?;
        let c = (0.5 - beta) * dt * dt;
        let pred = (0..u0.len()).map(|i| u0[i] + dt * v0[i] + c * a[i]).collect();
        let m = system.m();
        Ok(Self {
            beta,
            gamma,
            dt,
            mass: system.mass.clone(),
            load: system.load.clone(),
            massless_contact: system.massless_contact(),
            factor,
            response,
            n: 0,
            u: u0,
            v: v0,
            a,
            lambda: 0.0,
            pred,
            rhs: vec![0.0; m],
        })
    }

    /// Crank–Nicolson, Newmark(1/4, 1/2).
    pub fn crank_nicolson(system: &System, dt: f64, u0: Vec<f64>, v0: Vec<f64>) -> Result<Self, SchemeError> {
        Self::new(system, 0.25, 0.5, dt, u0, v0)
    }

    /// The acceleration Aⁿ.
    pub fn acceleration(&self) -> &[f64] {
        &self.a
    }
}

impl super::Scheme for Newmark {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: self.lambda }
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let (dt, beta, gamma) = (self.dt, self.beta, self.gamma);
        let sigma = beta * dt * dt;
        let c = (0.5 - beta) * dt * dt;
        self.mass.mul_add_into(&self.pred, sigma, Some(&self.load), &mut self.rhs);
        self.factor.solve_in_place(&mut self.rhs);
        let lambda = contact_multiplier(self.rhs[0], 0.0, sigma, self.response[0]);
        let s = sigma * lambda;
        if lambda != 0.0 {
            self.rhs[0] = s * self.response[0]; // so that u_0 = x_0 − s z_0 = 0 exactly
        }
        let u0_old = self.u[0];
        let inv_sigma = 1.0 / sigma;
        let m = self.u.len();
        let (u, v, a, pred) = (&mut self.u[..m], &mut self.v[..m], &mut self.a[..m], &mut self.pred[..m]);
        let (x, z) = (&self.rhs[..m], &self.response[..m]);
        for i in 0..m {
            let u_new = x[i] - s * z[i];
            let a_new = (u_new - pred[i]) * inv_sigma;
            let v_new = v[i] + dt * ((1.0 - gamma) * a[i] + gamma * a_new);
            u[i] = u_new;
            v[i] = v_new;
            a[i] = a_new;
            pred[i] = u_new + dt * v_new + c * a_new;
        }
        if self.massless_contact {
            // The contact node is quasi-static: its a and v enter no equation (see module docs).
            a[0] = 0.0;
            v[0] = (u[0] - u0_old) / dt;
            pred[0] = u[0] + dt * v[0];
        }
        self.lambda = lambda;
        self.n += 1;
        check_finite(&self.u, lambda, self.n, self.n as f64 * dt)
    }
}
