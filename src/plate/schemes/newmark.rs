//! Newmark(β, γ) with exact many-node contact (paper eq. (4.4) with `−Σ_c λ_c e_c`).
//!
//! ```text
//! U^{n+1} = Uⁿ + Δt Vⁿ + (½ − β) Δt² Aⁿ + β Δt² A^{n+1}
//! V^{n+1} = Vⁿ + (1 − γ) Δt Aⁿ + γ Δt A^{n+1}
//! M A^{n+1} + S U^{n+1} = F − Σ_c λ_c^{n+1} e_c,     0 ≤ u_c^{n+1} ⊥ λ_c^{n+1} ≤ 0
//! ```
//!
//! As in 1D ([`crate::schemes::Newmark`]): with `Ũ = Uⁿ + Δt Vⁿ + (½ − β) Δt² Aⁿ`,
//! `(M + β Δt² S) U^{n+1} = M Ũ + β Δt² (F − Σ λ_c e_c)`, solved exactly by
//! [`ContactSolver2d`] (σ = β Δt², lower bounds 0). Crank–Nicolson is (β, γ) = (¼, ½). With
//! massless contact nodes their rows are the quasi-static Signorini rows
//! `(S U)_C = F_C − λ` at every time level.

use super::{PlateScheme, PlateSchemeError, PlateState, check_finite, contact_err, initial_acceleration};
use crate::plate::assembly::ContactSystem;
use crate::plate::contact::ContactSolver2d;
use crate::plate::sparse::{self, SpMat};
use crate::schemes::check_range;

#[derive(Debug)]
pub struct Newmark2d {
    beta: f64,
    gamma: f64,
    dt: f64,
    mass: SpMat,
    load: Vec<f64>,
    massless: Vec<bool>,
    contact: ContactSolver2d,
    lower: Vec<f64>,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: Vec<f64>,
    pred: Vec<f64>,
    rhs: Vec<f64>,
    pivots: usize,
}

impl Newmark2d {
    pub const NAME: &'static str = "newmark";

    /// Newmark(β, γ) with 0 < β ≤ 1 and 0 ≤ γ ≤ 1.
    pub fn new(
        system: &ContactSystem,
        beta: f64,
        gamma: f64,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, PlateSchemeError> {
        check_range(Self::NAME, "beta", beta, beta > 0.0 && beta <= 1.0, "(0, 1]")?;
        check_range(Self::NAME, "gamma", gamma, (0.0..=1.0).contains(&gamma), "[0, 1]")?;
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let k = sparse::combine(&system.mass, 1.0, &system.stiffness, beta * dt * dt, "M + β Δt² S")?;
        let contact = ContactSolver2d::new(&k, &system.contact, "M + β Δt² S")?;
        let a = initial_acceleration(system, &u0)?;
        let (n, nc) = (system.n(), system.contact.len());
        Ok(Self {
            beta,
            gamma,
            dt,
            mass: system.mass.clone(),
            load: system.load.clone(),
            massless: system.massless.clone(),
            contact,
            lower: vec![0.0; nc],
            n: 0,
            u: u0,
            v: v0,
            a,
            lambda: vec![0.0; nc],
            pred: vec![0.0; n],
            rhs: vec![0.0; n],
            pivots: 0,
        })
    }

    /// Crank–Nicolson, Newmark(¼, ½).
    pub fn crank_nicolson(
        system: &ContactSystem,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, PlateSchemeError> {
        Self::new(system, 0.25, 0.5, dt, u0, v0)
    }
}

impl PlateScheme for Newmark2d {
    fn state(&self) -> PlateState<'_> {
        PlateState { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: &self.lambda }
    }

    fn pivots(&self) -> usize {
        self.pivots
    }

    fn step(&mut self) -> Result<(), PlateSchemeError> {
        let (dt, beta, gamma) = (self.dt, self.beta, self.gamma);
        let sigma = beta * dt * dt;
        let c = (0.5 - beta) * dt * dt;
        for i in 0..self.u.len() {
            self.pred[i] = self.u[i] + dt * self.v[i] + c * self.a[i];
        }
        sparse::sym_mul_into(&self.mass, &self.pred, &mut self.rhs);
        for (r, f) in self.rhs.iter_mut().zip(&self.load) {
            *r += sigma * f;
        }
        let (step, time) = (self.n + 1, (self.n + 1) as f64 * dt);
        self.pivots =
            self.contact.solve(&mut self.rhs, &self.lower, sigma, &mut self.lambda).map_err(contact_err(step, time))?;
        for i in 0..self.u.len() {
            if self.massless[i] {
                // Quasi-static node: its a and v enter no equation (module docs of `schemes`).
                self.v[i] = (self.rhs[i] - self.u[i]) / dt;
                self.a[i] = 0.0;
            } else {
                let a_new = (self.rhs[i] - self.pred[i]) / sigma;
                self.v[i] += dt * ((1.0 - gamma) * self.a[i] + gamma * a_new);
                self.a[i] = a_new;
            }
            self.u[i] = self.rhs[i];
        }
        self.n = step;
        check_finite(&self.u, &self.lambda, step, time)
    }
}
