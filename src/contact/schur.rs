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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::sparse::{from_triplets, sym_mul_into};

    /// Two set-up blocks (70 contact nodes > [`MAX_BLOCK`]) and a step with active and inactive
    /// nodes: the returned U solves `K U = r + E μ` (μ = −σλ) with `lb ≤ u_C ⊥ λ ≤ 0`.
    /// mutation: drop the correction solve (`if any` → `if false`) -> fails with
    /// "0.6867036979092086 vs 0.8632093666488739" (row 0 of K U = r + E μ).
    #[test]
    fn solve_meets_the_equations_and_complementarity() {
        // 5-point Laplacian + I on a 3 × 70 grid (eigenvalues in [1, 9]: κ ≤ 9).
        let (nx, ny) = (3usize, 70usize);
        let n = nx * ny;
        let id = |x: usize, y: usize| y * nx + x;
        let mut t = Vec::new();
        for y in 0..ny {
            for x in 0..nx {
                t.push((id(x, y), id(x, y), 5.0));
                if x + 1 < nx {
                    t.extend([(id(x, y), id(x + 1, y), -1.0), (id(x + 1, y), id(x, y), -1.0)]);
                }
                if y + 1 < ny {
                    t.extend([(id(x, y), id(x, y + 1), -1.0), (id(x, y + 1), id(x, y), -1.0)]);
                }
            }
        }
        let k = from_triplets(n, &t, "test").unwrap();
        let contact: Vec<usize> = (0..ny).map(|y| id(0, y)).collect();
        let mut schur = Schur::new(&k, &contact, "test").unwrap();
        let r: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        let lower = vec![0.0; ny];
        let sigma = 0.5;
        let (mut u, mut lambda) = (r.clone(), vec![0.0; ny]);
        schur.solve(&mut u, &lower, sigma, &mut lambda).unwrap();
        assert!(lambda.iter().any(|&l| l < 0.0) && lambda.iter().any(|&l| l == 0.0), "both states occur");
        let mut ku = vec![0.0; n];
        sym_mul_into(&k, &u, &mut ku);
        let mut rhs = r.clone();
        for (c, &i) in contact.iter().enumerate() {
            rhs[i] -= sigma * lambda[c];
        }
        // Backward-stable solves with κ(K) ≤ 9 and |K| ≤ 9 per row: a few ε n of the scale.
        let scale = 1.0 + rhs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let tol = 64.0 * n as f64 * f64::EPSILON * scale;
        for (a, b) in ku.iter().zip(&rhs) {
            assert!((a - b).abs() <= tol, "{a} vs {b} (tol {tol:e})");
        }
        for (c, &i) in contact.iter().enumerate() {
            assert!(u[i] >= lower[c] - tol && lambda[c] <= 0.0);
            assert!(lambda[c] == 0.0 || u[i] == lower[c], "complementarity holds exactly");
        }
    }
}
