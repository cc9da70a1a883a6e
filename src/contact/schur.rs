//! Exact solution of the many-node Signorini condition inside an implicit step, for sparse
//! back-ends (plates and solids; with one contact node it is [`super::OneNode`]'s formula).
//!
//! Each full-system scheme solves, per step,
//!
//! ```text
//! K U = r − σ Σ_c λ_c e_c,     0 ≤ u_c − lb_c ⊥ λ_c ≤ 0   for every contact unknown c,
//! ```
//!
//! K SPD, σ > 0 the scheme's force scale. With E the contact columns of I, `U* = K⁻¹ r` and
//! `μ = −σ λ ≥ 0`, `U = U* + K⁻¹ E μ`, so on the contact nodes `u_C = U*_C + D μ` with the Schur
//! complement `D = Eᵀ K⁻¹ E` (SPD):
//!
//! ```text
//! w = (U*_C − lb) + D μ ≥ 0,   μ ≥ 0,   μᵀ w = 0,
//! ```
//!
//! an LCP with an SPD matrix, solved exactly by [`Lcp`] (Murty's principal pivoting).
//!
//! Only the n_c × n_c matrix D is kept. K is factored once; D is built once from the solves
//! `K⁻¹ e_c`, done in blocks of columns (faer's supernodal solve on several right-hand sides)
//! whose contact rows are kept and the rest dropped, so set-up memory is one block, not
//! `n × n_c`. A step costs one sparse solve for U*, the LCP, and, only if some node is active,
//! one more sparse solve for the correction `K⁻¹ (E μ)` (E μ has n_c nonzeros). With one contact
//! node this is the 1D formula `λ = (u*_0 − lb)/(σ z_0)`.

use super::ContactSolver;
use super::lcp::{Lcp, LcpError};
use crate::linalg::sparse::{SpMat, SparseError, SparseLlt};

/// Doubles of the set-up block of unit responses (16 MB): the block width is this divided by
/// the number of unknowns, at least 1 and at most [`MAX_BLOCK`].
const BLOCK_VALUES: usize = 1 << 21;
/// Widest block of right-hand sides: beyond a few dozen columns the blocked solve gains little.
const MAX_BLOCK: usize = 64;

#[derive(Debug)]
pub struct Schur {
    factor: SparseLlt,
    contact: Vec<usize>,
    lcp: Lcp,
    q: Vec<f64>,
    /// Work vector of the correction solve, `E μ` then `K⁻¹ E μ` (n values).
    correction: Vec<f64>,
}

impl Schur {
    /// Factors K and builds D = Eᵀ K⁻¹ E (symmetrised: D is symmetric in exact arithmetic, the
    /// computed columns differ by round-off).
    pub fn new(k: &SpMat, contact: &[usize], matrix: &'static str) -> Result<Self, SparseError> {
        let n = k.nrows();
        let nc = contact.len();
        let factor = SparseLlt::new(k, matrix)?;
        // d[a * nc + b] = (K⁻¹ e_b)_{contact[a]}, then symmetrised in place.
        let mut d = vec![0.0; nc * nc];
        let width = (BLOCK_VALUES / n.max(1)).clamp(1, MAX_BLOCK).min(nc.max(1));
        let mut block = vec![0.0; n * width];
        for first in (0..nc).step_by(width) {
            let cols = width.min(nc - first);
            let block = &mut block[..n * cols];
            block.iter_mut().for_each(|v| *v = 0.0);
            for j in 0..cols {
                block[j * n + contact[first + j]] = 1.0;
            }
            factor.solve_many_in_place(block, cols);
            for j in 0..cols {
                let col = &block[j * n..(j + 1) * n];
                for (a, &i) in contact.iter().enumerate() {
                    d[a * nc + first + j] = col[i];
                }
            }
        }
        drop(block);
        for a in 0..nc {
            for b in a + 1..nc {
                let s = 0.5 * (d[a * nc + b] + d[b * nc + a]);
                d[a * nc + b] = s;
                d[b * nc + a] = s;
            }
        }
        let correction = vec![0.0; n];
        Ok(Self { factor, contact: contact.to_vec(), lcp: Lcp::new(d, nc), q: vec![0.0; nc], correction })
    }
}

impl ContactSolver for Schur {
    /// Solves `K U = r − σ Σ λ_c e_c`, `lb ≤ u_C ⊥ λ ≤ 0` in place (`rhs` = r on entry, U on
    /// exit) and writes λ. On active nodes `u_c = lb_c` is set exactly. Returns the pivot count.
    fn solve(&mut self, rhs: &mut [f64], lower: &[f64], sigma: f64, lambda: &mut [f64]) -> Result<usize, LcpError> {
        self.factor.solve_in_place(rhs);
        for (c, &i) in self.contact.iter().enumerate() {
            self.q[c] = rhs[i] - lower[c];
        }
        let (mu, _) = self.lcp.solve(&self.q)?;
        let mut any = false;
        for (c, &m) in mu.iter().enumerate() {
            lambda[c] = if m > 0.0 { -m / sigma } else { 0.0 };
            any |= m > 0.0;
        }
        if any {
            // U = U* + K⁻¹ (E μ): one more solve on a right-hand side with n_c nonzeros.
            self.correction.iter_mut().for_each(|v| *v = 0.0);
            for (&m, &i) in mu.iter().zip(&self.contact) {
                self.correction[i] = m;
            }
            self.factor.solve_in_place(&mut self.correction);
            for (u, z) in rhs.iter_mut().zip(&self.correction) {
                *u += z;
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
