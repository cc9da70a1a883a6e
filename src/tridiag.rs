//! Symmetric tridiagonal matrices and their LDLᵀ factorisation.
//!
//! Every 1D iteration matrix of the paper (`M + β Δt² S`, `M + Δt² S`, `hM* + Δt²/(4h) S*`) is
//! symmetric tridiagonal, so a step costs one forward and one backward substitution of length m.
//! The factor is computed once per (system, Δt) and reused without allocation.

use thiserror::Error;

/// Failure of an LDLᵀ factorisation: the matrix is not positive definite.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FactorError {
    #[error(
        "pivot {index} of the LDLᵀ factorisation is {pivot:e} (not positive): the matrix is singular or indefinite"
    )]
    NonPositivePivot { index: usize, pivot: f64 },
}

/// A symmetric tridiagonal matrix: `diag[i] = A[i][i]`, `off[i] = A[i][i+1] = A[i+1][i]`.
#[derive(Debug, Clone, PartialEq)]
pub struct SymTridiag {
    pub diag: Vec<f64>,
    pub off: Vec<f64>,
}

impl SymTridiag {
    pub fn zeros(n: usize) -> Self {
        Self { diag: vec![0.0; n], off: vec![0.0; n.saturating_sub(1)] }
    }

    pub fn len(&self) -> usize {
        self.diag.len()
    }

    pub fn is_empty(&self) -> bool {
        self.diag.is_empty()
    }

    /// Entry (i, j); zero outside the three diagonals.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        match i.abs_diff(j) {
            0 => self.diag[i],
            1 => self.off[i.min(j)],
            _ => 0.0,
        }
    }

    /// `a·self + b·other`, entry by entry.
    pub fn combine(&self, a: f64, other: &SymTridiag, b: f64) -> SymTridiag {
        let zip = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| a * p + b * q).collect();
        SymTridiag { diag: zip(&self.diag, &other.diag), off: zip(&self.off, &other.off) }
    }

    /// The principal submatrix on rows and columns `start..`.
    pub fn trailing(&self, start: usize) -> SymTridiag {
        SymTridiag { diag: self.diag[start..].to_vec(), off: self.off[start.min(self.off.len())..].to_vec() }
    }

    /// `y = A x`.
    pub fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        let n = self.diag.len();
        debug_assert!(x.len() == n && y.len() == n);
        for i in 0..n {
            let mut s = self.diag[i] * x[i];
            if i > 0 {
                s += self.off[i - 1] * x[i - 1];
            }
            if i + 1 < n {
                s += self.off[i] * x[i + 1];
            }
            y[i] = s;
        }
    }

    /// `xᵀ A x`.
    pub fn quad_form(&self, x: &[f64]) -> f64 {
        let n = self.diag.len();
        let mut s = 0.0;
        for i in 0..n {
            s += self.diag[i] * x[i] * x[i];
            if i + 1 < n {
                s += 2.0 * self.off[i] * x[i] * x[i + 1];
            }
        }
        s
    }

    /// Sum of all entries, `1ᵀ A 1`.
    pub fn total(&self) -> f64 {
        self.diag.iter().sum::<f64>() + 2.0 * self.off.iter().sum::<f64>()
    }

    /// LDLᵀ factorisation; fails on a pivot that is not strictly positive.
    pub fn factor(&self) -> Result<LdlT, FactorError> {
        let n = self.diag.len();
        let mut inv_d = vec![0.0; n];
        let mut l = vec![0.0; n.saturating_sub(1)];
        for i in 0..n {
            // d_i = a_ii - l_{i-1}² d_{i-1}, l_{i-1} = a_{i-1,i} / d_{i-1}
            let d = if i == 0 { self.diag[0] } else { self.diag[i] - l[i - 1] * self.off[i - 1] };
            if !(d > 0.0) || !d.is_finite() {
                return Err(FactorError::NonPositivePivot { index: i, pivot: d });
            }
            inv_d[i] = 1.0 / d;
            if i + 1 < n {
                l[i] = self.off[i] / d;
            }
        }
        Ok(LdlT { inv_d, l })
    }
}

/// `A = L D Lᵀ` with unit lower bidiagonal `L` (subdiagonal `l`) and diagonal `D` (stored inverted).
#[derive(Debug, Clone)]
pub struct LdlT {
    inv_d: Vec<f64>,
    l: Vec<f64>,
}

impl LdlT {
    pub fn len(&self) -> usize {
        self.inv_d.len()
    }

    pub fn is_empty(&self) -> bool {
        self.inv_d.is_empty()
    }

    /// Overwrites `b` with `A⁻¹ b` (no allocation).
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let n = self.inv_d.len();
        debug_assert_eq!(b.len(), n);
        for i in 1..n {
            b[i] -= self.l[i - 1] * b[i - 1];
        }
        b[n - 1] *= self.inv_d[n - 1];
        for i in (0..n - 1).rev() {
            b[i] = b[i] * self.inv_d[i] - self.l[i] * b[i + 1];
        }
    }

    /// `A⁻¹ e_k`, the response to a unit load at index k.
    pub fn unit_response(&self, k: usize) -> Vec<f64> {
        let mut e = vec![0.0; self.len()];
        e[k] = 1.0;
        self.solve_in_place(&mut e);
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solve_recovers_known_vector() {
        // A = tridiag(-1, 4, -1) is SPD; x known, b = A x, solve back.
        let n = 50;
        let a = SymTridiag { diag: vec![4.0; n], off: vec![-1.0; n - 1] };
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut b = vec![0.0; n];
        a.mul_into(&x, &mut b);
        a.factor().unwrap().solve_in_place(&mut b);
        // The condition number of A is below 3, so the error is a few ulps times n.
        let tol = 8.0 * f64::EPSILON * n as f64;
        for (p, q) in b.iter().zip(&x) {
            assert!((p - q).abs() <= tol, "{p} vs {q}");
        }
    }

    #[test]
    fn singular_matrix_reports_the_pivot() {
        let a = SymTridiag { diag: vec![1.0, 1.0, 2.0], off: vec![1.0, 0.5] };
        assert!(matches!(a.factor(), Err(FactorError::NonPositivePivot { index: 1, .. })));
    }
}
