//! Backward Euler with exact many-node contact (paper eq. (4.5)).
//!
//! ```text
//! U^{n+1} = Uⁿ + Δt V^{n+1},   V^{n+1} = Vⁿ + Δt A^{n+1},
//! M A^{n+1} + S U^{n+1} = F − Σ_c λ_c^{n+1} e_c,   0 ≤ u_c^{n+1} ⊥ λ_c^{n+1} ≤ 0,
//! ```
//!
//! i.e. `(M + Δt² S) U^{n+1} = M (Uⁿ + Δt Vⁿ) + Δt² (F − Σ λ_c e_c)` (σ = Δt²). The 1D energy
//! argument ([`crate::schemes::BackwardEuler`]) holds node by node:
//! `ΔE = −½ δᵀMδ − ½ ΔUᵀSΔU + Σ_c λ_c^{n+1} u_cⁿ ≤ 0`, since `λ_c^{n+1} u_c^{n+1} = 0`,
//! `λ_c ≤ 0` and `u_cⁿ ≥ 0` for every contact node.

use super::{PlateScheme, PlateSchemeError, PlateState, check_finite, contact_err};
use crate::plate::assembly::ContactSystem;
use crate::plate::contact::ContactSolver2d;
use crate::plate::sparse::{self, SpMat};
use crate::schemes::check_range;

#[derive(Debug)]
pub struct BackwardEuler2d {
    dt: f64,
    mass: SpMat,
    load: Vec<f64>,
    contact: ContactSolver2d,
    lower: Vec<f64>,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    lambda: Vec<f64>,
    pred: Vec<f64>,
    rhs: Vec<f64>,
    pivots: usize,
}

impl BackwardEuler2d {
    pub const NAME: &'static str = "backward-euler";

    pub fn new(system: &ContactSystem, dt: f64, u0: Vec<f64>, v0: Vec<f64>) -> Result<Self, PlateSchemeError> {
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let k = sparse::combine(&system.mass, 1.0, &system.stiffness, dt * dt, "M + Δt² S")?;
        let contact = ContactSolver2d::new(&k, &system.contact, "M + Δt² S")?;
        let (n, nc) = (system.n(), system.contact.len());
        Ok(Self {
            dt,
            mass: system.mass.clone(),
            load: system.load.clone(),
            contact,
            lower: vec![0.0; nc],
            n: 0,
            u: u0,
            v: v0,
            lambda: vec![0.0; nc],
            pred: vec![0.0; n],
            rhs: vec![0.0; n],
            pivots: 0,
        })
    }
}

impl PlateScheme for BackwardEuler2d {
    fn state(&self) -> PlateState<'_> {
        PlateState { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: &self.lambda }
    }

    fn pivots(&self) -> usize {
        self.pivots
    }

    fn step(&mut self) -> Result<(), PlateSchemeError> {
        let dt = self.dt;
        let sigma = dt * dt;
        for i in 0..self.u.len() {
            self.pred[i] = self.u[i] + dt * self.v[i];
        }
        sparse::sym_mul_into(&self.mass, &self.pred, &mut self.rhs);
        for (r, f) in self.rhs.iter_mut().zip(&self.load) {
            *r += sigma * f;
        }
        let (step, time) = (self.n + 1, (self.n + 1) as f64 * dt);
        self.pivots =
            self.contact.solve(&mut self.rhs, &self.lower, sigma, &mut self.lambda).map_err(contact_err(step, time))?;
        for i in 0..self.u.len() {
            self.v[i] = (self.rhs[i] - self.u[i]) / dt;
            self.u[i] = self.rhs[i];
        }
        self.n = step;
        check_finite(&self.u, &self.lambda, step, time)
    }
}
