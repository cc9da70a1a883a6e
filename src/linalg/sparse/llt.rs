//! [`SparseLlt`]: faer's supernodal sparse `LLᵀ` with an AMD ordering (optionally with chosen
//! unknowns eliminated last), its solves done in a work space allocated once (`sparse`'s module
//! docs).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::{Conj, MatMut, Par, Side};

use super::{SpMat, SparseError, principal};

/// A sparse `A = LLᵀ` (supernodal, with a fill-reducing AMD permutation) and its solve work
/// space.
///
/// Optionally a set of "trailing" unknowns T is ordered last (AMD orders the others): then the
/// last |T| columns of L hold the dense Cholesky factor `L_TT` of the Schur complement
/// `A_TT − A_TI A_II⁻¹ A_IT`, so that `(A⁻¹)_TT = L_TT⁻ᵀ L_TT⁻¹` and a right-hand side supported
/// on T changes only the trailing block of the forward substitution `L⁻¹ P b`
/// ([`SparseLlt::solve_split`]). The contact solver ([`crate::contact::Schur`]) puts the
/// contact unknowns there.
pub struct SparseLlt {
    n: usize,
    trailing: usize,
    symbolic: SymbolicCholesky<usize>,
    /// `fwd[p]` = the unknown at position p of the elimination order.
    fwd: Vec<usize>,
    values: Vec<f64>,
    /// The permuted right-hand side (n values).
    work: Vec<f64>,
    scratch: MemBuffer,
}

impl std::fmt::Debug for SparseLlt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLlt").field("n", &self.n).field("factor_nnz", &self.values.len()).finish()
    }
}

/// The elimination order: AMD on the principal submatrix without `last`, then `last` in its
/// given order. Returns `fwd` (position → unknown).
fn ordering(a: &SpMat, last: &[usize], matrix: &'static str) -> Result<Vec<usize>, SparseError> {
    let n = a.nrows();
    let mut is_last = vec![false; n];
    for &i in last {
        is_last[i] = true;
    }
    let keep: Vec<usize> = (0..n).filter(|&i| !is_last[i]).collect();
    let sub = principal(a, &keep, matrix)?;
    let m = keep.len();
    let (mut perm, mut inv) = (vec![0usize; m], vec![0usize; m]);
    if m > 0 {
        let nnz = sub.symbolic().row_idx().len();
        let mut mem = MemBuffer::new(amd::order_maybe_unsorted_scratch::<usize>(m, nnz));
        amd::order_maybe_unsorted(&mut perm, &mut inv, sub.symbolic(), Default::default(), MemStack::new(&mut mem))
            .map_err(|e| SparseError::Structure { matrix, detail: format!("{e:?}") })?;
    }
    Ok(perm.iter().map(|&p| keep[p]).chain(last.iter().copied()).collect())
}

impl SparseLlt {
    /// Symbolic analysis and numeric factorisation of the symmetric matrix `a` (its lower
    /// triangle is read). Fails if `a` is not numerically positive definite.
    pub fn new(a: &SpMat, matrix: &'static str) -> Result<Self, SparseError> {
        Self::with_trailing(a, &[], matrix)
    }

    /// The same with the distinct unknowns `last` eliminated last, in that order (type docs).
    pub fn with_trailing(a: &SpMat, last: &[usize], matrix: &'static str) -> Result<Self, SparseError> {
        let n = a.nrows();
        // The ordering and the symbolic analysis first: AMD's work space (exact) and, for the
        // principal copy and the elimination tree, 32 bytes a stored entry and 64 an unknown
        // (measured: a 600² plate's mass matrix, 3.2e6 entries, failed on a 122 MB block here).
        let nnz = a.symbolic().row_idx().len();
        let analysis =
            amd::order_maybe_unsorted_scratch::<usize>(n, nnz).size_bytes() as u64 + 32 * nnz as u64 + 64 * n as u64;
        let (limit, in_use) = (super::super::memory_limit(), super::super::memory_in_use());
        if analysis > limit.saturating_sub(in_use) {
            return Err(SparseError::AnalysisTooLarge { matrix, n, nnz, bytes: analysis, limit, in_use });
        }
        let fwd = ordering(a, last, matrix)?;
        let mut factor = Self::with_ordering(a, fwd, matrix)?;
        factor.trailing = last.len();
        Ok(factor)
    }

    /// Symbolic analysis and numeric factorisation in the given elimination order (`fwd`:
    /// position → unknown, a permutation of 0..n), no ordering computed (a principal block keeps
    /// the relative order its unknowns had in the factor of the whole matrix:
    /// [`crate::contact::layer`]).
    pub fn with_ordering(a: &SpMat, fwd: Vec<usize>, matrix: &'static str) -> Result<Self, SparseError> {
        let n = a.nrows();
        debug_assert_eq!(fwd.len(), n);
        let structure = |e: faer::sparse::FaerError| SparseError::Structure { matrix, detail: format!("{e:?}") };
        let limit = super::super::memory_limit();
        let mut inv = vec![0usize; n];
        for (p, &i) in fwd.iter().enumerate() {
            inv[i] = p;
        }
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let perm = PermRef::new_checked(&fwd, &inv, n);
        let symbolic = factorize_symbolic_cholesky(a.symbolic(), Side::Lower, SymmetricOrdering::Custom(perm), params)
            .map_err(structure)?;
        // The factor's size and the work spaces of its factorisation and its solves are exact
        // here: refuse what cannot fit in what is left of the limit before allocating them.
        let scratch = symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
        let solve_scratch = symbolic.solve_in_place_scratch::<f64>(1, Par::Seq);
        let bytes = (symbolic.len_val() as u64 + n as u64).saturating_mul(8)
            + scratch.size_bytes() as u64
            + solve_scratch.size_bytes() as u64;
        let in_use = super::super::memory_in_use();
        if bytes > limit.saturating_sub(in_use) {
            return Err(SparseError::TooLarge { matrix, n, values: symbolic.len_val(), bytes, limit, in_use });
        }
        let mut values = vec![0.0; symbolic.len_val()];
        numeric(&symbolic, &mut values, a, MemBuffer::new(scratch), matrix)?;
        let scratch = MemBuffer::new(solve_scratch);
        Ok(Self { n, trailing: 0, symbolic, fwd, values, work: vec![0.0; n], scratch })
    }

    /// The elimination order (position → unknown).
    pub fn ordering(&self) -> &[usize] {
        &self.fwd
    }

    pub fn len(&self) -> usize {
        self.n
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Stored entries of L (the fill).
    pub fn factor_len(&self) -> usize {
        self.values.len()
    }

    fn supernodal(&self) -> Option<SupernodalLltRef<'_, usize, f64>> {
        supernodal(&self.symbolic, &self.values)
    }

    /// The trailing block `L_TT` of L (T the unknowns `last` of [`Self::with_trailing`], in that
    /// order), transposed: row-major upper triangular `t × t`, `U = L_TTᵀ`.
    pub fn trailing_upper(&self) -> Vec<f64> {
        let (n, t) = (self.n, self.trailing);
        let mut u = vec![0.0; t * t];
        let Some(llt) = self.supernodal() else { return u };
        for s in 0..llt.symbolic().n_supernodes() {
            let sn = llt.supernode(s);
            let (start, val) = (sn.start(), sn.val());
            let size = val.ncols();
            if start + size <= n - t {
                continue;
            }
            // Rows of the supernode: its own columns, then its pattern.
            let rows = (start..start + size).chain(sn.pattern().iter().copied());
            for (r, i) in rows.enumerate() {
                for c in 0..size {
                    let j = start + c;
                    if j >= n - t && i >= j {
                        u[(j + t - n) * t + (i + t - n)] = val[(r, c)];
                    }
                }
            }
        }
        u
    }

    /// Overwrites the k columns of `b` (column-major, n × k) with `A⁻¹ b`: one pass through the
    /// factor for all of them, its dense kernels on k columns (many solves at once cost far less
    /// than one at a time when the factor does not stay in cache). Allocates its work space.
    pub fn solve_columns_in_place(&mut self, b: &mut [f64], k: usize) {
        let n = self.n;
        debug_assert_eq!(b.len(), n * k);
        if n == 0 || k == 0 {
            return;
        }
        let mut work = vec![0.0; n * k];
        permute_in(&self.fwd, b, &mut work);
        let mut scratch = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(k, Par::Seq));
        let llt = supernodal(&self.symbolic, &self.values);
        halves(llt, &mut work, k, &mut scratch, |_| Ok::<(), ()>(())).expect("no error without a hook");
        permute_out(&self.fwd, &work, b);
    }

    /// Overwrites `b` with `A⁻¹ b` (no allocation).
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        self.solve_split(b, |_| Ok::<(), ()>(())).expect("no error without a hook");
    }

    /// Solves `A x = b` in place in two halves: `y = L⁻¹ P b`, then `between` may change the
    /// trailing block of y (|T| values, elimination order), then `x = Pᵀ L⁻ᵀ y`. Changing the
    /// trailing block by `L_TT⁻¹ g` solves for `b + E g` instead (E the columns of T), since
    /// `L⁻¹ P E g` is zero above the trailing block. No allocation.
    pub fn solve_split<E>(
        &mut self,
        b: &mut [f64],
        between: impl FnOnce(&mut [f64]) -> Result<(), E>,
    ) -> Result<(), E> {
        debug_assert_eq!(b.len(), self.n);
        let Self { n, trailing, symbolic, fwd, values, work, scratch } = self;
        let start = *n - *trailing;
        permute_in(fwd, b, work);
        let result = halves(supernodal(symbolic, values), work, 1, scratch, |y| between(&mut y[start..]));
        permute_out(fwd, work, b);
        result
    }
}

/// `work ← P b` column by column (n × k column-major blocks, n = `fwd.len()`; nothing for n = 0).
fn permute_in(fwd: &[usize], b: &[f64], work: &mut [f64]) {
    if fwd.is_empty() {
        return;
    }
    for (w, x) in work.chunks_exact_mut(fwd.len()).zip(b.chunks_exact(fwd.len())) {
        for (w, &i) in w.iter_mut().zip(fwd) {
            *w = x[i];
        }
    }
}

/// `b ← Pᵀ work` column by column (the inverse of [`permute_in`]).
fn permute_out(fwd: &[usize], work: &[f64], b: &mut [f64]) {
    if fwd.is_empty() {
        return;
    }
    for (w, x) in work.chunks_exact(fwd.len()).zip(b.chunks_exact_mut(fwd.len())) {
        for (w, &i) in w.iter().zip(fwd) {
            x[i] = *w;
        }
    }
}

/// `x ← L⁻ᵀ between(L⁻¹ x)` on the n × k column-major block `x` (elimination order, n =
/// `x.len() / k`); `between` sees the whole block after the forward solve. Without a factor
/// (n = 0) only `between` runs.
fn halves<E>(
    llt: Option<SupernodalLltRef<'_, usize, f64>>,
    x: &mut [f64],
    k: usize,
    scratch: &mut MemBuffer,
    between: impl FnOnce(&mut [f64]) -> Result<(), E>,
) -> Result<(), E> {
    let Some(llt) = llt else { return between(x) };
    let n = x.len() / k;
    llt.l_solve_with_conj(Conj::No, MatMut::from_column_major_slice_mut(x, n, k), Par::Seq, MemStack::new(scratch));
    let result = between(x);
    llt.l_transpose_solve_with_conj(
        Conj::No,
        MatMut::from_column_major_slice_mut(x, n, k),
        Par::Seq,
        MemStack::new(scratch),
    );
    result
}

/// The numeric factorisation of `a` into `values` on the symbolic analysis `symbolic`, with its
/// work space `work`.
fn numeric(
    symbolic: &SymbolicCholesky<usize>,
    values: &mut [f64],
    a: &SpMat,
    mut work: MemBuffer,
    matrix: &'static str,
) -> Result<(), SparseError> {
    symbolic
        .factorize_numeric_llt(
            values,
            a.as_ref(),
            Side::Lower,
            Default::default(),
            Par::Seq,
            MemStack::new(&mut work),
            Default::default(),
        )
        .map(|_| ())
        .map_err(|e| match e {
            faer::linalg::solvers::LltError::NonPositivePivot { index } => {
                SparseError::NotPositiveDefinite { matrix, index }
            }
        })
}

/// The supernodal factor, None only for n = 0 (faer picks the simplicial variant when the flop
/// ratio is 0/0).
fn supernodal<'a>(
    symbolic: &'a SymbolicCholesky<usize>,
    values: &'a [f64],
) -> Option<SupernodalLltRef<'a, usize, f64>> {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(s) => Some(SupernodalLltRef::new(s, values)),
        SymbolicCholeskyRaw::Simplicial(_) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::super::{from_triplets, sym_mul_into};
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
