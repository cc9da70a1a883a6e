//! A discretised problem of any geometry: its contact system, initial data and (if known) exact
//! solution, and the one place where a scene's scheme is built on it.
//!
//! A geometry ([`Geometry`]) is a mesh with its assembled [`ContactSystem`] and what reports
//! need of it (contact means, exact L² norms, nodal values). Each geometry implements it in its
//! own folder (`bar/geometry.rs` over a tridiagonal back-end, `plate/geometry.rs` and
//! `solid/geometry.rs` over a sparse one); this module names none of them. Schemes are generic
//! over the back-end and the contact law; what a geometry offers them ([`Geometry::one_node`],
//! [`Geometry::lumped_mass`]) was checked against what they need when the scene was validated
//! (`crate::scene`'s compatibility rule), so building a scheme refuses nothing again.

use crate::column::Column;
use crate::contact::Backend;
use crate::contact::law::ContactLaw;
use crate::exact::Exact;
use crate::schemes::{
    BackwardEuler, Beta, CentralDifference, Formulation, Gamma, Hybrid, MoreauJean, Newmark, NewmarkReduced,
    OneNodeContact, PaoliSchatzman, Scheme, SchemeError, SchemeSpec, StiffnessOperator,
};
use crate::system::ContactSystem;

/// Whether every scheme built from now on starts from perturbed initial data (see
/// [`set_roundoff_audit`]).
static ROUNDOFF_AUDIT: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// The round-off audit of `massredist reproduce --roundoff-audit` (hidden; issue 22: "no digit
/// that a 1e-13 perturbation changes"): from this call on, every scheme this process builds
/// ([`Problem::scheme_with`], the one place schemes are built) starts from `U⁰_i (1 + δ_i)` and
/// `V⁰_i (1 + δ_i) + δ_i·1e0` with `|δ_i| ≤ 1e-13`, a pattern none of the report's own perturbed
/// copies uses. A report computed so must print the same digits as the plain one, up to
/// rounding of a shared digit (`tests/roundoff_audit.rs`). Process-wide, set once by the binary
/// before anything runs; nothing in the library sets it.
pub fn set_roundoff_audit(on: bool) {
    ROUNDOFF_AUDIT.store(on, std::sync::atomic::Ordering::Relaxed);
}

fn roundoff_audit() -> bool {
    ROUNDOFF_AUDIT.load(std::sync::atomic::Ordering::Relaxed)
}

/// The audit's perturbation of (U⁰, V⁰): δ_i ∈ {−1, −½, 0, ½, 1}·1e-13 by a fixed pattern,
/// relative on both and absolute (unit velocity scale) on V⁰, whose entries are often 0.
fn audit_perturb(u: &mut [f64], v: &mut [f64]) {
    const SIZE: f64 = 1e-13;
    let delta = |i: usize| (((11 * i + 2) % 5) as f64 / 2.0 - 1.0) * SIZE;
    for (i, x) in u.iter_mut().enumerate() {
        *x *= 1.0 + delta(i);
    }
    for (i, x) in v.iter_mut().enumerate() {
        *x = *x * (1.0 + delta(i + 1)) + delta(i + 1);
    }
}

/// How the divergence watch gets `E_F = ½ F_rᵀ S_rr⁻¹ F_r` ([`crate::driver`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LoadEnergy {
    /// The driver factors `S_rr` of the system's whole stiffness (and takes the free-flight
    /// scale if that factor fails: a free body).
    Factor,
    /// `E_F` as the geometry computed it (a lean system's conjugate gradients).
    Known(f64),
    /// `S_rr` is singular (a lean body that keeps a rigid motion): the free-flight scale.
    FreeFlight,
}

/// What the driver and the observers need of a geometry (object safe).
pub trait GeometryView: std::fmt::Debug + Send + Sync {
    /// "bar", "plate" or "solid", for messages.
    fn name(&self) -> &'static str;
    /// Space dimension of the mesh (1 for a bar, 2 for a plate, 2 or 3 for a solid).
    fn dim(&self) -> usize;
    /// Whether its contact nodes have tangential directions (a solid's: it reports the friction
    /// keys of `summary.json`).
    fn has_tangential(&self) -> bool {
        false
    }
    /// The mesh size along x.
    fn h(&self) -> f64;
    /// The extent L along x (contact at x = 0, far end at x = L).
    fn length(&self) -> f64;
    /// `|Ω|/L`: 1 for a bar, the height H for a plate.
    fn section(&self) -> f64;
    /// `|Γ_C|`: 1 for a bar (a point), the length of the contact edge for a plate.
    fn contact_measure(&self) -> f64;
    /// The contact unknowns (λ order); the first is the reference node (x = 0, lowest y).
    fn contact(&self) -> &[usize];
    /// The mean of u over Γ_C, `∫_{Γ_C} u_h / |Γ_C|` (u_0 for a bar).
    fn contact_mean(&self, u: &[f64]) -> f64;
    /// The reported contact displacement `u0`: u at the reference contact node (bars, plates);
    /// solids report the plain mean over the contact-face nodes.
    fn u0(&self, u: &[f64]) -> f64 {
        u[self.contact()[0]]
    }
    /// `‖u_h − u(·, t)‖_{L²(Ω)}` against an x-only exact solution (NaN where the geometry
    /// cannot integrate it: [`GeometryView::integrates`]).
    fn l2_error(&self, u: &[f64], exact: &Exact, t: f64) -> f64;
    /// Whether [`GeometryView::l2_error`] can integrate this exact solution (bars and plates
    /// always; solids on structured tensor-product meshes).
    fn integrates(&self, _exact: &Exact) -> bool {
        true
    }
    /// `‖I_h u(·, t)‖_{L²(Ω)}`; `scratch` holds the interpolant (reused between calls).
    fn interp_norm(&self, exact: &Exact, t: f64, scratch: &mut Vec<f64>) -> f64;
    /// `max |u(x, y) − u(x, y_min)|` over the unknowns (0 for a bar).
    fn y_variation(&self, _u: &[f64]) -> f64 {
        0.0
    }
    /// Number of mesh nodes (Dirichlet nodes included).
    fn n_nodes(&self) -> usize;
    /// Values per node: 1 for scalar fields (bars, plates), d for a solid's displacement.
    fn components(&self) -> usize {
        1
    }
    /// Values at all mesh nodes (0 on the Dirichlet boundary) from values on the unknowns:
    /// `n_nodes() · components()` of them, interleaved `node · components() + component`.
    fn nodal_values(&self, u: &[f64], out: &mut [f64]);
    /// The series columns this geometry computes itself from a state, beyond what the driver
    /// computes for every geometry (at most `crate::observe::MAX_OWN_COLUMNS`); a column the
    /// driver computes too (`contact_force`) then takes the geometry's value. Empty by default.
    fn own_columns(&self) -> &[Column] {
        &[]
    }
    /// The values of [`GeometryView::own_columns`] at a state (u, v, λ), in that order.
    fn own_values(&self, _u: &[f64], _v: &[f64], _lambda: &[f64], _out: &mut [f64]) {}
    /// A fresh accumulator of the keys this geometry adds to `summary.json` from the values of
    /// its own columns over a run (None: it adds none).
    fn own_summary(&self) -> Option<Box<dyn OwnSummary>> {
        None
    }
}

/// The keys a geometry adds to `summary.json` ([`GeometryView::own_summary`]), accumulated
/// from the values of its own columns at each state shown.
pub trait OwnSummary: std::fmt::Debug + Send {
    /// Takes a state's time and values of the geometry's own columns
    /// ([`GeometryView::own_columns`] order).
    fn observe(&mut self, t: f64, values: &[f64]);
    /// The keys over the states taken (none if no state was taken).
    fn keys(&self) -> serde_json::Map<String, serde_json::Value>;
}

/// A geometry with its contact system over a linear-algebra back-end.
pub trait Geometry: GeometryView {
    type Matrix: Backend;
    fn system(&self) -> &ContactSystem<Self::Matrix>;

    /// The one-node tridiagonal contact system of a bar (Paoli–Schatzman and the reduced
    /// formulation need it); None for the other geometries.
    fn one_node(&self) -> Option<OneNodeContact<'_>> {
        None
    }

    /// The lumped mass `M_L` on the unknowns: the row sums of the weighted mass over all nodes,
    /// taken before the Dirichlet nodes are removed (explicit schemes, issue 20). None where the
    /// geometry does not provide it: the explicit schemes refuse such a geometry, naming it.
    fn lumped_mass(&self) -> Option<Vec<f64>> {
        None
    }

    /// Central differences' stiffness as an operator on the unknowns for `scheme.operator =
    /// choice` (issue 31), equal to [`ContactSystem::stiffness`] to round-off: a matrix-free
    /// one where the geometry has it and `choice` allows it, or the operator of a system
    /// whose own stiffness holds only the massless rows (a lean system, `crate::solid::lean`).
    /// None: the scheme multiplies the system's stiffness (and `matrix-free` is refused).
    fn stiffness_operator(&self, choice: StiffnessOperator) -> Option<Box<dyn crate::linalg::Operator>> {
        let _ = choice;
        None
    }

    /// The divergence watch's load scale where the geometry knows it (a lean system, whose
    /// stiffness matrix is not whole); [`LoadEnergy::Factor`]: the driver factors `S_rr`.
    fn load_energy(&self) -> LoadEnergy {
        LoadEnergy::Factor
    }

    /// The scene key of its force expressions (`bar.force`, `plate.force`, `solid.force`), for
    /// the run's messages (a force not finite at some time, [`crate::driver`]).
    fn force_key(&self) -> &'static str;

    /// [`Geometry::load_energy`] of another load `f` on the unknowns (a time-dependent load's
    /// largest sample, [`crate::driver`]): a lean system's conjugate gradients on `f` (not kept).
    fn load_energy_of(&self, f: &[f64]) -> LoadEnergy {
        let _ = f;
        LoadEnergy::Factor
    }

    /// The per-step diagnostics of a run on this geometry (energy, exact L² error, interpolant
    /// norm) with their workspaces, allocated once per run. The default evaluates
    /// [`ContactSystem::energy_at`], [`GeometryView::l2_error`] and
    /// [`GeometryView::interp_norm`]; a geometry with faster kernels (the bar's one-pass
    /// tridiagonal ones) returns its own, equal to round-off.
    fn diagnostics(&self) -> Box<dyn Diagnostics + '_> {
        Box::new(GeneralDiagnostics { geometry: self, load: Vec::new(), interp: Vec::new() })
    }
}

/// What a run computes of a state for its observers (see [`Geometry::diagnostics`]).
pub trait Diagnostics {
    /// The discrete energy `½VᵀMV + ½UᵀSU − UᵀF(t)`.
    fn energy(&mut self, u: &[f64], v: &[f64], t: f64) -> f64;
    /// `(‖u_h − u(·, t)‖_{L²(Ω)}, ‖I_h u(·, t)‖_{L²(Ω)})`.
    fn l2(&mut self, u: &[f64], exact: &Exact, t: f64) -> (f64, f64);
}

/// [`Diagnostics`] of any geometry from its [`ContactSystem`] and [`GeometryView`].
struct GeneralDiagnostics<'g, G: Geometry + ?Sized> {
    geometry: &'g G,
    /// F(t) of a time-dependent load.
    load: Vec<f64>,
    /// The exact solution at the nodes.
    interp: Vec<f64>,
}

impl<G: Geometry + ?Sized> Diagnostics for GeneralDiagnostics<'_, G> {
    fn energy(&mut self, u: &[f64], v: &[f64], t: f64) -> f64 {
        self.geometry.system().energy_at(u, v, t, &mut self.load)
    }

    fn l2(&mut self, u: &[f64], exact: &Exact, t: f64) -> (f64, f64) {
        (self.geometry.l2_error(u, exact, t), self.geometry.interp_norm(exact, t, &mut self.interp))
    }
}

/// A discretised problem: the geometry with its system, initial data and (if known) the exact
/// solution.
#[derive(Debug, Clone)]
pub struct Problem<G> {
    pub system: G,
    pub u0: Vec<f64>,
    pub v0: Vec<f64>,
    pub exact: Option<Exact>,
}

impl<G: Geometry> Problem<G> {
    /// Builds the scheme of a scene on this problem with exact contact (factors its matrices
    /// once).
    pub fn scheme(&self, spec: &SchemeSpec, dt: f64) -> Result<Box<dyn Scheme>, SchemeError> {
        self.scheme_with(spec, &ContactLaw::Exact, dt)
    }

    /// Builds the scheme of a scene on this problem with the contact law of its `[contact]`.
    pub fn scheme_with(&self, spec: &SchemeSpec, law: &ContactLaw, dt: f64) -> Result<Box<dyn Scheme>, SchemeError> {
        // The scheme's own copy of the initial state (perturbed under the round-off audit).
        let initial = || {
            let (mut u, mut v) = (self.u0.clone(), self.v0.clone());
            if roundoff_audit() {
                audit_perturb(&mut u, &mut v);
            }
            (u, v)
        };
        let s = self.system.system();
        let geometry = self.system.name();
        // What the scene's compatibility rule has checked; guards for callers of the library.
        debug_assert!(
            law.needs().treatments.contains(&spec.needs().contact),
            "{} with contact.method = {}",
            spec.name(),
            law.method()
        );
        let needs = |reason| SchemeError::Unsupported { key: "scheme.kind", geometry, reason };
        let one_node = || self.system.one_node().ok_or_else(|| needs("it needs a bar's one-node system"));
        Ok(match *spec {
            SchemeSpec::CrankNicolson { formulation: Formulation::Full } => {
                let (u, v) = initial();
                Box::new(Newmark::with_law(s, law, Beta::DEFAULT, Gamma::DEFAULT, dt, u, v)?)
            }
            SchemeSpec::Newmark { beta, gamma, formulation: Formulation::Full } => {
                let (u, v) = initial();
                Box::new(Newmark::with_law(s, law, beta, gamma, dt, u, v)?)
            }
            SchemeSpec::BackwardEuler => {
                let (u, v) = initial();
                Box::new(BackwardEuler::with_law(s, law, dt, u, v)?)
            }
            SchemeSpec::CentralDifference { operator } => {
                let lumped = self.system.lumped_mass().ok_or_else(|| needs("it needs a lumped mass"))?;
                let op = self.system.stiffness_operator(operator);
                if operator == StiffnessOperator::MatrixFree && op.is_none() {
                    return Err(SchemeError::Unsupported {
                        key: StiffnessOperator::KEY,
                        geometry,
                        reason: "it has no matrix-free stiffness",
                    });
                }
                // The state is copied once Δt_c is known (the set-up's peak at scale).
                Box::new(CentralDifference::with_operator(s, op, lumped, law, dt, initial)?)
            }
            SchemeSpec::Hybrid => {
                let (u, v) = initial();
                Box::new(Hybrid::with_law(s, law, dt, u, v)?)
            }
            SchemeSpec::MoreauJean { theta, restitution } => {
                let (u, v) = initial();
                Box::new(MoreauJean::new(s, theta, restitution, dt, u, v)?)
            }
            SchemeSpec::PaoliSchatzman { beta, restitution } => {
                let (u, v) = initial();
                Box::new(PaoliSchatzman::new(one_node()?, beta, restitution, dt, u, v)?)
            }
            SchemeSpec::CrankNicolson { formulation: Formulation::Reduced } => {
                let (u, v) = initial();
                Box::new(NewmarkReduced::new(one_node()?, Beta::DEFAULT, Gamma::DEFAULT, dt, u, v)?)
            }
            SchemeSpec::Newmark { beta, gamma, formulation: Formulation::Reduced } => {
                let (u, v) = initial();
                Box::new(NewmarkReduced::new(one_node()?, beta, gamma, dt, u, v)?)
            }
        })
    }

    /// The discrete energy `½VᵀMV + ½UᵀSU − UᵀF` of a state.
    pub fn energy(&self, u: &[f64], v: &[f64]) -> f64 {
        self.system.system().energy(u, v)
    }
}
