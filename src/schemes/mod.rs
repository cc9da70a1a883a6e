//! Time schemes for `M Ü + S U = F − λ e_0`, `0 ≤ u_0 ⊥ λ ≤ 0` (paper §4.2 and §5).
//!
//! One file per scheme of the paper. Each scheme factors its iteration matrix once in `new`,
//! allocates its work vectors once, and then `step` advances one Δt without allocating.
//! Conventions shared by all (so that results compare with other codes):
//! - U⁰, V⁰ are the nodal interpolants at all free nodes, the contact node included; λ⁰ = 0;
//! - A⁰ solves the equation of motion `M A⁰ = F − S U⁰`; with a massless contact node (w_0 = 0)
//!   only rows 1..m−1 are determined and A⁰_0 = 0 (see [`initial_acceleration`]);
//! - with a massless contact node its velocity and acceleration enter no equation (row and column
//!   0 of M vanish); the schemes report `v_0 = (u_0^{n+1} − u_0^n)/Δt` and keep `a_0 = 0`.

pub mod backward_euler;
pub mod hybrid;
pub mod newmark;
pub mod newmark_reduced;
pub mod paoli_schatzman;

use crate::assembly::System;
use crate::tridiag::FactorError;
use thiserror::Error;

pub use backward_euler::BackwardEuler;
pub use hybrid::Hybrid;
pub use newmark::Newmark;
pub use newmark_reduced::NewmarkReduced;
pub use paoli_schatzman::PaoliSchatzman;

/// The discrete state at `t_n = n Δt`, borrowed from the scheme (no copy).
#[derive(Debug, Clone, Copy)]
pub struct StateView<'a> {
    pub n: usize,
    pub t: f64,
    /// Displacements at the free nodes 0..m−1 (node 0 = contact node).
    pub u: &'a [f64],
    /// Velocities at the free nodes.
    pub v: &'a [f64],
    /// Contact force λⁿ ≤ 0 (the Lagrange multiplier of `−λ e_0`).
    pub lambda: f64,
}

/// A one-step time integrator of the contact problem.
pub trait Scheme: Send {
    fn state(&self) -> StateView<'_>;
    fn step(&mut self) -> Result<(), SchemeError>;
}

#[derive(Debug, Clone, PartialEq, Error)]
pub enum SchemeError {
    #[error("the {matrix} matrix cannot be factored: {source}")]
    Factor { matrix: &'static str, source: FactorError },
    #[error("{scheme}: {key} = {value} is outside the allowed range {range}")]
    Parameter { scheme: &'static str, key: &'static str, value: f64, range: &'static str },
    #[error(
        "{scheme} needs a massless contact node (w_0 = 0: mass.kind = mod1, mod2, mod3 or custom weights with weights[0] = 0), got w_0 = {w0}"
    )]
    NeedsMasslessContact { scheme: &'static str, w0: f64 },
    #[error("the solution is not finite at step {step} (t = {time}): the scheme is unstable for this Δt / mass")]
    NonFinite { step: usize, time: f64 },
}

pub(crate) fn factor_err(matrix: &'static str) -> impl Fn(FactorError) -> SchemeError {
    move |source| SchemeError::Factor { matrix, source }
}

/// Checks `lo < value ≤ hi` style ranges; `range` is the text shown to the user.
pub(crate) fn check_range(
    scheme: &'static str,
    key: &'static str,
    value: f64,
    ok: bool,
    range: &'static str,
) -> Result<(), SchemeError> {
    if ok && value.is_finite() { Ok(()) } else { Err(SchemeError::Parameter { scheme, key, value, range }) }
}

/// A⁰ from the equation of motion `M A⁰ = F − S U⁰` (λ⁰ = 0). With a massless contact node the
/// system is solved on rows and columns 1..m−1 (M* is SPD there) and A⁰_0 = 0.
pub fn initial_acceleration(system: &System, u: &[f64]) -> Result<Vec<f64>, SchemeError> {
    let m = system.m();
    let k = system.first_massive();
    let mut r = vec![0.0; m];
    system.stiffness.mul_into(u, &mut r);
    for (ri, fi) in r.iter_mut().zip(&system.load) {
        *ri = fi - *ri;
    }
    let factor = system.mass.trailing(k).factor().map_err(factor_err("mass"))?;
    let mut a = vec![0.0; m];
    a[k..].copy_from_slice(&r[k..]);
    factor.solve_in_place(&mut a[k..]);
    Ok(a)
}

/// Exact solution of the one-node Signorini condition inside an implicit step.
///
/// Every full-system scheme solves, at each step, `K U = r − σ λ e_0` with `lb ≤ u_0 ⊥ λ ≤ 0`
/// (lb = 0 for Newmark and backward Euler, lb = −e u_0^{n−1} for Paoli–Schatzman), K symmetric
/// positive definite and σ > 0 the scheme's force scale. With the unconstrained `u* = K⁻¹ r` and
/// the precomputed `z = K⁻¹ e_0` (z_0 > 0 since K is SPD): λ = 0 if `u*_0 ≥ lb`, else
/// `λ = (u*_0 − lb)/(σ z_0) < 0`, and the constrained solution is `u* − σ λ z` with `u_0 = lb` set
/// exactly (complementarity then holds bit for bit). The schemes apply the correction inside their
/// update loop (one pass over the nodes instead of two).
#[inline]
pub(crate) fn contact_multiplier(u0_star: f64, lower: f64, sigma: f64, z0: f64) -> f64 {
    if u0_star >= lower { 0.0 } else { (u0_star - lower) / (sigma * z0) }
}

/// Cheap per-step finiteness check: a NaN or ∞ anywhere reaches both ends of the chain within
/// one tridiagonal solve, so checking the contact node, the last node and λ suffices.
pub(crate) fn check_finite(u: &[f64], lambda: f64, step: usize, time: f64) -> Result<(), SchemeError> {
    if u[0].is_finite() && u[u.len() - 1].is_finite() && lambda.is_finite() {
        Ok(())
    } else {
        Err(SchemeError::NonFinite { step, time })
    }
}
