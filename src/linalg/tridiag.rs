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

    /// The principal submatrix on rows and columns `..end`.
    pub fn leading(&self, end: usize) -> SymTridiag {
        SymTridiag { diag: self.diag[..end].to_vec(), off: self.off[..end.saturating_sub(1)].to_vec() }
    }

    /// The principal submatrix on rows and columns `start..`.
    pub fn trailing(&self, start: usize) -> SymTridiag {
        SymTridiag { diag: self.diag[start..].to_vec(), off: self.off[start.min(self.off.len())..].to_vec() }
    }

    /// `y = A x`.
    pub fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        self.mul_add_into(x, 0.0, None, y);
    }

    /// `y = A x + c f` in one pass (f = 0 if `None`). The interior rows run without branches or
    /// bounds checks so that the loop vectorises; every row sums `a_ii x_i + a_{i,i−1} x_{i−1} +
    /// a_{i,i+1} x_{i+1}` in that order, as [`Self::mul_row`] does, then adds `c f_i`.
    pub fn mul_add_into(&self, x: &[f64], c: f64, f: Option<&[f64]>, y: &mut [f64]) {
        let n = self.diag.len();
        assert!(x.len() == n && y.len() == n && f.is_none_or(|f| f.len() == n), "vector lengths");
        let fi = |i: usize| f.map_or(0.0, |f| c * f[i]);
        if n < 3 {
            for i in 0..n {
                y[i] = self.mul_row(x, i) + fi(i);
            }
            return;
        }
        let (d, o, x, y) = (&self.diag[..n], &self.off[..n - 1], &x[..n], &mut y[..n]);
        y[0] = self.mul_row(x, 0) + fi(0);
        match f {
            None => {
                for i in 1..n - 1 {
                    y[i] = d[i] * x[i] + o[i - 1] * x[i - 1] + o[i] * x[i + 1];
                }
            }
            Some(f) => {
                let f = &f[..n];
                for i in 1..n - 1 {
                    y[i] = d[i] * x[i] + o[i - 1] * x[i - 1] + o[i] * x[i + 1] + c * f[i];
                }
            }
        }
        y[n - 1] = self.mul_row(x, n - 1) + fi(n - 1);
    }

    /// `y = A x + b B z + c f` in one pass (B = `other`, with its vector z), each row summed as
    /// `(A x)_i + b (B z)_i + c f_i`.
    #[allow(clippy::too_many_arguments)]
    pub fn mul2_add_into(&self, x: &[f64], other: &SymTridiag, b: f64, z: &[f64], c: f64, f: &[f64], y: &mut [f64]) {
        let n = self.diag.len();
        assert!(x.len() == n && y.len() == n && z.len() == n && f.len() == n && other.len() == n, "lengths");
        if n < 3 {
            for i in 0..n {
                y[i] = self.mul_row(x, i) + b * other.mul_row(z, i) + c * f[i];
            }
            return;
        }
        let (d, o, x, y) = (&self.diag[..n], &self.off[..n - 1], &x[..n], &mut y[..n]);
        let (bd, bo, z, f) = (&other.diag[..n], &other.off[..n - 1], &z[..n], &f[..n]);
        y[0] = self.mul_row(x, 0) + b * other.mul_row(z, 0) + c * f[0];
        for i in 1..n - 1 {
            y[i] = (d[i] * x[i] + o[i - 1] * x[i - 1] + o[i] * x[i + 1])
                + b * (bd[i] * z[i] + bo[i - 1] * z[i - 1] + bo[i] * z[i + 1])
                + c * f[i];
        }
        y[n - 1] = self.mul_row(x, n - 1) + b * other.mul_row(z, n - 1) + c * f[n - 1];
    }

    /// Row i of `A x`, `(A x)_i`.
    #[inline]
    pub fn mul_row(&self, x: &[f64], i: usize) -> f64 {
        let mut s = self.diag[i] * x[i];
        if i > 0 {
            s += self.off[i - 1] * x[i - 1];
        }
        if i + 1 < self.diag.len() {
            s += self.off[i] * x[i + 1];
        }
        s
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

/// Two-sided ("burn at both ends", twisted) factorisation `A = N_k D_k N_kᵀ` of a symmetric
/// positive definite tridiagonal matrix, twisted at `k ≈ n/2`.
///
/// Rows `0..k` are eliminated from the top (`d_0 = a_0`, `l_i = b_i/d_i`,
/// `d_{i+1} = a_{i+1} − l_i b_i`), rows `n−1..k` from the bottom (`e_{n−1} = a_{n−1}`,
/// `r_i = b_{i−1}/e_i`, `e_{i−1} = a_{i−1} − r_i b_{i−1}`), and the twist pivot is
/// `γ_k = a_k − l_{k−1} b_{k−1} − r_{k+1} b_k` (both Schur complements meet at row k). A solve
/// then runs two independent substitution chains of length ≈ n/2 instead of one of length n,
/// in both sweeps, so a latency-bound core finishes it in about half the time of [`LdlT`]
/// (Parlett & Dhillon's twisted factorisations; for SPD A every pivot is a positive Schur
/// complement, so it is as stable as LDLᵀ). The results equal LDLᵀ's up to round-off.
///
/// With fused multiply-add (detected at run time on x86-64) each link of a chain is one
/// instruction; see [`Self::solve_in_place`].
#[derive(Debug, Clone)]
pub struct TwistedFactor {
    twist: usize,
    /// `l_i` for i < k, `r_i` for i > k (unused at k).
    mult: Vec<f64>,
    /// `1/d_i` for i < k, `1/γ_k` at k, `1/e_i` for i > k.
    inv_piv: Vec<f64>,
}

impl SymTridiag {
    /// The twisted factorisation ([`TwistedFactor`]); fails on a pivot that is not strictly
    /// positive (the index is the row whose pivot failed).
    pub fn factor_twisted(&self) -> Result<TwistedFactor, FactorError> {
        let n = self.diag.len();
        let (a, b) = (&self.diag, &self.off);
        // Top chain has k rows (0..k), bottom chain n−1−k rows (k+1..n); the bottom gets the
        // extra row when n is even, matching the sweep loops below.
        let k = n.saturating_sub(1) / 2;
        let mut mult = vec![0.0; n];
        let mut inv_piv = vec![0.0; n];
        let check = |index: usize, pivot: f64| {
            if pivot > 0.0 && pivot.is_finite() {
                Ok(pivot)
            } else {
                Err(FactorError::NonPositivePivot { index, pivot })
            }
        };
        for i in 0..k {
            let d = check(i, if i == 0 { a[0] } else { a[i] - mult[i - 1] * b[i - 1] })?;
            inv_piv[i] = 1.0 / d;
            mult[i] = b[i] / d;
        }
        for i in (k + 1..n).rev() {
            let e = check(i, if i == n - 1 { a[i] } else { a[i] - mult[i + 1] * b[i] })?;
            inv_piv[i] = 1.0 / e;
            mult[i] = b[i - 1] / e;
        }
        if n > 0 {
            let mut g = a[k];
            if k > 0 {
                g -= mult[k - 1] * b[k - 1];
            }
            if k + 1 < n {
                g -= mult[k + 1] * b[k];
            }
            inv_piv[k] = 1.0 / check(k, g)?;
        }
        Ok(TwistedFactor { twist: k, mult, inv_piv })
    }
}

impl TwistedFactor {
    pub fn len(&self) -> usize {
        self.inv_piv.len()
    }

    pub fn is_empty(&self) -> bool {
        self.inv_piv.is_empty()
    }

    /// The twist row k.
    pub fn twist(&self) -> usize {
        self.twist
    }

    /// Overwrites `b` with `A⁻¹ b` (no allocation): forward elimination from both ends towards
    /// the twist, then back substitution outwards from it.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU supports FMA (checked on the line above).
            return unsafe { self.solve_fma(b) };
        }
        self.solve_impl::<false>(b)
    }

    /// [`Self::solve_in_place`] without fused multiply-add even where the CPU has it (for
    /// benchmarks: separates the gain of the two chains from the gain of FMA).
    pub fn solve_in_place_without_fma(&self, b: &mut [f64]) {
        self.solve_impl::<false>(b)
    }

    /// `A⁻¹ e_k`, the response to a unit load at index k.
    pub fn unit_response(&self, k: usize) -> Vec<f64> {
        let mut e = vec![0.0; self.len()];
        e[k] = 1.0;
        self.solve_in_place(&mut e);
        e
    }

    // The substitution chains are latency-bound: each link is `c − a·b` on the previous value.
    // With FMA that is one fused instruction (4 cycles of latency instead of 8 for a multiply then
    // a subtraction, and one rounding instead of two, so results differ from the plain form in
    // the last bits only). x86-64's baseline has no FMA, so the sweeps are compiled twice and
    // the FMA form is chosen at run time when the CPU has it.

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "fma")]
    fn solve_fma(&self, b: &mut [f64]) {
        self.solve_impl::<true>(b)
    }

    #[inline(always)]
    fn solve_impl<const FMA: bool>(&self, y: &mut [f64]) {
        let n = self.inv_piv.len();
        assert_eq!(y.len(), n, "right-hand side length");
        if n == 0 {
            return;
        }
        let k = self.twist;
        let nb = n - 1 - k; // rows below the twist, ≥ k (rows above it)
        let (mult, inv) = (&self.mult[..n], &self.inv_piv[..n]);
        // Forward: y_i −= l_{i−1} y_{i−1} (i = 1..k−1) and y_i −= r_{i+1} y_{i+1} (i = n−2..k+1),
        // the two chains interleaved; each carries its last value in a register.
        let (mut top, mut bot) = (y[0], y[n - 1]);
        for j in 1..k {
            let (i, ib) = (j, n - 1 - j);
            top = nmul_add::<FMA>(mult[i - 1], top, y[i]);
            bot = nmul_add::<FMA>(mult[ib + 1], bot, y[ib]);
            y[i] = top;
            y[ib] = bot;
        }
        for j in k.max(1)..nb {
            let ib = n - 1 - j;
            bot = nmul_add::<FMA>(mult[ib + 1], bot, y[ib]);
            y[ib] = bot;
        }
        // Twist row: both eliminated neighbours enter, x_k = (y_k − l_{k−1} y_{k−1} − r_{k+1} y_{k+1})/γ_k.
        let mut g = y[k];
        if k > 0 {
            g -= mult[k - 1] * y[k - 1];
        }
        if k + 1 < n {
            g -= mult[k + 1] * y[k + 1];
        }
        y[k] = g * inv[k];
        // Back: x_i = y_i/d_i − l_i x_{i+1} (i < k), x_i = y_i/e_i − r_i x_{i−1} (i > k).
        let (mut top, mut bot) = (y[k], y[k]);
        for j in 1..=k {
            let (i, ib) = (k - j, k + j);
            top = nmul_add::<FMA>(mult[i], top, y[i] * inv[i]);
            bot = nmul_add::<FMA>(mult[ib], bot, y[ib] * inv[ib]);
            y[i] = top;
            y[ib] = bot;
        }
        for j in k + 1..=nb {
            let ib = k + j;
            bot = nmul_add::<FMA>(mult[ib], bot, y[ib] * inv[ib]);
            y[ib] = bot;
        }
    }
}

/// `c − a·b`, fused (one rounding) when `FMA` (only instantiated inside FMA-enabled code).
#[inline(always)]
fn nmul_add<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA { (-a).mul_add(b, c) } else { c - a * b }
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

    /// A reproducible SPD tridiagonal matrix with varied entries (diagonally dominant).
    fn spd(n: usize, seed: u64) -> SymTridiag {
        let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % 1_000_000) as f64 / 1_000_000.0
        };
        let off: Vec<f64> = (0..n.saturating_sub(1)).map(|_| next() * 2.0 - 1.0).collect();
        let diag = (0..n)
            .map(|i| {
                let left = if i > 0 { off[i - 1].abs() } else { 0.0 };
                let right = if i + 1 < n { off[i].abs() } else { 0.0 };
                left + right + 0.1 + next()
            })
            .collect();
        SymTridiag { diag, off }
    }

    #[test]
    fn twisted_solve_matches_ldlt() {
        for n in (1..=12).chain([999, 1000, 1001]) {
            let a = spd(n, n as u64);
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.71).cos()).collect();
            let mut x1 = b.clone();
            a.factor().unwrap().solve_in_place(&mut x1);
            let tw = a.factor_twisted().unwrap();
            let mut x2 = b.clone();
            tw.solve_in_place(&mut x2);
            let mut x4 = b.clone();
            tw.solve_in_place_without_fma(&mut x4);
            // Diagonal dominance ≥ 0.1 bounds ‖A⁻¹‖ ≤ 10 and κ ≤ ~40: a few ulps times n.
            let tol = 64.0 * f64::EPSILON * n as f64;
            for i in 0..n {
                assert!((x1[i] - x2[i]).abs() <= tol * x1[i].abs().max(1.0), "n={n} i={i}: {} vs {}", x1[i], x2[i]);
                assert!((x4[i] - x2[i]).abs() <= tol * x1[i].abs().max(1.0), "n={n} i={i}: FMA and plain sweeps");
            }
            // Residual check of the twisted solution itself.
            let mut r = vec![0.0; n];
            a.mul_into(&x2, &mut r);
            for i in 0..n {
                assert!((r[i] - b[i]).abs() <= tol, "n={n} i={i}: residual {}", r[i] - b[i]);
            }
        }
    }

    #[test]
    fn twisted_factor_reports_a_bad_pivot() {
        let a = SymTridiag { diag: vec![1.0, 1.0, 2.0], off: vec![1.0, 0.5] };
        assert!(matches!(a.factor_twisted(), Err(FactorError::NonPositivePivot { .. })));
        let neg = SymTridiag { diag: vec![1.0, -1.0, 1.0, 1.0], off: vec![0.0; 3] };
        assert!(matches!(neg.factor_twisted(), Err(FactorError::NonPositivePivot { index: 1, .. })));
    }
}
