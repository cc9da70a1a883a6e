//! Nitsche contact on the bar (issue 20): `M Ü + K U + N(U) = F` with Nitsche's term N of
//! [`crate::contact::nitsche`] (Chouly–Hild–Renard, ESAIM M2AN 49(2) 481–502, 2015; signs and
//! the units of γ = γ₀ E/h there), marched by
//!
//! - **Newmark(β, γ_N)**, Crank–Nicolson at (¼, ½) ([`NitscheNewmark`]; CHR 2015), the contact term
//!   at t_{n+1}, fully implicit, each step solved exactly in closed form;
//! - **explicit Verlet** = central differences on the lumped mass ([`NitscheVerlet`];
//!   Chouly–Renard, AMSES 5:31, 2018), the contact term at t_n.
//!
//! Built for bars only (one contact point whose σ_n comes from its P1 cell): plates and solids
//! are refused in [`build`], naming `contact.method` and the geometry.
//!
//! **Choices where the papers leave room.** γ₀ defaults to 100 (the issue's `[contact]`
//! default; GetFEM's 1D demo uses 5) and must exceed 1 here (the coercivity of `K − (θ/γ)ssᵀ` for θ = 1 and
//! the monotonicity of every contact row for all θ; [`crate::contact::nitsche`]); θ defaults to
//! 1 (the symmetric variant, the only one whose N is a gradient: it has a conserved energy). Every mass is allowed: the consistent
//! standard one and the redistributed ones (a massless contact node makes its row quasi-static;
//! in 1D with no load at the contact node this row gives `u_0 = max(lb, u_1)` and N_1 = 0, so
//! Nitsche then coincides with exact contact whatever θ and γ₀: tested). Both schemes start from
//! the interpolated data; Verlet replaces a massless u⁰_0 by its quasi-static value (as central
//! differences do). The energy reported is CHR's `E^θ = ½V·MV + ½U·KU − F·U + θΦ(U)` with
//! `Φ = −(1/2γ)σ_n² + (1/2γ)[P]_+²` (M_L for Verlet), θ-weighted as GetFEM's
//! `demo_dynamic_contact_1D.py` (Renard, Chouly) computes it; N = ∇Φ only for θ = 1, so only
//! then is a conservation claimed (the identity of [`NitscheNewmark`]).

use super::parts::GeometryParts;
use super::{Beta, Formulation, Gamma, Scheme, SchemeError, SchemeSpec, StateView, check_finite, check_range};
use crate::contact::law::ContactLaw;
use crate::contact::nitsche::{NitscheShape, NitscheTerm};
use crate::contact::{Backend, ContactSolver};
use crate::linalg::SymMatrix;
use crate::system::ContactSystem;

const NAME: &str = "Nitsche contact";

/// Builds the Nitsche scheme of `spec` on a geometry (the one place Nitsche is refused).
pub fn build<A: Backend, L: FnOnce() -> Option<Vec<f64>>>(
    geometry: GeometryParts<'_, A, L>,
    spec: &SchemeSpec,
    law: &ContactLaw,
    dt: f64,
    u: Vec<f64>,
    v: Vec<f64>,
) -> Result<Box<dyn Scheme>, SchemeError> {
    let key = "contact.method = \"nitsche\"";
    let ContactLaw::Nitsche { theta, gamma0 } = *law else {
        let reason = "this builder is the Nitsche law's";
        return Err(SchemeError::Unsupported { key: "contact.method", geometry: geometry.name, reason });
    };
    let theta = f64::from(theta);
    let system = geometry.system;
    if geometry.name != "bar" {
        let reason = "Nitsche contact is built for bars only (one contact point, σ_n from its P1 cell; Chouly–Hild–Renard 2015): use exact or penalty";
        return Err(SchemeError::Unsupported { key, geometry: geometry.name, reason });
    }
    let term =
        NitscheTerm::new(&system.stiffness, &system.contact, &system.lower, theta, gamma0).map_err(|e| match e {
            NitscheShape::Gamma0(g) => SchemeError::Parameter {
                scheme: NAME,
                key: ContactLaw::GAMMA0_KEY,
                value: g,
                range: ContactLaw::GAMMA0_RANGE,
            },
            NitscheShape::ContactCount(_) | NitscheShape::NotOneCell => SchemeError::Unsupported {
                key,
                geometry: geometry.name,
                reason: "Nitsche contact needs one contact node whose stiffness row is one P1 cell",
            },
        })?;
    match *spec {
        SchemeSpec::CrankNicolson { formulation: Formulation::Full } => {
            let (b, g) = (Beta::DEFAULT.get(), Gamma::DEFAULT.get());
            Ok(Box::new(NitscheNewmark::new(system, term, b, g, dt, u, v)?))
        }
        SchemeSpec::Newmark { beta, gamma, formulation: Formulation::Full } => {
            Ok(Box::new(NitscheNewmark::new(system, term, beta.get(), gamma.get(), dt, u, v)?))
        }
        SchemeSpec::CentralDifference => {
            let Some(lumped) = (geometry.lumped_mass)() else {
                let reason = "its lumped mass is not built";
                return Err(SchemeError::Unsupported { key: "scheme.kind", geometry: geometry.name, reason });
            };
            Ok(Box::new(NitscheVerlet::new(system, term, lumped, dt, u, v)?))
        }
        _ => Err(SchemeError::Unsupported {
            key,
            geometry: geometry.name,
            reason: "Nitsche contact is built for crank-nicolson, newmark (full formulation) and central-difference (explicit Verlet)",
        }),
    }
}

/// Plain solves `x ← (M + σK − σ(θ/γ)ssᵀ)⁻¹ x`: the factor of B = M + σK and Sherman–Morrison
/// for the rank-one Nitsche term, `A⁻¹x = B⁻¹x + α (sᵀB⁻¹x)/(1 − α sᵀB⁻¹s) B⁻¹s`, α = σθ/γ.
#[derive(Debug)]
struct RankOne<S: ContactSolver> {
    plain: S,
    floor: [f64; 1],
    unused: [f64; 1],
    term: NitscheTerm,
    /// α / (1 − α sᵀB⁻¹s) and B⁻¹s.
    coef: f64,
    b_inv_s: Vec<f64>,
}

impl<S: ContactSolver> RankOne<S> {
    fn new(mut plain: S, n: usize, term: NitscheTerm, sigma: f64) -> Result<Self, SchemeError> {
        let (floor, mut unused) = ([f64::MIN], [0.0]);
        let mut b_inv_s = vec![0.0; n];
        let s = term.vectors()[0];
        b_inv_s[term.c] = s.0;
        b_inv_s[term.j] = s.1;
        plain.solve(&mut b_inv_s, &floor, 1.0, &mut unused).map_err(super::contact_err(0, 0.0))?;
        let alpha = sigma * term.theta / term.gamma;
        let den = 1.0 - alpha * term.sigma_n(&b_inv_s);
        // den > 0 iff A = B − α ssᵀ is SPD (B SPD): true for γ₀ > 1 (module docs of contact::nitsche).
        check_range(NAME, ContactLaw::GAMMA0_KEY, term.gamma / term.k, den > 0.0, ContactLaw::GAMMA0_RANGE)?;
        Ok(Self { plain, floor, unused, term, coef: alpha / den, b_inv_s })
    }

    fn solve(&mut self, x: &mut [f64], step: usize, time: f64) -> Result<(), SchemeError> {
        self.plain.solve(x, &self.floor, 1.0, &mut self.unused).map_err(super::contact_err(step, time))?;
        let f = self.coef * self.term.sigma_n(x);
        x.iter_mut().zip(&self.b_inv_s).for_each(|(x, y)| *x += f * y);
        Ok(())
    }
}

/// Newmark(β, γ_N) with Nitsche's term at t_{n+1} (module docs):
///
/// ```text
/// (M + σK) U^{n+1} + σ N(U^{n+1}) = M Ũ + σ F^{n+1},   σ = βΔt²,   Ũ = Uⁿ + ΔtVⁿ + (½ − β)Δt²Aⁿ,
/// A^{n+1} = (U^{n+1} − Ũ)/σ,   V^{n+1} = Vⁿ + Δt((1 − γ_N)Aⁿ + γ_N A^{n+1}).
/// ```
///
/// **The step, exactly.** With `A = M + σK − σ(θ/γ)ssᵀ` it reads `A U = r + σ[P(U)]_+ w`. Let
/// `y = A⁻¹ r`, `z = A⁻¹ w` (once), `c = σ qᵀz` (once) and the trial `p* = P(y) = −qᵀy + γ lb`.
/// Then `U = y + σ[p]_+ z` with p = P(U) solving the scalar piecewise-linear equation
/// `p + c [p]_+ = p*`; for `1 + c > 0` its left side is strictly increasing, so its one root is
/// `p = p*` if p* ≤ 0 and `p = p*/(1 + c)` otherwise: semismooth Newton on the single contact
/// dof from the inactive guess, converged after one correction (finite termination, and no
/// second solve: z is stored). 1 + c > 0 holds for θ = 1 (c = (σ/γ) qᵀA⁻¹q ≥ 0) and is checked
/// at construction for θ = 0, −1 (refused otherwise, naming γ₀).
///
/// **Energy** (θ = 1, CN, F constant): summing the scheme's identities, `E^{n+1} − Eⁿ = −δ_n`
/// with `δ_n = (1/2γ)[(p_{n+1} − p_n)([p_n]_+ + [p_{n+1}]_+) − [p_{n+1}]_+² + [p_n]_+²]` (the
/// trapezoidal rule on Φ's piecewise-quadratic part): δ_n = 0 unless P changes sign in the
/// step; at an impact (p_n ≤ 0 < p_{n+1}) `δ_n = −p_n p_{n+1}/2γ ≥ 0` (dissipated), at a release
/// `δ_n = p_n p_{n+1}/2γ ≤ 0` (gained). So the energy is conserved exactly between sign
/// changes and `|E^{n+1} − Eⁿ| ≤ |p_n p_{n+1}|/2γ` at them ([`NitscheNewmark::last_defect`];
/// `tests/nitsche.rs` checks the identity step by step).
#[derive(Debug)]
pub struct NitscheNewmark<A: Backend> {
    beta: f64,
    gamma_n: f64,
    dt: f64,
    sigma: f64,
    term: NitscheTerm,
    mass: A,
    stiffness: A,
    load: Vec<f64>,
    forcing: Option<crate::system::Forcing>,
    massless: Vec<usize>,
    massless_old: Vec<f64>,
    solver: RankOne<A::Solver>,
    z: Vec<f64>,
    c: f64,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: [f64; 1],
    pred: Vec<f64>,
    rhs: Vec<f64>,
    /// δ_n of the last step (energy docs).
    defect: f64,
}

impl<A: Backend> NitscheNewmark<A> {
    pub fn new(
        system: &ContactSystem<A>,
        term: NitscheTerm,
        beta: f64,
        gamma_n: f64,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        check_range(NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let sigma = beta * dt * dt;
        let name = "M + σ S";
        let b = system.mass.combine(1.0, &system.stiffness, sigma, name)?;
        let n = system.n();
        let mut solver = RankOne::new(b.contact_solver(&system.contact, name)?, n, term, sigma)?;
        let [_, q, w] = term.vectors();
        let mut z = vec![0.0; n];
        (z[term.c], z[term.j]) = w;
        solver.solve(&mut z, 0, 0.0)?;
        let c = sigma * (q.0 * z[term.c] + q.1 * z[term.j]);
        check_range(NAME, ContactLaw::GAMMA0_KEY, term.gamma / term.k, 1.0 + c > 0.0, "(1, ∞) with 1 + σqᵀA⁻¹w > 0")?;
        // A⁰ from M A⁰ = F − K U⁰ − N(U⁰).
        let mut with_force = system.clone();
        term.add_force(&u0, -1.0, &mut with_force.load);
        let a = with_force.initial_acceleration(&u0)?;
        let massless: Vec<usize> = (0..n).filter(|&i| system.massless[i]).collect();
        let mut s = Self {
            beta,
            gamma_n,
            dt,
            sigma,
            term,
            mass: system.mass.clone(),
            stiffness: system.stiffness.clone(),
            load: system.load.clone(),
            forcing: system.forcing.clone(),
            massless_old: vec![0.0; massless.len()],
            massless,
            solver,
            z,
            c,
            n: 0,
            lambda: [term.lambda(&u0)],
            pred: vec![0.0; n],
            rhs: vec![0.0; n],
            u: u0,
            v: v0,
            a,
            defect: 0.0,
        };
        s.predict();
        Ok(s)
    }

    fn predict(&mut self) {
        let c = (0.5 - self.beta) * self.dt * self.dt;
        for i in 0..self.u.len() {
            self.pred[i] = self.u[i] + self.dt * self.v[i] + c * self.a[i];
        }
    }

    /// CHR's energy `½V·MV + ½U·KU − F·U + θΦ(U)` (F of the last step's time).
    pub fn energy(&self) -> f64 {
        let work: f64 = self.u.iter().zip(&self.load).map(|(u, f)| u * f).sum();
        0.5 * self.mass.quad_form(&self.v) + 0.5 * self.stiffness.quad_form(&self.u) - work
            + self.term.theta * self.term.potential(&self.u)
    }

    /// δ_n of the last step: for θ = 1, CN and a constant load, `E^{n+1} − Eⁿ = −δ_n` (struct docs).
    pub fn last_defect(&self) -> f64 {
        self.defect
    }

    /// `c = σ qᵀA⁻¹w` of the closed-form step (struct docs).
    pub fn coupling(&self) -> f64 {
        self.c
    }
}

/// δ of the trapezoidal rule on `½[p]_+²/γ` between p0 and p1 (energy docs of [`NitscheNewmark`]).
pub fn trapezoid_defect(p0: f64, p1: f64, gamma: f64) -> f64 {
    let (a, b) = (p0.max(0.0), p1.max(0.0));
    ((p1 - p0) * (a + b) - b * b + a * a) / (2.0 * gamma)
}

impl<A: Backend> Scheme for NitscheNewmark<A> {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: &self.lambda }
    }

    fn energy(&self) -> Option<f64> {
        Some(Self::energy(self))
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let (dt, sigma) = (self.dt, self.sigma);
        let (step, time) = (self.n + 1, (self.n + 1) as f64 * dt);
        if let Some(f) = &self.forcing {
            (f.0)(time, &mut self.load);
        }
        let p_old = self.term.p(&self.u);
        self.mass.mul_add_into(&self.pred, sigma, &self.load, &mut self.rhs);
        for (old, &i) in self.massless_old.iter_mut().zip(&self.massless) {
            *old = self.u[i];
        }
        self.solver.solve(&mut self.rhs, step, time)?;
        // The closed form of the step (struct docs): p* = P(y), [p]_+ = [p*]_+/(1 + c).
        let p_plus = self.term.p(&self.rhs).max(0.0) / (1.0 + self.c);
        if p_plus > 0.0 {
            let f = sigma * p_plus;
            self.rhs.iter_mut().zip(&self.z).for_each(|(u, z)| *u += f * z);
        }
        for i in 0..self.u.len() {
            let u_new = self.rhs[i];
            let a_new = (u_new - self.pred[i]) / sigma;
            self.v[i] += dt * ((1.0 - self.gamma_n) * self.a[i] + self.gamma_n * a_new);
            self.a[i] = a_new;
            self.u[i] = u_new;
        }
        for (&old, &i) in self.massless_old.iter().zip(&self.massless) {
            self.a[i] = 0.0;
            self.v[i] = (self.u[i] - old) / dt;
        }
        self.lambda[0] = -p_plus;
        self.defect = trapezoid_defect(p_old, self.term.p(&self.u), self.term.gamma);
        self.predict();
        self.n = step;
        check_finite(&self.u, &self.lambda, A::SOLVE_SPREADS_NAN, step, time)
    }
}

/// Explicit Verlet with Nitsche's term at t_n (Chouly–Renard 2018), on the lumped mass M_L of
/// [`super::CentralDifference`] (row sums before Dirichlet removal):
///
/// ```text
/// Aⁿ_I = M_L,II⁻¹ (F_I(t_n) − (K Uⁿ)_I − N_I(Uⁿ)),   U^{n+1}_I = Uⁿ_I + ΔtVⁿ_I + ½Δt²Aⁿ_I,
/// V^{n+1}_I = Vⁿ_I + ½Δt (Aⁿ_I + A^{n+1}_I);
/// ```
///
/// a massless contact node (redistributed mass) is quasi-static at t_{n+1}:
/// `(KU)_0 + N_0(U) = F_0`, which is `σ_n + [P]_+ = −f̃`, `f̃ = F_0/(1 − θ/γ₀)`, decreasing in
/// u_0 for γ₀ > 1, so its one root is `u_0 = u_1 + f̃/(E/h)` if P ≤ 0 there, else
/// `u_0 = lb + f̃/γ` (closed form; no load: `u_0 = max(lb, u_1)`, exact contact).
///
/// **Stable step.** Δt ≤ Δt_c = 2/√λ_max(M_L,II⁻¹ B_II) with
/// `B = K + 2γ e_0e_0ᵀ + (1/γ)ssᵀ` (Lanczos as [`super::stable_limit`], its Gershgorin bound
/// when unconverged). How B bounds the Nitsche term: the tangent of K + N is
/// `K − (θ/γ)ssᵀ` out of contact and `K + γe_0e_0ᵀ + e_0sᵀ + θ se_0ᵀ` in contact; by
/// `2|x_0 sᵀx| ≤ γx_0² + (sᵀx)²/γ` the symmetric part of each is ≤ B for every θ ∈ {1, 0, −1}.
/// For θ = 1 the tangents are symmetric, so B bounds their λ_max in every contact state (the
/// linearised step is stable); for θ = 0, −1 it bounds only their symmetric parts, and we claim
/// no stability proof (we have not checked Chouly–Renard's analysis for them; measured bounded
/// at Δt_c in `tests/nitsche.rs`). With a massless contact
/// node the γ e_0e_0ᵀ term sits on a row outside I: the condensed stiffness is then ≤ B_II, whose
/// only addition to K_II is (E/h)²/γ on node 1 (Δt_c within a factor (1 + 1/γ₀)^{1/2} of the
/// exact-contact one). With a massive contact node the bound is of order
/// 2/√(2γ/m_0) ~ h/(c√γ₀): the known cost of an explicit penalty-like term.
#[derive(Debug)]
pub struct NitscheVerlet<A: SymMatrix> {
    dt: f64,
    term: NitscheTerm,
    stiffness: A,
    load: Vec<f64>,
    forcing: Option<crate::system::Forcing>,
    lumped: Vec<f64>,
    inv_mass: Vec<f64>,
    /// Whether the contact node is massless (quasi-static), and its value at the step's start.
    quasi: bool,
    u0_old: f64,
    limit: f64,
    lanczos_steps: usize,
    converged: bool,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: [f64; 1],
}

impl<A: SymMatrix> NitscheVerlet<A> {
    pub const NAME: &'static str = "central-difference (Verlet) with Nitsche contact";
    const SPRING: &'static str = " + 2γ e_0e_0ᵀ + ssᵀ/γ";

    /// Refuses `dt > Δt_c` (struct docs) and massless unknowns other than the contact node.
    pub fn new(
        system: &ContactSystem<A>,
        term: NitscheTerm,
        lumped: Vec<f64>,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let n = system.n();
        if (0..n).any(|i| i != term.c && lumped[i] <= 0.0) {
            let reason = "Nitsche with central differences needs mass on every unknown but the contact node";
            return Err(SchemeError::Unsupported { key: "mass", geometry: "bar", reason });
        }
        let inv_mass: Vec<f64> = lumped.iter().map(|&m| if m > 0.0 { 1.0 / m } else { 0.0 }).collect();
        let inv_sqrt: Vec<f64> = inv_mass.iter().map(|x| x.sqrt()).collect();
        let (s, g) = (term.vectors()[0], term.gamma);
        let (theta, lanczos_steps, converged) = super::stable_limit::lambda_max_of(
            |x, y| {
                system.stiffness.mul_into(x, y);
                y[term.c] += 2.0 * g * x[term.c];
                let sx = s.0 * x[term.c] + s.1 * x[term.j];
                y[term.c] += sx * s.0 / g;
                y[term.j] += sx * s.1 / g;
            },
            &inv_sqrt,
        );
        // Unconverged: Gershgorin; |B − K| has row sums 2γ + 2k²/γ (node 0) and 2k²/γ (node 1).
        let lam = if converged {
            theta
        } else {
            let extra = 2.0 * g + 2.0 * term.k * term.k / g;
            super::stable_limit::gershgorin(&system.stiffness, &inv_sqrt, &[term.c, term.j], extra)
        };
        let limit = if lam > 0.0 { 2.0 / lam.sqrt() } else { f64::INFINITY };
        if super::stable_limit::refuses(dt, limit) {
            return Err(SchemeError::AboveStableLimit { scheme: Self::NAME, dt, limit, spring: Self::SPRING });
        }
        let mut s = Self {
            dt,
            term,
            stiffness: system.stiffness.clone(),
            load: system.load.clone(),
            forcing: system.forcing.clone(),
            quasi: lumped[term.c] <= 0.0,
            lumped,
            inv_mass,
            u0_old: 0.0,
            limit,
            lanczos_steps,
            converged,
            n: 0,
            u: u0,
            v: v0,
            a: vec![0.0; n],
            lambda: [0.0],
        };
        s.quasi_static();
        s.accelerations();
        Ok(s)
    }

    /// The stable limit Δt_c and the Lanczos steps that computed it.
    pub fn stable_limit(&self) -> (f64, usize) {
        (self.limit, self.lanczos_steps)
    }

    /// `½V·M_L V + ½U·KU − F·U + θΦ(U)`.
    pub fn energy(&self) -> f64 {
        let kinetic: f64 = self.v.iter().zip(&self.lumped).map(|(v, m)| m * v * v).sum();
        let work: f64 = self.u.iter().zip(&self.load).map(|(u, f)| u * f).sum();
        0.5 * kinetic + 0.5 * self.stiffness.quad_form(&self.u) - work + self.term.theta * self.term.potential(&self.u)
    }

    /// The massless contact node's closed form (struct docs).
    fn quasi_static(&mut self) {
        if !self.quasi {
            return;
        }
        let t = self.term;
        let f = self.load[t.c] / (1.0 - t.theta * t.k / t.gamma);
        self.u[t.c] = self.u[t.j] + f / t.k;
        if t.p(&self.u) > 0.0 {
            self.u[t.c] = t.lower + f / t.gamma;
        }
    }

    /// `A = M_L⁻¹ (F − K U − N(U))` on I, 0 on the massless node; λ = −[P(U)]_+.
    fn accelerations(&mut self) {
        self.stiffness.mul_into(&self.u, &mut self.a);
        self.a.iter_mut().zip(&self.load).for_each(|(a, f)| *a = f - *a);
        self.term.add_force(&self.u, -1.0, &mut self.a);
        self.a.iter_mut().zip(&self.inv_mass).for_each(|(a, m)| *a *= m);
        self.lambda[0] = self.term.lambda(&self.u);
    }
}

impl<A: SymMatrix + Send> Scheme for NitscheVerlet<A> {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: &self.lambda }
    }

    fn energy(&self) -> Option<f64> {
        Some(Self::energy(self))
    }

    fn note(&self) -> Option<String> {
        Some(format!(
            "{}: stable limit Δt_c = {} (2/√λ_max(M_L,II⁻¹ (K{})), {}); time.dt = {}",
            Self::NAME,
            crate::numfmt::fmt_f64(self.limit),
            Self::SPRING,
            if self.converged {
                format!("Lanczos, {} steps, to ~{:e} relative", self.lanczos_steps, super::stable_limit::REL_TOL)
            } else {
                format!("Gershgorin bound: Lanczos unconverged after {} steps", self.lanczos_steps)
            },
            crate::numfmt::fmt_f64(self.dt),
        ))
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let dt = self.dt;
        let (step, time) = (self.n + 1, (self.n + 1) as f64 * dt);
        self.u0_old = self.u[self.term.c];
        for i in 0..self.u.len() {
            self.v[i] += 0.5 * dt * self.a[i];
            self.u[i] += dt * self.v[i] * (self.inv_mass[i] > 0.0) as u8 as f64;
        }
        if let Some(f) = &self.forcing {
            (f.0)(time, &mut self.load);
        }
        self.quasi_static();
        self.accelerations();
        for i in 0..self.u.len() {
            self.v[i] += 0.5 * dt * self.a[i];
        }
        if self.quasi {
            self.v[self.term.c] = (self.u[self.term.c] - self.u0_old) / dt;
        }
        self.n = step;
        check_finite(&self.u, &self.lambda, false, step, time)
    }
}
