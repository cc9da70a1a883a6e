//! Newmark(β, γ) (Crank–Nicolson at (¼, ½)) and backward Euler with the penalty contact law
//! (issue 20): the contact force is the spring `R_c = κ d_c⁻` at t_{n+1}, fully implicit.
//!
//! ```text
//! Newmark:  (M + βΔt² S) U^{n+1} = M Ũ + βΔt² (F^{n+1} − Σ_c λ_c e_c),   Ũ = Uⁿ + ΔtVⁿ + (½ − β)Δt²Aⁿ
//! BE:       (M + Δt² S) U^{n+1} = M (Uⁿ + ΔtVⁿ) + Δt² (F^{n+1} − Σ_c λ_c e_c),   V^{n+1} = (U^{n+1} − Uⁿ)/Δt
//! λ_c = κ min(0, u_c^{n+1} − lb_c)
//! ```
//!
//! (as [`super::Newmark`] and [`super::BackwardEuler`], with the exact Signorini solve replaced
//! by the penalty one). The step is piecewise linear in U^{n+1}; it is solved exactly by
//! [`crate::contact::penalty::PenaltySolver`] (an LCP on `Z + I/(σκ)`, Murty's finite
//! active-set pivoting). The scheme starts from the interpolated data, as Crank–Nicolson does;
//! A⁰ solves `M A⁰ = F − S U⁰ − Σ λ⁰_c e_c` with `λ⁰ = κ min(0, d⁰)` (0 unless the data
//! penetrate). The energy `½V·MV + ½U·SU − F·U + Σ ½κ (d_c⁻)²` is [`PenaltyImplicit::energy`].

use super::{SchemeError, StateView, check_finite, check_range, contact_err};
use crate::contact::Backend;
use crate::contact::law::ContactLaw;
use crate::contact::penalty::PenaltySolver;
use crate::system::ContactSystem;

/// Which implicit scheme.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Implicit {
    Newmark { beta: f64, gamma: f64 },
    BackwardEuler,
}

#[derive(Debug)]
pub struct PenaltyImplicit<A: Backend> {
    kind: Implicit,
    dt: f64,
    kappa: f64,
    mass: A,
    stiffness: A,
    load: Vec<f64>,
    forcing: Option<crate::system::Forcing>,
    contact: Vec<usize>,
    lower: Vec<f64>,
    massless: Vec<usize>,
    massless_old: Vec<f64>,
    solver: PenaltySolver<A::Solver>,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: Vec<f64>,
    /// Newmark's predictor Ũ, or BE's Uⁿ + ΔtVⁿ.
    pred: Vec<f64>,
    u_old: Vec<f64>,
    rhs: Vec<f64>,
    pivots: usize,
}

impl<A: Backend> PenaltyImplicit<A> {
    pub const NAME: &'static str = "penalty contact";

    pub fn new(
        system: &ContactSystem<A>,
        kind: Implicit,
        law: &ContactLaw,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        let kappa = law.penalty_stiffness().unwrap_or(f64::NAN);
        check_range(Self::NAME, ContactLaw::PENALTY_KEY, kappa, kappa > 0.0, ContactLaw::PENALTY_RANGE)?;
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let sigma = match kind {
            Implicit::Newmark { beta, .. } => beta * dt * dt,
            Implicit::BackwardEuler => dt * dt,
        };
        let name = "M + σ S";
        let k = system.mass.combine(1.0, &system.stiffness, sigma, name)?;
        let plain = k.contact_solver(&system.contact, name)?;
        let solver =
            PenaltySolver::new(plain, system.n(), &system.contact, sigma, kappa).map_err(contact_err(0, 0.0))?;
        // A⁰ with the spring force of the data (0 unless they penetrate).
        let mut with_force = system.clone();
        for (&c, lb) in system.contact.iter().zip(&system.lower) {
            with_force.load[c] -= kappa * (u0[c] - lb).min(0.0);
        }
        let a = with_force.initial_acceleration(&u0)?;
        let n = system.n();
        let massless: Vec<usize> = (0..n).filter(|&i| system.massless[i]).collect();
        let mut s = Self {
            kind,
            dt,
            kappa,
            mass: system.mass.clone(),
            stiffness: system.stiffness.clone(),
            load: system.load.clone(),
            forcing: system.forcing.clone(),
            contact: system.contact.clone(),
            lower: system.lower.clone(),
            massless_old: vec![0.0; massless.len()],
            massless,
            solver,
            n: 0,
            lambda: system.contact.iter().zip(&system.lower).map(|(&c, lb)| kappa * (u0[c] - lb).min(0.0)).collect(),
            pred: vec![0.0; n],
            u_old: vec![0.0; n],
            rhs: vec![0.0; n],
            u: u0,
            v: v0,
            a,
            pivots: 0,
        };
        s.predict();
        Ok(s)
    }

    fn predict(&mut self) {
        let dt = self.dt;
        let c = match self.kind {
            Implicit::Newmark { beta, .. } => (0.5 - beta) * dt * dt,
            Implicit::BackwardEuler => 0.0,
        };
        for i in 0..self.u.len() {
            self.pred[i] = self.u[i] + dt * self.v[i] + c * self.a[i];
        }
    }

    /// `½V·MV + ½U·SU − F·U + Σ ½κ (d_c⁻)²` of the current state (F of the last step's time).
    pub fn energy(&self) -> f64 {
        let work: f64 = self.u.iter().zip(&self.load).map(|(u, f)| u * f).sum();
        let spring =
            ContactLaw::Penalty { penalty: self.kappa }.energy(self.contact.iter().map(|&c| self.u[c]), &self.lower);
        0.5 * self.mass.quad_form(&self.v) + 0.5 * self.stiffness.quad_form(&self.u) - work + spring
    }
}

impl<A: Backend> super::Scheme for PenaltyImplicit<A> {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: &self.lambda }
    }

    fn pivots(&self) -> usize {
        self.pivots
    }

    fn energy(&self) -> Option<f64> {
        Some(Self::energy(self))
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let dt = self.dt;
        let (step, time) = (self.n + 1, (self.n + 1) as f64 * dt);
        let sigma = match self.kind {
            Implicit::Newmark { beta, .. } => beta * dt * dt,
            Implicit::BackwardEuler => dt * dt,
        };
        if let Some(f) = &self.forcing {
            (f.0)(time, &mut self.load);
        }
        self.mass.mul_add_into(&self.pred, sigma, &self.load, &mut self.rhs);
        self.u_old.copy_from_slice(&self.u);
        for (old, &i) in self.massless_old.iter_mut().zip(&self.massless) {
            *old = self.u[i];
        }
        self.pivots =
            self.solver.solve(&mut self.rhs, &self.lower, &mut self.lambda).map_err(contact_err(step, time))?;
        for i in 0..self.u.len() {
            let u_new = self.rhs[i];
            match self.kind {
                Implicit::Newmark { gamma, .. } => {
                    let a_new = (u_new - self.pred[i]) / sigma;
                    self.v[i] += dt * ((1.0 - gamma) * self.a[i] + gamma * a_new);
                    self.a[i] = a_new;
                }
                Implicit::BackwardEuler => self.v[i] = (u_new - self.u_old[i]) / dt,
            }
            self.u[i] = u_new;
        }
        for (&old, &i) in self.massless_old.iter().zip(&self.massless) {
            self.a[i] = 0.0;
            self.v[i] = (self.u[i] - old) / dt;
        }
        self.predict();
        self.n = step;
        check_finite(&self.u, &self.lambda, A::SOLVE_SPREADS_NAN, step, time)
    }
}
