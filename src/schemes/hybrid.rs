//! The paper's hybrid scheme (P^hyb) (§5), for one or many quasi-static contact nodes.
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
//! **Many nodes (plates, solids).** The same equations with vectors: for the interior unknowns I and contact unknowns C
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
//! the back-end's [`ContactSolver`] with σ = Δt²/4 and lower bounds `u_Cⁿ/2` — then `U^{n+1} = 2Ū − Uⁿ`,
//! `V^{n+1} = 2(U^{n+1} − Uⁿ)/Δt − Vⁿ`, and Φ is one more LCP with the SPD matrix S_CC.
//! With one contact node (a bar) this is the paper's (P^hyb) step for step: the midpoint form
//! `K Ū = M_red (Uⁿ + Δt/2 Vⁿ) + Δt²/4 (F + g e_1)` with `K = M_red + Δt²/4 S_red` and the
//! piecewise-linear contact term g of the paper, which the two cases above reproduce.
//!
//! **Free massless unknowns (solids).** With a vector field every component of a contact-face
//! node is massless, but only the normal one carries a Signorini condition; the tangential ones
//! F are free (frictionless contact). They are quasi-static too: the midpoint solve gives them
//! `S_F· X̄ = F_F` (their mass rows vanish), and Φ sets them with the contact values
//! ([`QuasiStatic`]: the LCP on the Schur complement `D = S_CC − S_CF S_FF⁻¹ S_FC`). The energy
//! proof below holds with C replaced by Q = C ∪ F, λ_F = 0 and no bound on F: with
//! `d = u_Q^{n+1} − ũ_Q`, `S_QQ d = 2 E_C (λ̄ − λ̂)` gives `d_F = −S_FF⁻¹ S_FC d_C`, so the last
//! term is `−½ d_Qᵀ S_QQ d_Q = −½ d_Cᵀ D d_C`: the same three terms with A = D.
//!
//! **A gap.** With the obstacle at `u_c = lb_c = −gap_c` every bound and every (·)⁺, H(·) acts
//! on `u − lb`: the midpoint bound is `ū ≥ (u_Cⁿ + lb)/2` and Φ solves `u ≥ lb`. The
//! derivation below holds for the shifted variables `u − lb` (only differences of u and the
//! complementarity relations enter it).
//!
//! **The initial state.** The scheme starts from the quasi-static contact values
//! `u_C⁰ = Φ(U⁰)` (in 1D `u_0⁰ = max(u_1⁰, −gap)`), not from the interpolated ones, and reports
//! that state (and its multipliers) at n = 0.
//!
//! **Friction** (issue 29; `contact.friction` with `mass.contact_directions = "normal"`: the
//! contact nodes' tangential unknowns keep their mass, only the normal ones are quasi-static).
//! The midpoint solve takes the frictional law ([`crate::contact::law::ContactLaw::midpoint_law`]):
//! the interior rows gain `E_t r̄_t`, the tangential reactions of the contact nodes at the
//! midpoint, with the conditions of `crate::contact::friction` on the step's increment
//! `ΔU_t = U_t^{n+1} − U_tⁿ = 2(Ū_t − U_tⁿ)` (stick: `Ū_t = U_tⁿ`; slide: r̄_t against ΔU_t, at
//! the bound) and the Coulomb bound `μ r̄_n` of the midpoint normal force λ̄ (the scheme's contact
//! force acts at t_{n+½}, the midpoint rule's level; midpoint schemes for frictional contact
//! put the bound there too, e.g. Armero & Petőcz, CMAME 179 (1999)). Φ is unchanged: it sets the normal
//! unknowns alone, whose rows carry no tangential force. Testing the interior rows with ΔU adds
//! `r̄_t · ΔU_t = −D_step ≤ 0` to ΔE below: `ΔE = [the three terms] − D_step`, so E still never
//! grows, and the `friction_dissipation` key adds D_step (`tests/friction.rs` checks the identity
//! at every step). A contact layer massless in every direction would need Φ to solve a
//! frictional problem too: refused (`crate::spec::compat`).
//!
//! **Energy: Lemma 5.1 carries over.** Let `E = ½VᵀMV + ½XᵀSX − XᵀF` with `X = (u_C, U)`,
//! and let both ends of a step be quasi-static (`u_C = Φ(U)`; true for every step n ≥ 1, and
//! for the first step the reported E⁰ uses the interpolated u_C⁰, whose energy is ≥ that of
//! Φ(U⁰) because Φ minimises the potential over u_C ≥ 0). Write `A = S_CC`, `ũ = 2ū − u_Cⁿ`
//! (≥ 0, ⊥ λ̄). Testing the interior rows with `U^{n+1} − Uⁿ` and using the contact rows at
//! t_n, t_{n+1} and at the midpoint, `A(û − ū) = λ̄ − λ̂` (hats: averages of n and n+1), gives
//! `ΔE = −(λ^{n+1} − λⁿ)ᵀ(û − ū) − (u_C^{n+1} − u_Cⁿ)ᵀλ̄`; with `û − ū = (u_C^{n+1} − ũ)/2` and
//! the three complementarity relations this is (lb = 0; with a gap, ũ and u_Cⁿ in the first two
//! terms become ũ − lb and u_Cⁿ − lb)
//!
//! ```text
//! ΔE = (λ^{n+1})ᵀ ũ + (u_Cⁿ)ᵀ λ̄ − ½ (u_C^{n+1} − ũ)ᵀ A (u_C^{n+1} − ũ)  ≤ 0,
//! ```
//!
//! each term ≤ 0 (λ ≤ 0 ≤ ũ, u_Cⁿ ≥ 0 ≥ λ̄, A SPD), for any mesh and any contact states along
//! Γ_C: no sign condition on S_CC's off-diagonal entries is used. In 1D (A = 1/h) this is the
//! five cases of Lemma 5.1 at once. [`Hybrid::energy_terms`] returns the three terms of the
//! last step (the tests check that they add up to the measured ΔE).

use super::{SchemeError, StateView, check_finite, check_range, contact_err};
use crate::contact::law::ContactLaw;
use crate::contact::{Backend, QuasiStatic, StepLaw};
use crate::system::ContactSystem;

#[derive(Debug)]
pub struct Hybrid<A: Backend> {
    dt: f64,
    mass: A,
    load: Vec<f64>,
    /// A time-dependent load: `load` is refreshed to F(t_{n+1}) at each step.
    forcing: Option<crate::system::Forcing>,
    contact_idx: Vec<usize>,
    /// The massless unknowns Φ sets: the contact unknowns, then the free massless ones.
    quasi_idx: Vec<usize>,
    /// Obstacle bounds lb (contact order).
    obstacle: Vec<f64>,
    /// The midpoint step's law (the exact condition, frictionless or with friction).
    law: Box<dyn StepLaw>,
    quasi_static: QuasiStatic,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    /// Reported λⁿ: the quasi-static multipliers of the contact rows at t_n.
    lambda: Vec<f64>,
    /// Quasi-static u_Cⁿ, and u_C of the previous step (bounds and energy terms).
    uc: Vec<f64>,
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

impl<A: Backend> Hybrid<A> {
    pub const NAME: &'static str = super::SchemeSpec::Hybrid.name();

    /// Needs every contact unknown massless (quasi-static contact rows). The contact entries of
    /// `u0` are replaced by the quasi-static values Φ(U⁰) (module docs). The exact law.
    pub fn new(system: &ContactSystem<A>, dt: f64, u0: Vec<f64>, v0: Vec<f64>) -> Result<Self, SchemeError> {
        Self::with_law(system, &ContactLaw::Exact, dt, u0, v0)
    }

    /// [`Self::new`] with the midpoint step's law (`ContactLaw::midpoint_law`: the exact law, or
    /// friction on massive tangential unknowns; module docs, "Friction").
    pub fn with_law(
        system: &ContactSystem<A>,
        law: &ContactLaw,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        if !system.massless_contact() {
            return Err(SchemeError::NeedsMasslessContact { scheme: Self::NAME, w0: system.contact_mass() });
        }
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let name = "M + Δt²/4 S";
        let k = system.mass.combine(1.0, &system.stiffness, dt * dt / 4.0, name)?;
        let mut law = law.midpoint_law(system, &k, name, dt * dt / 4.0, dt)?;
        // Massless unknowns without a contact condition (a solid's tangential components on
        // Γ_C) are quasi-static too: Φ sets them with the contact values (module docs).
        let mut is_contact = vec![false; system.n()];
        for &c in &system.contact {
            is_contact[c] = true;
        }
        let free: Vec<usize> = (0..system.n()).filter(|&i| system.massless[i] && !is_contact[i]).collect();
        let mut quasi_static = QuasiStatic::with_free(&system.stiffness, &system.load, &system.contact, &free)?;
        let quasi_idx: Vec<usize> = system.contact.iter().chain(&free).copied().collect();
        let (n, nc) = (system.n(), system.contact.len());
        let mut u = u0;
        let mut lambda = vec![0.0; nc];
        quasi_static.apply(&mut u, &system.lower, &mut lambda).map_err(contact_err(0, 0.0))?;
        law.start(&u);
        let uc: Vec<f64> = system.contact.iter().map(|&i| u[i]).collect();
        let pred = u.iter().zip(&v0).map(|(u, v)| u + 0.5 * dt * v).collect();
        Ok(Self {
            dt,
            mass: system.mass.clone(),
            load: system.load.clone(),
            forcing: system.forcing.clone(),
            contact_idx: system.contact.clone(),
            scratch: vec![0.0; quasi_idx.len()],
            quasi_idx,
            obstacle: system.lower.clone(),
            law,
            quasi_static,
            n: 0,
            u,
            v: v0,
            lambda,
            uc_prev: uc.clone(),
            uc,
            u_bar: vec![0.0; nc],
            lam_bar: vec![0.0; nc],
            lower: vec![0.0; nc],
            pred,
            rhs: vec![0.0; n],
            pivots: 0,
        })
    }

    /// The three terms `[(λ^{n+1})ᵀ(ũ − lb), (u_Cⁿ − lb)ᵀλ̄, −½‖u_C^{n+1} − ũ‖²_{S_CC}]` of the
    /// last step's energy change, `ũ = 2ū − u_Cⁿ` (module docs): each ≤ 0, and their sum is ΔE.
    pub fn energy_terms(&self) -> [f64; 3] {
        let nc = self.uc.len();
        let tilde = |c: usize| 2.0 * self.u_bar[c] - self.uc_prev[c];
        let t1: f64 = (0..nc).map(|c| self.lambda[c] * (tilde(c) - self.obstacle[c])).sum();
        let t2: f64 = (0..nc).map(|c| (self.uc_prev[c] - self.obstacle[c]) * self.lam_bar[c]).sum();
        let mut t3 = 0.0;
        for a in 0..nc {
            for b in 0..nc {
                t3 += (self.uc[a] - tilde(a)) * self.quasi_static.d(a, b) * (self.uc[b] - tilde(b));
            }
        }
        [t1, t2, -0.5 * t3]
    }
}

impl<A: Backend> super::Scheme for Hybrid<A> {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: &self.lambda }
    }

    fn pivots(&self) -> usize {
        self.pivots
    }

    fn friction(&self) -> Option<&crate::contact::friction::FrictionRecord> {
        self.law.friction()
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let dt = self.dt;
        let sigma = dt * dt / 4.0;
        // `pred` = Uⁿ + Δt/2 Vⁿ, kept by the previous step's update pass (and by `new`).
        if let Some(f) = &self.forcing {
            // The midpoint equation is written at t_{n+½}; Φ(U^{n+1}) below at t_{n+1}.
            (f.0)((self.n as f64 + 0.5) * dt, &mut self.load);
        }
        self.mass.mul_add_into(&self.pred, sigma, &self.load, &mut self.rhs);
        for ((l, u), lb) in self.lower.iter_mut().zip(&self.uc).zip(&self.obstacle) {
            *l = 0.5 * (u + lb);
        }
        let (step, time) = (self.n + 1, (self.n + 1) as f64 * dt);
        let err = contact_err(step, time);
        let p1 = self.law.solve(&mut self.rhs, &self.lower, &mut self.lam_bar).map_err(&err)?;
        for (c, &i) in self.contact_idx.iter().enumerate() {
            self.u_bar[c] = self.rhs[i];
        }
        // U^{n+1} = 2Ū − Uⁿ, V^{n+1} = 2(U^{n+1} − Uⁿ)/Δt − Vⁿ and the next predictor, in one
        // branch-free pass over all unknowns; the massless entries are then replaced: u by Φ
        // (which reads the other entries only), v from the saved uⁿ.
        for (c, &i) in self.quasi_idx.iter().enumerate() {
            self.scratch[c] = self.u[i];
        }
        let m = self.u.len();
        let (u, v, pred, x) = (&mut self.u[..m], &mut self.v[..m], &mut self.pred[..m], &self.rhs[..m]);
        for i in 0..m {
            let u_new = 2.0 * x[i] - u[i];
            let v_new = 2.0 * (u_new - u[i]) / dt - v[i];
            u[i] = u_new;
            v[i] = v_new;
            pred[i] = u_new + 0.5 * dt * v_new;
        }
        if let Some(f) = &self.forcing {
            (f.0)(time, &mut self.load);
            self.quasi_static.set_load(&self.load);
        }
        let p2 = self.quasi_static.apply(&mut self.u, &self.obstacle, &mut self.lambda).map_err(&err)?;
        std::mem::swap(&mut self.uc_prev, &mut self.uc);
        for (c, &i) in self.quasi_idx.iter().enumerate() {
            self.v[i] = (self.u[i] - self.scratch[c]) / dt;
            self.pred[i] = self.u[i] + 0.5 * dt * self.v[i];
        }
        for (c, &i) in self.contact_idx.iter().enumerate() {
            self.uc[c] = self.u[i];
        }
        self.pivots = p1 + p2;
        self.n = step;
        check_finite(&self.u, &self.lambda, A::SOLVE_SPREADS_NAN, step, time)
    }
}
