//! Time schemes for `M Ü + S U = F − Σ_c λ_c e_c`, `0 ≤ u_c − lb_c ⊥ λ_c ≤ 0` (paper §4.2 and
//! §5), written once for every geometry: generic over the linear-algebra back-end
//! ([`crate::linalg::SymMatrix`]: tridiagonal for bars, sparse for plates and solids) and its exact contact
//! solver ([`crate::contact::Backend`], [`crate::contact::ContactSolver`]).
//!
//! One file per scheme of the paper. Each scheme factors its iteration matrix once in `new`,
//! allocates its work vectors once, and then `step` advances one Δt without allocating.
//! Conventions shared by all (so that results compare with other codes):
//! - U⁰, V⁰ are the nodal interpolants at all free nodes, the contact nodes included; λ⁰ = 0;
//! - A⁰ solves the equation of motion `M A⁰ = F − S U⁰` on the unknowns with mass and is 0 on
//!   massless ones ([`ContactSystem::initial_acceleration`]);
//! - a massless unknown's velocity and acceleration enter no equation (its row and column of M
//!   vanish); the schemes report `v = (u^{n+1} − uⁿ)/Δt` and keep `a = 0`.
//!
//! On a bar's one-node system only ([`OneNodeContact`]; what each scheme needs is declared by
//! [`SchemeSpec::needs`]): [`PaoliSchatzman`] (its projection of S on (ker M)^⊥ and its one-node
//! impact law) and [`NewmarkReduced`] (the reduced unknowns 1..m−1 with `u_0 = u_1⁺`).
//!
//! The contact law is a seam ([`crate::contact::StepLaw`] for the implicit step,
//! [`crate::contact::ExplicitLaw`] for central differences): Newmark/Crank–Nicolson, backward
//! Euler and central differences are written once for every law.

pub mod backward_euler;
pub mod central_difference;
pub mod hybrid;
pub mod moreau_jean;
pub mod newmark;
pub mod newmark_reduced;
pub mod paoli_schatzman;
mod spec;
pub mod stable_limit;

use crate::contact::lcp::LcpError;
use crate::linalg::LinalgError;
use crate::linalg::tridiag::FactorError;
use thiserror::Error;

pub use crate::system::ContactSystem;

/// What Paoli–Schatzman and the reduced Newmark formulation need of a bar: its tridiagonal
/// contact system, whose one contact unknown is u_0, its mesh size h and the weight w_0 of its
/// contact element (for messages). The bar offers it (`crate::problem::Geometry::one_node`);
/// the scenes' compatibility rule refuses these schemes elsewhere ([`SchemeSpec::needs`]).
#[derive(Debug, Clone, Copy)]
pub struct OneNodeContact<'a> {
    pub system: &'a ContactSystem<crate::linalg::tridiag::SymTridiag>,
    pub h: f64,
    pub w0: f64,
}

impl OneNodeContact<'_> {
    /// The gap between u_0 and the obstacle, `−lb_0`.
    pub fn gap(&self) -> f64 {
        -self.system.lower[0]
    }
}
pub use backward_euler::BackwardEuler;
pub use central_difference::CentralDifference;
pub use hybrid::Hybrid;
pub use moreau_jean::MoreauJean;
pub use newmark::Newmark;
pub use newmark_reduced::NewmarkReduced;
pub use paoli_schatzman::PaoliSchatzman;
pub use spec::{
    Beta, Formulation, Gamma, ImpactRestitution, ParamError, Restitution, SchemeNeeds, SchemeSpec, StiffnessOperator,
    Theta,
};

/// The discrete state at `t_n = n Δt`, borrowed from the scheme (no copy).
#[derive(Debug, Clone, Copy)]
pub struct StateView<'a> {
    pub n: usize,
    pub t: f64,
    /// Displacements on the free unknowns.
    pub u: &'a [f64],
    /// Velocities on the free unknowns.
    pub v: &'a [f64],
    /// Contact multipliers λ_c ≤ 0, one per contact unknown (in `ContactSystem::contact`
    /// order): nodal contact forces (in 1D the contact force λ of paper eq. (3.1)).
    pub lambda: &'a [f64],
}

/// A one-step time integrator of the contact problem.
pub trait Scheme: Send {
    fn state(&self) -> StateView<'_>;
    fn step(&mut self) -> Result<(), SchemeError>;
    /// Principal pivots used by the contact solves of the last step (0 for closed forms).
    fn pivots(&self) -> usize {
        0
    }
    /// The scheme's own energy of its state, where it is not the system's `½VᵀMV + ½UᵀSU − UᵀF`
    /// (central differences: the lumped mass; the penalty law: its spring energy). None: the
    /// system's, which the run computes.
    fn energy(&self) -> Option<f64> {
        None
    }
    /// What `check` says of the scheme beyond the resolved scene (central differences: the
    /// stable limit), one line, or None.
    fn note(&self) -> Option<String> {
        None
    }
    /// What friction did so far (None for a frictionless law or a scheme without one).
    fn friction(&self) -> Option<&crate::contact::friction::FrictionRecord> {
        None
    }
    /// An explicit scheme's stable limit Δt_c and its estimator (`"lanczos"`, `"element"` or
    /// `"gershgorin"`; [`stable_limit::Method`]); None for implicit schemes. The summary prints
    /// both (`stable_step`, `stable_step_method`).
    fn stable_limit(&self) -> Option<(f64, &'static str)> {
        None
    }
}

#[derive(Debug, Clone, PartialEq, Error)]
pub enum SchemeError {
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// The system lacks what the contact law needs (a caller of the library past the scenes'
    /// compatibility rule).
    #[error("contact.method: {0}")]
    Law(&'static str),
    #[error("{scheme}: {key} = {value} is outside the allowed range {range}")]
    Parameter { scheme: &'static str, key: &'static str, value: f64, range: &'static str },
    #[error(
        "{scheme} needs massless contact nodes (mass.kind = mod1, mod2, mod3 or custom weights with zero weight on the cells touching the contact boundary), got a contact mass {w0}"
    )]
    NeedsMasslessContact { scheme: &'static str, w0: f64 },
    #[error("the solution is not finite at step {step} (t = {time}): the scheme is unstable for this Δt / mass")]
    NonFinite { step: usize, time: f64 },
    #[error("{key} is not available for {geometry} scenes: {reason}")]
    Unsupported { key: &'static str, geometry: &'static str, reason: &'static str },
    #[error("step {step} (t = {time}): {source}")]
    Contact { step: usize, time: f64, source: LcpError },
    #[error("{}", stable_limit::above(scheme, *dt, *limit, spring))]
    AboveStableLimit { scheme: &'static str, dt: f64, limit: f64, spring: &'static str },
    #[error("{key}: {scheme} needs {what}, got {value} ({reason})")]
    Needs { scheme: &'static str, key: &'static str, what: &'static str, value: f64, reason: &'static str },
}

/// A law that cannot be built: its factor, its contact solve and its parameters keep the
/// variants (and messages) of the schemes' own.
impl From<crate::contact::law::SetupError> for SchemeError {
    fn from(e: crate::contact::law::SetupError) -> Self {
        use crate::contact::law::SetupError as E;
        match e {
            E::Linalg(e) => SchemeError::Linalg(e),
            E::Contact(source) => SchemeError::Contact { step: 0, time: 0.0, source },
            E::Parameter { key, value, range } => SchemeError::Parameter { scheme: "contact law", key, value, range },
            E::Shape(reason) => SchemeError::Law(reason),
        }
    }
}

pub(crate) fn factor_err(matrix: &'static str) -> impl Fn(FactorError) -> SchemeError {
    move |source| SchemeError::Linalg(LinalgError::Factor { matrix, source })
}

pub(crate) fn contact_err(step: usize, time: f64) -> impl Fn(LcpError) -> SchemeError {
    move |source| SchemeError::Contact { step, time, source }
}

/// Checks `lo < value ≤ hi` style ranges; `range` is the text shown to the user.
pub(crate) fn check_range(
    scheme: &'static str,
    key: &'static str,
    value: f64,
    ok: bool,
    range: &'static str,
) -> Result<(), SchemeError> {
    if ok && value.is_finite() { Ok(()) } else { Err(SchemeError::Parameter { scheme, key, value, range }) }
}

/// Per-step finiteness check. After a tridiagonal solve a NaN or ∞ anywhere reaches both ends
/// of the chain, so the first and last unknowns and λ suffice there (`spreads`); a sparse solve
/// need not spread it to every entry, so all are checked.
pub(crate) fn check_finite(
    u: &[f64],
    lambda: &[f64],
    spreads: bool,
    step: usize,
    time: f64,
) -> Result<(), SchemeError> {
    let ok = if spreads {
        u[0].is_finite() && u[u.len() - 1].is_finite() && lambda.iter().all(|l| l.is_finite())
    } else {
        u.iter().chain(lambda).all(|x| x.is_finite())
    };
    if ok { Ok(()) } else { Err(SchemeError::NonFinite { step, time }) }
}
