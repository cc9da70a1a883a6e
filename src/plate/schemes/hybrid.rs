//! The paper's hybrid scheme (P^hyb) (§5) generalised to many quasi-static contact nodes.
//!
//! **The 1D scheme as a contact problem.** Keep the massless contact node 0 as an unknown with
//! its quasi-static row `S_00 u_0 + S_01 u_1 = −λ` (so `u_0 = u_1⁺`). The contact term of
//! (P^hyb) is `g e_1 = −S_10 ū_0` with
//! `ū_0 = H(−u_1ⁿ) (Ū_1)⁺ + H(u_1ⁿ) ((u_1ⁿ)⁺ + (u_1^{n+1})⁺)/2`, `Ū = (Uⁿ + U^{n+1})/2`. For each
//! sign of u_1ⁿ this ū_0 is the solution of the one-node problem
//!
//! ```text
//! S_00 ū_0 + S_01 Ū_1 = −λ̄,     0 ≤ 2 ū_0 − u_0ⁿ ⊥ λ̄ ≤ 0,     u_0ⁿ = (u_1ⁿ)⁺:
//! ```
//!
//! - u_1ⁿ ≤ 0: u_0ⁿ = 0, the bound is ū_0 ≥ 0 and ū_0 = (Ū_1)⁺ (the midpoint rule);
//! - u_1ⁿ > 0: ū_0 = max(Ū_1, u_1ⁿ/2) = (u_1ⁿ + (u_1^{n+1})⁺)/2 (the trapezoidal rule);
//!
//! (at u_1ⁿ = 0 both rules agree, so H(0) = ½ changes nothing). The contact node's state after
//! the step is again quasi-static, `u_0^{n+1} = (u_1^{n+1})⁺` (not `2ū_0 − u_0ⁿ`).
//!
//! **2D.** The same equations with vectors: for the interior unknowns I and contact unknowns C
//! (all massless),
//!
//! ```text
//! M_II (V^{n+1} − Vⁿ)/Δt + S_II Ū + S_IC ū = F_I,      U^{n+1} = Uⁿ + Δt (Vⁿ + V^{n+1})/2,
//! S_CI Ū + S_CC ū = F_C − λ̄,                           0 ≤ 2ū − u_Cⁿ ⊥ λ̄ ≤ 0 node-wise,
//! u_C^{n+1} = Φ(U^{n+1}):  S_CC u + S_CI U = F_C − λ,  0 ≤ u ⊥ λ ≤ 0   (quasi-static contact).
//! ```
//!
//! A node in contact at t_n (u_cⁿ = 0) gets the midpoint condition, a free one the trapezoidal
//! condition on its end value, as in 1D; in 2D S_CC couples the nodes, so the two rules are mixed
//! inside one problem. Multiplying by Δt²/4 with `X̄ = (ū, Ū)`:
//! `(M + Δt²/4 S) X̄ = M (Xⁿ + Δt/2 Vⁿ) + Δt²/4 (F − Σ λ̄_c e_c)` — the Crank–Nicolson matrix and
//! [`ContactSolver2d`] with σ = Δt²/4 and lower bounds `u_Cⁿ/2` — then `U^{n+1} = 2Ū − Uⁿ`,
//! `V^{n+1} = 2(U^{n+1} − Uⁿ)/Δt − Vⁿ`, and Φ is one more LCP with the SPD matrix S_CC.
//! With one contact node this is the 1D [`crate::schemes::Hybrid`] step for step.
//!
//! **Energy: Lemma 5.1 carries over.** Let `E = ½VᵀMV + ½XᵀSX − XᵀF` with `X = (u_C, U)`,
//! and let both ends of a step be quasi-static (`u_C = Φ(U)`; true for every step n ≥ 1, and
//! for the first step the reported E⁰ uses the interpolated u_C⁰, whose energy is ≥ that of
//! Φ(U⁰) because Φ minimises the potential over u_C ≥ 0). Write `A = S_CC`, `ũ = 2ū − u_Cⁿ`
//! (≥ 0, ⊥ λ̄). Testing the interior rows with `U^{n+1} − Uⁿ` and using the contact rows at
//! t_n, t_{n+1} and at the midpoint, `A(û − ū) = λ̄ − λ̂` (hats: averages of n and n+1), gives
//! `ΔE = −(λ^{n+1} − λⁿ)ᵀ(û − ū) − (u_C^{n+1} − u_Cⁿ)ᵀλ̄`; with `û − ū = (u_C^{n+1} − ũ)/2` and
//! the three complementarity relations this is
//!
//! ```text
//! ΔE = (λ^{n+1})ᵀ ũ + (u_Cⁿ)ᵀ λ̄ − ½ (u_C^{n+1} − ũ)ᵀ A (u_C^{n+1} − ũ)  ≤ 0,
//! ```
//!
//! each term ≤ 0 (λ ≤ 0 ≤ ũ, u_Cⁿ ≥ 0 ≥ λ̄, A SPD), for any mesh and any contact states along
//! Γ_C: no sign condition on S_CC's off-diagonal entries is used. In 1D (A = 1/h) this is the
//! five cases of Lemma 5.1 at once. [`Hybrid2d::energy_terms`] returns the three terms of the
//! last step (tests/plate.rs checks that they add up to the measured ΔE).

use super::{PlateScheme, PlateSchemeError, PlateState, check_finite, contact_err};
use crate::plate::assembly::ContactSystem;
use crate::plate::contact::ContactSolver2d;
use crate::plate::lcp::Lcp;
use crate::plate::sparse::{self, SpMat};
use crate::schemes::{SchemeError, check_range};

/// The quasi-static contact map Φ: for interior values U, the contact values u ≥ 0 and
/// multipliers λ ≤ 0 with `S_CC u + S_CI U − F_C = −λ`, `u ⊥ λ`.
#[derive(Debug, Clone)]
pub struct QuasiStatic {
    contact: Vec<usize>,
    /// `(c, j, S_{contact[c], j})` for j not a contact unknown.
    coupling: Vec<(usize, usize, f64)>,
    load: Vec<f64>,
    lcp: Lcp,
    q: Vec<f64>,
}

impl QuasiStatic {
    pub fn new(system: &ContactSystem) -> Self {
        let nc = system.contact.len();
        let mut slot = vec![usize::MAX; system.n()];
        for (c, &i) in system.contact.iter().enumerate() {
            slot[i] = c;
        }
        let mut d = vec![0.0; nc * nc];
        let mut coupling = Vec::new();
        for (i, j, s) in sparse::triplets(&system.stiffness) {
            if slot[i] == usize::MAX {
                continue;
            }
            if slot[j] == usize::MAX {
                coupling.push((slot[i], j, s));
            } else {
                d[slot[i] * nc + slot[j]] += s;
            }
        }
        let load = system.contact.iter().map(|&i| system.load[i]).collect();
        Self { contact: system.contact.clone(), coupling, load, lcp: Lcp::new(d, nc), q: vec![0.0; nc] }
    }

    /// Overwrites the contact entries of `u` with Φ(U_I) and writes λ; returns the pivots.
    pub fn apply(&mut self, u: &mut [f64], lambda: &mut [f64]) -> Result<usize, crate::plate::lcp::LcpError> {
        for (q, f) in self.q.iter_mut().zip(&self.load) {
            *q = -f;
        }
        for &(c, j, s) in &self.coupling {
            self.q[c] += s * u[j];
        }
        let (x, w) = self.lcp.solve(&self.q)?;
        for (c, &i) in self.contact.iter().enumerate() {
            u[i] = x[c];
            lambda[c] = -w[c];
        }
        Ok(self.lcp.pivots())
    }
}

#[derive(Debug)]
pub struct Hybrid2d {
    dt: f64,
    mass: SpMat,
    load: Vec<f64>,
    is_contact: Vec<bool>,
    contact_idx: Vec<usize>,
    solver: ContactSolver2d,
    quasi_static: QuasiStatic,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    /// Reported λⁿ (0 at n = 0, as in 1D).
    lambda: Vec<f64>,
    /// Quasi-static (u_Cⁿ, λⁿ), and u_C of the previous step (bounds and energy terms).
    uc: Vec<f64>,
    lam: Vec<f64>,
    uc_prev: Vec<f64>,
    /// Mid-step ū and λ̄ of the last step.
    u_bar: Vec<f64>,
    lam_bar: Vec<f64>,
    lower: Vec<f64>,
    pred: Vec<f64>,
    rhs: Vec<f64>,
    scratch: Vec<f64>,
    pivots: usize,
}

impl Hybrid2d {
    pub const NAME: &'static str = "hybrid";

    /// Needs every contact unknown massless (quasi-static contact rows).
    pub fn new(system: &ContactSystem, dt: f64, u0: Vec<f64>, v0: Vec<f64>) -> Result<Self, PlateSchemeError> {
        if !system.massless_contact() {
            return Err(SchemeError::NeedsMasslessContact { scheme: Self::NAME, w0: system.contact_mass() }.into());
        }
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let k = sparse::combine(&system.mass, 1.0, &system.stiffness, dt * dt / 4.0, "M + Δt²/4 S")?;
        let solver = ContactSolver2d::new(&k, &system.contact, "M + Δt²/4 S")?;
        let mut quasi_static = QuasiStatic::new(system);
        let (n, nc) = (system.n(), system.contact.len());
        let mut is_contact = vec![false; n];
        for &c in &system.contact {
            is_contact[c] = true;
        }
        // The bounds of the first step use the quasi-static contact state of U⁰ (in 1D the
        // scheme reads (u_1⁰)⁺, not the interpolated u_0⁰).
        let mut x = u0.clone();
        let mut lam = vec![0.0; nc];
        quasi_static.apply(&mut x, &mut lam).map_err(contact_err(0, 0.0))?;
        let uc: Vec<f64> = system.contact.iter().map(|&i| x[i]).collect();
        Ok(Self {
            dt,
            mass: system.mass.clone(),
            load: system.load.clone(),
            is_contact,
            contact_idx: system.contact.clone(),
            solver,
            quasi_static,
            n: 0,
            u: u0,
            v: v0,
            lambda: vec![0.0; nc],
            uc_prev: uc.clone(),
            uc,
            lam,
            u_bar: vec![0.0; nc],
            lam_bar: vec![0.0; nc],
            lower: vec![0.0; nc],
            pred: vec![0.0; n],
            rhs: vec![0.0; n],
            scratch: vec![0.0; nc],
            pivots: 0,
        })
    }

    /// The three terms `[(λ^{n+1})ᵀũ, (u_Cⁿ)ᵀλ̄, −½‖u_C^{n+1} − ũ‖²_{S_CC}]` of the last step's
    /// energy change, `ũ = 2ū − u_Cⁿ` (module docs): each ≤ 0, and their sum is ΔE when both
    /// ends of the step are quasi-static (every step but the first).
    pub fn energy_terms(&self) -> [f64; 3] {
        let nc = self.uc.len();
        let tilde = |c: usize| 2.0 * self.u_bar[c] - self.uc_prev[c];
        let t1: f64 = (0..nc).map(|c| self.lam[c] * tilde(c)).sum();
        let t2: f64 = (0..nc).map(|c| self.uc_prev[c] * self.lam_bar[c]).sum();
        let mut t3 = 0.0;
        for a in 0..nc {
            for b in 0..nc {
                t3 += (self.uc[a] - tilde(a)) * self.quasi_static.lcp.d(a, b) * (self.uc[b] - tilde(b));
            }
        }
        [t1, t2, -0.5 * t3]
    }

    /// The mid-step multipliers λ̄ of the last step.
    pub fn mid_step_lambda(&self) -> &[f64] {
        &self.lam_bar
    }
}

impl PlateScheme for Hybrid2d {
    fn state(&self) -> PlateState<'_> {
        PlateState { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: &self.lambda }
    }

    fn pivots(&self) -> usize {
        self.pivots
    }

    fn step(&mut self) -> Result<(), PlateSchemeError> {
        let dt = self.dt;
        let sigma = dt * dt / 4.0;
        for i in 0..self.u.len() {
            self.pred[i] = self.u[i] + 0.5 * dt * self.v[i];
        }
        sparse::sym_mul_into(&self.mass, &self.pred, &mut self.rhs);
        for (r, f) in self.rhs.iter_mut().zip(&self.load) {
            *r += sigma * f;
        }
        for (l, u) in self.lower.iter_mut().zip(&self.uc) {
            *l = 0.5 * u;
        }
        let (step, time) = (self.n + 1, (self.n + 1) as f64 * dt);
        let err = contact_err(step, time);
        let p1 = self.solver.solve(&mut self.rhs, &self.lower, sigma, &mut self.lam_bar).map_err(&err)?;
        for (c, &i) in self.contact_idx.iter().enumerate() {
            self.u_bar[c] = self.rhs[i];
        }
        // Interior: U^{n+1} = 2Ū − Uⁿ, V^{n+1} = 2(U^{n+1} − Uⁿ)/Δt − Vⁿ. Contact entries keep
        // uⁿ until Φ overwrites them (Φ reads interior entries only).
        for i in 0..self.u.len() {
            if !self.is_contact[i] {
                let u_new = 2.0 * self.rhs[i] - self.u[i];
                self.v[i] = 2.0 * (u_new - self.u[i]) / dt - self.v[i];
                self.u[i] = u_new;
            }
        }
        for (c, &i) in self.contact_idx.iter().enumerate() {
            self.scratch[c] = self.u[i];
        }
        let p2 = self.quasi_static.apply(&mut self.u, &mut self.lambda).map_err(&err)?;
        std::mem::swap(&mut self.uc_prev, &mut self.uc);
        for (c, &i) in self.contact_idx.iter().enumerate() {
            self.v[i] = (self.u[i] - self.scratch[c]) / dt;
            self.uc[c] = self.u[i];
            self.lam[c] = self.lambda[c];
        }
        self.pivots = p1 + p2;
        self.n = step;
        check_finite(&self.u, &self.lambda, step, time)
    }
}
