//! [`RunMat`]: a symmetric sparse matrix stored as runs of consecutive rows, for the explicit
//! scheme's bandwidth-bound products (bit-identical to the compressed-column ones).

use super::{PAR_ROWS, SpMat};

/// A symmetric sparse matrix whose columns are stored as runs of consecutive rows: for each
/// run its first row (u32) and length, the values in the same order as the compressed
/// columns. Vector fields interleaved per node give runs of d rows (d·k where k neighbouring
/// nodes are numbered consecutively: 9 runs of 9 per column of a structured hex mesh), so the
/// row indices take about 8 bytes per run instead of 8 per entry: a product streams ~45% fewer
/// bytes in 3D (the explicit scheme is bound by memory bandwidth). Each `y_j` is summed in the
/// same order as [`super::sym_mul_into`]: the products are equal bit for bit.
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
    /// [`super::sym_mul_into`] on the matrix it was built from.
    pub fn par_mul_into(&self, x: &[f64], y: &mut [f64]) {
        use rayon::prelude::*;
        y.par_chunks_mut(PAR_ROWS).enumerate().for_each(|(c, ys)| self.rows(x, c * PAR_ROWS, ys));
    }

    /// `xᵀ A x` (row sums in [`super::quad_form`]'s order).
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
impl crate::linalg::Operator for RunMat {
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

#[cfg(test)]
mod tests {
    use super::super::from_triplets;
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
}
