//! Exact solution of the one-node Signorini condition inside an implicit step.
//!
//! Every full-system scheme of the paper solves, at each step, `K U = r − σ λ e_0` together with
//! `lb ≤ u_0 ⊥ λ ≤ 0` (lb = 0 for Newmark and backward Euler, lb = −e u_0^{n−1} for
//! Paoli–Schatzman), K symmetric positive definite and σ > 0 the scheme's force scale. With
//! `z = K⁻¹ e_0` (z_0 > 0 since K is SPD) the solution is explicit: solve `K U* = r`; if
//! `u*_0 ≥ lb` then λ = 0, otherwise `λ = (u*_0 − lb)/(σ z_0) < 0` and `U = U* − σ λ z`.

use crate::tridiag::{FactorError, LdlT, SymTridiag};

/// A factored iteration matrix with its precomputed response to a unit load on the contact node.
#[derive(Debug, Clone)]
pub struct ContactSolver {
    factor: LdlT,
    response: Vec<f64>,
}

impl ContactSolver {
    pub fn new(k: &SymTridiag) -> Result<Self, FactorError> {
        let factor = k.factor()?;
        let response = factor.unit_response(0);
        Ok(Self { factor, response })
    }

    /// Solves `K U = r − σ λ e_0`, `lb ≤ u_0 ⊥ λ ≤ 0` in place (`rhs` = r on entry, U on exit)
    /// and returns λ. On contact `u_0 = lb` is set exactly, so complementarity holds bit for bit.
    pub fn solve(&self, rhs: &mut [f64], lower: f64, sigma: f64) -> f64 {
        self.factor.solve_in_place(rhs);
        if rhs[0] >= lower {
            return 0.0;
        }
        let lambda = (rhs[0] - lower) / (sigma * self.response[0]);
        let s = sigma * lambda;
        for (u, z) in rhs.iter_mut().zip(&self.response) {
            *u -= s * z;
        }
        rhs[0] = lower;
        lambda
    }
}
