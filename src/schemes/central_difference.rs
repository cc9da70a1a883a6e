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
//!
//! **Stability**: `Δt ≤ Δt_c = 2/√λ_max(M_L,II⁻¹ K_II)` ([`super::stable_limit`]: Lanczos, its
//! accuracy stated there). The massless unknowns enter the interior rows through the quasi-static
//! map: with C free the effective stiffness is the Schur complement `K_II − K_IC K_CC⁻¹ K_CI`,
//! with C on the obstacle it is K_II; both are ≤ K_II, so K_II's λ_max bounds every contact
//! state. `Δt = Δt_c` is not stable (the highest mode grows linearly): `time.dt ≥ Δt_c (1 − REL_TOL)`
//! is refused naming Δt_c, the margin being the stated accuracy of Δt_c
//! ([`super::stable_limit::REL_TOL`] relative; [`super::stable_limit::refuses`]).
//!
//! **Penalty** (`[contact] method = "penalty"`): on a massive contact node the spring force of
//! the current displacement enters Aⁿ (force at t_n, `λ_c = κ min(0, u_cⁿ − lb_c)`); on massless
//! contact nodes the quasi-static rows carry the spring, solved exactly
//! ([`crate::contact::penalty::PenaltyQuasiStatic`]). The springs enter the stable limit through
//! the massive contact nodes only: Δt_c is computed for `K + κ Σ_{c massive} e_c e_cᵀ` (all
//! springs engaged: adding a positive semi-definite term can only raise λ_max, so this bounds every
//! contact state; on massless nodes the spring stiffens the quasi-static rows, whose condensed
//! stiffness stays ≤ K_II).
//!
//! **Parallel**: `K U` ([`SymMatrix::par_mul_into`]) and the element-wise force and update loops
//! run on rayon's threads ([`PAR_ROWS`] entries per task at least, so small systems stay on one
//! thread); every entry is computed as in the sequential loops, so the results do not depend on
//! the number of threads (bit for bit).
//!
//! **Energy**: `½ V·M_L V + ½ U·K U − F·U (+ Σ ½κ (d_c⁻)²)` ([`CentralDifference::energy`]); without contact and
//! with Δt < Δt_c it stays within O(Δt²) of its initial value (a shadow energy is conserved).

use super::{SchemeError, StateView, check_finite, check_range, contact_err};
use crate::contact::QuasiStatic;
use crate::contact::law::ContactLaw;
use crate::contact::penalty::PenaltyQuasiStatic;
use crate::linalg::SymMatrix;
use crate::linalg::sparse::PAR_ROWS;
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

    /// The stiffness the steps use: the compact row-run form where the back-end has one
    /// (sparse: bit-identical products, ~45% fewer bytes streamed in 3D), else a copy (borrowed)
    /// or the matrix itself (owned).
    fn stiffness(self) -> Stiffness<A> {
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
}

impl<A: SymMatrix> Stiffness<A> {
    fn par_mul_into(&self, x: &[f64], y: &mut [f64]) {
        match self {
            Stiffness::Plain(a) => a.par_mul_into(x, y),
            Stiffness::Runs(r) => r.par_mul_into(x, y),
        }
    }

    fn quad_form(&self, x: &[f64]) -> f64 {
        match self {
            Stiffness::Plain(a) => a.quad_form(x),
            Stiffness::Runs(r) => r.quad_form(x),
        }
    }
}

/// The quasi-static map of the massless unknowns under the contact law.
#[derive(Debug)]
enum Phi {
    Exact(QuasiStatic),
    Penalty(PenaltyQuasiStatic),
}

/// The quasi-static massless contact unknowns: Φ with its contact subset (slots into the
/// contact order) and bounds.
#[derive(Debug)]
struct Massless {
    phi: Phi,
    slots: Vec<usize>,
    lower: Vec<f64>,
    lambda: Vec<f64>,
}

#[derive(Debug)]
pub struct CentralDifference<A: SymMatrix> {
    dt: f64,
    stiffness: Stiffness<A>,
    load: Vec<f64>,
    forcing: Option<crate::system::Forcing>,
    lumped: Vec<f64>,
    /// `1/M_L,ii` on I, 0 on C.
    inv_mass: Vec<f64>,
    lower: Vec<f64>,
    contact: Vec<usize>,
    /// Massive contact nodes: (slot in contact order, unknown).
    kinematic: Vec<(usize, usize)>,
    /// The penalty κ (None: exact contact).
    kappa: Option<f64>,
    quasi: Option<Massless>,
    /// All massless unknowns and their value at the start of the step.
    massless: Vec<usize>,
    massless_old: Vec<f64>,
    limit: f64,
    lanczos_steps: usize,
    /// Whether Lanczos converged (false: Δt_c from the Gershgorin bound).
    converged: bool,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: Vec<f64>,
    ku: Vec<f64>,
    pivots: usize,
}

impl<A: SymMatrix> CentralDifference<A> {
    pub const NAME: &'static str = super::SchemeSpec::CentralDifference.name();

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
        Self::build(Source::Borrowed(system), lumped, law, dt, u0, v0)
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
        Self::build(Source::Owned(system), lumped, law, dt, u0, v0)
    }

    fn build(
        source: Source<'_, A>,
        lumped: Vec<f64>,
        law: &ContactLaw,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        let system = source.get();
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        let kappa = match *law {
            ContactLaw::Exact => None,
            ContactLaw::Penalty { penalty } => {
                check_range(Self::NAME, ContactLaw::PENALTY_KEY, penalty, penalty > 0.0, ContactLaw::PENALTY_RANGE)?;
                Some(penalty)
            }
            ContactLaw::Nitsche { .. } => {
                let reason = "Nitsche contact is not built for central differences";
                return Err(SchemeError::Unsupported { key: "contact.method", geometry: "central-difference", reason });
            }
        };
        let n = system.n();
        let inv_mass: Vec<f64> = lumped.iter().map(|&m| if m > 0.0 { 1.0 / m } else { 0.0 }).collect();
        let (limit, lanczos_steps, converged) = stable_limit_of(system, &lumped, kappa);
        let springs = system.contact.iter().filter(|&&c| lumped[c] > 0.0).count();
        // dt = Δt_c is not stable, and Δt_c is known to REL_TOL: refused from Δt_c (1 − REL_TOL)
        // down (a free–free uniform chain has Δt_c = h/c exactly: Courant 1 is refused there).
        if super::stable_limit::refuses(dt, limit) {
            let spring = if kappa.is_some() && springs > 0 { " + κ E_Cᵀ E_C" } else { "" };
            return Err(SchemeError::AboveStableLimit { scheme: Self::NAME, dt, limit, spring });
        }
        let massless: Vec<usize> = (0..n).filter(|&i| lumped[i] <= 0.0).collect();
        let kinematic: Vec<(usize, usize)> =
            system.contact.iter().enumerate().filter(|&(_, &c)| lumped[c] > 0.0).map(|(s, &c)| (s, c)).collect();
        let quasi = if massless.is_empty() { None } else { Some(massless_map(system, &lumped, &massless, kappa)?) };
        let (load, forcing, lower, contact) =
            (system.load.clone(), system.forcing.clone(), system.lower.clone(), system.contact.clone());
        let lambda = vec![0.0; contact.len()];
        let mut s = Self {
            dt,
            stiffness: source.stiffness(),
            load,
            forcing,
            lumped,
            inv_mass,
            lower,
            contact,
            kinematic,
            kappa,
            quasi,
            massless_old: vec![0.0; massless.len()],
            massless,
            limit,
            lanczos_steps,
            converged,
            n: 0,
            u: u0,
            a: vec![0.0; n],
            v: v0,
            lambda,
            ku: vec![0.0; n],
            pivots: 0,
        };
        s.quasi_static(0, 0.0)?;
        s.accelerations(0.0, 0.5);
        Ok(s)
    }

    /// The stable limit Δt_c and the Lanczos steps that computed it.
    pub fn stable_limit(&self) -> (f64, usize) {
        (self.limit, self.lanczos_steps)
    }

    /// `½ V·M_L V + ½ U·K U − F(t_n)·U` of the current state, `+ Σ ½κ (d_c⁻)²` with the
    /// penalty.
    pub fn energy(&self) -> f64 {
        let kinetic: f64 = self.v.iter().zip(&self.lumped).map(|(v, m)| m * v * v).sum();
        let work: f64 = self.u.iter().zip(&self.load).map(|(u, f)| u * f).sum();
        let spring = self.kappa.map_or(0.0, |penalty| {
            ContactLaw::Penalty { penalty }.energy(self.contact.iter().map(|&c| self.u[c]), &self.lower)
        });
        0.5 * kinetic + 0.5 * self.stiffness.quad_form(&self.u) - work + spring
    }

    /// The massless unknowns from the quasi-static rows at t (F(t) already in `load`).
    fn quasi_static(&mut self, step: usize, time: f64) -> Result<(), SchemeError> {
        if let Some(q) = &mut self.quasi {
            let err = contact_err(step, time);
            self.pivots = match &mut q.phi {
                Phi::Exact(phi) => {
                    if self.forcing.is_some() {
                        phi.set_load(&self.load);
                    }
                    phi.apply(&mut self.u, &q.lower, &mut q.lambda).map_err(err)?
                }
                Phi::Penalty(phi) => {
                    if self.forcing.is_some() {
                        phi.set_load(&self.load);
                    }
                    phi.apply(&mut self.u, &q.lower, &mut q.lambda).map_err(err)?
                }
            };
            for (&s, &l) in q.slots.iter().zip(&q.lambda) {
                self.lambda[s] = l;
            }
        }
        Ok(())
    }

    /// `A = M_L⁻¹ (F − K U − λ)` on I, with the forward-increment multipliers of the massive
    /// contact nodes (module docs; `kappa` = 1 in a step, ½ at n = 0; `v` holds the half-step
    /// velocity in a step, V⁰ at n = 0).
    fn accelerations(&mut self, _time: f64, kappa: f64) {
        self.stiffness.par_mul_into(&self.u, &mut self.ku);
        (&mut self.a[..], &self.inv_mass[..], &self.load[..], &self.ku[..])
            .into_par_iter()
            .with_min_len(PAR_ROWS)
            .for_each(|(a, m, f, ku)| *a = m * (f - ku));
        let dt2 = kappa * self.dt * self.dt;
        for &(s, c) in &self.kinematic {
            let l = match self.kappa {
                // Penalty: the spring at the current displacement (force at t_n).
                Some(k) => k * (self.u[c] - self.lower[s]).min(0.0),
                None => {
                    let predicted = self.u[c] + self.dt * self.v[c] + dt2 * self.a[c];
                    ((predicted - self.lower[s]) * self.lumped[c] / dt2).min(0.0)
                }
            };
            self.lambda[s] = l;
            self.a[c] -= l * self.inv_mass[c];
        }
    }
}

/// `(Δt_c, Lanczos steps, converged)` of central differences on `system` with the lumped mass
/// `lumped` and the penalty κ (None: exact contact), module docs: Lanczos on
/// `M_L,II^{−½} (K + κ Σ_{c massive} e_c e_cᵀ) M_L,II^{−½}`, or the Gershgorin bound if it did
/// not converge.
pub fn stable_limit_of<A: SymMatrix>(
    system: &ContactSystem<A>,
    lumped: &[f64],
    kappa: Option<f64>,
) -> (f64, usize, bool) {
    let inv_sqrt: Vec<f64> = lumped.iter().map(|&m| if m > 0.0 { (1.0 / m).sqrt() } else { 0.0 }).collect();
    // With the penalty, the springs of the massive contact nodes all engaged: K + κ Σ e_c e_cᵀ
    // bounds K's λ_max in every contact state (module docs).
    let springs: Vec<usize> = system.contact.iter().copied().filter(|&c| lumped[c] > 0.0).collect();
    let k_spring = kappa.unwrap_or(0.0);
    let (theta, lanczos_steps, converged) = super::stable_limit::lambda_max_of(
        |x, y| {
            system.stiffness.par_mul_into(x, y);
            springs.iter().for_each(|&c| y[c] += k_spring * x[c]);
        },
        &inv_sqrt,
    );
    // Unconverged Lanczos: the Gershgorin upper bound instead (conservative; stable_limit docs).
    let lam = if converged {
        theta
    } else {
        super::stable_limit::gershgorin(&system.stiffness, &inv_sqrt, &springs, k_spring)
    };
    (if lam > 0.0 { 2.0 / lam.sqrt() } else { f64::INFINITY }, lanczos_steps, converged)
}

/// The quasi-static map of the massless unknowns `massless` under the law (κ: penalty).
fn massless_map<A: SymMatrix>(
    system: &ContactSystem<A>,
    lumped: &[f64],
    massless: &[usize],
    kappa: Option<f64>,
) -> Result<Massless, SchemeError> {
    let mut is_contact = vec![false; system.n()];
    system.contact.iter().for_each(|&c| is_contact[c] = true);
    let slots: Vec<usize> = (0..system.contact.len()).filter(|&s| lumped[system.contact[s]] <= 0.0).collect();
    let qc: Vec<usize> = slots.iter().map(|&s| system.contact[s]).collect();
    let free: Vec<usize> = massless.iter().copied().filter(|&i| !is_contact[i]).collect();
    let phi = match kappa {
        None => Phi::Exact(QuasiStatic::with_free(&system.stiffness, &system.load, &qc, &free)?),
        Some(_) if !free.is_empty() => {
            let reason = "penalty contact with free massless unknowns (a contact layer) is not built";
            return Err(SchemeError::Unsupported { key: "contact.method", geometry: "central-difference", reason });
        }
        Some(k) => Phi::Penalty(PenaltyQuasiStatic::new(&system.stiffness, &system.load, &qc, k).map_err(|pivot| {
            crate::linalg::LinalgError::Unsupported {
                matrix: "stiffness",
                detail: format!("its contact block is not positive definite (pivot {pivot})"),
            }
        })?),
    };
    let lower = slots.iter().map(|&s| system.lower[s]).collect();
    Ok(Massless { phi, lambda: vec![0.0; slots.len()], slots, lower })
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

    fn note(&self) -> Option<String> {
        Some(format!(
            "central-difference: stable limit Δt_c = {} (2/√λ_max(M_L,II⁻¹ K_II{}), {}); time.dt = {}",
            crate::numfmt::fmt_f64(self.limit),
            if self.kappa.is_some() && !self.kinematic.is_empty() { " + κ E_Cᵀ E_C" } else { "" },
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
        self.accelerations(time, 1.0);
        (&mut self.v[..], &self.a[..]).into_par_iter().with_min_len(PAR_ROWS).for_each(|(v, a)| *v += 0.5 * dt * a);
        for (&old, &i) in self.massless_old.iter().zip(&self.massless) {
            self.v[i] = (self.u[i] - old) / dt;
        }
        self.n = step;
        check_finite(&self.u, &self.lambda, false, step, time)
    }
}
