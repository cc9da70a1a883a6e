//! Exact solution of a small linear complementarity problem with a symmetric positive definite
//! matrix, by Murty's least-index principal pivoting method.
//!
//! ```text
//! find μ ∈ ℝⁿ:   w = q + D μ ≥ 0,   μ ≥ 0,   μᵀ w = 0        (D SPD)
//! ```
//!
//! A complementary basis is a set α ("active"): `μ_α` solves `D_αα μ_α = −q_α`, `μ_β = 0`,
//! `w_α = 0`, `w_β = q_β + D_βα μ_α`. If every basic value (μ on α, w on β) is ≥ 0 the pair
//! solves the problem; otherwise the least index i with a negative basic value changes side.
//! For a P-matrix (SPD matrices are) the LCP has exactly one solution and this least-index rule
//! reaches it in finitely many pivots from any starting basis (K. G. Murty, "Note on a Bard-type
//! scheme for solving the complementarity problem", Opsearch 11 (1974) 123–130; Murty, *Linear
//! Complementarity, Linear and Nonlinear Programming*, 1988, §4.2). So the previous step's set
//! is a valid warm start, and the method has no tolerance-driven stopping rule: it stops when the
//! signs are right. The pivot cap only guards against a defect (round-off turning D indefinite):
//! hitting it is an error carrying the residual, never a silent stop.
//!
//! Signs are tested against a round-off allowance: each basic value is computed by a
//! backward-stable Cholesky solve of size ≤ n, so its absolute error is at most a few
//! `n ε (‖q‖∞ + max|D| ‖μ‖₁)`; values above minus that allowance count as ≥ 0.
//! All work arrays are allocated once in [`Lcp::new`]: solving does not allocate.

use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum LcpError {
    #[error("the contact problem did not converge after {pivots} principal pivots (natural residual {residual:e})")]
    NotConverged { pivots: usize, residual: f64 },
    #[error(
        "the contact Schur complement restricted to {size} active nodes is not positive definite (pivot {pivot:e}); natural residual {residual:e}"
    )]
    Breakdown { size: usize, pivot: f64, residual: f64 },
    /// A new factor of the massless layer's block (its contact set changed) could not be made
    /// ([`super::layer`]: the memory it would take).
    #[error("the massless contact layer's block could not be factored for its new contact set: {0}")]
    Factor(crate::linalg::sparse::SparseError),
}

impl LcpError {
    pub fn residual(&self) -> f64 {
        match *self {
            LcpError::NotConverged { residual, .. } | LcpError::Breakdown { residual, .. } => residual,
            LcpError::Factor(_) => f64::NAN,
        }
    }
}

/// An LCP solver for a fixed SPD matrix D with reusable work space and a warm-start set.
#[derive(Debug, Clone)]
pub struct Lcp {
    n: usize,
    /// D, row-major.
    d: Vec<f64>,
    max_abs_d: f64,
    active: Vec<bool>,
    idx: Vec<usize>,
    chol: Vec<f64>,
    /// The active set whose factor `chol` holds, if `factored_valid`: a step whose warm-start
    /// set is already right reuses it.
    factored: Vec<usize>,
    factored_valid: bool,
    y: Vec<f64>,
    mu: Vec<f64>,
    w: Vec<f64>,
    pivots: usize,
}

impl Lcp {
    /// D is n × n, row-major, symmetric positive definite.
    pub fn new(d: Vec<f64>, n: usize) -> Self {
        assert_eq!(d.len(), n * n);
        let max_abs_d = d.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        Self {
            n,
            d,
            max_abs_d,
            active: vec![false; n],
            idx: Vec::with_capacity(n),
            chol: vec![0.0; n * n],
            factored: Vec::with_capacity(n),
            factored_valid: false,
            y: vec![0.0; n],
            mu: vec![0.0; n],
            w: vec![0.0; n],
            pivots: 0,
        }
    }

    pub fn len(&self) -> usize {
        self.n
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Entry (i, j) of D.
    pub fn d(&self, i: usize, j: usize) -> f64 {
        self.d[i * self.n + j]
    }

    /// Pivots used by the last solve.
    pub fn pivots(&self) -> usize {
        self.pivots
    }

    /// The largest number of pivots a solve may take before it is declared failed: far above
    /// what Murty's rule needs in practice (about one pivot per node whose state changes).
    pub fn max_pivots(&self) -> usize {
        50 * self.n + 100
    }

    /// Solves the LCP for q; returns `(μ, w)`. The active set of the solution is kept as the
    /// warm start of the next solve. On the active set `w = 0` exactly, on the inactive set
    /// `μ = 0` exactly.
    pub fn solve(&mut self, q: &[f64]) -> Result<(&[f64], &[f64]), LcpError> {
        assert_eq!(q.len(), self.n);
        let n = self.n;
        let qmax = q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        self.pivots = 0;
        loop {
            // Basic solution for the current set.
            self.idx.clear();
            self.idx.extend((0..n).filter(|&i| self.active[i]));
            if let Err(pivot) = self.solve_active(q) {
                self.mu.iter_mut().for_each(|m| *m = 0.0);
                let residual = self.residual(q);
                return Err(LcpError::Breakdown { size: self.idx.len(), pivot, residual });
            }
            for i in 0..n {
                if self.active[i] {
                    self.w[i] = 0.0;
                } else {
                    let mut s = q[i];
                    for &j in &self.idx {
                        s += self.d[i * n + j] * self.mu[j];
                    }
                    self.w[i] = s;
                }
            }
            let mu_sum: f64 = self.idx.iter().map(|&j| self.mu[j].abs()).sum();
            // Round-off allowance of the basic values (module docs).
            let tol = 4.0 * (n as f64 + 1.0) * f64::EPSILON * (qmax + self.max_abs_d * mu_sum);
            let violated = (0..n).find(|&i| if self.active[i] { self.mu[i] < -tol } else { self.w[i] < -tol });
            match violated {
                None => {
                    for i in 0..n {
                        if self.active[i] {
                            self.mu[i] = self.mu[i].max(0.0);
                        }
                    }
                    return Ok((&self.mu, &self.w));
                }
                Some(i) => {
                    self.active[i] = !self.active[i];
                    self.pivots += 1;
                    if self.pivots > self.max_pivots() {
                        let residual = self.residual(q);
                        return Err(LcpError::NotConverged { pivots: self.pivots, residual });
                    }
                }
            }
        }
    }

    /// `μ_α = −D_αα⁻¹ q_α` by a dense Cholesky factorisation of D_αα; μ_β = 0. Err(pivot) if
    /// D_αα is not numerically positive definite.
    fn solve_active(&mut self, q: &[f64]) -> Result<(), f64> {
        let (n, k) = (self.n, self.idx.len());
        self.mu.iter_mut().for_each(|m| *m = 0.0);
        // L (k × k, row-major in chol) with D_αα = L Lᵀ, unless chol holds it already.
        if !(self.factored_valid && self.factored == self.idx) {
            self.factor_active()?;
        }
        for a in 0..k {
            let mut s = -q[self.idx[a]];
            for c in 0..a {
                s -= self.chol[a * n + c] * self.y[c];
            }
            self.y[a] = s / self.chol[a * n + a];
        }
        for a in (0..k).rev() {
            let mut s = self.y[a];
            for c in a + 1..k {
                s -= self.chol[c * n + a] * self.y[c];
            }
            self.y[a] = s / self.chol[a * n + a];
        }
        for a in 0..k {
            self.mu[self.idx[a]] = self.y[a];
        }
        Ok(())
    }

    /// The dense Cholesky factor of D_αα (α = idx) into chol; Err(pivot) if not positive.
    fn factor_active(&mut self) -> Result<(), f64> {
        let (n, k) = (self.n, self.idx.len());
        self.factored_valid = false;
        for a in 0..k {
            for b in 0..=a {
                let mut s = self.d[self.idx[a] * n + self.idx[b]];
                for c in 0..b {
                    s -= self.chol[a * n + c] * self.chol[b * n + c];
                }
                if a == b {
                    if !(s > 0.0) {
                        return Err(s);
                    }
                    self.chol[a * n + a] = s.sqrt();
                } else {
                    self.chol[a * n + b] = s / self.chol[b * n + b];
                }
            }
        }
        self.factored.clear();
        self.factored.extend_from_slice(&self.idx);
        self.factored_valid = true;
        Ok(())
    }

    /// Natural residual `max_i |min(μ_i, (q + Dμ)_i)|` of the current μ.
    fn residual(&self, q: &[f64]) -> f64 {
        natural_residual(&self.d, self.n, q, &self.mu)
    }
}

/// `max_i |min(μ_i, (q + Dμ)_i)|`: zero exactly at the LCP's solution.
pub fn natural_residual(d: &[f64], n: usize, q: &[f64], mu: &[f64]) -> f64 {
    (0..n)
        .map(|i| {
            let w = q[i] + (0..n).map(|j| d[i * n + j] * mu[j]).sum::<f64>();
            mu[i].min(w).abs()
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A seeded SPD matrix `D = BᵀB + n I` and vectors q (no external RNG: a linear
    /// congruential sequence is enough to vary signs).
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    #[test]
    fn random_spd_problems_are_solved_exactly() {
        let mut seed = 7u64;
        for n in [1usize, 2, 5, 21, 41] {
            let b: Vec<f64> = (0..n * n).map(|_| lcg(&mut seed)).collect();
            let mut d = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..n {
                    d[i * n + j] =
                        (0..n).map(|k| b[k * n + i] * b[k * n + j]).sum::<f64>() + if i == j { 0.1 } else { 0.0 };
                }
            }
            let mut lcp = Lcp::new(d.clone(), n);
            for _ in 0..20 {
                let q: Vec<f64> = (0..n).map(|_| lcg(&mut seed)).collect();
                let (mu, w) = lcp.solve(&q).unwrap();
                let (mu, w) = (mu.to_vec(), w.to_vec());
                let scale =
                    1.0 + mu.iter().map(|m| m.abs()).sum::<f64>() * d.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                // κ(D) ≤ (max eigenvalue)/0.1 ≲ 10 n²: allow ε·n·κ of the scale.
                let tol = 1e2 * (n * n * n) as f64 * f64::EPSILON * scale;
                assert!(natural_residual(&d, n, &q, &mu) <= tol, "n = {n}");
                assert!(mu.iter().zip(&w).all(|(m, w)| *m >= 0.0 && (*m == 0.0 || *w == 0.0)));
            }
        }
    }
}
