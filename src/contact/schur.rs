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
//! K is factored once with the contact unknowns eliminated last
//! ([`SparseLlt::with_trailing`]): `P K Pᵀ = L Lᵀ` whose trailing n_c × n_c block `L_CC` is the
//! Cholesky factor of the Schur complement of the other unknowns, so `D = (K⁻¹)_CC =
//! L_CC⁻ᵀ L_CC⁻¹` comes from the dense triangular inverse of `L_CC` (O(n_c³), no sparse solve).
//! A step is one forward substitution `y = L⁻¹ P r`, the contact values
//! `U*_C = L_CC⁻ᵀ y_C` (dense, O(n_c²)), the LCP, and one backward substitution after the
//! trailing block is replaced by `L_CCᵀ u_C` with `u_C = U*_C + D μ = w + lb` (the forward substitution
//! of `r + E μ`, since E's rows are eliminated last): the cost of one sparse solve with or
//! without contact. With one contact node this is the 1D formula `λ = (u*_0 − lb)/(σ z_0)`.

use super::ContactSolver;
use super::lcp::{Lcp, LcpError};
use crate::linalg::sparse::{SpMat, SparseError, SparseLlt};
use faer::{Mat, Par};

#[derive(Debug)]
pub struct Schur {
    factor: SparseLlt,
    contact: Vec<usize>,
    /// `L_CCᵀ`, row-major upper triangular n_c × n_c.
    upper: Vec<f64>,
    lcp: Lcp,
    q: Vec<f64>,
    /// Work vector: `U*_C`, then `u_C`.
    uc: Vec<f64>,
}

impl Schur {
    /// Factors K (contact unknowns last) and builds D = Eᵀ K⁻¹ E from the trailing block of
    /// the factor (symmetrised: D is symmetric in exact arithmetic).
    pub fn new(k: &SpMat, contact: &[usize], matrix: &'static str) -> Result<Self, SparseError> {
        let nc = contact.len();
        let factor = SparseLlt::with_trailing(k, contact, matrix)?;
        let upper = factor.trailing_upper();
        let d = trailing_inverse(&upper, nc);
        let (q, uc) = (vec![0.0; nc], vec![0.0; nc]);
        Ok(Self { factor, contact: contact.to_vec(), upper, lcp: Lcp::new(d, nc), q, uc })
    }
}

/// `D = (K⁻¹)_TT = L_TT⁻ᵀ L_TT⁻¹` from `upper = L_TTᵀ` (row-major n × n): X = L_TT⁻¹ by a
/// dense triangular solve, D = Xᵀ X, symmetrised (symmetric in exact arithmetic); row-major.
pub(crate) fn trailing_inverse(upper: &[f64], n: usize) -> Vec<f64> {
    let l = Mat::<f64>::from_fn(n, n, |i, j| upper[j * n + i]);
    let mut x = Mat::<f64>::identity(n, n);
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), x.as_mut(), Par::Seq);
    let dm = x.transpose() * &x;
    let mut d = vec![0.0; n * n];
    for a in 0..n {
        for b in 0..n {
            d[a * n + b] = 0.5 * (dm[(a, b)] + dm[(b, a)]);
        }
    }
    d
}

impl ContactSolver for Schur {
    /// Solves `K U = r − σ Σ λ_c e_c`, `lb ≤ u_C ⊥ λ ≤ 0` in place (`rhs` = r on entry, U on
    /// exit) and writes λ. On active nodes `u_c = lb_c` is set exactly. Returns the pivot count.
    fn solve(&mut self, rhs: &mut [f64], lower: &[f64], sigma: f64, lambda: &mut [f64]) -> Result<usize, LcpError> {
        let Self { factor, upper, lcp, q, uc, .. } = self;
        let nc = uc.len();
        factor.solve_split(rhs, |y| {
            // U*_C = L_CC⁻ᵀ y_C (back substitution with the rows of U = L_CCᵀ).
            for a in (0..nc).rev() {
                let row = &upper[a * nc..(a + 1) * nc];
                let s: f64 = (a + 1..nc).map(|b| row[b] * uc[b]).sum();
                uc[a] = (y[a] - s) / row[a];
            }
            for c in 0..nc {
                q[c] = uc[c] - lower[c];
            }
            let (mu, w) = lcp.solve(q)?;
            let mut any = false;
            for (c, &m) in mu.iter().enumerate() {
                lambda[c] = if m > 0.0 { -m / sigma } else { 0.0 };
                any |= m > 0.0;
            }
            if any {
                // u_C = U*_C + D μ = w + lb, and the trailing block of L⁻¹ P (r + E μ) is
                // L_CCᵀ u_C.
                for ((u, w), l) in uc.iter_mut().zip(w).zip(lower) {
                    *u = w + l;
                }
                for a in 0..nc {
                    let row = &upper[a * nc..(a + 1) * nc];
                    y[a] = (a..nc).map(|b| row[b] * uc[b]).sum();
                }
            }
            Ok(())
        })?;
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

    /// 70 contact nodes eliminated last and a step with active and inactive nodes: the returned
    /// U solves `K U = r + E μ` (μ = −σλ) with `lb ≤ u_C ⊥ λ ≤ 0`.
    /// mutation: keep the forward block y_C instead of `L_CCᵀ u_C` before the backward solve
    /// (the contact correction lost) -> fails with "0.6867036979092087 vs 0.8632093666488739"
    /// (row 0 of K U = r + E μ).
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
