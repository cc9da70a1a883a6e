//! Sparse symmetric matrices (faer's `SparseColMat`) and a sparse Cholesky factor that solves
//! without allocating.
//!
//! Every matrix of the 2D problem (M, S, M + β Δt² S, …) is symmetric, so its compressed
//! sparse column arrays are also its compressed sparse row arrays: column j lists the entries
//! of row j. Products are computed row by row as gathers (`y_j = Σ_k a_jk x_k`), which needs
//! no zeroing and no scatter.
//!
//! [`SparseLlt`] wraps faer 0.24's sparse `LLᵀ` (`faer::sparse::linalg::cholesky`): an AMD
//! ordering and symbolic analysis, then one numeric factorisation, both done once per
//! (system, Δt). The high-level `Llt::solve_in_place` of faer allocates its work space on every
//! call; here the work space (`solve_in_place_scratch`) is allocated once and reused, so the
//! time loop does not allocate.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Par, Side};
use thiserror::Error;

/// A sparse matrix with `usize` indices and `f64` values.
pub type SpMat = SparseColMat<usize, f64>;

/// Failure to build or factor a sparse matrix.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SparseError {
    #[error(
        "the {matrix} matrix is not positive definite: the sparse Cholesky factorisation met a non-positive pivot at (permuted) index {index}"
    )]
    NotPositiveDefinite { matrix: &'static str, index: usize },
    #[error("the {matrix} matrix cannot be built or analysed: {detail}")]
    Structure { matrix: &'static str, detail: String },
}

/// Builds an `n × n` matrix from triplets, summing duplicates (finite-element assembly).
pub fn from_triplets(n: usize, triplets: &[(usize, usize, f64)], matrix: &'static str) -> Result<SpMat, SparseError> {
    let t: Vec<Triplet<usize, usize, f64>> = triplets.iter().map(|&(i, j, v)| Triplet::new(i, j, v)).collect();
    SpMat::try_new_from_triplets(n, n, &t).map_err(|e| SparseError::Structure { matrix, detail: format!("{e:?}") })
}

/// The entries `(i, j, a_ij)` of a matrix, column by column.
pub fn triplets(a: &SpMat) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
    let (ptr, idx, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    (0..a.ncols()).flat_map(move |j| (ptr[j]..ptr[j + 1]).map(move |k| (idx[k], j, val[k])))
}

/// `ca·A + cb·B` (union of the patterns).
pub fn combine(a: &SpMat, ca: f64, b: &SpMat, cb: f64, matrix: &'static str) -> Result<SpMat, SparseError> {
    let t: Vec<(usize, usize, f64)> =
        triplets(a).map(|(i, j, v)| (i, j, ca * v)).chain(triplets(b).map(|(i, j, v)| (i, j, cb * v))).collect();
    from_triplets(a.nrows(), &t, matrix)
}

/// The principal submatrix on the index set `keep` (in that order).
pub fn principal(a: &SpMat, keep: &[usize], matrix: &'static str) -> Result<SpMat, SparseError> {
    let mut new = vec![usize::MAX; a.nrows()];
    for (k, &i) in keep.iter().enumerate() {
        new[i] = k;
    }
    let t: Vec<(usize, usize, f64)> = triplets(a)
        .filter(|&(i, j, _)| new[i] != usize::MAX && new[j] != usize::MAX)
        .map(|(i, j, v)| (new[i], new[j], v))
        .collect();
    from_triplets(keep.len(), &t, matrix)
}

/// Entry (i, j), 0 outside the pattern.
pub fn get(a: &SpMat, i: usize, j: usize) -> f64 {
    let (ptr, idx) = (a.symbolic().col_ptr(), a.symbolic().row_idx());
    let rows = &idx[ptr[j]..ptr[j + 1]];
    match rows.binary_search(&i) {
        Ok(k) => a.val()[ptr[j] + k],
        Err(_) => 0.0,
    }
}

/// The dense matrix, row by row (for small cross-checks and tests).
pub fn to_dense(a: &SpMat) -> Vec<Vec<f64>> {
    let mut d = vec![vec![0.0; a.ncols()]; a.nrows()];
    for (i, j, v) in triplets(a) {
        d[i][j] += v;
    }
    d
}

/// Compressed sparse row arrays `(indptr, indices, data)` of a symmetric matrix (its CSC arrays).
pub fn csr_arrays(a: &SpMat) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    (a.symbolic().col_ptr().to_vec(), a.symbolic().row_idx().to_vec(), a.val().to_vec())
}

/// `y = A x` for symmetric A (row j of A is column j).
pub fn sym_mul_into(a: &SpMat, x: &[f64], y: &mut [f64]) {
    let (ptr, idx, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    debug_assert!(x.len() == a.ncols() && y.len() == a.nrows());
    for (j, yj) in y.iter_mut().enumerate() {
        let mut s = 0.0;
        for k in ptr[j]..ptr[j + 1] {
            s += val[k] * x[idx[k]];
        }
        *yj = s;
    }
}

/// `xᵀ A x`.
pub fn quad_form(a: &SpMat, x: &[f64]) -> f64 {
    let (ptr, idx, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    let mut s = 0.0;
    for (j, &xj) in x.iter().enumerate() {
        let mut r = 0.0;
        for k in ptr[j]..ptr[j + 1] {
            r += val[k] * x[idx[k]];
        }
        s += xj * r;
    }
    s
}

/// Sum of all entries, `1ᵀ A 1`.
pub fn total(a: &SpMat) -> f64 {
    a.val().iter().sum()
}

/// A sparse `A = LLᵀ` (with a fill-reducing AMD permutation) and its solve work space.
pub struct SparseLlt {
    n: usize,
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    scratch: MemBuffer,
}

impl std::fmt::Debug for SparseLlt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLlt").field("n", &self.n).field("factor_nnz", &self.values.len()).finish()
    }
}

impl SparseLlt {
    /// Symbolic analysis and numeric factorisation of the symmetric matrix `a` (its lower
    /// triangle is read). Fails if `a` is not numerically positive definite.
    pub fn new(a: &SpMat, matrix: &'static str) -> Result<Self, SparseError> {
        let n = a.nrows();
        let structure = |e: faer::sparse::FaerError| SparseError::Structure { matrix, detail: format!("{e:?}") };
        let symbolic =
            factorize_symbolic_cholesky(a.symbolic(), Side::Lower, SymmetricOrdering::Amd, Default::default())
                .map_err(structure)?;
        let mut values = vec![0.0; symbolic.len_val()];
        let mut work = MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()));
        symbolic
            .factorize_numeric_llt(
                &mut values,
                a.as_ref(),
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut work),
                Default::default(),
            )
            .map_err(|e| match e {
                faer::linalg::solvers::LltError::NonPositivePivot { index } => {
                    SparseError::NotPositiveDefinite { matrix, index }
                }
            })?;
        let scratch = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        Ok(Self { n, symbolic, values, scratch })
    }

    pub fn len(&self) -> usize {
        self.n
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Overwrites the `ncols` columns of `b` (column-major, `n` values each) with `A⁻¹ b`: one
    /// blocked solve (faer's supernodal kernels work on all columns at once). Allocates its work
    /// space: meant for set-up, not for the time loop.
    pub fn solve_many_in_place(&self, b: &mut [f64], ncols: usize) {
        debug_assert_eq!(b.len(), self.n * ncols);
        let mut work = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(ncols, Par::Seq));
        let rhs = MatMut::from_column_major_slice_mut(b, self.n, ncols);
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut work),
        );
    }

    /// Overwrites `b` with `A⁻¹ b` (no allocation).
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        debug_assert_eq!(b.len(), self.n);
        let rhs = MatMut::from_column_major_slice_mut(b, self.n, 1);
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.scratch),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_solves_a_laplacian() {
        // 1D Laplacian tridiag(−1, 2, −1) + I (SPD, condition number < 5).
        let n = 30;
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 3.0));
            if i + 1 < n {
                t.push((i, i + 1, -1.0));
                t.push((i + 1, i, -1.0));
            }
        }
        let a = from_triplets(n, &t, "test").unwrap();
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.3).cos()).collect();
        let mut b = vec![0.0; n];
        sym_mul_into(&a, &x, &mut b);
        let mut f = SparseLlt::new(&a, "test").unwrap();
        f.solve_in_place(&mut b);
        // Backward-stable solve, condition number < 5: a few ulps times n.
        for (p, q) in b.iter().zip(&x) {
            assert!((p - q).abs() <= 8.0 * f64::EPSILON * n as f64, "{p} vs {q}");
        }
    }

    #[test]
    fn indefinite_matrix_is_reported() {
        let a = from_triplets(2, &[(0, 0, 1.0), (0, 1, 2.0), (1, 0, 2.0), (1, 1, 1.0)], "test").unwrap();
        assert!(matches!(SparseLlt::new(&a, "test"), Err(SparseError::NotPositiveDefinite { .. })));
    }
}
