//! Explicit central differences with a redistributed, lumped mass (Doyen–Ern–Piperno 2011,
//! "semi-explicit modified mass"; issue 20).
//!
//! `M_L = diag(row sums of the weighted mass over all nodes, before the Dirichlet nodes are
//! removed)` (a bar node i weighs `ρh/2 (w_{i−1} + w_i)`), given by the geometry
//! ([`crate::problem::Geometry::lumped_mass`]). I = the unknowns with `M_L,ii > 0`, C = the
//! massless ones (the contact nodes of a redistributed mass, and the massless unknowns of a
//! contact layer). In velocity-Verlet form:
//!
//! ```text
//! Aⁿ_I = M_L,II⁻¹ (F_I(t_n) − (K Uⁿ)_I − λⁿ_I)
//! U^{n+1}_I = Uⁿ_I + Δt Vⁿ_I + ½ Δt² Aⁿ_I
//! K_CC U^{n+1}_C + K_CI U^{n+1}_I = F_C(t_{n+1}) − λ^{n+1}_C,   0 ≤ u_c − lb_c ⊥ λ_c ≤ 0
//! V^{n+1}_I = Vⁿ_I + ½ Δt (Aⁿ_I + A^{n+1}_I)
//! ```
//!
//! The massless rows are quasi-static at t_{n+1}, Signorini solved exactly by
//! [`crate::contact::QuasiStatic`] (the LCP on K_CC, or on its Schur complement when a contact
//! layer has free massless unknowns); in 1D `u_0 = max(−gap, (F_0 − K_01 u_1)/K_00)`. A massless
//! unknown reports `v = (u^{n+1} − uⁿ)/Δt` and `a = 0` (module docs of `schemes`). The scheme
//! starts from the interpolated data with U⁰_C replaced by its quasi-static contact value (as
//! [`super::Hybrid`] does).
//!
//! **Massive contact nodes** (the standard mass) with exact contact: the forward-increment
//! Lagrange multiplier method (Carpenter, Taylor, Katona, IJNME 32, 1991): the contact force in
//! Aⁿ is the one that puts U^{n+1} on the obstacle if the step without it would cross it. M_L
//! is diagonal and each contact condition acts on its own unknown, so it is one closed form per
//! node: with `ũ_c = u_cⁿ + Δt v_c^{n−½} + Δt² a_c` (a_c without contact, `v^{n−½} = V^{n−1} +
//! ½ΔtA^{n−1}`; at n = 0, `ũ_c = u_c⁰ + Δt v_c⁰ + ½Δt² a_c`, coefficient ½ instead of 1),
//! `λ_c = min(0, (ũ_c − lb_c) m_c / (κ Δt²))`, κ = 1 (κ = ½ at n = 0).
//! With friction the tangential unknowns of a massive contact node take the same forward
//! increment, returned onto the friction disc ([`crate::contact::friction::FrictionMassive`]).
//!
//! **Stability**: `Δt ≤ Δt_c = 2/√λ_max(M_L,II⁻¹ K_II)` ([`super::stable_limit`]: Lanczos, its
//! accuracy stated there). The massless unknowns enter the interior rows through the quasi-static
//! map: with C free the effective stiffness is the Schur complement `K_II − K_IC K_CC⁻¹ K_CI`,
//! with C on the obstacle it is K_II; both are ≤ K_II, so K_II's λ_max bounds every contact
//! state. `Δt = Δt_c` is not stable (the highest mode grows linearly): `time.dt ≥ Δt_c (1 − REL_TOL)`
//! is refused naming Δt_c, the margin being the stated accuracy of Δt_c
//! ([`super::stable_limit::REL_TOL`] relative; [`super::stable_limit::refuses`]).
//!
//! **Matrix-free** (`scheme.operator`, issue 31): with an [`Operator`] the product K u and
//! Δt_c come from it ([`stable_limit_of_operator`]: Lanczos on the operator, without a stored
//! basis above `LARGE` interior unknowns, the Gershgorin bound from `|K| 1_I` where Lanczos does
//! not converge); the system's stiffness is read only by the law, for the massless unknowns'
//! rows, so a set-up may hold those rows alone ([`crate::solid::lean`]).
//!
//! **Other laws** ([`crate::contact::ExplicitLaw`]): the scheme is written once for every law.
//! The law adds its force of the current state (Nitsche: −N(Uⁿ) in the residual before M_L⁻¹;
//! the penalty: its springs on the massive contact nodes), solves the quasi-static rows of the
//! massless unknowns with its own condition, and adds its term B to K in the stable limit
//! (`Δt_c = 2/√λ_max(M_L,II⁻¹ (K + B)_II)`; the penalty's `κ Σ_{c massive} e_c e_cᵀ`, all
//! springs engaged: adding a positive semi-definite term can only raise λ_max, so this bounds
//! every contact state; Nitsche's in [`crate::contact::nitsche::NitscheExplicit`]).
//!
//! **Parallel**: `K U` ([`SymMatrix::par_mul_into`]) and the element-wise force and update loops
//! run on rayon's threads ([`PAR_ROWS`] entries per task at least, so small systems stay on one
//! thread); every entry is computed as in the sequential loops, so the results do not depend on
//! the number of threads (bit for bit).
//!
//! **Energy**: `½ V·M_L V + ½ U·K U − F·U` plus the law's ([`CentralDifference::energy`]); without contact and
//! with Δt < Δt_c it stays within O(Δt²) of its initial value (a shadow energy is conserved).

use super::stable_limit::Method;
use super::{SchemeError, StateView, check_finite, check_range, contact_err};
use crate::contact::law::ContactLaw;
use crate::contact::{ExplicitLaw, Massive};
use crate::linalg::sparse::PAR_ROWS;
use crate::linalg::{Operator, SymMatrix};
use crate::system::ContactSystem;
use rayon::prelude::*;

/// The system a scheme is built from: borrowed (its stiffness copied) or owned (moved).
enum Source<'a, A> {
    Borrowed(&'a ContactSystem<A>),
    Owned(ContactSystem<A>),
}

impl<A: SymMatrix> Source<'_, A> {
    fn get(&self) -> &ContactSystem<A> {
        match self {
            Source::Borrowed(s) => s,
            Source::Owned(s) => s,
        }
    }

    /// The stiffness the steps use: a matrix-free operator if one is given, else the compact
    /// row-run form where the back-end has one (sparse: bit-identical products, ~45% fewer
    /// bytes streamed in 3D), else a copy (borrowed) or the matrix itself (owned).
    fn stiffness(self, operator: Option<Box<dyn Operator>>) -> Stiffness<A> {
        if let Some(op) = operator {
            return Stiffness::Free(op);
        }
        match self {
            Source::Borrowed(s) => {
                s.stiffness.run_mat().map_or_else(|| Stiffness::Plain(s.stiffness.clone()), Stiffness::Runs)
            }
            Source::Owned(s) => s.stiffness.into_run_mat().map_or_else(Stiffness::Plain, Stiffness::Runs),
        }
    }
}

/// K in the form the steps use ([`Source::stiffness`]).
#[derive(Debug)]
enum Stiffness<A> {
    Plain(A),
    Runs(crate::linalg::sparse::RunMat),
    /// Matrix-free (`scheme.operator`).
    Free(Box<dyn Operator>),
}

impl<A: SymMatrix> Stiffness<A> {
    fn par_mul_into(&self, x: &[f64], y: &mut [f64]) {
        match self {
            Stiffness::Plain(a) => a.par_mul_into(x, y),
            Stiffness::Runs(r) => r.par_mul_into(x, y),
            Stiffness::Free(op) => op.apply(x, y),
        }
    }

    fn quad_form(&self, x: &[f64]) -> f64 {
        match self {
            Stiffness::Plain(a) => a.quad_form(x),
            Stiffness::Runs(r) => r.quad_form(x),
            Stiffness::Free(op) => op.quad_form(x),
        }
    }
}

/// The vectors of n values a step reads or writes, pass by pass ([`CentralDifference::streamed_bytes`];
/// a law without residual): the half-step update reads v, u, a, M_L⁻¹ and writes v, u (6); the
/// product K u reads u once (its neighbours' values come from cache on a mesh numbered by
/// node) and writes Ku into a (2); `a = M_L⁻¹ (F − Ku)` reads M_L⁻¹, F, Ku and writes a (4); the last
/// half-step reads v, a and writes v (3).
pub const VECTOR_PASSES: usize = 15;

#[derive(Debug)]
pub struct CentralDifference<A: SymMatrix> {
    dt: f64,
    stiffness: Stiffness<A>,
    load: Vec<f64>,
    forcing: Option<crate::system::Forcing>,
    lumped: Vec<f64>,
    /// `1/M_L,ii` on I, 0 on C.
    inv_mass: Vec<f64>,
    /// The contact law (its force, quasi-static rows and stable-limit term).
    law: Box<dyn ExplicitLaw>,
    /// All massless unknowns and their value at the start of the step.
    massless: Vec<usize>,
    massless_old: Vec<f64>,
    limit: f64,
    lanczos_steps: usize,
    /// Which estimator gave Δt_c.
    method: Method,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: Vec<f64>,
    pivots: usize,
}

impl<A: SymMatrix> CentralDifference<A> {
    pub const NAME: &'static str = super::SchemeSpec::CENTRAL_DIFFERENCE.name();

    /// On `system` with the lumped mass `lumped` (one entry per unknown, ≥ 0) and the contact law
    /// (exact or penalty).
    /// Refuses `dt ≥ Δt_c (1 − REL_TOL)` ([`SchemeError::AboveStableLimit`]).
    pub fn new(
        system: &ContactSystem<A>,
        lumped: Vec<f64>,
        law: &ContactLaw,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        Self::build(Source::Borrowed(system), None, lumped, law, dt, || (u0, v0))
    }

    /// [`Self::new`] with the stiffness taken from `operator` where one is given (equal to
    /// `system.stiffness` to round-off: `scheme.operator`): the product and the stable limit
    /// ([`stable_limit_of_operator`]). `system.stiffness` is then read only by the law (the
    /// massless unknowns' quasi-static rows: those rows and columns suffice). The initial state
    /// `(u⁰, v⁰)` is made by `initial` once Δt_c is known: at scale the stable limit's Lanczos
    /// vectors and the state are then not held at once (issue 31: the set-up's peak memory).
    pub fn with_operator(
        system: &ContactSystem<A>,
        operator: Option<Box<dyn Operator>>,
        lumped: Vec<f64>,
        law: &ContactLaw,
        dt: f64,
        initial: impl FnOnce() -> (Vec<f64>, Vec<f64>),
    ) -> Result<Self, SchemeError> {
        if let Some(op) = &operator {
            assert_eq!(op.n(), system.n(), "the operator acts on the system's unknowns");
        }
        Self::build(Source::Borrowed(system), operator, lumped, law, dt, initial)
    }

    /// [`Self::new`] owning the system: its stiffness moves into the scheme instead of being
    /// copied (explicit at scale: one stiffness in memory).
    pub fn from_system(
        system: ContactSystem<A>,
        lumped: Vec<f64>,
        law: &ContactLaw,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        Self::build(Source::Owned(system), None, lumped, law, dt, || (u0, v0))
    }

    fn build(
        source: Source<'_, A>,
        operator: Option<Box<dyn Operator>>,
        lumped: Vec<f64>,
        law: &ContactLaw,
        dt: f64,
        initial: impl FnOnce() -> (Vec<f64>, Vec<f64>),
    ) -> Result<Self, SchemeError> {
        let system = source.get();
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let law = law.explicit_law(system, &lumped, dt)?;
        let n = system.n();
        let (limit, lanczos_steps, method) = match &operator {
            Some(op) => stable_limit_of_operator(op.as_ref(), &lumped, Some(law.as_ref())),
            None => stable_limit_of(system, &lumped, Some(law.as_ref())),
        };
        // dt = Δt_c is not stable, and Δt_c is known to REL_TOL: refused from Δt_c (1 − REL_TOL)
        // down (a free–free uniform chain has Δt_c = h/c exactly: Courant 1 is refused there).
        if super::stable_limit::refuses(dt, limit) {
            return Err(SchemeError::AboveStableLimit { scheme: Self::NAME, dt, limit, spring: law.bound() });
        }
        // Made after Δt_c (the peak of an explicit set-up at scale is its Lanczos vectors).
        let inv_mass: Vec<f64> = lumped.iter().map(|&m| if m > 0.0 { 1.0 / m } else { 0.0 }).collect();
        let (u0, v0) = initial();
        let massless: Vec<usize> = (0..n).filter(|&i| lumped[i] <= 0.0).collect();
        let (load, forcing) = (system.load.clone(), system.forcing.clone());
        let lambda = vec![0.0; system.contact.len()];
        let mut s = Self {
            dt,
            stiffness: source.stiffness(operator),
            load,
            forcing,
            lumped,
            inv_mass,
            law,
            massless_old: vec![0.0; massless.len()],
            massless,
            limit,
            lanczos_steps,
            method,
            n: 0,
            u: u0,
            a: vec![0.0; n],
            v: v0,
            lambda,
            pivots: 0,
        };
        s.quasi_static(0, 0.0)?;
        s.accelerations(0.5);
        Ok(s)
    }

    /// The stable limit Δt_c and the Lanczos steps that computed it.
    pub fn stable_limit(&self) -> (f64, usize) {
        (self.limit, self.lanczos_steps)
    }

    /// `½ V·M_L V + ½ U·K U − F(t_n)·U` of the current state plus the law's energy (the
    /// penalty's `Σ ½κ (d_c⁻)²`, Nitsche's θΦ; 0 for the exact law).
    pub fn energy(&self) -> f64 {
        let kinetic: f64 = self.v.iter().zip(&self.lumped).map(|(v, m)| m * v * v).sum();
        let work: f64 = self.u.iter().zip(&self.load).map(|(u, f)| u * f).sum();
        0.5 * kinetic + 0.5 * self.stiffness.quad_form(&self.u) - work + self.law.energy(&self.u)
    }

    /// The bytes a step streams through memory, counted from the data structures with STREAM's
    /// convention (each array read or written once per pass counts its size once; no
    /// write-allocate): the stiffness in row-run form ([`crate::linalg::sparse::RunMat::bytes`])
    /// or a matrix-free operator's passes ([`Operator::streamed_bytes`]), and [`VECTOR_PASSES`]
    /// vectors of n values. The contact law's work on the contact nodes
    /// (a few per thousand unknowns at scale) is not counted. None where the count does not
    /// hold: a stiffness not in row-run form, or a law with a residual (penalty, Nitsche: more
    /// passes).
    pub fn streamed_bytes(&self) -> Option<usize> {
        match &self.stiffness {
            Stiffness::Runs(r) if !self.law.has_residual() => Some(r.bytes() + VECTOR_PASSES * 8 * self.u.len()),
            Stiffness::Free(op) if !self.law.has_residual() => {
                Some(op.streamed_bytes() + VECTOR_PASSES * 8 * self.u.len())
            }
            _ => None,
        }
    }

    /// The massless unknowns from the quasi-static rows at t (F(t) already in `load`).
    fn quasi_static(&mut self, step: usize, time: f64) -> Result<(), SchemeError> {
        if !self.massless.is_empty() {
            let forced = self.forcing.is_some();
            self.pivots = self
                .law
                .quasi_static(&mut self.u, &self.load, forced, &mut self.lambda)
                .map_err(contact_err(step, time))?;
        }
        Ok(())
    }

    /// `A = M_L⁻¹ (F − K U − the law's force)` on I (module docs; `kappa` = 1 in a step, ½ at
    /// n = 0; `v` holds the half-step velocity in a step, V⁰ at n = 0).
    fn accelerations(&mut self, kappa: f64) {
        // K U is written into `a` and read back in place (no vector of its own: issue 31's
        // memory per unknown).
        self.stiffness.par_mul_into(&self.u, &mut self.a);
        if self.law.has_residual() {
            (&mut self.a[..], &self.load[..]).into_par_iter().with_min_len(PAR_ROWS).for_each(|(a, f)| *a = f - *a);
            self.law.add_residual(&self.u, &mut self.a);
            (&mut self.a[..], &self.inv_mass[..]).into_par_iter().with_min_len(PAR_ROWS).for_each(|(a, m)| *a *= m);
        } else {
            (&mut self.a[..], &self.inv_mass[..], &self.load[..])
                .into_par_iter()
                .with_min_len(PAR_ROWS)
                .for_each(|(a, m, f)| *a = m * (f - *a));
        }
        self.law.massive(Massive {
            u: &self.u,
            v: &self.v,
            a: &mut self.a,
            lumped: &self.lumped,
            inv_mass: &self.inv_mass,
            dt: self.dt,
            kappa,
            lambda: &mut self.lambda,
        });
    }
}

/// `(Δt_c, Lanczos steps, converged)` of central differences on `system` with the lumped mass
/// `lumped` and the law `law` (module docs): Lanczos on `M_L,II^{−½} (K + B) M_L,II^{−½}` with
/// the law's term B (None: no term, as the exact law), or the Gershgorin bound if it did not
/// converge.
pub fn stable_limit_of<A: SymMatrix>(
    system: &ContactSystem<A>,
    lumped: &[f64],
    law: Option<&dyn ExplicitLaw>,
) -> (f64, usize, Method) {
    let inv_sqrt = inv_sqrt(lumped);
    let (theta, lanczos_steps, converged) = super::stable_limit::lambda_max_of(
        |x, y| stiffened(|x, y| system.stiffness.par_mul_into(x, y), law, x, y),
        &inv_sqrt,
    );
    // Unconverged Lanczos: the Gershgorin upper bound instead (conservative; stable_limit docs).
    let lam = if converged {
        theta
    } else {
        let (rows, extra) = law.map_or((Vec::new(), 0.0), |l| l.gershgorin());
        super::stable_limit::gershgorin(&system.stiffness, &inv_sqrt, &rows, extra)
    };
    (limit_of(lam), lanczos_steps, if converged { Method::Lanczos } else { Method::Gershgorin })
}

/// [`stable_limit_of`] with the stiffness a matrix-free operator: Lanczos on the operator
/// ([`super::stable_limit::lambda_max_lean`]: no stored basis above `LARGE` interior unknowns),
/// and where it does not converge the smaller of two upper bounds: the element eigenvalue bound
/// where the operator has one ([`Operator::element_bound`], plus the law's term by Weyl's
/// inequality, [`super::stable_limit::law_term_bound`]) and the Gershgorin bound from the
/// operator's `|K| 1_I` ([`super::stable_limit::gershgorin_of`]). No assembled matrix is read.
pub fn stable_limit_of_operator(
    op: &dyn Operator,
    lumped: &[f64],
    law: Option<&dyn ExplicitLaw>,
) -> (f64, usize, Method) {
    let inv_sqrt = inv_sqrt(lumped);
    let (theta, lanczos_steps, converged) =
        super::stable_limit::lambda_max_lean(|x, y| stiffened(|x, y| op.apply(x, y), law, x, y), &inv_sqrt);
    if converged {
        return (limit_of(theta), lanczos_steps, Method::Lanczos);
    }
    let (rows, extra) = law.map_or((Vec::new(), 0.0), |l| l.gershgorin());
    let gershgorin = super::stable_limit::gershgorin_of(|x, y| op.apply_abs(x, y), &inv_sqrt, &rows, extra);
    let element = op.element_bound(lumped).map(|b| b + super::stable_limit::law_term_bound(&inv_sqrt, &rows, extra));
    match element {
        Some(e) if e <= gershgorin => (limit_of(e), lanczos_steps, Method::Element),
        _ => (limit_of(gershgorin), lanczos_steps, Method::Gershgorin),
    }
}

/// `M_L^{−½}` on I, 0 on the massless unknowns.
fn inv_sqrt(lumped: &[f64]) -> Vec<f64> {
    lumped.iter().map(|&m| if m > 0.0 { (1.0 / m).sqrt() } else { 0.0 }).collect()
}

/// `y = K x` plus the law's term B x.
fn stiffened(mul: impl Fn(&[f64], &mut [f64]), law: Option<&dyn ExplicitLaw>, x: &[f64], y: &mut [f64]) {
    mul(x, y);
    if let Some(law) = law {
        law.stiffen(x, y);
    }
}

/// `Δt_c = 2/√λ_max` (∞ for λ_max = 0).
fn limit_of(lam: f64) -> f64 {
    if lam > 0.0 { 2.0 / lam.sqrt() } else { f64::INFINITY }
}

impl<A: SymMatrix + Send> super::Scheme for CentralDifference<A> {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: &self.lambda }
    }

    fn pivots(&self) -> usize {
        self.pivots
    }

    fn energy(&self) -> Option<f64> {
        Some(Self::energy(self))
    }

    fn friction(&self) -> Option<&crate::contact::friction::FrictionRecord> {
        self.law.friction()
    }

    fn stable_limit(&self) -> Option<(f64, &'static str)> {
        Some((self.limit, self.method.name()))
    }

    fn note(&self) -> Option<String> {
        let product = match &self.stiffness {
            Stiffness::Free(op) if op.is_matrix_free() => format!("; K u matrix-free ({})", op.name()),
            _ => String::new(),
        };
        Some(format!(
            "central-difference: stable limit Δt_c = {} (2/√λ_max(M_L,II⁻¹ K_II{}), {}); time.dt = {}{product}",
            crate::numfmt::fmt_f64(self.limit),
            self.law.bound(),
            match self.method {
                Method::Lanczos =>
                    format!("Lanczos, {} steps, to ~{:e} relative", self.lanczos_steps, super::stable_limit::REL_TOL),
                Method::Element =>
                    format!("element eigenvalue bound: Lanczos unconverged after {} steps", self.lanczos_steps),
                Method::Gershgorin =>
                    format!("Gershgorin bound: Lanczos unconverged after {} steps", self.lanczos_steps),
            },
            crate::numfmt::fmt_f64(self.dt),
        ))
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let dt = self.dt;
        let (step, time) = (self.n + 1, (self.n + 1) as f64 * dt);
        for (old, &i) in self.massless_old.iter_mut().zip(&self.massless) {
            *old = self.u[i];
        }
        // v ← V^{n+½} = Vⁿ + ½ΔtAⁿ, U^{n+1} = Uⁿ + Δt V^{n+½} on I (a = 0 on C leaves v there).
        (&mut self.v[..], &mut self.u[..], &self.a[..], &self.inv_mass[..])
            .into_par_iter()
            .with_min_len(PAR_ROWS)
            .for_each(|(v, u, a, m)| {
                *v += 0.5 * dt * a;
                *u += dt * *v * (*m > 0.0) as u8 as f64;
            });
        if let Some(f) = &self.forcing {
            (f.0)(time, &mut self.load);
        }
        self.quasi_static(step, time)?;
        self.accelerations(1.0);
        (&mut self.v[..], &self.a[..]).into_par_iter().with_min_len(PAR_ROWS).for_each(|(v, a)| *v += 0.5 * dt * a);
        for (&old, &i) in self.massless_old.iter().zip(&self.massless) {
            self.v[i] = (self.u[i] - old) / dt;
        }
        self.n = step;
        check_finite(&self.u, &self.lambda, false, step, time)
    }
}
