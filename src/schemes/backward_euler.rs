//! Backward Euler with exact contact (paper eq. (4.5), "theta method3").
//!
//! ```text
//! U^{n+1} = Uⁿ + Δt V^{n+1},   V^{n+1} = Vⁿ + Δt A^{n+1},
//! M A^{n+1} + S U^{n+1} = F − λ^{n+1} e_0,   0 ≤ u_0^{n+1} ⊥ λ^{n+1} ≤ 0.
//! ```
//!
//! Eliminating V and A: `(M + Δt² S) U^{n+1} = M (Uⁿ + Δt Vⁿ) + Δt² (F − λ e_0)`, solved for
//! the contact by `contact_multiplier` (schemes/mod.rs) (σ = Δt²). First order, and the energy E = ½VᵀMV + ½UᵀSU − UᵀF never
//! increases: testing the equation with V^{n+1} gives, with `δ = V^{n+1} − Vⁿ`, `ΔU = U^{n+1} − Uⁿ`,
//! `ΔE = −½ δᵀMδ − ½ ΔUᵀSΔU + λ^{n+1} u_0ⁿ ≤ 0` (λ^{n+1} u_0^{n+1} = 0, λ ≤ 0 and u_0ⁿ ≥ 0).

//!
//! A step is three passes: right-hand side, two-sided solve ([`TwistedFactor`]), one update
//! pass (contact correction, V^{n+1}, next predictor Uⁿ⁺¹ + Δt Vⁿ⁺¹).

use super::{SchemeError, StateView, check_finite, check_range, contact_multiplier, factor_err};
use crate::assembly::System;
use crate::tridiag::{SymTridiag, TwistedFactor};

#[derive(Debug, Clone)]
pub struct BackwardEuler {
    dt: f64,
    mass: SymTridiag,
    load: Vec<f64>,
    factor: TwistedFactor,
    /// z = K⁻¹ e_0.
    response: Vec<f64>,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    lambda: f64,
    /// Uⁿ + Δt Vⁿ for the next step.
    pred: Vec<f64>,
    rhs: Vec<f64>,
}

impl BackwardEuler {
    pub const NAME: &'static str = "backward-euler";

    pub fn new(system: &System, dt: f64, u0: Vec<f64>, v0: Vec<f64>) -> Result<Self, SchemeError> {
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let k = system.mass.combine(1.0, &system.stiffness, dt * dt);
        let factor = k.factor_twisted().map_err(factor_err("M + Δt² S"))?;
        let response = factor.unit_response(0);
        let pred = u0.iter().zip(&v0).map(|(u, v)| u + dt * v).collect();
        let m = system.m();
        Ok(Self {
            dt,
            mass: system.mass.clone(),
            load: system.load.clone(),
            factor,
            response,
            n: 0,
            u: u0,
            v: v0,
            lambda: 0.0,
            pred,
            rhs: vec![0.0; m],
        })
    }
}

impl super::Scheme for BackwardEuler {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: self.lambda }
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let dt = self.dt;
        let sigma = dt * dt;
        self.mass.mul_add_into(&self.pred, sigma, Some(&self.load), &mut self.rhs);
        self.factor.solve_in_place(&mut self.rhs);
        self.lambda = contact_multiplier(self.rhs[0], 0.0, sigma, self.response[0]);
        let s = sigma * self.lambda;
        if self.lambda != 0.0 {
            self.rhs[0] = s * self.response[0]; // so that u_0 = x_0 − s z_0 = 0 exactly
        }
        let m = self.u.len();
        let (u, v, pred) = (&mut self.u[..m], &mut self.v[..m], &mut self.pred[..m]);
        let (x, z) = (&self.rhs[..m], &self.response[..m]);
        for i in 0..m {
            let u_new = x[i] - s * z[i];
            let v_new = (u_new - u[i]) / dt;
            u[i] = u_new;
            v[i] = v_new;
            pred[i] = u_new + dt * v_new;
        }
        self.n += 1;
        check_finite(&self.u, self.lambda, self.n, self.n as f64 * dt)
    }
}
