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
use faer::perm::PermRef;
use faer::sparse::SparseColMat;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering, factorize_symbolic_cholesky,
};
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
    /// The factor's size is known from the symbolic analysis, before it is allocated; `bytes`
    /// counts its values and its factorisation's work space, against the limit less what the
    /// process holds already (`in_use`).
    #[error(
        "the Cholesky factor of the {matrix} matrix ({n} unknowns) would take {values} values ({gb:.2} GB with its work spaces), over the {left_gb:.2} GB left of the memory limit of {limit_gb:.2} GB (the available memory, or `ulimit -v`; the run holds {in_use_gb:.2} GB already)",
        gb = *bytes as f64 / 1e9, limit_gb = *limit as f64 / 1e9, in_use_gb = *in_use as f64 / 1e9,
        left_gb = limit.saturating_sub(*in_use) as f64 / 1e9
    )]
    TooLarge { matrix: &'static str, n: usize, values: usize, bytes: u64, limit: u64, in_use: u64 },
    /// The ordering and symbolic analysis of the matrix (`nnz` stored entries) would not fit.
    #[error(
        "ordering the {matrix} matrix ({n} unknowns, {nnz} stored entries) for its Cholesky factor would take {gb:.2} GB, over the {left_gb:.2} GB left of the memory limit of {limit_gb:.2} GB (the available memory, or `ulimit -v`; the run holds {in_use_gb:.2} GB already)",
        gb = *bytes as f64 / 1e9, limit_gb = *limit as f64 / 1e9, in_use_gb = *in_use as f64 / 1e9,
        left_gb = limit.saturating_sub(*in_use) as f64 / 1e9
    )]
    AnalysisTooLarge { matrix: &'static str, n: usize, nnz: usize, bytes: u64, limit: u64, in_use: u64 },
}

/// Builds an `n × n` matrix from triplets, summing duplicates (finite-element assembly) in
/// the order given.
pub fn from_triplets(n: usize, triplets: &[(usize, usize, f64)], matrix: &'static str) -> Result<SpMat, SparseError> {
    let pattern = Pattern::new(n, triplets.iter().map(|&(i, j, _)| (i, j)), matrix)?;
    let values: Vec<f64> = triplets.iter().map(|t| t.2).collect();
    Ok(pattern.assemble(&values))
}

/// The compressed pattern of a list of entry positions `(i, j)` (duplicates allowed) and where
/// each position lands, so that several matrices with the same positions (mass and stiffness
/// of one mesh) are assembled with one sort. Built by two stable counting sorts (by row, then
/// by column): O(n + nnz), no comparison sort.
#[derive(Debug, Clone)]
pub struct Pattern {
    n: usize,
    /// Entries per column (`col_ptr[j + 1]`), turned into offsets by [`from_columns`].
    col_counts: Vec<usize>,
    row_idx: Vec<usize>,
    /// Position t of the input → its stored entry.
    slot: Vec<usize>,
}

impl Pattern {
    pub fn new(
        n: usize,
        positions: impl Iterator<Item = (usize, usize)>,
        matrix: &'static str,
    ) -> Result<Self, SparseError> {
        let pos: Vec<(usize, usize)> = positions.collect();
        if let Some(&(i, j)) = pos.iter().find(|&&(i, j)| i >= n || j >= n) {
            let detail = format!("entry ({i}, {j}) is outside the {n} × {n} matrix");
            return Err(SparseError::Structure { matrix, detail });
        }
        let bucket = |order: &[usize], key: &dyn Fn(usize) -> usize| {
            let mut start = vec![0usize; n + 1];
            for &t in order {
                start[key(t) + 1] += 1;
            }
            for k in 0..n {
                start[k + 1] += start[k];
            }
            let mut out = vec![0usize; order.len()];
            for &t in order {
                let k = key(t);
                out[start[k]] = t;
                start[k] += 1;
            }
            out
        };
        let by_row = bucket(&(0..pos.len()).collect::<Vec<_>>(), &|t| pos[t].0);
        let sorted = bucket(&by_row, &|t| pos[t].1);
        let mut col_counts = vec![0usize; n + 1];
        let (mut row_idx, mut slot) = (Vec::with_capacity(pos.len()), vec![0usize; pos.len()]);
        let mut last = (usize::MAX, usize::MAX);
        for &t in &sorted {
            let (i, j) = pos[t];
            if (i, j) != last {
                row_idx.push(i);
                col_counts[j + 1] += 1;
                last = (i, j);
            }
            slot[t] = row_idx.len() - 1;
        }
        Ok(Self { n, col_counts, row_idx, slot })
    }

    /// The matrix with value `values[t]` added at position t (in input order).
    pub fn assemble(&self, values: &[f64]) -> SpMat {
        assert_eq!(values.len(), self.slot.len(), "one value per position");
        let mut val = vec![0.0; self.row_idx.len()];
        for (&k, &v) in self.slot.iter().zip(values) {
            val[k] += v;
        }
        from_columns(self.n, self.col_counts.clone(), self.row_idx.clone(), val)
    }
}

/// The matrix from per-column entry counts (`col_ptr[j + 1]` = entries of column j) and the
/// rows and values column by column, rows increasing.
fn from_columns(n: usize, mut col_ptr: Vec<usize>, row_idx: Vec<usize>, val: Vec<f64>) -> SpMat {
    for j in 0..n {
        col_ptr[j + 1] += col_ptr[j];
    }
    SpMat::new(faer::sparse::SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx), val)
}

/// The matrix from compressed columns (`col_ptr` cumulative, n + 1 entries; rows increasing
/// within a column).
pub fn from_csc(n: usize, col_ptr: Vec<usize>, row_idx: Vec<usize>, val: Vec<f64>) -> SpMat {
    SpMat::new(faer::sparse::SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx), val)
}

/// The entries `(i, j, a_ij)` of a matrix, column by column.
pub fn triplets(a: &SpMat) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
    let (ptr, idx, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    (0..a.ncols()).flat_map(move |j| (ptr[j]..ptr[j + 1]).map(move |k| (idx[k], j, val[k])))
}

/// `ca·A + cb·B` (union of the patterns), merging the sorted columns.
pub fn combine(a: &SpMat, ca: f64, b: &SpMat, cb: f64, _matrix: &'static str) -> Result<SpMat, SparseError> {
    let n = a.nrows();
    let (pa, ia, va) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    let (pb, ib, vb) = (b.symbolic().col_ptr(), b.symbolic().row_idx(), b.val());
    let mut col_ptr = vec![0usize; n + 1];
    let cap = ia.len().max(ib.len());
    let (mut row_idx, mut val) = (Vec::with_capacity(cap), Vec::with_capacity(cap));
    for j in 0..n {
        let (mut p, mut q) = (pa[j], pb[j]);
        let before = row_idx.len();
        while p < pa[j + 1] || q < pb[j + 1] {
            let ra = if p < pa[j + 1] { ia[p] } else { usize::MAX };
            let rb = if q < pb[j + 1] { ib[q] } else { usize::MAX };
            let r = ra.min(rb);
            let mut v = 0.0;
            if ra == r {
                v += ca * va[p];
                p += 1;
            }
            if rb == r {
                v += cb * vb[q];
                q += 1;
            }
            row_idx.push(r);
            val.push(v);
        }
        col_ptr[j + 1] = row_idx.len() - before;
    }
    Ok(from_columns(n, col_ptr, row_idx, val))
}

/// The principal submatrix on the index set `keep` (in that order).
pub fn principal(a: &SpMat, keep: &[usize], _matrix: &'static str) -> Result<SpMat, SparseError> {
    let mut new = vec![usize::MAX; a.nrows()];
    for (k, &i) in keep.iter().enumerate() {
        new[i] = k;
    }
    let (ptr, idx, v) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    let m = keep.len();
    let mut col_ptr = vec![0usize; m + 1];
    // Allocated once at its size (a growing vector holds up to twice its entries at the peak).
    let kept = |j: usize| idx[ptr[j]..ptr[j + 1]].iter().filter(|&&i| new[i] != usize::MAX).count();
    let nnz = keep.iter().map(|&j| kept(j)).sum();
    let (mut row_idx, mut val) = (Vec::with_capacity(nnz), Vec::with_capacity(nnz));
    let mut column: Vec<(usize, f64)> = Vec::new();
    for (k, &j) in keep.iter().enumerate() {
        column.clear();
        column.extend((ptr[j]..ptr[j + 1]).filter(|&p| new[idx[p]] != usize::MAX).map(|p| (new[idx[p]], v[p])));
        // Already increasing when `keep` is; otherwise a small per-column sort.
        if column.windows(2).any(|w| w[0].0 > w[1].0) {
            column.sort_unstable_by_key(|e| e.0);
        }
        row_idx.extend(column.iter().map(|e| e.0));
        val.extend(column.iter().map(|e| e.1));
        col_ptr[k + 1] = column.len();
    }
    Ok(from_columns(m, col_ptr, row_idx, val))
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

/// Rows per rayon task of [`par_sym_mul_into`] (about 1e5 stored entries in 3D, 3e4 in 2D:
/// large enough that scheduling is negligible against the gathers).
pub const PAR_ROWS: usize = 4096;

/// `y = A x` for symmetric A with rows split among rayon's threads ([`PAR_ROWS`] per task).
/// Each `y_j` is the same gather as in [`sym_mul_into`], summed in the same order, so the result
/// is bit-identical to the sequential product whatever the number of threads (the explicit
/// scheme uses it; the implicit ones keep [`sym_mul_into`]).
pub fn par_sym_mul_into(a: &SpMat, x: &[f64], y: &mut [f64]) {
    use rayon::prelude::*;
    let (ptr, idx, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    debug_assert!(x.len() == a.ncols() && y.len() == a.nrows());
    y.par_chunks_mut(PAR_ROWS).enumerate().for_each(|(c, ys)| {
        for (r, yj) in ys.iter_mut().enumerate() {
            let j = c * PAR_ROWS + r;
            let mut s = 0.0;
            for k in ptr[j]..ptr[j + 1] {
                s += val[k] * x[idx[k]];
            }
            *yj = s;
        }
    });
}

/// A symmetric sparse matrix whose columns are stored as runs of consecutive rows: for each
/// run its first row (u32) and length, the values in the same order as the compressed
/// columns. Vector fields interleaved per node give runs of d rows (d·k where k neighbouring
/// nodes are numbered consecutively: 9 runs of 9 per column of a structured hex mesh), so the
/// row indices take about 8 bytes per run instead of 8 per entry: a product streams ~45% fewer
/// bytes in 3D (the explicit scheme is bound by memory bandwidth). Each `y_j` is summed in the
/// same order as [`sym_mul_into`]: the products are equal bit for bit.
#[derive(Debug, Clone)]
pub struct RunMat {
    val: Vec<f64>,
    /// Column j's values start at `val_ptr[j]`, its runs at `run_ptr[j]`.
    val_ptr: Vec<usize>,
    run_ptr: Vec<usize>,
    /// (first row, length) of each run.
    runs: Vec<(u32, u32)>,
}

impl RunMat {
    /// From a compressed-column matrix (its values copied); None if it has more than u32::MAX
    /// rows.
    pub fn new(a: &SpMat) -> Option<Self> {
        let (ptr, idx) = (a.symbolic().col_ptr(), a.symbolic().row_idx());
        let (val_ptr, run_ptr, runs) = Self::runs_of(a.nrows(), ptr, idx)?;
        Some(Self { val: a.val().to_vec(), val_ptr, run_ptr, runs })
    }

    /// From a matrix it takes over (its values moved, its row indices dropped: no second copy);
    /// Err(a) if it has more than u32::MAX rows.
    pub fn from_owned(a: SpMat) -> Result<Self, SpMat> {
        let n = a.nrows();
        let Some((val_ptr, run_ptr, runs)) = Self::runs_of(n, a.symbolic().col_ptr(), a.symbolic().row_idx()) else {
            return Err(a);
        };
        let (_, val) = a.into_parts();
        Ok(Self { val, val_ptr, run_ptr, runs })
    }

    /// The column pointers, run pointers and runs of a pattern.
    #[allow(clippy::type_complexity)]
    fn runs_of(n: usize, ptr: &[usize], idx: &[usize]) -> Option<(Vec<usize>, Vec<usize>, Vec<(u32, u32)>)> {
        u32::try_from(n).ok()?;
        let mut run_ptr = Vec::with_capacity(n + 1);
        let mut runs: Vec<(u32, u32)> = Vec::new();
        run_ptr.push(0);
        for j in 0..n {
            let first = runs.len();
            for &i in &idx[ptr[j]..ptr[j + 1]] {
                let extends = runs.len() > first && runs.last().is_some_and(|&(a, l)| (a + l) as usize == i);
                match runs.last_mut() {
                    Some((_, len)) if extends => *len += 1,
                    _ => runs.push((i as u32, 1)),
                }
            }
            run_ptr.push(runs.len());
        }
        runs.shrink_to_fit();
        Some((ptr[..=n].to_vec(), run_ptr, runs))
    }

    pub fn dim(&self) -> usize {
        self.val_ptr.len() - 1
    }

    /// The bytes a product reads of the matrix: its values (8 each), its runs (8 each) and its
    /// two pointer arrays (8 per column each).
    pub fn bytes(&self) -> usize {
        8 * (self.val.len() + self.runs.len() + self.val_ptr.len() + self.run_ptr.len())
    }

    /// `y_j = Σ_k a_jk x_k` for the rows of `ys`, j from `first`.
    fn rows(&self, x: &[f64], first: usize, ys: &mut [f64]) {
        self.rows_of(x, first, ys, |v| v)
    }

    /// [`Self::rows`] with each entry mapped by `entry` (`|a_jk|`: the Gershgorin row sums).
    #[inline(always)]
    fn rows_of(&self, x: &[f64], first: usize, ys: &mut [f64], entry: impl Fn(f64) -> f64) {
        for (r, yj) in ys.iter_mut().enumerate() {
            let j = first + r;
            let mut k = self.val_ptr[j];
            let mut s = 0.0;
            for &(start, len) in &self.runs[self.run_ptr[j]..self.run_ptr[j + 1]] {
                let (xs, vs) = (&x[start as usize..(start + len) as usize], &self.val[k..k + len as usize]);
                for (v, xi) in vs.iter().zip(xs) {
                    s += entry(*v) * xi;
                }
                k += len as usize;
            }
            *yj = s;
        }
    }

    /// `y = A x` on rayon's threads ([`PAR_ROWS`] rows per task), bit-identical to
    /// [`sym_mul_into`] on the matrix it was built from.
    pub fn par_mul_into(&self, x: &[f64], y: &mut [f64]) {
        use rayon::prelude::*;
        y.par_chunks_mut(PAR_ROWS).enumerate().for_each(|(c, ys)| self.rows(x, c * PAR_ROWS, ys));
    }

    /// `xᵀ A x` (row sums in [`quad_form`]'s order).
    pub fn quad_form(&self, x: &[f64]) -> f64 {
        let mut y = [0.0];
        let mut s = 0.0;
        for (j, &xj) in x.iter().enumerate() {
            self.rows(x, j, &mut y);
            s += xj * y[0];
        }
        s
    }
}

/// The assembled stiffness as an operator (central differences on a run's lean system,
/// [`crate::solid::SolidSystem`]): the same products, bit for bit.
impl super::Operator for RunMat {
    fn n(&self) -> usize {
        self.dim()
    }

    fn apply(&self, x: &[f64], y: &mut [f64]) {
        self.par_mul_into(x, y)
    }

    fn quad_form(&self, x: &[f64]) -> f64 {
        RunMat::quad_form(self, x)
    }

    fn apply_abs(&self, x: &[f64], y: &mut [f64]) {
        use rayon::prelude::*;
        y.par_chunks_mut(PAR_ROWS).enumerate().for_each(|(c, ys)| self.rows_of(x, c * PAR_ROWS, ys, f64::abs));
    }

    /// The matrix's bytes ([`Self::bytes`]): as counted for the row-run stiffness a scheme
    /// holds itself (x read and y written are the scheme's vector passes).
    fn streamed_bytes(&self) -> usize {
        self.bytes()
    }

    fn name(&self) -> &'static str {
        "the assembled stiffness"
    }

    fn is_matrix_free(&self) -> bool {
        false
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
        let (limit, in_use) = (super::memory_limit(), super::memory_in_use());
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
        let limit = super::memory_limit();
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
        let in_use = super::memory_in_use();
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
    use super::*;

    /// `RunMat::bytes` of matrices whose runs are known by hand: the 5 × 5 path Laplacian (13
    /// entries, one run per column: 5 runs, 6 + 6 pointers) and the 2 × 2 identity plus a
    /// coupling of rows 0 and 2 in a 3 × 3 matrix (column 0 holds rows 0 and 2: two runs).
    #[test]
    fn a_row_run_matrix_counts_its_bytes() {
        let mut t = Vec::new();
        for i in 0..5 {
            t.push((i, i, 2.0));
            if i + 1 < 5 {
                t.extend([(i, i + 1, -1.0), (i + 1, i, -1.0)]);
            }
        }
        let path = RunMat::new(&from_triplets(5, &t, "path").unwrap()).unwrap();
        assert_eq!(path.bytes(), 8 * (13 + 5 + 6 + 6));
        let t = [(0, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0), (0, 2, 0.5), (2, 0, 0.5)];
        let gap = RunMat::new(&from_triplets(3, &t, "gap").unwrap()).unwrap();
        assert_eq!(gap.bytes(), 8 * (5 + 5 + 4 + 4));
    }

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
