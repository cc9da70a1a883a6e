//! Newmark(β, γ) on the reduced formulation (P^mod_U) of a massless contact node (paper §3).
//!
//! With w_0 = 0 the contact node is eliminated by `u_0 = u_1⁺` (eq. (3.2)), leaving on nodes
//! 1..m−1 the Lipschitz system
//!
//! ```text
//! h M* Ü + (1/h) S* U = F + (1/h) u_1⁺ e_1,     h M* = M[1.., 1..],  S*/h = S[1.., 1..].
//! ```
//!
//! Newmark gives `K U^{n+1} = M_red Ũ + β Δt² F + (β Δt²/h) (u_1^{n+1})⁺ e_1` with
//! `K = M_red + β Δt² S_red`. With `W = K⁻¹(M_red Ũ + β Δt² F)` and `z = K⁻¹ e_1`,
//! `u_1 = W_1 + c u_1⁺`, `c = β Δt² z_1 / h`, whose unique solution is `u_1 = W_1` if `W_1 ≤ 0`,
//! else `u_1 = W_1/(1 − c)`. Uniqueness: `z_1 ≤ (β Δt² S_red)⁻¹_11 = h(m−1)/(m β Δt²)`, so
//! `c ≤ (m−1)/m < 1`. The result equals the full formulation ([`super::Newmark`]) step by step.

//!
//! A step is three passes over the nodes, as in [`super::Newmark`]: right-hand side, two-sided
//! solve ([`TwistedFactor`]), then one update pass.

use super::{Beta, Gamma, SchemeError, StateView, check_finite, check_range, factor_err};
use crate::linalg::tridiag::{SymTridiag, TwistedFactor};

#[derive(Debug, Clone)]
pub struct NewmarkReduced {
    beta: f64,
    gamma: f64,
    dt: f64,
    h: f64,
    mass: SymTridiag,
    load: Vec<f64>,
    /// A time-dependent load and its full vector (row 0 dropped into `load` at each step, at
    /// t_{n+1}).
    forcing: Option<(crate::system::Forcing, Vec<f64>)>,
    factor: TwistedFactor,
    response: Vec<f64>,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: [f64; 1],
    /// The predictor Ũ of the next step on nodes 1..m−1.
    pred: Vec<f64>,
    rhs: Vec<f64>,
}

impl NewmarkReduced {
    pub const NAME: &'static str = "newmark (reduced formulation)";

    pub fn new(
        bar: super::OneNodeContact<'_>,
        beta: Beta,
        gamma: Gamma,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        let system = bar.system;
        if !system.massless_contact() {
            return Err(SchemeError::NeedsMasslessContact { scheme: Self::NAME, w0: bar.w0 });
        }
        if bar.gap() != 0.0 {
            // Its closed form u_0 = u_1⁺ is written for the obstacle at 0 (a bar's one-node system).
            return Err(SchemeError::Parameter { scheme: Self::NAME, key: "gap", value: bar.gap(), range: "0" });
        }
        let (beta, gamma) = (beta.get(), gamma.get());
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let mass = system.mass.trailing(1);
        let k = mass.combine(1.0, &system.stiffness.trailing(1), beta * dt * dt);
        let factor = k.factor_twisted().map_err(factor_err("M* + β Δt² S*"))?;
        let response = factor.unit_response(0);
        // Same A⁰ as the full formulation (it uses the given U⁰_0), so both agree step by step.
        let a = system.initial_acceleration(&u0)?;
        let c = (0.5 - beta) * dt * dt;
        let pred = (1..u0.len()).map(|i| u0[i] + dt * v0[i] + c * a[i]).collect();
        let m = system.n();
        Ok(Self {
            beta,
            gamma,
            dt,
            h: bar.h,
            mass,
            load: system.load[1..].to_vec(),
            forcing: system.forcing.clone().map(|f| (f, system.load.clone())),
            factor,
            response,
            n: 0,
            u: u0,
            v: v0,
            a,
            lambda: [0.0],
            pred,
            rhs: vec![0.0; m - 1],
        })
    }
}

impl super::Scheme for NewmarkReduced {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: &self.lambda }
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let (dt, beta, gamma, h) = (self.dt, self.beta, self.gamma, self.h);
        let sigma = beta * dt * dt;
        let c2 = (0.5 - beta) * dt * dt;
        if let Some((f, full)) = &mut self.forcing {
            (f.0)((self.n + 1) as f64 * dt, full);
            self.load.copy_from_slice(&full[1..]);
        }
        self.mass.mul_add_into(&self.pred, sigma, Some(&self.load), &mut self.rhs);
        self.factor.solve_in_place(&mut self.rhs);
        let c = sigma * self.response[0] / h;
        let w1 = self.rhs[0];
        let u1 = if w1 <= 0.0 { w1 } else { w1 / (1.0 - c) };
        let s = sigma / h * u1.max(0.0);
        let u0_old = self.u[0];
        let inv_sigma = 1.0 / sigma;
        let r = self.pred.len();
        let (u, v, a) = (&mut self.u[1..=r], &mut self.v[1..=r], &mut self.a[1..=r]);
        let (x, z, pred) = (&self.rhs[..r], &self.response[..r], &mut self.pred[..r]);
        for i in 0..r {
            let u_new = x[i] + s * z[i];
            let a_new = (u_new - pred[i]) * inv_sigma;
            let v_new = v[i] + dt * ((1.0 - gamma) * a[i] + gamma * a_new);
            u[i] = u_new;
            v[i] = v_new;
            a[i] = a_new;
            pred[i] = u_new + dt * v_new + c2 * a_new;
        }
        self.u[0] = self.u[1].max(0.0);
        self.v[0] = (self.u[0] - u0_old) / dt;
        // Contact row (u_0 − u_1)/h = −λ with u_0 = u_1⁺.
        self.lambda[0] = self.u[1].min(0.0) / h;
        self.n += 1;
        check_finite(&self.u, &self.lambda, true, self.n, self.n as f64 * dt)
    }
}
