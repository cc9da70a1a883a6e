//! Exact solution of the many-node Signorini condition inside an implicit step, for sparse
//! back-ends (plates and solids; with one contact node it is [`super::OneNode`]'s formula).
//!
//! Each full-system scheme solves, per step,
//!
//! ```text
//! K U = r − σ Σ_c λ_c e_c,     0 ≤ u_c − lb_c ⊥ λ_c ≤ 0   for every contact unknown c,
//! ```
//!
//! K SPD, σ > 0 the scheme's force scale. With `Z = K⁻¹ E` (E the contact columns of I) and
//! `U* = K⁻¹ r`, `U = U* − σ Z λ`, so on the contact nodes `u_C = U*_C + D μ` with the Schur
//! complement `D = Eᵀ K⁻¹ E` (SPD) and `μ = −σ λ ≥ 0`:
//!
//! ```text
//! w = (U*_C − lb) + D μ ≥ 0,   μ ≥ 0,   μᵀ w = 0,
//! ```
//!
//! an LCP with an SPD matrix, solved exactly by [`Lcp`] (Murty's principal pivoting). K is
//! factored once and Z computed once (one solve per contact node); a step costs one sparse
//! solve, the LCP on the contact nodes, and `n × (active nodes)` multiply-adds. With one contact
//! node this is the 1D formula `λ = (u*_0 − lb)/(σ z_0)`.

use super::ContactSolver;
use super::lcp::{Lcp, LcpError};
use crate::linalg::sparse::{SpMat, SparseError, SparseLlt};

#[derive(Debug)]
pub struct Schur {
    factor: SparseLlt,
    contact: Vec<usize>,
    /// Column c of Z = K⁻¹ e_{contact[c]}, stored column after column (n per column).
    z: Vec<f64>,
    lcp: Lcp,
    q: Vec<f64>,
}

impl Schur {
    /// Factors K and precomputes Z and D = Z_C (symmetrised: D is symmetric in exact
    /// arithmetic, the computed columns differ by round-off).
    pub fn new(k: &SpMat, contact: &[usize], matrix: &'static str) -> Result<Self, SparseError> {
        let n = k.nrows();
        let nc = contact.len();
        let mut factor = SparseLlt::new(k, matrix)?;
        let mut z = vec![0.0; n * nc];
        for (c, &i) in contact.iter().enumerate() {
            let col = &mut z[c * n..(c + 1) * n];
            col[i] = 1.0;
            factor.solve_in_place(col);
        }
        let mut d = vec![0.0; nc * nc];
        for a in 0..nc {
            for b in 0..nc {
                d[a * nc + b] = 0.5 * (z[b * n + contact[a]] + z[a * n + contact[b]]);
            }
        }
        Ok(Self { factor, contact: contact.to_vec(), z, lcp: Lcp::new(d, nc), q: vec![0.0; nc] })
    }
}

impl ContactSolver for Schur {
    /// Solves `K U = r − σ Σ λ_c e_c`, `lb ≤ u_C ⊥ λ ≤ 0` in place (`rhs` = r on entry, U on
    /// exit) and writes λ. On active nodes `u_c = lb_c` is set exactly. Returns the pivot count.
    fn solve(&mut self, rhs: &mut [f64], lower: &[f64], sigma: f64, lambda: &mut [f64]) -> Result<usize, LcpError> {
        let n = rhs.len();
        self.factor.solve_in_place(rhs);
        for (c, &i) in self.contact.iter().enumerate() {
            self.q[c] = rhs[i] - lower[c];
        }
        let (mu, _) = self.lcp.solve(&self.q)?;
        for (c, &m) in mu.iter().enumerate() {
            lambda[c] = if m > 0.0 { -m / sigma } else { 0.0 };
            if m > 0.0 {
                let col = &self.z[c * n..(c + 1) * n];
                for (u, zc) in rhs.iter_mut().zip(col) {
                    *u += m * zc;
                }
            }
        }
        for (c, &i) in self.contact.iter().enumerate() {
            if lambda[c] < 0.0 {
                rhs[i] = lower[c];
            }
        }
        Ok(self.lcp.pivots())
    }
}
