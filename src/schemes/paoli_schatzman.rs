//! The Paoli–Schatzman scheme with restitution coefficient e (paper eq. (4.6), "paoli_method1").
//!
//! ```text
//! M (U^{n+1} − 2Uⁿ + U^{n−1})/Δt² + S (β U^{n+1} + (1−2β) Uⁿ + β U^{n−1}) = F − λⁿ e_0,
//! 0 ≤ (u_0^{n+1} + e u_0^{n−1})/(1+e) ⊥ λⁿ ≤ 0.
//! ```
//!
//! `(M + β Δt² S) U^{n+1} = M (2Uⁿ − U^{n−1}) − Δt² P S((1−2β)Uⁿ + β U^{n−1}) + Δt² (F − λⁿ e_0)`,
//! where, as the paper prescribes for a massless contact node (w_0 = 0), P projects S Uⁿ and
//! S U^{n−1} on (ker M)^⊥ = {e_0}^⊥ (their contact components are dropped); P = I otherwise. The
//! contact condition is `u_0^{n+1} ≥ −e u_0^{n−1}`, solved exactly as in
//! `contact_multiplier` (schemes/mod.rs) (σ = Δt²).
//!
//! With the projection, the contact row reads `β (S U^{n+1})_0 = −λⁿ`: the multiplier is β times
//! the elastic force on the contact node, so the reported contact force is λⁿ/β in that case
//! (the same normalisation as the other schemes, `λ = −(S U)_0`); U does not depend on it.
//!
//! U¹ comes from one Crank–Nicolson step with contact. The velocity is the central difference
//! `Vⁿ = (U^{n+1} − U^{n−1})/(2Δt)`, so the scheme runs one step ahead of the state it reports.
//! With β = 1/4 and no contact it conserves `½ DᵀMD + ½ ΣᵀSΣ` with
//! `D = (U^{n+1} − Uⁿ)/Δt`, `Σ = (U^{n+1} + Uⁿ)/2` (the energy at half steps).

//!
//! A step is four passes: the combinations `2Uⁿ − U^{n−1}` and `(1−2β)Uⁿ + βU^{n−1}`, the
//! right-hand side, the two-sided solve ([`TwistedFactor`]), and one pass for the contact
//! correction and the velocity.

use super::{
    Beta, Newmark, Restitution, Scheme, SchemeError, SchemeSpec, StateView, check_finite, check_range, factor_err,
};
use crate::contact::contact_multiplier;
use crate::linalg::tridiag::{SymTridiag, TwistedFactor};

#[derive(Debug, Clone)]
pub struct PaoliSchatzman {
    beta: f64,
    restitution: f64,
    dt: f64,
    mass: SymTridiag,
    stiffness: SymTridiag,
    load: Vec<f64>,
    /// A time-dependent load: `load` is refreshed to F(t_{n+1}) (the central difference at
    /// t_{n+1} gives U^{n+2}).
    forcing: Option<crate::system::Forcing>,
    project: bool,
    factor: TwistedFactor,
    /// z = K⁻¹ e_0.
    response: Vec<f64>,
    n: usize,
    /// U^{n−1}, Uⁿ, U^{n+1}.
    prev: Vec<f64>,
    cur: Vec<f64>,
    next: Vec<f64>,
    /// Vⁿ (central) and the contact force at t_n.
    v: Vec<f64>,
    lambda: [f64; 1],
    /// The obstacle bound lb = −gap.
    obstacle: f64,
    /// `2U^{n+1} − Uⁿ` and `(1−2β)U^{n+1} + βUⁿ`.
    inertia: Vec<f64>,
    elastic: Vec<f64>,
}

impl PaoliSchatzman {
    pub const NAME: &'static str = SchemeSpec::PAOLI_SCHATZMAN.name();

    pub fn new(
        bar: super::OneNodeContact<'_>,
        beta: Beta,
        restitution: Restitution,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        let (beta, restitution) = (beta.get(), restitution.get());
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let system = bar.system;
        let k = system.mass.combine(1.0, &system.stiffness, beta * dt * dt);
        let factor = k.factor_twisted().map_err(factor_err("M + β Δt² S"))?;
        let response = factor.unit_response(0);
        let mut start = Newmark::crank_nicolson(system, dt, u0.clone(), v0.clone())?;
        start.step()?;
        let m = system.n();
        Ok(Self {
            beta,
            restitution,
            dt,
            mass: system.mass.clone(),
            stiffness: system.stiffness.clone(),
            load: system.load.clone(),
            forcing: system.forcing.clone(),
            project: system.massless_contact(),
            obstacle: system.lower[0],
            factor,
            response,
            n: 0,
            prev: vec![0.0; m],
            cur: u0,
            next: start.state().u.to_vec(),
            v: v0,
            lambda: [0.0],
            inertia: vec![0.0; m],
            elastic: vec![0.0; m],
        })
    }

    /// `Uⁿ⁺¹` (the scheme is one step ahead of the reported state).
    pub fn lookahead(&self) -> &[f64] {
        &self.next
    }
}

impl Scheme for PaoliSchatzman {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.cur, v: &self.v, lambda: &self.lambda }
    }

    /// Computes U^{n+2} from (U^{n+1}, Uⁿ), then reports t_{n+1}.
    fn step(&mut self) -> Result<(), SchemeError> {
        let (dt, beta, e) = (self.dt, self.beta, self.restitution);
        let dt2 = dt * dt;
        let m = self.cur.len();
        if let Some(f) = &self.forcing {
            (f.0)((self.n + 1) as f64 * dt, &mut self.load);
        }
        // Here "cur" = Uⁿ and "next" = U^{n+1}: the new iterate is U^{n+2} (written into prev).
        let (u_old, u_mid) = (&self.cur[..m], &self.next[..m]);
        let (inertia, elastic) = (&mut self.inertia[..m], &mut self.elastic[..m]);
        for i in 0..m {
            inertia[i] = 2.0 * u_mid[i] - u_old[i];
            elastic[i] = (1.0 - 2.0 * beta) * u_mid[i] + beta * u_old[i];
        }
        // r = M(2U^{n+1} − Uⁿ) − Δt² P S((1−2β)U^{n+1} + βUⁿ) + Δt² F; P drops row 0.
        let (inertia, elastic) = (&self.inertia, &self.elastic);
        self.mass.mul2_add_into(inertia, &self.stiffness, -dt2, elastic, dt2, &self.load, &mut self.prev);
        if self.project {
            self.prev[0] = self.mass.mul_row(inertia, 0) + dt2 * self.load[0];
        }
        self.factor.solve_in_place(&mut self.prev);
        // Impact law on the shifted u − lb: u_0^{n+2} − lb ≥ −e (u_0ⁿ − lb).
        let lower = self.obstacle - e * (u_old[0] - self.obstacle);
        let lambda = contact_multiplier(self.prev[0], lower, dt2, self.response[0]);
        let s = dt2 * lambda;
        // prev now holds U^{n+2} before the contact correction; V^{n+1} = (U^{n+2} − Uⁿ)/(2Δt).
        let (x, z, v) = (&mut self.prev[..m], &self.response[..m], &mut self.v[..m]);
        let inv_2dt = 1.0 / (2.0 * dt);
        for i in 0..m {
            let u_new = x[i] - s * z[i];
            x[i] = u_new;
            v[i] = (u_new - u_old[i]) * inv_2dt;
        }
        if lambda != 0.0 {
            x[0] = lower;
            v[0] = (lower - u_old[0]) * inv_2dt;
        }
        self.lambda[0] = if self.project { lambda / beta } else { lambda };
        // Rotate (U^{n}, U^{n+1}, U^{n+2}) -> (prev, cur, next).
        std::mem::swap(&mut self.prev, &mut self.cur); // cur = U^{n+2}, prev = Uⁿ
        std::mem::swap(&mut self.cur, &mut self.next); // cur = U^{n+1}, next = U^{n+2}
        self.n += 1;
        check_finite(&self.next, &self.lambda, true, self.n, self.n as f64 * dt)
    }
}
