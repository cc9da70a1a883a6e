//! The quasi-static massless layer of central differences, solved with a sparse factor.
//!
//! The same map Φ as [`super::QuasiStatic`] (its docs): for the massive values U, the contact
//! unknowns C (Signorini rows) and the free massless unknowns F of the layer L = C ∪ F solve
//!
//! ```text
//! S_LL u_L = b − E_Cᵀ λ,   b = F_L − S_LI U,     0 ≤ u_c − lb_c ⊥ λ_c ≤ 0   (c ∈ C),
//! ```
//!
//! the minimisation of `½ u_Lᵀ S_LL u_L − bᵀ u_L` over `u_C ≥ lb` (S_LL SPD, a principal block
//! of the SPD stiffness). [`super::QuasiStatic`] forms the dense Schur complement of F
//! (cubic in |L|); here nothing dense is formed, so the cost follows the sparse factor of
//! S_LL (for a 3D contact face, a 2D mesh graph: fill O(|L| log |L|) under the AMD ordering).
//!
//! **A complementary basis is an active set A ⊂ C** (the nodes on the obstacle): u_a = lb_a
//! on A, λ = 0 off A, and the other unknowns solve S_LL restricted to L \ A. The basic values
//! are `y_c = u_c − lb_c` off A and `w_a = −λ_a = (S_LL u_L − b)_a` on A; A solves the problem
//! iff all of them are ≥ 0.
//!
//! **One factor for many sets.** The factor held is that of a reference set A0: the principal
//! block `S_RR` of S_LL on R = L \ A0, the unknowns not fixed by A0 (the tangential unknowns
//! of a face on the obstacle). S_LL is ordered once (AMD); a new reference is the symbolic
//! analysis and numeric factorisation of S_RR in the order its unknowns have in S_LL's
//! ([`SparseLlt::with_ordering`]). A factor of S_RR alone, rather than of S_LL with the rows of
//! A0 kept as diagonal rows, holds about (2/3)² of the entries when a 3D face is on the
//! obstacle, and its solve, the one solve of a step whose contact set does not change, costs
//! that much less (docs/bench.md). A set A that differs from A0 on the freed nodes
//! I = A0 \ A and the newly fixed J = A \ A0 is solved from `z0 = S_RR⁻¹ (b_R − S_R,A0∩A lb)`
//! by the bordered system of the k = |I| + |J| nodes ([`Correction`]: k columns solved in one
//! pass through the factor and faer's dense k × k LU with partial pivoting, kept while A
//! stays): with
//! `G = S_RR⁻¹ S_RI`, `H = S_RR⁻¹ E_Jᵀ`,
//!
//! ```text
//! [ S_II − S_IR G    −G_Jᵀ ] [x_I]   [b_I − S_I,A0∩A lb − S_IR z0]
//! [ −G_J             −H_JJ ] [ μ ] = [lb_J − z0_J                ],   x_R = z0 − G x_I − H μ,
//! ```
//!
//! (eliminate x_R from the rows of R, I and the constraints x_J = lb_J with multipliers μ). When
//! k passes a limit set by the factor's size (a factorisation costs about (stored
//! entries)²/|L| flops, entries/(4|L|) solves; a correction's column about a third of a solve:
//! the limit is 3 entries/(4|L|), [`Layer::new`]), A becomes the reference and is factored.
//! Both ways solve the same system: `tests/layer.rs` checks them against each other and
//! against the dense solver.
//!
//! **Pivoting** (J. J. Júdice, F. M. Pires, "A block principal pivoting algorithm for
//! large-scale strictly monotone linear complementarity problems", Comput. Oper. Res. 21 (1994)
//! 587–596): every node with a negative basic value changes side at once (a block pivot, the
//! primal–dual active set step) while the number of such nodes keeps reaching a new minimum;
//! after [`BLOCK_TRIES`] block pivots without a new minimum, one node changes side, the least
//! index (Murty's rule, finite for the P-matrix problem in u_C: see [`super::lcp`]), until a
//! new minimum is reached. New minima can happen only finitely often, so the method ends in
//! finitely many pivots from any start, and it stops when the signs are right (no tolerance on a
//! residual). The set of the last step is the start of the next: a step whose contact state
//! does not change costs one right-hand side, one sparse solve and the rows of A (no
//! factorisation).
//!
//! **Signs** are tested with the round-off allowance of [`super::lcp`] in force units,
//! `tol = 4 (|C| + 1) ε (‖b‖∞ + max|S_LL| ‖y‖₁)`: `w_a < −tol` and `S_cc y_c < −tol` are
//! negative. On return u_a = lb_a is set exactly on A and `y_c ≥ 0` off A (a value within the
//! allowance below 0 is set to 0), so complementarity holds bit for bit, as with the dense
//! solver.
//!
//! **Cost** (issue 31): set-up = one AMD ordering, one symbolic analysis and one numeric
//! factorisation of S_LL; a step = the coupling product (entries of S_LI), one sparse solve and,
//! when the contact set changes, per pivot a correction (few nodes) or a new factor of S_RR
//! (many). Measured against 10² … 10⁴ contact nodes by `massredist bench --layer`.

use super::lcp::LcpError;
use crate::linalg::sparse::{self, SpMat, SparseError, SparseLlt};
use crate::linalg::{LinalgError, SymMatrix};
use faer::Mat;
use faer::linalg::solvers::{PartialPivLu, Solve};

/// Block pivots allowed without a new minimum of the number of wrong signs before single
/// (least-index) pivots take over (Júdice–Pires' p; 3 is their value).
pub const BLOCK_TRIES: usize = 3;

/// Layer rows per task of the coupling product (a few thousand entries of S_LI).
const COUPLING_ROWS: usize = 256;

/// The massless layer's map Φ with a sparse factor (module docs).
#[derive(Debug)]
pub struct Layer {
    /// Global unknowns of the layer, contact first (slots 0..nc), then free (nc..).
    unknowns: Vec<usize>,
    nc: usize,
    /// `(j, S_{unknowns[slot], j})` for j outside the layer, by slot (row) from
    /// `coupling_ptr[slot]`, j increasing: each row's sum is taken in registers, its loads of U
    /// independent (they miss the cache: U's coupled values lie a node row apart), in the order
    /// of the stiffness's columns.
    coupling: Vec<(usize, f64)>,
    coupling_ptr: Vec<usize>,
    load: Vec<f64>,
    /// S_LL in slot numbering.
    s: SpMat,
    diag: Vec<f64>,
    max_abs_s: f64,
    /// The elimination order of S_LL's factor (position → slot), kept for the factors of its
    /// principal blocks S_RR.
    order: Vec<usize>,
    /// The factor of `S_RR`, R = L \ A0, the reference set's other unknowns: `free[r]` is
    /// the slot of R's unknown r, `gather` its R values (the factor's right-hand side). None
    /// while a new factor is made (the old one is dropped first: the two are never held at
    /// once, issue 31's peak memory) and after that failed: the next solve factors again.
    factor: Option<SparseLlt>,
    free: Vec<usize>,
    gather: Vec<f64>,
    /// The warm-start set, and the reference set A0 whose `S_RR` `factor` holds.
    active: Vec<bool>,
    reference: Vec<bool>,
    /// The correction of the reference factor to the current set, kept while the set is the
    /// same (steps whose contact state does not change).
    correction: Option<Correction>,
    /// Nodes whose side may differ from the reference set before it is factored again.
    update_limit: usize,
    rhs: Vec<f64>,
    x: Vec<f64>,
    w: Vec<f64>,
    pivots: usize,
}

/// The factor of the reference set: [`Layer::solve_basis`] makes one first where there is none.
fn reference_factor(factor: &mut Option<SparseLlt>) -> &mut SparseLlt {
    factor.as_mut().expect("solve_basis factors the reference set first")
}

impl Layer {
    /// Φ of the contact unknowns `contact` and the free massless unknowns `free` (disjoint).
    /// Fails only if S_LL is not positive definite (or its factor does not fit in memory).
    pub fn new<A: SymMatrix>(
        stiffness: &A,
        load: &[f64],
        contact: &[usize],
        free: &[usize],
    ) -> Result<Self, LinalgError> {
        let nc = contact.len();
        let unknowns: Vec<usize> = contact.iter().chain(free).copied().collect();
        let nl = unknowns.len();
        let mut slot = vec![usize::MAX; stiffness.dim()];
        for (k, &i) in unknowns.iter().enumerate() {
            slot[i] = k;
        }
        let (mut inner, mut coupling) = (Vec::new(), Vec::new());
        stiffness.for_each_entry(&mut |i, j, s| match (slot[i], slot[j]) {
            (a, b) if a != usize::MAX && b != usize::MAX => inner.push((a, b, s)),
            (a, _) if a != usize::MAX => coupling.push((a, j, s)),
            _ => {}
        });
        // By row, j increasing within each (a stable sort of the column-order entries).
        coupling.sort_by_key(|&(a, _, _)| a);
        let mut coupling_ptr = vec![0; nl + 1];
        for &(a, _, _) in &coupling {
            coupling_ptr[a + 1] += 1;
        }
        for k in 0..nl {
            coupling_ptr[k + 1] += coupling_ptr[k];
        }
        let coupling: Vec<(usize, f64)> = coupling.into_iter().map(|(_, j, s)| (j, s)).collect();
        let s = sparse::from_triplets(nl, &inner, "stiffness")?;
        let diag: Vec<f64> = (0..nl).map(|k| sparse::get(&s, k, k)).collect();
        let max_abs_s = s.val().iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let factor = SparseLlt::new(&s, "stiffness").map_err(layer_error)?;
        let order = factor.ordering().to_vec();
        // A refactorisation costs about (stored entries)²/|L| flops (Σ_j of a column's count
        // squared, with the mean count), a solve 4 per stored entry: their ratio is
        // entries/(4|L|) solves (24 on the 69³ cube's layer; measured 17: 25 ms against 1.4 ms).
        // A correction of k nodes solves its k columns in one pass through the factor, about a
        // third of a solve each (24 columns: 9.7 ms against 24 solves' 34 ms): refactor once k
        // passes three times that ratio.
        let update_limit = (3 * factor.factor_len() / (4 * nl.max(1))).max(1);
        Ok(Self {
            load: unknowns.iter().map(|&i| load[i]).collect(),
            s,
            diag,
            max_abs_s,
            order,
            factor: Some(factor),
            free: (0..nl).collect(),
            gather: vec![0.0; nl],
            active: vec![false; nc],
            reference: vec![false; nc],
            correction: None,
            update_limit,

            rhs: vec![0.0; nl],
            x: vec![0.0; nl],
            w: vec![0.0; nc],
            pivots: 0,
            unknowns,
            nc,
            coupling,
            coupling_ptr,
        })
    }

    /// Unknowns of the layer (contact and free).
    pub fn len(&self) -> usize {
        self.unknowns.len()
    }

    pub fn is_empty(&self) -> bool {
        self.unknowns.is_empty()
    }

    /// Sets the number of nodes whose side may differ from the factored reference set before it
    /// is factored again (the default follows the factor's size; tests use 0 and ∞ to check
    /// both ways give the same solution).
    pub fn set_update_limit(&mut self, limit: usize) {
        self.update_limit = limit;
    }

    /// Stored entries of the factor of S_LL (its fill).
    pub fn factor_len(&self) -> usize {
        self.factor.as_ref().map_or(0, SparseLlt::factor_len)
    }

    /// Takes the layer's entries of a new load vector (a time-dependent load).
    pub fn set_load(&mut self, load: &[f64]) {
        for (f, &i) in self.load.iter_mut().zip(&self.unknowns) {
            *f = load[i];
        }
    }

    /// Overwrites the layer's entries of `u` with Φ(U) and writes λ (contact order); returns
    /// the pivots.
    pub fn apply(&mut self, u: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError> {
        let nc = self.nc;
        // b = F_L − S_LI U (in the `rhs` buffer, taken out while the pivoting borrows `self`).
        let mut b = std::mem::take(&mut self.rhs);
        // Rows in parallel, each summed in its one order (the same bits on any number of threads).
        let row = |k: usize| {
            let mut sum = self.load[k];
            for &(j, s) in &self.coupling[self.coupling_ptr[k]..self.coupling_ptr[k + 1]] {
                sum -= s * u[j];
            }
            sum
        };
        {
            use rayon::prelude::*;
            b.par_chunks_mut(COUPLING_ROWS).enumerate().for_each(|(c, bs)| {
                for (r, bk) in bs.iter_mut().enumerate() {
                    *bk = row(c * COUPLING_ROWS + r);
                }
            });
        }
        let bmax = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        self.pivots = 0;
        let (mut best, mut tries) = (usize::MAX, 0usize);
        let result = loop {
            if let Err(e) = self.solve_basis(&b, lower) {
                break Err(e);
            }
            let y_sum: f64 = (0..nc).filter(|&c| !self.active[c]).map(|c| (self.x[c] - lower[c]).abs()).sum();
            // Round-off allowance of the basic values (module docs).
            let tol = 4.0 * (nc as f64 + 1.0) * f64::EPSILON * (bmax + self.max_abs_s * y_sum);
            let wrong = |c: usize| {
                if self.active[c] { self.w[c] < -tol } else { self.diag[c] * (self.x[c] - lower[c]) < -tol }
            };
            let n_wrong = (0..nc).filter(|&c| wrong(c)).count();
            if n_wrong == 0 {
                break Ok(());
            }
            self.pivots += 1;
            if self.pivots > 50 * nc + 100 {
                break Err(LcpError::NotConverged { pivots: self.pivots, residual: self.residual(lower) });
            }
            if n_wrong < best {
                (best, tries) = (n_wrong, 0);
            } else {
                tries += 1;
            }
            if tries < BLOCK_TRIES {
                let flip: Vec<usize> = (0..nc).filter(|&c| wrong(c)).collect();
                flip.into_iter().for_each(|c| self.active[c] = !self.active[c]);
            } else {
                let c = (0..nc).find(|&c| wrong(c)).expect("n_wrong > 0");
                self.active[c] = !self.active[c];
            }
        };
        self.rhs = b;
        result?;
        for (c, &i) in self.unknowns[..nc].iter().enumerate() {
            if self.active[c] {
                u[i] = lower[c];
                lambda[c] = -self.w[c];
            } else {
                u[i] = self.x[c].max(lower[c]);
                lambda[c] = 0.0;
            }
        }
        for (k, &i) in self.unknowns.iter().enumerate().skip(nc) {
            u[i] = self.x[k];
        }
        Ok(self.pivots)
    }

    /// The basic solution of the current set: `x` (u_L with u_A = lb_A) and `w` on A (module
    /// docs: the factor of the reference set, corrected by [`Correction`] or factored again).
    fn solve_basis(&mut self, b: &[f64], lower: &[f64]) -> Result<(), LcpError> {
        let nc = self.nc;
        let changed = (0..nc).filter(|&c| self.active[c] != self.reference[c]).count();
        if changed > self.update_limit || self.factor.is_none() {
            self.refactor()?;
        }
        // z0 = S_RR⁻¹ (b_R − Σ_{a ∈ A0 ∩ A} S_Ra lb_a), R = L \ A0 (zero on the rows of A0).
        self.x.copy_from_slice(b);
        let (ptr, idx, val) = (self.s.symbolic().col_ptr(), self.s.symbolic().row_idx(), self.s.val());
        for a in (0..nc).filter(|&a| self.active[a] && self.reference[a]) {
            for p in ptr[a]..ptr[a + 1] {
                self.x[idx[p]] -= val[p] * lower[a];
            }
        }
        self.solve_free();
        if changed > 0 && changed <= self.update_limit {
            self.correct(b, lower)?;
        }
        for a in (0..nc).filter(|&a| self.active[a]) {
            self.x[a] = lower[a];
        }
        // w_a = (S_LL x − b)_a (column a = row a).
        let (ptr, idx, val) = (self.s.symbolic().col_ptr(), self.s.symbolic().row_idx(), self.s.val());
        for a in 0..nc {
            self.w[a] = if self.active[a] {
                (ptr[a]..ptr[a + 1]).map(|p| val[p] * self.x[idx[p]]).sum::<f64>() - b[a]
            } else {
                0.0
            };
        }
        Ok(())
    }

    /// Overwrites `self.x` (slot numbering) on R = L \ A0 with `S_RR⁻¹ x_R` and sets it to zero
    /// on A0.
    fn solve_free(&mut self) {
        for (g, &k) in self.gather.iter_mut().zip(&self.free) {
            *g = self.x[k];
        }
        reference_factor(&mut self.factor).solve_in_place(&mut self.gather);
        for a in (0..self.nc).filter(|&a| self.reference[a]) {
            self.x[a] = 0.0;
        }
        for (&g, &k) in self.gather.iter().zip(&self.free) {
            self.x[k] = g;
        }
    }

    /// The same for the `k` columns of `cols` (|L| each, zero on A0), in one pass through the
    /// factor ([`SparseLlt::solve_columns_in_place`]).
    fn solve_free_columns(&mut self, cols: &mut [f64], k: usize) {
        let (nl, nr) = (self.unknowns.len(), self.free.len());
        let mut gathered = vec![0.0; nr * k];
        for (g, col) in gathered.chunks_exact_mut(nr.max(1)).zip(cols.chunks_exact(nl)) {
            for (g, &slot) in g.iter_mut().zip(&self.free) {
                *g = col[slot];
            }
        }
        reference_factor(&mut self.factor).solve_columns_in_place(&mut gathered, k);
        for (g, col) in gathered.chunks_exact(nr.max(1)).zip(cols.chunks_exact_mut(nl)) {
            for (&g, &slot) in g.iter().zip(&self.free) {
                col[slot] = g;
            }
        }
    }

    /// Factors `S_RR` for the current set A, which becomes the reference set A0 (R = L \ A:
    /// the principal block, in the elimination order its unknowns have in S_LL's factor; the
    /// rows of A are u_a = lb_a, not in the factor).
    fn refactor(&mut self) -> Result<(), LcpError> {
        let nc = self.nc;
        let in_r = |k: usize| !(k < nc && self.active[k]);
        let free: Vec<usize> = (0..self.unknowns.len()).filter(|&k| in_r(k)).collect();
        let mut position = vec![usize::MAX; self.unknowns.len()];
        for (r, &k) in free.iter().enumerate() {
            position[k] = r;
        }
        let fwd: Vec<usize> = self.order.iter().filter(|&&k| in_r(k)).map(|&k| position[k]).collect();
        self.correction = None;
        let s_rr = sparse::principal(&self.s, &free, "stiffness").map_err(LcpError::Factor)?;
        self.factor = None;
        match SparseLlt::with_ordering(&s_rr, fwd, "stiffness") {
            Ok(factor) => self.factor = Some(factor),
            Err(SparseError::NotPositiveDefinite { .. }) => return Err(self.breakdown()),
            Err(e) => return Err(LcpError::Factor(e)),
        }
        self.gather = vec![0.0; free.len()];
        self.free = free;
        self.reference.copy_from_slice(&self.active);
        Ok(())
    }

    fn breakdown(&self) -> LcpError {
        let size = self.active.iter().filter(|&&a| a).count();
        LcpError::Breakdown { size, pivot: f64::NAN, residual: f64::NAN }
    }

    /// Turns `x` = z0 (the reference set's solution) into the current set's (module docs:
    /// the bordered system of the freed nodes I = A0 \ A and the newly fixed J = A \ A0).
    fn correct(&mut self, b: &[f64], lower: &[f64]) -> Result<(), LcpError> {
        let nc = self.nc;
        if self.correction.as_ref().is_none_or(|c| c.set != self.active) {
            self.correction = None;
            let c = Correction::new(self)?;
            self.correction = Some(c);
        }
        let c = self.correction.as_mut().expect("just built");
        let (ptr, idx, val) = (self.s.symbolic().col_ptr(), self.s.symbolic().row_idx(), self.s.val());
        // Right-hand side: rhs_I − S_IR z0 (rhs_I = b_I − Σ_{a ∈ A0 ∩ A} S_Ia lb_a), lb_J − z0_J.
        let r = &mut c.r;
        for (m, &i) in c.freed.iter().enumerate() {
            let mut s = b[i];
            for p in ptr[i]..ptr[i + 1] {
                let l = idx[p];
                if l < nc && self.reference[l] {
                    if self.active[l] {
                        s -= val[p] * lower[l];
                    }
                } else {
                    s -= val[p] * self.x[l];
                }
            }
            r[(m, 0)] = s;
        }
        for (m, &j) in c.fixed.iter().enumerate() {
            r[(c.freed.len() + m, 0)] = lower[j] - self.x[j];
        }
        c.lu.solve_in_place(r.as_mut());
        // x_R −= Σ cols · (x_I, μ); x_I set.
        let nl = self.unknowns.len();
        for m in 0..r.nrows() {
            let (col, y) = (&c.cols[m * nl..(m + 1) * nl], r[(m, 0)]);
            for (x, g) in self.x.iter_mut().zip(col) {
                *x -= g * y;
            }
        }
        for (m, &i) in c.freed.iter().enumerate() {
            self.x[i] = r[(m, 0)];
        }
        Ok(())
    }

    /// Natural residual `max_c |min(S_cc y_c, w_c)|` of the current basic solution.
    fn residual(&self, lower: &[f64]) -> f64 {
        (0..self.nc)
            .map(|c| {
                let y = if self.active[c] { 0.0 } else { self.diag[c] * (self.x[c] - lower[c]) };
                y.min(self.w[c]).abs()
            })
            .fold(0.0, f64::max)
    }
}

/// S_LL not positive definite: the error names the block.
fn layer_error(e: SparseError) -> LinalgError {
    match e {
        SparseError::NotPositiveDefinite { index, .. } => LinalgError::Unsupported {
            matrix: "stiffness",
            detail: format!("its block on the massless contact layer is not positive definite (pivot {index})"),
        },
        other => LinalgError::Sparse(other),
    }
}

/// The bordered system that turns the reference set's solution into the current set's
/// (module docs): I = A0 \ A (freed), J = A \ A0 (newly fixed), the columns
/// `g_i = S_RR⁻¹ S_Ri`, `h_j = S_RR⁻¹ e_j` (R = L \ A0) and the LU factor of
///
/// ```text
/// C = [ S_II − S_IR G    −G_Jᵀ ]      [x_I]   [rhs_I − S_IR z0]
///     [ −G_J             −H_JJ ],   C [ μ ] = [lb_J − z0_J    ],   x_R = z0 − G x_I − H μ.
/// ```
#[derive(Debug)]
struct Correction {
    set: Vec<bool>,
    freed: Vec<usize>,
    fixed: Vec<usize>,
    /// The k columns (g then h), |L| each, zero on the rows of A0.
    cols: Vec<f64>,
    /// C's LU factor with partial pivoting (faer).
    lu: PartialPivLu<f64>,
    /// The k-vector of the right-hand side and solution, kept between steps.
    r: Mat<f64>,
}

impl Correction {
    fn new(layer: &mut Layer) -> Result<Self, LcpError> {
        let (nc, nl) = (layer.nc, layer.unknowns.len());
        let freed: Vec<usize> = (0..nc).filter(|&c| !layer.active[c] && layer.reference[c]).collect();
        let fixed: Vec<usize> = (0..nc).filter(|&c| layer.active[c] && !layer.reference[c]).collect();
        let (ni, k) = (freed.len(), freed.len() + fixed.len());
        let mut cols = vec![0.0; k * nl];
        let reference = layer.reference.clone();
        let in_r = |l: usize| !(l < nc && reference[l]);
        {
            let (ptr, idx, val) = (layer.s.symbolic().col_ptr(), layer.s.symbolic().row_idx(), layer.s.val());
            for (m, &i) in freed.iter().enumerate() {
                for p in ptr[i]..ptr[i + 1] {
                    if in_r(idx[p]) {
                        cols[m * nl + idx[p]] = val[p];
                    }
                }
            }
            for (m, &j) in fixed.iter().enumerate() {
                cols[(ni + m) * nl + j] = 1.0;
            }
        }
        layer.solve_free_columns(&mut cols, k);
        let (ptr, idx, val) = (layer.s.symbolic().col_ptr(), layer.s.symbolic().row_idx(), layer.s.val());
        let mut c = Mat::<f64>::zeros(k, k);
        for (m, &i) in freed.iter().enumerate() {
            for m2 in 0..k {
                // −S_iR · (column m2), plus S_ii' for a freed i'.
                let col = &cols[m2 * nl..(m2 + 1) * nl];
                let mut v = 0.0;
                for p in ptr[i]..ptr[i + 1] {
                    let l = idx[p];
                    if in_r(l) {
                        v -= val[p] * col[l];
                    } else if m2 < ni && l == freed[m2] {
                        v += val[p];
                    }
                }
                c[(m, m2)] = v;
            }
        }
        for (m, &j) in fixed.iter().enumerate() {
            for m2 in 0..k {
                c[(ni + m, m2)] = -cols[m2 * nl + j];
            }
        }
        let lu = c.partial_piv_lu();
        // C is nonsingular when S_LL is positive definite: a zero or non-finite pivot of U is a
        // breakdown.
        let u = lu.U();
        if let Some(pivot) = (0..k).map(|m| u[(m, m)]).find(|p| *p == 0.0 || !p.is_finite()) {
            let size = layer.active.iter().filter(|&&a| a).count();
            return Err(LcpError::Breakdown { size, pivot, residual: f64::NAN });
        }
        Ok(Self { set: layer.active.clone(), freed, fixed, cols, lu, r: Mat::zeros(k, 1) })
    }
}
