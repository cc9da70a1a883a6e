//! Exact solvers of the Signorini conditions inside one implicit step.
//!
//! Every scheme of [`crate::schemes`] solves, once or twice per step,
//!
//! ```text
//! K U = r − σ Σ_c λ_c e_c,     0 ≤ u_c − lb_c ⊥ λ_c ≤ 0   for every contact unknown c,
//! ```
//!
//! with K symmetric positive definite (factored once), σ > 0 the scheme's force scale and lb the
//! lower bounds (the obstacle `−gap`, or a scheme's own bound). One trait, [`ContactSolver`], two
//! implementations: [`OneNode`] (a bar: one contact node, the closed form of paper eq. (3.2))
//! and [`Schur`] (plates and solids: many nodes, an LCP on the contact Schur complement solved
//! exactly by [`lcp::Lcp`]). [`QuasiStatic`] solves the quasi-static contact rows of massless
//! contact nodes (the hybrid scheme's `u_0 = u_1⁺` in 1D).
//!
//! **Contact laws.** A law is how the contact force enters a scheme; each is one file behind
//! two traits, and the schemes that take a law (Newmark/Crank–Nicolson, backward Euler, central
//! differences) are written once for all of them:
//! - [`StepLaw`]: one implicit step `K U = r − σ Σ_c λ_c(U) e_c` solved exactly, with the law's
//!   own force and energy;
//! - [`ExplicitLaw`]: central differences' treatment (the force of the current state on massive
//!   contact nodes, the quasi-static rows of massless ones, the term the law adds to the stable
//!   limit).
//!
//! The laws: [`exact`] (the Signorini condition, solved by the back-end's [`ContactSolver`]),
//! [`friction`] (the same with Tresca or Coulomb friction on a solid's tangential unknowns,
//! `crate::system::Tangential`; so far [`StepLaw`] only), [`penalty`] and [`nitsche`];
//! [`law::ContactLaw`] (the scene's `[contact]`) builds them and declares what each needs.

pub mod exact;
pub mod friction;
pub mod law;
pub mod layer;
pub mod lcp;
pub mod nitsche;
pub mod penalty;
pub mod schur;

use crate::linalg::tridiag::{SymTridiag, TwistedFactor};
use crate::linalg::{LinalgError, SymMatrix};
use lcp::{Lcp, LcpError};
pub use schur::Schur;
use std::fmt::Debug;
use thiserror::Error;

/// A matrix back-end with its exact contact solver: what the schemes need to factor an iteration
/// matrix `K` once and solve each step's contact problem with it.
pub trait Backend: SymMatrix {
    /// The exact solver of one implicit step with contact for `K = self`.
    type Solver: ContactSolver + 'static;

    /// Factors `self` once and prepares the contact solves on the unknowns `contact`.
    fn contact_solver(&self, contact: &[usize], matrix: &'static str) -> Result<Self::Solver, LinalgError>;

    /// The frictional step on `self` ([`friction::FrictionStep`]; `midpoint`: the hybrid
    /// scheme's, [`friction::FrictionStep::midpoint`]): a back-end without tangential
    /// directions (a bar's) has none.
    fn friction_step(
        &self,
        _contact: &[usize],
        _tangential: &friction::Tangential,
        _friction: friction::Friction,
        _matrix: &'static str,
        _sigma_dt_midpoint: (f64, f64, bool),
    ) -> Result<Box<dyn StepLaw>, SetupError> {
        Err(SetupError::Shape("friction needs tangential directions (a solid)"))
    }
}

/// Bars: one contact node, closed form.
impl Backend for SymTridiag {
    type Solver = OneNode;

    fn contact_solver(&self, contact: &[usize], matrix: &'static str) -> Result<OneNode, LinalgError> {
        OneNode::new(self, contact, matrix)
    }
}

/// Plates and solids: many contact nodes, the exact LCP on the Schur complement.
impl Backend for crate::linalg::sparse::SpMat {
    type Solver = Schur;

    fn contact_solver(&self, contact: &[usize], matrix: &'static str) -> Result<Schur, LinalgError> {
        Ok(Schur::new(self, contact, matrix)?)
    }

    fn friction_step(
        &self,
        contact: &[usize],
        tangential: &friction::Tangential,
        friction: friction::Friction,
        matrix: &'static str,
        (sigma, dt, midpoint): (f64, f64, bool),
    ) -> Result<Box<dyn StepLaw>, SetupError> {
        let step = friction::FrictionStep::new(self, contact, tangential, friction, matrix, sigma, dt)?;
        Ok(Box::new(if midpoint { step.midpoint() } else { step }))
    }
}

/// The exact contact solve of one implicit step (module docs).
pub trait ContactSolver: Debug + Send {
    /// Solves `K U = r − σ Σ λ_c e_c`, `lb ≤ u_C ⊥ λ ≤ 0` in place (`rhs` = r on entry, U on
    /// exit) and writes λ (one entry per contact unknown). On active nodes `u_c = lb_c` is set
    /// exactly, so complementarity holds bit for bit. Returns the principal pivots used.
    fn solve(&mut self, rhs: &mut [f64], lower: &[f64], sigma: f64, lambda: &mut [f64]) -> Result<usize, LcpError>;
}

/// Why a law cannot be built on a system (a caller of the library past the scenes'
/// compatibility rule, or a matrix that cannot be factored).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SetupError {
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    #[error(transparent)]
    Contact(#[from] LcpError),
    /// A parameter outside the range this system allows (Nitsche's γ₀ with θ = 0, −1).
    #[error("{key} = {value}: allowed range is {range}", value = crate::numfmt::fmt_f64(*value))]
    Parameter { key: &'static str, value: f64, range: &'static str },
    /// The system does not have what the law needs.
    #[error("{0}")]
    Shape(&'static str),
}

/// One implicit step with a contact law (module docs), built once per scheme for its K and σ:
/// the seam every implicit scheme is generic over.
pub trait StepLaw: Debug + Send {
    /// Solves `K U = r − σ Σ_c λ_c e_c` with the law's λ(U) in place (`rhs` = r on entry, U on
    /// exit) and writes λ (one entry per contact unknown). Returns the principal pivots used.
    fn solve(&mut self, rhs: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError>;
    /// Whether the law has a force of the state (penalty, Nitsche: in A⁰ and the energy); the
    /// exact law's is a multiplier of the step only.
    fn has_force(&self) -> bool {
        false
    }
    /// Adds `scale ·` the law's contact force at U (the force vector in `M Ü + K U + N(U) = F`)
    /// to `out`.
    fn add_force(&self, _u: &[f64], _lower: &[f64], _scale: f64, _out: &mut [f64]) {}
    /// λ of the state U (the data at t = 0); the exact law leaves 0.
    fn lambda_of(&self, _u: &[f64], _lower: &[f64], _lambda: &mut [f64]) {}
    /// The law's energy at U (penalty springs, Nitsche's θΦ); None for the exact law.
    fn energy(&self, _u: &[f64], _lower: &[f64]) -> Option<f64> {
        None
    }
    /// Takes the initial state U⁰ (the frictional law keeps `u_t⁰`, the first step's
    /// tangential targets); nothing for the other laws.
    fn start(&mut self, _u0: &[f64]) {}
    /// What friction did so far (None for a frictionless law).
    fn friction(&self) -> Option<&friction::FrictionRecord> {
        None
    }
    /// How Newmark forms `A^{n+1} = (U^{n+1} − Ũ)/σ`: as a product with 1/σ (true: the exact
    /// law's scheme as first written) or as a division (the other laws, written later). Both
    /// are kept so every number stays bit-identical (they differ by one rounding).
    fn reciprocal_sigma(&self) -> bool {
        false
    }
}

/// What central differences hand a law at the massive contact nodes after `A = M_L⁻¹(F − KU)`
/// (docs of `crate::schemes::central_difference`).
pub struct Massive<'a> {
    pub u: &'a [f64],
    pub v: &'a [f64],
    pub a: &'a mut [f64],
    pub lumped: &'a [f64],
    pub inv_mass: &'a [f64],
    pub dt: f64,
    /// 1 in a step, ½ at n = 0 (the forward increment's coefficient).
    pub kappa: f64,
    pub lambda: &'a mut [f64],
}

/// A contact law in explicit central differences (module docs), built once for the system and
/// its lumped mass M_L (the massless unknowns are those with `M_L,ii = 0`).
pub trait ExplicitLaw: Debug + Send {
    /// `y += B x` with B the term the law adds to K in the stable-limit bound (0 by default).
    fn stiffen(&self, _x: &[f64], _y: &mut [f64]) {}
    /// The rows of B and a bound of their absolute row sums: every row i of B not listed is
    /// zero, and `Σ_j |B_ij| ≤ extra` for every listed one. Both the Gershgorin bound of K + B and
    /// the element bound plus B's term ([`crate::schemes::stable_limit::law_term_bound`]: Weyl's
    /// inequality with `λ_max(D B D) ≤ max_i d_i² extra`) rest on exactly this, so a law must
    /// bound |B|'s row sums here, not those of a difference with K.
    fn gershgorin(&self) -> (Vec<usize>, f64) {
        (Vec::new(), 0.0)
    }
    /// B as messages write it (` + κ E_Cᵀ E_C`), "" without one.
    fn bound(&self) -> &'static str {
        ""
    }
    /// Whether [`ExplicitLaw::add_residual`] adds anything.
    fn has_residual(&self) -> bool {
        false
    }
    /// Adds the law's force at U to the residual `F − K U` before `M_L⁻¹` (Nitsche: −N(U)).
    fn add_residual(&self, _u: &[f64], _r: &mut [f64]) {}
    /// The contact forces of the massive contact nodes after `A = M_L⁻¹(F − KU)`: writes their λ
    /// and corrects their A.
    fn massive(&mut self, _s: Massive<'_>) {}
    /// The quasi-static massless unknowns at the current time (`load` = F(t), `forced`: F depends
    /// on t); writes their λ. Returns the pivots.
    fn quasi_static(
        &mut self,
        u: &mut [f64],
        load: &[f64],
        forced: bool,
        lambda: &mut [f64],
    ) -> Result<usize, LcpError>;
    /// The law's energy at U (0 for the exact law).
    fn energy(&self, _u: &[f64]) -> f64 {
        0.0
    }
    /// What friction did so far (None for a frictionless law).
    fn friction(&self) -> Option<&friction::FrictionRecord> {
        None
    }
}

/// The one-node Signorini solve in closed form.
///
/// With the unconstrained `u* = K⁻¹ r` and the precomputed `z = K⁻¹ e_c` (z_c > 0 since K is
/// SPD): λ = 0 if `u*_c ≥ lb`, else `λ = (u*_c − lb)/(σ z_c) < 0`, and the constrained solution
/// is `u* − σ λ z` with `u_c = lb` set exactly.
#[inline]
pub fn contact_multiplier(u_star: f64, lower: f64, sigma: f64, z: f64) -> f64 {
    if u_star >= lower { 0.0 } else { (u_star - lower) / (sigma * z) }
}

/// One contact node on a tridiagonal matrix: the two-sided solve ([`TwistedFactor`]) and
/// [`contact_multiplier`].
#[derive(Debug, Clone)]
pub struct OneNode {
    factor: TwistedFactor,
    node: usize,
    /// z = K⁻¹ e_node, the response to a unit contact force.
    response: Vec<f64>,
}

impl OneNode {
    pub fn new(k: &SymTridiag, contact: &[usize], matrix: &'static str) -> Result<Self, LinalgError> {
        let &[node] = contact else {
            let detail = format!("a bar has one contact node, got {}", contact.len());
            return Err(LinalgError::Unsupported { matrix, detail });
        };
        let factor = k.factor_twisted().map_err(|source| LinalgError::Factor { matrix, source })?;
        let response = factor.unit_response(node);
        Ok(Self { factor, node, response })
    }
}

impl ContactSolver for OneNode {
    fn solve(&mut self, rhs: &mut [f64], lower: &[f64], sigma: f64, lambda: &mut [f64]) -> Result<usize, LcpError> {
        self.factor.solve_in_place(rhs);
        let c = self.node;
        let l = contact_multiplier(rhs[c], lower[0], sigma, self.response[c]);
        lambda[0] = l;
        if l != 0.0 {
            let s = sigma * l;
            for (u, z) in rhs.iter_mut().zip(&self.response) {
                *u -= s * z;
            }
            rhs[c] = lower[0];
        }
        Ok(0)
    }
}

/// The quasi-static map Φ of the massless unknowns: for the other values U, the contact values
/// u (with Signorini rows) and the free massless values u_F (no condition: the tangential
/// components of a solid's contact-face nodes), and the multipliers λ, with
///
/// ```text
/// S_CC u + S_CF u_F + S_CI U − F_C = −λ,     0 ≤ u − lb ⊥ λ ≤ 0,
/// S_FC u + S_FF u_F + S_FI U − F_F = 0.
/// ```
///
/// Eliminating u_F (S_FF SPD, a principal block of the SPD stiffness) leaves an LCP in
/// `y = u − lb` with the SPD Schur complement `D = S_CC − S_CF S_FF⁻¹ S_FC`:
/// `w = (q_C − S_CF S_FF⁻¹ q_F + D lb) + D y`, `q = S_·I U − F_·`; then
/// `u_F = −S_FF⁻¹ (q_F + S_FC u)`. Without free massless unknowns (bars, plates) `D = S_CC`
/// and the map is the one of the contact rows alone; in 1D (`S_00 = 1/h`, `S_01 = −1/h`,
/// lb = −gap) it is `u_0 = max(u_1, −gap)`.
#[derive(Debug, Clone)]
pub struct QuasiStatic {
    contact: Vec<usize>,
    /// `(c, j, S_{contact[c], j})` for j neither a contact nor a free massless unknown.
    coupling: Vec<(usize, usize, f64)>,
    load: Vec<f64>,
    lcp: Lcp,
    q: Vec<f64>,
    free: FreeBlock,
}

/// The free massless unknowns F of [`QuasiStatic`]: their couplings, the dense Cholesky factor
/// of S_FF and `G = S_FF⁻¹ S_FC` (empty for bars and plates).
#[derive(Debug, Clone, Default)]
struct FreeBlock {
    idx: Vec<usize>,
    /// `(f, j, S_{idx[f], j})` for j outside C ∪ F.
    coupling: Vec<(usize, usize, f64)>,
    load: Vec<f64>,
    /// Lower Cholesky factor of S_FF, row-major nf × nf.
    chol: Vec<f64>,
    /// S_FC, row-major nf × nc, and G = S_FF⁻¹ S_FC.
    s_fc: Vec<f64>,
    g: Vec<f64>,
    q: Vec<f64>,
}

impl FreeBlock {
    /// Overwrites b with S_FF⁻¹ b (two triangular solves with the stored factor).
    fn solve(&self, b: &mut [f64]) {
        let (n, l) = (self.idx.len(), &self.chol);
        for i in 0..n {
            let s: f64 = (0..i).map(|k| l[i * n + k] * b[k]).sum();
            b[i] = (b[i] - s) / l[i * n + i];
        }
        for i in (0..n).rev() {
            let s: f64 = (i + 1..n).map(|k| l[k * n + i] * b[k]).sum();
            b[i] = (b[i] - s) / l[i * n + i];
        }
    }
}

/// Dense lower Cholesky factor of the SPD row-major n × n matrix `a`, in place; Err(pivot index)
/// if a pivot is not positive.
fn dense_cholesky(a: &mut [f64], n: usize) -> Result<(), usize> {
    for j in 0..n {
        let d = a[j * n + j] - (0..j).map(|k| a[j * n + k] * a[j * n + k]).sum::<f64>();
        if !(d > 0.0) {
            return Err(j);
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let s: f64 = (0..j).map(|k| a[i * n + k] * a[j * n + k]).sum();
            a[i * n + j] = (a[i * n + j] - s) / d;
        }
        for k in j + 1..n {
            a[j * n + k] = 0.0;
        }
    }
    Ok(())
}

impl QuasiStatic {
    /// Φ of the contact unknowns alone (every massless unknown is a contact unknown).
    pub fn new<A: SymMatrix>(stiffness: &A, load: &[f64], contact: &[usize]) -> Self {
        Self::with_free(stiffness, load, contact, &[]).expect("no free block to factor")
    }

    /// Φ of the contact unknowns and of the free massless unknowns `free` (disjoint from
    /// `contact`). Fails only if S_FF is not positive definite.
    pub fn with_free<A: SymMatrix>(
        stiffness: &A,
        load: &[f64],
        contact: &[usize],
        free: &[usize],
    ) -> Result<Self, LinalgError> {
        let (nc, nf) = (contact.len(), free.len());
        // slot: 0..nc contact, nc..nc+nf free, MAX elsewhere.
        let mut slot = vec![usize::MAX; stiffness.dim()];
        for (c, &i) in contact.iter().chain(free).enumerate() {
            slot[i] = c;
        }
        let mut d = vec![0.0; nc * nc];
        let mut coupling = Vec::new();
        let mut fb =
            FreeBlock { idx: free.to_vec(), chol: vec![0.0; nf * nf], s_fc: vec![0.0; nf * nc], ..Default::default() };
        stiffness.for_each_entry(&mut |i, j, s| {
            let (a, b) = (slot[i], slot[j]);
            match (a < nc, a != usize::MAX, b < nc, b != usize::MAX) {
                (true, _, true, _) => d[a * nc + b] += s,
                (true, _, false, false) => coupling.push((a, j, s)),
                (false, true, true, _) => fb.s_fc[(a - nc) * nc + b] += s,
                (false, true, false, true) => fb.chol[(a - nc) * nf + (b - nc)] += s,
                (false, true, false, false) => fb.coupling.push((a - nc, j, s)),
                _ => {} // a C–F entry (its transpose is the F–C one) or a row outside C ∪ F
            }
        });
        let load_c = contact.iter().map(|&i| load[i]).collect();
        if nf > 0 {
            dense_cholesky(&mut fb.chol, nf).map_err(|pivot| LinalgError::Unsupported {
                matrix: "stiffness",
                detail: format!("its block on the free massless unknowns is not positive definite (pivot {pivot})"),
            })?;
            fb.load = free.iter().map(|&i| load[i]).collect();
            fb.q = vec![0.0; nf];
            fb.g = fb.s_fc.clone();
            let mut col = vec![0.0; nf];
            for c in 0..nc {
                for f in 0..nf {
                    col[f] = fb.s_fc[f * nc + c];
                }
                fb.solve(&mut col);
                for f in 0..nf {
                    fb.g[f * nc + c] = col[f];
                }
            }
            // D = S_CC − S_CF G, symmetrised (symmetric in exact arithmetic).
            for a in 0..nc {
                for b in 0..nc {
                    let ab: f64 = (0..nf).map(|f| fb.s_fc[f * nc + a] * fb.g[f * nc + b]).sum();
                    let ba: f64 = (0..nf).map(|f| fb.s_fc[f * nc + b] * fb.g[f * nc + a]).sum();
                    d[a * nc + b] -= 0.5 * (ab + ba);
                }
            }
        }
        let lcp = Lcp::new(d, nc);
        Ok(Self { contact: contact.to_vec(), coupling, load: load_c, lcp, q: vec![0.0; nc], free: fb })
    }

    /// Takes the contact (and free massless) entries of a new load vector (a time-dependent
    /// load).
    pub fn set_load(&mut self, load: &[f64]) {
        for (f, &i) in self.load.iter_mut().zip(&self.contact) {
            *f = load[i];
        }
        for (f, &i) in self.free.load.iter_mut().zip(&self.free.idx) {
            *f = load[i];
        }
    }

    /// The LCP matrix entry (a, b) in contact order: `S_CC` without free massless unknowns,
    /// else its Schur complement D (type docs).
    pub fn d(&self, a: usize, b: usize) -> f64 {
        self.lcp.d(a, b)
    }

    /// Overwrites the contact and free massless entries of `u` with Φ(U) and writes λ;
    /// returns the pivots.
    pub fn apply(&mut self, u: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError> {
        let nc = self.contact.len();
        for (q, f) in self.q.iter_mut().zip(&self.load) {
            *q = -f;
        }
        for &(c, j, s) in &self.coupling {
            self.q[c] += s * u[j];
        }
        let fb = &mut self.free;
        if !fb.idx.is_empty() {
            // q_C ← q_C − S_CF S_FF⁻¹ q_F = q_C − Gᵀ q_F.
            for (q, f) in fb.q.iter_mut().zip(&fb.load) {
                *q = -f;
            }
            for &(f, j, s) in &fb.coupling {
                fb.q[f] += s * u[j];
            }
            let mut qf = std::mem::take(&mut fb.q);
            fb.solve(&mut qf);
            for (f, &x) in qf.iter().enumerate() {
                for c in 0..nc {
                    self.q[c] -= fb.s_fc[f * nc + c] * x;
                }
            }
            fb.q = qf;
        }
        if lower.iter().any(|&l| l != 0.0) {
            for a in 0..nc {
                self.q[a] += (0..nc).map(|b| self.lcp.d(a, b) * lower[b]).sum::<f64>();
            }
        }
        let (y, w) = self.lcp.solve(&self.q)?;
        for (c, &i) in self.contact.iter().enumerate() {
            u[i] = y[c] + lower[c];
            lambda[c] = -w[c];
        }
        // u_F = −S_FF⁻¹ q_F − G u_C (fb.q holds S_FF⁻¹ q_F).
        let fb = &self.free;
        for (f, &i) in fb.idx.iter().enumerate() {
            let gu: f64 = self.contact.iter().enumerate().map(|(c, &k)| fb.g[f * nc + c] * u[k]).sum();
            u[i] = -fb.q[f] - gu;
        }
        Ok(self.lcp.pivots())
    }
}
