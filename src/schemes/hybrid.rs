//! The paper's hybrid scheme (P^hyb) (§5) on the reduced system of a massless contact node.
//!
//! Unknowns are nodes 1..m−1 with `u_0 = u_1⁺`. With `M_red = M[1..,1..] = h M*` and
//! `S_red = S[1..,1..] = S*/h` (the paper's (P^hyb) writes M*, S*; the scaling of (P^mod_U)
//! requires h M* and S*/h, as its energy (3.4) and the 1/(2h) factors of the contact term show):
//!
//! ```text
//! U^{n+1} = Uⁿ + Δt/2 (V^{n+1} + Vⁿ),   V^{n+1} = Vⁿ + Δt/2 (A^{n+1} + Aⁿ),
//! M_red A^{n+½} + S_red U^{n+½} = F + g e_1,
//! g = H(−u_1ⁿ)/(2h) (u_1ⁿ + u_1^{n+1})⁺ + H(u_1ⁿ)/(2h) ((u_1ⁿ)⁺ + (u_1^{n+1})⁺),
//! ```
//!
//! H(0) = ½. Since `A^{n+½} = (V^{n+1} − Vⁿ)/Δt` and `V^{n+1} = 2(U^{n+1} − Uⁿ)/Δt − Vⁿ`, A never
//! appears. In the midpoint `Ū = (U^{n+1} + Uⁿ)/2` (so `U^{n+1} = 2Ū − Uⁿ`,
//! `V^{n+1} = 4(Ū − Uⁿ)/Δt − Vⁿ`) the step is, multiplying the equation by Δt²/4,
//! `K Ū = M_red (Uⁿ + Δt/2 Vⁿ) + Δt²/4 (F + g e_1)` with `K = M_red + Δt²/4 S_red`: one matrix–vector
//! product per step. With `W̄` the solution for g = 0 and `z = K⁻¹ e_1`, the new u_1 = x = 2ū_1 − u_1ⁿ
//! solves `φ(x) = x − c g(x) = W_1`, `W_1 = 2W̄_1 − u_1ⁿ`, `c = Δt² z_1/2`. g is piecewise linear in x with kinks at
//! x = −u_1ⁿ and x = 0 and slopes in [0, 1/h], and `c/h ≤ (m−1)/m < 1`, so φ is strictly
//! increasing and piecewise linear: we locate the piece from φ at the kinks and solve it exactly.
//!
//! Lemma 5.1: the energy `ℰ = ½VᵀM_redV + ½UᵀS_redU − (u_1⁺)²/(2h) − UᵀF` never increases; it
//! equals the full-system energy with `u_0 = u_1⁺`.
//!
//! A step is three passes: the right-hand side `M_red Ũ + Δt²/4 F` (Ũ = Uⁿ + Δt/2 Vⁿ, kept from
//! the previous update), the two-sided solve for W̄ ([`TwistedFactor`]), then one update pass
//! `Ū = W̄ + Δt²/4 g z`, U^{n+1}, V^{n+1} and the next Ũ.

use super::{SchemeError, StateView, check_finite, check_range, factor_err};
use crate::assembly::System;
use crate::tridiag::{SymTridiag, TwistedFactor};

#[derive(Debug, Clone)]
pub struct Hybrid {
    dt: f64,
    h: f64,
    mass: SymTridiag,
    load: Vec<f64>,
    factor: TwistedFactor,
    response: Vec<f64>,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    lambda: f64,
    /// Ũ = Uⁿ + Δt Vⁿ on nodes 1..m−1 for the next step.
    pred: Vec<f64>,
    rhs: Vec<f64>,
}

/// H(s) of the paper: 1 for s > 0, ½ for s = 0, 0 for s < 0.
fn heaviside(s: f64) -> f64 {
    if s > 0.0 {
        1.0
    } else if s == 0.0 {
        0.5
    } else {
        0.0
    }
}

/// The contact term g(x) of (P^hyb) for u_1ⁿ = p, and its slope on the piece containing x.
fn contact_term(p: f64, x: f64, h: f64) -> (f64, f64) {
    let (a, b) = (heaviside(-p) / (2.0 * h), heaviside(p) / (2.0 * h));
    let g = a * (p + x).max(0.0) + b * (p.max(0.0) + x.max(0.0));
    let slope = a * f64::from(u8::from(p + x > 0.0)) + b * f64::from(u8::from(x > 0.0));
    (g, slope)
}

/// Exact root of `x − c g(x) = w` (φ strictly increasing, piecewise linear, kinks at −p and 0).
pub(crate) fn solve_contact_step(p: f64, w: f64, c: f64, h: f64) -> f64 {
    let (k0, k1) = if -p < 0.0 { (-p, 0.0) } else { (0.0, -p) };
    let phi = |x: f64| x - c * contact_term(p, x, h).0;
    // A reference point strictly inside the piece that contains the root.
    let x_ref = if w <= phi(k0) {
        k0 - 1.0
    } else if w <= phi(k1) {
        0.5 * (k0 + k1)
    } else {
        k1 + 1.0
    };
    let (g_ref, slope) = contact_term(p, x_ref, h);
    // On the piece g(x) = g_ref + slope (x − x_ref): x − c(g_ref + slope(x − x_ref)) = w.
    (w + c * (g_ref - slope * x_ref)) / (1.0 - c * slope)
}

impl Hybrid {
    pub const NAME: &'static str = "hybrid";

    pub fn new(system: &System, dt: f64, u0: Vec<f64>, v0: Vec<f64>) -> Result<Self, SchemeError> {
        if !system.massless_contact() {
            return Err(SchemeError::NeedsMasslessContact { scheme: Self::NAME, w0: system.weights[0] });
        }
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let mass = system.mass.trailing(1);
        let stiffness = system.stiffness.trailing(1);
        let k = mass.combine(1.0, &stiffness, dt * dt / 4.0);
        let factor = k.factor_twisted().map_err(factor_err("M_red + Δt²/4 S_red"))?;
        let response = factor.unit_response(0);
        let pred = (1..u0.len()).map(|i| u0[i] + 0.5 * dt * v0[i]).collect();
        let m = system.m();
        Ok(Self {
            dt,
            h: system.h(),
            mass,
            load: system.load[1..].to_vec(),
            factor,
            response,
            n: 0,
            u: u0,
            v: v0,
            lambda: 0.0,
            pred,
            rhs: vec![0.0; m - 1],
        })
    }
}

impl super::Scheme for Hybrid {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: self.lambda }
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let (dt, h) = (self.dt, self.h);
        let r = self.pred.len();
        let (quarter, half) = (dt * dt / 4.0, dt * dt / 2.0);
        self.mass.mul_add_into(&self.pred, quarter, Some(&self.load), &mut self.rhs);
        self.factor.solve_in_place(&mut self.rhs);
        let p = self.u[1];
        let c = half * self.response[0];
        let x = solve_contact_step(p, 2.0 * self.rhs[0] - p, c, h);
        let g = contact_term(p, x, h).0;
        let s = quarter * g;
        let u0_old = self.u[0];
        let (four_over_dt, half_dt) = (4.0 / dt, 0.5 * dt);
        let (u, v) = (&mut self.u[1..=r], &mut self.v[1..=r]);
        let (w, z, pred) = (&self.rhs[..r], &self.response[..r], &mut self.pred[..r]);
        for i in 0..r {
            let mid = w[i] + s * z[i];
            let u_new = 2.0 * mid - u[i];
            let v_new = (mid - u[i]) * four_over_dt - v[i];
            u[i] = u_new;
            v[i] = v_new;
            pred[i] = u_new + half_dt * v_new;
        }
        self.u[0] = self.u[1].max(0.0);
        self.v[0] = (self.u[0] - u0_old) / dt;
        self.lambda = self.u[1].min(0.0) / h;
        self.n += 1;
        check_finite(&self.u, self.lambda, self.n, self.n as f64 * dt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contact_step_root_satisfies_its_equation() {
        let h = 0.1;
        for &p in &[-0.3, -1e-3, 0.0, 1e-3, 0.2] {
            for &w in &[-0.5, -0.01, 0.0, 0.01, 0.4] {
                for &c in &[0.0, 0.01, 0.05, 0.099] {
                    let x = solve_contact_step(p, w, c, h);
                    let residual = x - c * contact_term(p, x, h).0 - w;
                    // x and g are O(1); a few ulps of each term.
                    assert!(residual.abs() <= 16.0 * f64::EPSILON, "p={p} w={w} c={c}: {residual}");
                }
            }
        }
    }
}
