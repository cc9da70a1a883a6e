//! Backward Euler with exact contact (paper eq. (4.5), "theta method3").
//!
//! ```text
//! U^{n+1} = Uⁿ + Δt V^{n+1},   V^{n+1} = Vⁿ + Δt A^{n+1},
//! M A^{n+1} + S U^{n+1} = F − λ^{n+1} e_0,   0 ≤ u_0^{n+1} ⊥ λ^{n+1} ≤ 0.
//! ```
//!
//! Eliminating V and A: `(M + Δt² S) U^{n+1} = M (Uⁿ + Δt Vⁿ) + Δt² (F − λ e_0)`, solved with
//! [`ContactSolver`] (σ = Δt²). First order, and the energy E = ½VᵀMV + ½UᵀSU − UᵀF never
//! increases: testing the equation with V^{n+1} gives, with `δ = V^{n+1} − Vⁿ`, `ΔU = U^{n+1} − Uⁿ`,
//! `ΔE = −½ δᵀMδ − ½ ΔUᵀSΔU + λ^{n+1} u_0ⁿ ≤ 0` (λ^{n+1} u_0^{n+1} = 0, λ ≤ 0 and u_0ⁿ ≥ 0).

use super::{SchemeError, StateView, check_finite, check_range, factor_err};
use crate::assembly::System;
use crate::contact::ContactSolver;
use crate::tridiag::SymTridiag;

#[derive(Debug, Clone)]
pub struct BackwardEuler {
    dt: f64,
    mass: SymTridiag,
    load: Vec<f64>,
    contact: ContactSolver,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    lambda: f64,
    pred: Vec<f64>,
    rhs: Vec<f64>,
}

impl BackwardEuler {
    pub const NAME: &'static str = "backward-euler";

    pub fn new(system: &System, dt: f64, u0: Vec<f64>, v0: Vec<f64>) -> Result<Self, SchemeError> {
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let k = system.mass.combine(1.0, &system.stiffness, dt * dt);
        let contact = ContactSolver::new(&k).map_err(factor_err("M + Δt² S"))?;
        let m = system.m();
        Ok(Self {
            dt,
            mass: system.mass.clone(),
            load: system.load.clone(),
            contact,
            n: 0,
            u: u0,
            v: v0,
            lambda: 0.0,
            pred: vec![0.0; m],
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
        for i in 0..self.u.len() {
            self.pred[i] = self.u[i] + dt * self.v[i];
        }
        self.mass.mul_into(&self.pred, &mut self.rhs);
        for (r, f) in self.rhs.iter_mut().zip(&self.load) {
            *r += sigma * f;
        }
        self.lambda = self.contact.solve(&mut self.rhs, 0.0, sigma);
        for i in 0..self.u.len() {
            self.v[i] = (self.rhs[i] - self.u[i]) / dt;
            self.u[i] = self.rhs[i];
        }
        self.n += 1;
        check_finite(&self.u, self.lambda, self.n, self.n as f64 * dt)
    }
}
