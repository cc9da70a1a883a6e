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

pub mod lcp;
pub mod schur;

use crate::linalg::tridiag::{SymTridiag, TwistedFactor};
use crate::linalg::{LinalgError, SymMatrix};
use lcp::{Lcp, LcpError};
pub use schur::Schur;
use std::fmt::Debug;

/// A matrix back-end with its exact contact solver: what the schemes need to factor an iteration
/// matrix `K` once and solve each step's contact problem with it.
pub trait Backend: SymMatrix {
    /// The exact solver of one implicit step with contact for `K = self`.
    type Solver: ContactSolver;

    /// Factors `self` once and prepares the contact solves on the unknowns `contact`.
    fn contact_solver(&self, contact: &[usize], matrix: &'static str) -> Result<Self::Solver, LinalgError>;
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
}

/// The exact contact solve of one implicit step (module docs).
pub trait ContactSolver: Debug + Send {
    /// Solves `K U = r − σ Σ λ_c e_c`, `lb ≤ u_C ⊥ λ ≤ 0` in place (`rhs` = r on entry, U on
    /// exit) and writes λ (one entry per contact unknown). On active nodes `u_c = lb_c` is set
    /// exactly, so complementarity holds bit for bit. Returns the principal pivots used.
    fn solve(&mut self, rhs: &mut [f64], lower: &[f64], sigma: f64, lambda: &mut [f64]) -> Result<usize, LcpError>;
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

/// The quasi-static contact map Φ of massless contact nodes: for the other values U, the
/// contact values u and multipliers λ with
///
/// ```text
/// S_CC u + S_CI U − F_C = −λ,     0 ≤ u − lb ⊥ λ ≤ 0,
/// ```
///
/// an LCP in `y = u − lb` with the SPD matrix `D = S_CC`: `w = (S_CI U − F_C + D lb) + D y`.
/// In 1D (`S_00 = 1/h`, `S_01 = −1/h`, lb = −gap) it is `u_0 = max(u_1, −gap)`.
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
    pub fn new<A: SymMatrix>(stiffness: &A, load: &[f64], contact: &[usize]) -> Self {
        let nc = contact.len();
        let mut slot = vec![usize::MAX; stiffness.dim()];
        for (c, &i) in contact.iter().enumerate() {
            slot[i] = c;
        }
        let mut d = vec![0.0; nc * nc];
        let mut coupling = Vec::new();
        stiffness.for_each_entry(&mut |i, j, s| {
            if slot[i] == usize::MAX {
                return;
            }
            if slot[j] == usize::MAX {
                coupling.push((slot[i], j, s));
            } else {
                d[slot[i] * nc + slot[j]] += s;
            }
        });
        let load = contact.iter().map(|&i| load[i]).collect();
        Self { contact: contact.to_vec(), coupling, load, lcp: Lcp::new(d, nc), q: vec![0.0; nc] }
    }

    /// Takes the contact entries of a new load vector (a time-dependent load).
    pub fn set_load(&mut self, load: &[f64]) {
        for (f, &i) in self.load.iter_mut().zip(&self.contact) {
            *f = load[i];
        }
    }

    /// `S_CC` entry (a, b) in contact order.
    pub fn d(&self, a: usize, b: usize) -> f64 {
        self.lcp.d(a, b)
    }

    /// Overwrites the contact entries of `u` with Φ(U) and writes λ; returns the pivots.
    pub fn apply(&mut self, u: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError> {
        let nc = self.contact.len();
        for (q, f) in self.q.iter_mut().zip(&self.load) {
            *q = -f;
        }
        for &(c, j, s) in &self.coupling {
            self.q[c] += s * u[j];
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
        Ok(self.lcp.pivots())
    }
}
