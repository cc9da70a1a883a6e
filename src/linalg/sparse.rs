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

use faer::sparse::SparseColMat;
use thiserror::Error;

mod llt;
mod runs;

pub use llt::SparseLlt;
pub use runs::RunMat;

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

/// The diagonal of `a` when it has no other entry and every diagonal entry is positive and
/// finite (a lumped mass); None otherwise.
pub fn positive_diagonal(a: &SpMat) -> Option<&[f64]> {
    let (ptr, idx) = (a.symbolic().col_ptr(), a.symbolic().row_idx());
    let diagonal = (0..a.ncols()).all(|j| ptr[j + 1] - ptr[j] == 1 && idx[ptr[j]] == j);
    (diagonal && a.val().iter().all(|&d| d > 0.0 && d.is_finite())).then(|| a.val())
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
