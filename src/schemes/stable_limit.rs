//! The stable time step of central differences on a lumped mass:
//! `Δt_c = 2/√λ_max(M_L,II⁻¹ K_II)` (the undamped central-difference scheme is stable iff
//! `Δt ω_max ≤ 2`; Hughes, *The Finite Element Method*, §9.1.1; Belytschko et al., *Nonlinear
//! Finite Elements*, §6.3).
//!
//! λ_max is that of the symmetric `B = D K_II D`, `D = M_L,II^{−1/2}`, computed by Lanczos with
//! full reorthogonalisation from a fixed start vector. After k steps the largest Ritz value θ_k
//! (the largest eigenvalue of the k × k tridiagonal, by Sturm bisection to round-off) satisfies
//! `θ_k ≤ λ_max`, and it increases with k. The iteration stops when θ_k has changed by less than
//! [`REL_TOL`] relative over the last [`WINDOW`] steps, or at k = n (then θ_k = λ_max up to
//! round-off), or at [`MAX_STEPS`] (not below [`EXHAUST`] interior unknowns: there it always
//! converges). **Stated accuracy**: θ is a lower bound of λ_max. When the
//! iteration stops by stagnation or exhausts the space, θ is used: it agrees with λ_max to about
//! `REL_TOL` on the meshes tested (the path Laplacian's closed form below), so Δt_c is accurate
//! to about `REL_TOL / 2` relative and errs, if at all, on the large side by that much. When it
//! stops at [`MAX_STEPS`] unconverged (large meshes: the top of the spectrum is dense, measured
//! θ 1.7e-5 below λ_max for a 2001-node bar), the caller uses the Gershgorin bound
//! ([`gershgorin`]: the row sums of `M_I⁻¹ K_II`), an upper bound of λ_max: Δt_c is then
//! conservative (exact for the uniform bar, whose highest mode attains it; `tests/central.rs`).
//! A matrix-free stiffness (issue 31) takes [`lambda_max_lean`] (no stored basis above
//! [`LARGE`]) and, unconverged, the smaller of [`gershgorin_of`] (the row sums as `|K| 1_I`)
//! and the operator's element eigenvalue bound where it has one
//! ([`crate::linalg::Operator::element_bound`], plus [`law_term_bound`]); [`Method`] names
//! the estimator used.

use crate::linalg::SymMatrix;

/// Which estimator gave Δt_c (the summary's `stable_step_method`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Lanczos converged (~[`REL_TOL`] relative).
    Lanczos,
    /// Lanczos unconverged; the element eigenvalue bound, an upper bound of λ_max (module docs).
    Element,
    /// Lanczos unconverged; the Gershgorin row-sum bound, an upper bound of λ_max.
    Gershgorin,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Lanczos => "lanczos",
            Method::Element => "element",
            Method::Gershgorin => "gershgorin",
        }
    }
}

/// An upper bound of `λ_max(M_I⁻¹ B)` for the law's term B whose rows `rows` have absolute row
/// sums at most `extra` ([`crate::contact::ExplicitLaw::gershgorin`]): the ∞-norm of
/// `M_I⁻¹ B`, `max_rows d_i² extra`. Added to a bound of `λ_max(M_I⁻¹ K_II)`, it bounds
/// `λ_max(M_I⁻¹ (K + B)_II)` (Weyl's inequality on `D K D + D B D`).
pub fn law_term_bound(inv_sqrt_mass: &[f64], rows: &[usize], extra: f64) -> f64 {
    rows.iter().map(|&c| extra * inv_sqrt_mass[c] * inv_sqrt_mass[c]).fold(0.0, f64::max)
}

/// Relative change of the Ritz value over [`WINDOW`] steps that stops the iteration.
pub const REL_TOL: f64 = 1e-12;

/// Whether `dt` is refused against the computed limit Δt_c: Δt = Δt_c is not stable (the
/// highest mode's amplification matrix has the double eigenvalue −1: it grows linearly, the
/// energy quadratically), and Δt_c is known to [`REL_TOL`] relative (module docs), so
/// `dt ≥ Δt_c (1 − REL_TOL)` is refused (issue 32, E7).
pub fn refuses(dt: f64, limit: f64) -> bool {
    !(dt < limit * (1.0 - REL_TOL))
}

/// The message of [`super::SchemeError::AboveStableLimit`]: Δt_c, the estimator's margin, and a
/// `time.dt` that is accepted (0.9 Δt_c, the usual safety factor), or, where Δt_c is so small
/// that no step is (a stiff penalty), the keys that raise it.
pub fn above(scheme: &str, dt: f64, limit: f64, spring: &str) -> String {
    use crate::numfmt::fmt_f64;
    let head = format!(
        "time.dt = {} is not below the stable limit of {scheme}, Δt_c = 2/√λ_max(M_L,II⁻¹ K_II{spring}) = {} \
         (Δt = Δt_c is not stable; Δt_c is computed to {REL_TOL:e} relative, so time.dt < Δt_c (1 − {REL_TOL:e}) is required)",
        fmt_f64(dt),
        fmt_f64(limit)
    );
    let advice = 0.9 * limit;
    if advice > 1e-300 {
        format!("{head}: use time.dt ≤ {} (0.9 Δt_c)", fmt_f64(advice))
    } else {
        format!(
            "{head}: no usable time.dt is below it; lower the stiffness (contact.penalty, the material's modulus) or use an implicit scheme (scheme.kind = \"crank-nicolson\")"
        )
    }
}
pub const WINDOW: usize = 5;
/// Upper bound on the Lanczos steps (its basis is stored for the reorthogonalisation), above
/// [`EXHAUST`] interior unknowns.
pub const MAX_STEPS: usize = 300;
/// Up to this many interior unknowns Lanczos is not capped: it runs until it stalls or exhausts
/// the space (k = n, where θ_k = λ_max up to round-off), so it always converges. A uniform bar of
/// 400 elements has the top of its spectrum clustered (relative gaps ~ (π/n)²) and did not stall
/// in [`MAX_STEPS`]: the Gershgorin fallback then decided Δt (issue 32, item 3). The cost is at
/// most `4 EXHAUST³` flops of reorthogonalisation (5e8: a fraction of a second).
pub const EXHAUST: usize = 512;
/// Above [`LARGE`] interior unknowns the steps are capped at [`LARGE_STEPS`], so that the stored
/// basis (k vectors) and the reorthogonalisation (O(k² n)) stay a small multiple of one SpMV's
/// cost and memory: Δt_c's set-up linear in n (issue 20, explicit at scale). Such meshes stop
/// unconverged and take the Gershgorin bound (as they would at [`MAX_STEPS`]: the top of the
/// spectrum of a large mesh is dense).
pub const LARGE: usize = 50_000;
pub const LARGE_STEPS: usize = 30;

/// λ_max(M_I⁻¹ K_II) for the unknowns with `inv_sqrt_mass[i] > 0` (the others are left out: `K`
/// restricted to I), the number of Lanczos steps taken, and whether it converged (false: stopped
/// at [`MAX_STEPS`]; θ is then only a lower bound).
pub fn lambda_max<A: SymMatrix>(stiffness: &A, inv_sqrt_mass: &[f64]) -> (f64, usize, bool) {
    lambda_max_of(|x, y| stiffness.mul_into(x, y), inv_sqrt_mass)
}

/// The row-sum (Gershgorin) bound `max_{i ∈ I} d_i² Σ_{j ∈ I} |K_ij| (+ κ d_i² on the spring
/// unknowns)` of `M_I⁻¹ K_II` (the ∞-norm bounds the spectral radius; its eigenvalues are those
/// of `D K D`), `d = inv_sqrt_mass`, I = {d_i > 0}. Attained by the uniform lumped chain.
pub fn gershgorin<A: SymMatrix>(stiffness: &A, inv_sqrt_mass: &[f64], springs: &[usize], kappa: f64) -> f64 {
    let d = inv_sqrt_mass;
    let mut row = vec![0.0; d.len()];
    stiffness.for_each_entry(&mut |i, j, k| {
        if d[j] > 0.0 {
            row[i] += d[i] * d[i] * k.abs();
        }
    });
    springs.iter().for_each(|&c| row[c] += kappa * d[c] * d[c]);
    row.iter().zip(d).filter(|(_, d)| **d > 0.0).map(|(r, _)| *r).fold(0.0, f64::max)
}

/// The Gershgorin bound of [`gershgorin`] for an operator given by `abs_mul` (`y = |K| x`):
/// the row sums over I are `|K| 1_I` (a matrix-free stiffness, issue 31).
pub fn gershgorin_of(
    abs_mul: impl Fn(&[f64], &mut [f64]),
    inv_sqrt_mass: &[f64],
    springs: &[usize],
    kappa: f64,
) -> f64 {
    let d = inv_sqrt_mass;
    let ones: Vec<f64> = d.iter().map(|&d| if d > 0.0 { 1.0 } else { 0.0 }).collect();
    let mut row = vec![0.0; d.len()];
    abs_mul(&ones, &mut row);
    row.iter_mut().zip(d).for_each(|(r, d)| *r *= d * d);
    springs.iter().for_each(|&c| row[c] += kappa * d[c] * d[c]);
    row.iter().zip(d).filter(|(_, d)| **d > 0.0).map(|(r, _)| *r).fold(0.0, f64::max)
}

/// [`lambda_max`] for the operator `y = K x` given as a function (a stiffness with penalty
/// springs added).
pub fn lambda_max_of(mul: impl Fn(&[f64], &mut [f64]), inv_sqrt_mass: &[f64]) -> (f64, usize, bool) {
    lanczos(mul, inv_sqrt_mass, true)
}

/// [`lambda_max_of`] in O(n) memory above [`LARGE`] interior unknowns: there the basis is not
/// stored and the recurrence is Lanczos's three-term one without reorthogonalisation (a
/// matrix-free stiffness, issue 31: 30 stored vectors would be 240 bytes per unknown, more than
/// the operator's whole step). Lost orthogonality makes copies of converged Ritz values, not a
/// larger one: θ_k is still the largest eigenvalue of a tridiagonal whose eigenvalues lie in
/// λ(B) up to round-off (Paige 1980), a lower bound of λ_max, and the same stopping rule applies.
/// Below [`LARGE`] it is [`lambda_max_of`].
pub fn lambda_max_lean(mul: impl Fn(&[f64], &mut [f64]), inv_sqrt_mass: &[f64]) -> (f64, usize, bool) {
    let ni = inv_sqrt_mass.iter().filter(|&&d| d > 0.0).count();
    lanczos(mul, inv_sqrt_mass, ni <= LARGE)
}

fn lanczos(mul: impl Fn(&[f64], &mut [f64]), inv_sqrt_mass: &[f64], reorthogonalise: bool) -> (f64, usize, bool) {
    let n = inv_sqrt_mass.len();
    let active = |i: usize| inv_sqrt_mass[i] > 0.0;
    let ni = (0..n).filter(|&i| active(i)).count();
    if ni == 0 {
        return (0.0, 0, true);
    }
    let kmax = if ni <= EXHAUST { ni } else { ni.min(if ni > LARGE { LARGE_STEPS } else { MAX_STEPS }) };
    // A fixed start vector with components on every eigenvector in general position.
    let mut q: Vec<f64> = (0..n)
        .map(|i| if active(i) { 1.0 + 0.5 * ((i as f64 + 1.0) * 0.618_033_988_749_895).fract() } else { 0.0 })
        .collect();
    normalise(&mut q);
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(if reorthogonalise { kmax } else { 0 });
    // q_{k−1} of the three-term recurrence (without reorthogonalisation).
    let mut previous = vec![0.0; if reorthogonalise { 0 } else { n }];
    let (mut alpha, mut beta) = (Vec::with_capacity(kmax), Vec::with_capacity(kmax));
    let (mut x, mut y) = (vec![0.0; n], vec![0.0; n]);
    let mut history: Vec<f64> = Vec::new();
    for k in 0..kmax {
        // w = B q = D K D q on I.
        for i in 0..n {
            x[i] = inv_sqrt_mass[i] * q[i];
        }
        mul(&x, &mut y);
        for i in 0..n {
            y[i] *= inv_sqrt_mass[i];
        }
        let a: f64 = y.iter().zip(&q).map(|(a, b)| a * b).sum();
        alpha.push(a);
        if reorthogonalise {
            basis.push(q.clone());
            // Full reorthogonalisation (twice is enough: Parlett's "twice is enough").
            for _ in 0..2 {
                for b in &basis {
                    let c: f64 = y.iter().zip(b).map(|(a, b)| a * b).sum();
                    for (yi, bi) in y.iter_mut().zip(b) {
                        *yi -= c * bi;
                    }
                }
            }
        } else {
            // The three-term recurrence: y − α_k q_k − β_{k−1} q_{k−1}.
            let b = beta.last().copied().unwrap_or(0.0);
            for ((yi, qi), pi) in y.iter_mut().zip(&q).zip(&previous) {
                *yi -= a * qi + b * pi;
            }
        }
        let theta = largest_eigenvalue(&alpha, &beta);
        history.push(theta);
        let norm = y.iter().map(|v| v * v).sum::<f64>().sqrt();
        let stalled = history.len() > WINDOW && {
            let old = history[history.len() - 1 - WINDOW];
            (theta - old).abs() <= REL_TOL * theta.abs()
        };
        let exhausted = k + 1 == ni || norm <= 1e-14 * theta.abs().max(f64::MIN_POSITIVE);
        if stalled || exhausted || k + 1 == kmax {
            return (theta, k + 1, stalled || exhausted);
        }
        beta.push(norm);
        if !reorthogonalise {
            previous.copy_from_slice(&q);
        }
        for (qi, yi) in q.iter_mut().zip(&y) {
            *qi = yi / norm;
        }
    }
    unreachable!("the loop returns at k = kmax − 1")
}

fn normalise(v: &mut [f64]) {
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    v.iter_mut().for_each(|x| *x /= n);
}

/// The largest eigenvalue of the symmetric tridiagonal (alpha, beta) by bisection on the Sturm
/// count, to round-off (Gershgorin interval, 200 halvings at most).
fn largest_eigenvalue(alpha: &[f64], beta: &[f64]) -> f64 {
    let k = alpha.len();
    let mut hi = f64::NEG_INFINITY;
    let mut lo = f64::INFINITY;
    for i in 0..k {
        let r = if i > 0 { beta[i - 1].abs() } else { 0.0 } + if i < beta.len() { beta[i].abs() } else { 0.0 };
        hi = hi.max(alpha[i] + r);
        lo = lo.min(alpha[i] - r);
    }
    // count(x) = number of eigenvalues < x.
    let count = |x: f64| {
        let mut c = 0;
        let mut d = 1.0;
        for i in 0..k {
            let b2 = if i > 0 { beta[i - 1] * beta[i - 1] } else { 0.0 };
            d = alpha[i] - x - if i > 0 { b2 / d } else { 0.0 };
            if d == 0.0 {
                d = -f64::EPSILON * (x.abs() + 1.0);
            }
            if d < 0.0 {
                c += 1;
            }
        }
        c
    };
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if count(mid) == k { hi = mid } else { lo = mid }
    }
    hi
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::tridiag::SymTridiag;

    /// The path graph Laplacian tridiag(−1, 2, −1) of order n has eigenvalues
    /// `4 sin²(jπ/(2(n+1)))`: the largest to 1e-12 relative (n = 50 < MAX_STEPS: Lanczos reaches
    /// the whole space or stalls at λ_max). (Mutation: dropping the reorthogonalisation loop ->
    /// spurious copies, still ≤ λ_max; dropping `y[i] *= inv_sqrt_mass[i]` -> fails.)
    #[test]
    fn lanczos_finds_the_largest_eigenvalue_of_the_path_laplacian() {
        let n = 50;
        let k = SymTridiag { diag: vec![2.0; n], off: vec![-1.0; n - 1] };
        let (lam, _, converged) = lambda_max(&k, &vec![0.5; n]);
        assert!(converged);
        let exact = 4.0 * (std::f64::consts::PI * n as f64 / (2.0 * (n as f64 + 1.0))).sin().powi(2) * 0.25;
        assert!((lam - exact).abs() <= 1e-12 * exact, "{lam} vs {exact}");
    }

    /// Without reorthogonalisation (above [`LARGE`]) the three-term recurrence must still be
    /// Lanczos's: on `diag(1, 2, 5, 1, 2, 5, …)` of order 60 000 with M = I, the Krylov space
    /// of any start vector has dimension 3, so the iteration exhausts it at k = 3 with
    /// θ = λ_max = 5 to round-off (tolerance: 1e-12, `REL_TOL`). And θ is a lower bound on the
    /// path Laplacian of order 60 000 (λ_max = 4 sin²(nπ/(2(n+1))), 30 steps, unconverged).
    /// (Mutation, as run: the β_{k−1} q_{k−1} term dropped -> the first case fails.)
    #[test]
    fn lanczos_without_a_stored_basis_is_lanczos() {
        let n = LARGE + 10_000;
        let diag: Vec<f64> = (0..n).map(|i| [1.0, 2.0, 5.0][i % 3]).collect();
        let mul = |x: &[f64], y: &mut [f64]| y.iter_mut().zip(x).zip(&diag).for_each(|((y, x), d)| *y = d * x);
        let (theta, steps, converged) = lambda_max_lean(mul, &vec![1.0; n]);
        assert!(converged && steps <= 4 && (theta - 5.0).abs() <= 1e-12 * 5.0, "{theta} {steps} {converged}");
        let k = SymTridiag { diag: vec![2.0; n], off: vec![-1.0; n - 1] };
        let exact = 4.0 * (n as f64 * std::f64::consts::PI / (2.0 * (n as f64 + 1.0))).sin().powi(2);
        let (theta, steps, _) = lambda_max_lean(|x, y| k.mul_into(x, y), &vec![1.0; n]);
        assert!(theta <= exact * (1.0 + 1e-14) && steps == LARGE_STEPS, "{theta} vs {exact} ({steps} steps)");
    }
}
