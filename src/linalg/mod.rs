//! Linear-algebra back-ends of the contact system: symmetric tridiagonal matrices for bars
//! ([`tridiag`]: the two-sided "twisted" LDLᵀ solve) and sparse symmetric matrices for plates and
//! solids ([`sparse`]: faer's sparse Cholesky with an AMD ordering).
//!
//! The schemes of [`crate::schemes`] are written once, generic over [`SymMatrix`] (how to
//! multiply, combine and factor) and [`crate::contact::Backend`] (which exact contact solver a
//! back-end factors into). This is diffsol's split of a method from its matrix and
//! linear-solver types (`ode_solver/bdf.rs` over `linear_solver/{faer,nalgebra}`).

pub mod sparse;
pub mod tridiag;

use sparse::{SpMat, SparseError, SparseLlt};
use std::sync::atomic::{AtomicU64, Ordering};

/// The memory, in bytes, that the process may take ([`memory_limit`]); `u64::MAX`: no limit.
static MEMORY_LIMIT: AtomicU64 = AtomicU64::new(u64::MAX);

/// How much of [`MEMORY_LIMIT`] the process holds now, as the limit counts it ([`memory_in_use`]).
static MEMORY_IN_USE: std::sync::RwLock<Option<fn() -> u64>> = std::sync::RwLock::new(None);

/// Sets the memory the process may take: the command line sets it once, from the machine
/// (`crate::machine::memory_limit`: the available memory and `ulimit -v`), before any scene is
/// validated; a library user may set their own. The kernels never read the environment.
pub fn set_memory_limit(bytes: u64) {
    MEMORY_LIMIT.store(bytes, Ordering::Relaxed);
}

/// The memory the process may take, in bytes (`u64::MAX` unless [`set_memory_limit`] was called).
pub fn memory_limit() -> u64 {
    MEMORY_LIMIT.load(Ordering::Relaxed)
}

/// Sets how the memory the process holds is measured (the command line: `crate::machine`'s
/// reading of `/proc/self/status`, the measure the limit counts: address space under
/// `ulimit -v`, resident memory against the available memory). Without it the process is taken
/// to hold nothing, and a factor may take the whole limit.
pub fn set_memory_in_use(measure: fn() -> u64) {
    *MEMORY_IN_USE.write().unwrap_or_else(std::sync::PoisonError::into_inner) = Some(measure);
}

/// The memory the process holds now ([`set_memory_in_use`]; 0 if no measure was set).
pub fn memory_in_use() -> u64 {
    MEMORY_IN_USE.read().unwrap_or_else(std::sync::PoisonError::into_inner).map_or(0, |f| f())
}

/// What an allocation may still take: [`memory_limit`] less [`memory_in_use`]. A factor is
/// refused when its values and its factorisation's work space exceed it (issue 32, E4: the
/// first factor of a 1200² plate fitted the limit, the second aborted the run).
pub fn memory_left() -> u64 {
    memory_limit().saturating_sub(memory_in_use())
}
use std::fmt::Debug;
use thiserror::Error;

/// A symmetric operator `y = A x` on n unknowns that is applied, not stored (issue 31: the
/// explicit scheme's stiffness without a matrix, [`crate::solid::stencil`]). `apply` and
/// `quad_form` take `&self`: an operator keeps its own work space (behind a lock).
pub trait Operator: Send + Sync + Debug {
    fn n(&self) -> usize;
    /// `y = A x`.
    fn apply(&self, x: &[f64], y: &mut [f64]);
    /// `xᵀ A x`.
    fn quad_form(&self, x: &[f64]) -> f64;
    /// `y = |A| x`, the entries' absolute values (the Gershgorin bound's row sums with x an
    /// indicator).
    fn apply_abs(&self, x: &[f64], y: &mut [f64]);
    /// The bytes one `apply` streams through memory, by STREAM's convention (each array read or
    /// written once per pass counts its size once).
    fn streamed_bytes(&self) -> usize;
    /// What it is, for the run's notes.
    fn name(&self) -> &'static str;
    /// Whether it holds no matrix (the run's note then says `K u matrix-free`).
    fn is_matrix_free(&self) -> bool;
    /// An upper bound of `λ_max(M_L,II⁻¹ A_II)` from the element eigenvalue inequality, I the
    /// unknowns with `lumped > 0` (where the operator knows its cells: the stable step of
    /// central differences, [`crate::schemes::stable_limit`]); None where it does not.
    fn element_bound(&self, _lumped: &[f64]) -> Option<f64> {
        None
    }
}

/// A shared operator is the operator (a run's system holds it, each scheme built on it a handle).
impl<T: Operator + ?Sized> Operator for std::sync::Arc<T> {
    fn n(&self) -> usize {
        (**self).n()
    }

    fn apply(&self, x: &[f64], y: &mut [f64]) {
        (**self).apply(x, y)
    }

    fn quad_form(&self, x: &[f64]) -> f64 {
        (**self).quad_form(x)
    }

    fn apply_abs(&self, x: &[f64], y: &mut [f64]) {
        (**self).apply_abs(x, y)
    }

    fn streamed_bytes(&self) -> usize {
        (**self).streamed_bytes()
    }

    fn name(&self) -> &'static str {
        (**self).name()
    }

    fn is_matrix_free(&self) -> bool {
        (**self).is_matrix_free()
    }

    fn element_bound(&self, lumped: &[f64]) -> Option<f64> {
        (**self).element_bound(lumped)
    }
}

/// The largest eigenvalue of the symmetric n × n matrix of entries `entry(i, j)` (faer's
/// symmetric solver; 0 for n = 0, ∞ where it fails): each cell's term of the matrix-free
/// operators' element eigenvalue bounds ([`Operator::element_bound`]).
pub fn largest_eigenvalue(n: usize, entry: impl Fn(usize, usize) -> f64) -> f64 {
    if n == 0 {
        return 0.0;
    }
    let a = faer::Mat::<f64>::from_fn(n, n, entry);
    a.self_adjoint_eigenvalues(faer::Side::Lower).ok().and_then(|v| v.last().copied()).unwrap_or(f64::INFINITY)
}

use tridiag::{FactorError, SymTridiag};

/// Failure to build, combine or factor a matrix of the contact system.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LinalgError {
    #[error("the {matrix} matrix cannot be factored: {source}")]
    Factor { matrix: &'static str, source: FactorError },
    #[error(transparent)]
    Sparse(#[from] SparseError),
    #[error("the {matrix} matrix: {detail}")]
    Unsupported { matrix: &'static str, detail: String },
}

/// A symmetric matrix of the contact system (mass M, stiffness S, an iteration matrix
/// `M + σ S`): what the schemes need of it, implemented once per back-end.
pub trait SymMatrix: Clone + Debug + Send + Sync + 'static {
    /// Whether a NaN or ∞ anywhere in a right-hand side reaches the first and last entries of
    /// the solution (true for a tridiagonal chain), so that checking those two suffices.
    const SOLVE_SPREADS_NAN: bool;

    /// Number of rows (= columns).
    fn dim(&self) -> usize;

    /// Diagonal entry `A_ii`.
    fn diag(&self, i: usize) -> f64;

    /// `y = A x + c f` (one pass where the back-end can fuse it).
    fn mul_add_into(&self, x: &[f64], c: f64, f: &[f64], y: &mut [f64]);

    /// `y = A x`.
    fn mul_into(&self, x: &[f64], y: &mut [f64]);

    /// `y = A x` on rayon's threads where the back-end splits it (the explicit scheme; equal
    /// to [`SymMatrix::mul_into`] bit for bit). Default: [`SymMatrix::mul_into`].
    fn par_mul_into(&self, x: &[f64], y: &mut [f64]) {
        self.mul_into(x, y)
    }

    /// The matrix in the explicit scheme's compact row-run form, where the back-end has one
    /// ([`sparse::RunMat`]: sparse matrices). Default: None.
    fn run_mat(&self) -> Option<sparse::RunMat> {
        None
    }

    /// [`SymMatrix::run_mat`] taking the matrix over (no second copy of its values); Err(self)
    /// where there is none.
    fn into_run_mat(self) -> Result<sparse::RunMat, Self> {
        Err(self)
    }

    /// `xᵀ A x`.
    fn quad_form(&self, x: &[f64]) -> f64;

    /// Sum of all entries, `1ᵀ A 1`.
    fn total(&self) -> f64;

    /// `a·self + b·other` (`other` has the same dimension; patterns are merged).
    fn combine(&self, a: f64, other: &Self, b: f64, matrix: &'static str) -> Result<Self, LinalgError>;

    /// Calls `f(i, j, A_ij)` for every stored entry (both triangles).
    fn for_each_entry(&self, f: &mut dyn FnMut(usize, usize, f64));

    /// Overwrites `b` (indexed like `keep`) with `A_KK⁻¹ b`, `A_KK` the principal submatrix on
    /// the rows and columns `keep` (increasing), which must be positive definite.
    fn solve_principal(&self, keep: &[usize], b: &mut [f64], matrix: &'static str) -> Result<(), LinalgError>;
}

impl SymMatrix for SymTridiag {
    const SOLVE_SPREADS_NAN: bool = true;

    fn dim(&self) -> usize {
        self.len()
    }

    fn diag(&self, i: usize) -> f64 {
        self.diag[i]
    }

    fn mul_add_into(&self, x: &[f64], c: f64, f: &[f64], y: &mut [f64]) {
        SymTridiag::mul_add_into(self, x, c, Some(f), y)
    }

    fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        SymTridiag::mul_into(self, x, y)
    }

    fn quad_form(&self, x: &[f64]) -> f64 {
        SymTridiag::quad_form(self, x)
    }

    fn total(&self) -> f64 {
        SymTridiag::total(self)
    }

    fn combine(&self, a: f64, other: &Self, b: f64, _matrix: &'static str) -> Result<Self, LinalgError> {
        Ok(SymTridiag::combine(self, a, other, b))
    }

    fn for_each_entry(&self, f: &mut dyn FnMut(usize, usize, f64)) {
        for i in 0..self.len() {
            if i > 0 {
                f(i, i - 1, self.off[i - 1]);
            }
            f(i, i, self.diag[i]);
            if i + 1 < self.len() {
                f(i, i + 1, self.off[i]);
            }
        }
    }

    /// Bars have massless nodes only at the contact end, so `keep` is a trailing range
    /// `k..n`; it is factored by LDLᵀ (as the 1D code always did).
    fn solve_principal(&self, keep: &[usize], b: &mut [f64], matrix: &'static str) -> Result<(), LinalgError> {
        let n = self.len();
        let k = n - keep.len();
        if keep.iter().enumerate().any(|(p, &i)| i != k + p) {
            let detail = "a tridiagonal principal solve needs a trailing range of rows".to_string();
            return Err(LinalgError::Unsupported { matrix, detail });
        }
        let factor = self.trailing(k).factor().map_err(|source| LinalgError::Factor { matrix, source })?;
        factor.solve_in_place(b);
        Ok(())
    }
}

impl SymMatrix for SpMat {
    const SOLVE_SPREADS_NAN: bool = false;

    fn dim(&self) -> usize {
        self.nrows()
    }

    fn diag(&self, i: usize) -> f64 {
        sparse::get(self, i, i)
    }

    fn mul_add_into(&self, x: &[f64], c: f64, f: &[f64], y: &mut [f64]) {
        sparse::sym_mul_into(self, x, y);
        for (yi, fi) in y.iter_mut().zip(f) {
            *yi += c * fi;
        }
    }

    fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        sparse::sym_mul_into(self, x, y)
    }

    fn par_mul_into(&self, x: &[f64], y: &mut [f64]) {
        sparse::par_sym_mul_into(self, x, y)
    }

    fn run_mat(&self) -> Option<sparse::RunMat> {
        sparse::RunMat::new(self)
    }

    fn into_run_mat(self) -> Result<sparse::RunMat, Self> {
        sparse::RunMat::from_owned(self)
    }

    fn quad_form(&self, x: &[f64]) -> f64 {
        sparse::quad_form(self, x)
    }

    fn total(&self) -> f64 {
        sparse::total(self)
    }

    fn combine(&self, a: f64, other: &Self, b: f64, matrix: &'static str) -> Result<Self, LinalgError> {
        Ok(sparse::combine(self, a, other, b, matrix)?)
    }

    fn for_each_entry(&self, f: &mut dyn FnMut(usize, usize, f64)) {
        for (i, j, v) in sparse::triplets(self) {
            f(i, j, v);
        }
    }

    /// A positive diagonal block (a lean system's lumped mass) is divided through, with no
    /// factor and its work space (issue 31's peak memory); any other is factored.
    fn solve_principal(&self, keep: &[usize], b: &mut [f64], matrix: &'static str) -> Result<(), LinalgError> {
        let sub = sparse::principal(self, keep, matrix)?;
        if let Some(diag) = sparse::positive_diagonal(&sub) {
            b.iter_mut().zip(diag).for_each(|(x, d)| *x /= d);
            return Ok(());
        }
        SparseLlt::new(&sub, matrix)?.solve_in_place(b);
        Ok(())
    }
}
