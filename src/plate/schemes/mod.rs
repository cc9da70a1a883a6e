//! Time schemes for the 2D contact problem `M Ü + S U = F − Σ_c λ_c e_c`,
//! `0 ≤ u_c ⊥ λ_c ≤ 0` (the paper's schemes of §4.2 and §5 with many contact nodes).
//!
//! One file per scheme, as in 1D ([`crate::schemes`]), with the same conventions, so that a
//! y-independent 2D run equals the 1D run step by step:
//! - U⁰, V⁰ are nodal interpolants on all free nodes (contact nodes included), λ⁰ = 0;
//! - A⁰ solves `M A⁰ = F − S U⁰` on the nodes with mass, and is 0 on massless nodes;
//! - a massless node's velocity is reported as `(u^{n+1} − uⁿ)/Δt` and its acceleration is 0.
//!
//! The schemes run on a mesh-free [`ContactSystem`]; `ContactSystem::from_bar` makes the 1D bar
//! one too, and the tests check that these schemes reproduce the 1D ones on it (the update
//! formulas are the 1D ones written for a vector of contact multipliers; only the linear
//! algebra differs: sparse Cholesky + LCP instead of a tridiagonal LDLᵀ + one-node formula).
//! Paoli–Schatzman and the reduced Newmark formulation are not ported (see the module docs of
//! [`crate::plate`]).

pub mod backward_euler;
pub mod hybrid;
pub mod newmark;

use super::assembly::ContactSystem;
use super::lcp::LcpError;
use super::sparse::{self, SparseError, SparseLlt};
use crate::schemes::SchemeError;
use thiserror::Error;

pub use backward_euler::BackwardEuler2d;
pub use hybrid::Hybrid2d;
pub use newmark::Newmark2d;

/// The discrete state at `t_n = n Δt`, borrowed from the scheme.
#[derive(Debug, Clone, Copy)]
pub struct PlateState<'a> {
    pub n: usize,
    pub t: f64,
    /// Displacements on the free unknowns.
    pub u: &'a [f64],
    /// Velocities on the free unknowns.
    pub v: &'a [f64],
    /// Contact multipliers λ_c ≤ 0, one per contact unknown (in `ContactSystem::contact` order):
    /// nodal contact forces, whose sum is the total contact force on Γ_C.
    pub lambda: &'a [f64],
}

/// A one-step time integrator of the 2D contact problem.
pub trait PlateScheme: Send {
    fn state(&self) -> PlateState<'_>;
    fn step(&mut self) -> Result<(), PlateSchemeError>;
    /// Principal pivots used by the contact solves of the last step.
    fn pivots(&self) -> usize;
}

#[derive(Debug, Clone, PartialEq, Error)]
pub enum PlateSchemeError {
    #[error(transparent)]
    Scheme(#[from] SchemeError),
    #[error(transparent)]
    Sparse(#[from] SparseError),
    #[error("step {step} (t = {time}): {source}")]
    Contact { step: usize, time: f64, source: LcpError },
}

/// A⁰ from `M A⁰ = F − S U⁰` on the unknowns with mass (M is SPD there); 0 on massless ones.
pub fn initial_acceleration(system: &ContactSystem, u: &[f64]) -> Result<Vec<f64>, PlateSchemeError> {
    let n = system.n();
    let massive: Vec<usize> = (0..n).filter(|&i| !system.massless[i]).collect();
    let mut r = vec![0.0; n];
    sparse::sym_mul_into(&system.stiffness, u, &mut r);
    let mut a = vec![0.0; n];
    if massive.is_empty() {
        return Ok(a);
    }
    let mm = sparse::principal(&system.mass, &massive, "mass")?;
    let mut factor = SparseLlt::new(&mm, "mass")?;
    let mut rp: Vec<f64> = massive.iter().map(|&i| system.load[i] - r[i]).collect();
    factor.solve_in_place(&mut rp);
    for (k, &i) in massive.iter().enumerate() {
        a[i] = rp[k];
    }
    Ok(a)
}

/// Per-step finiteness check (all unknowns and multipliers: a sparse solve need not spread a
/// NaN to a fixed entry).
pub(crate) fn check_finite(u: &[f64], lambda: &[f64], step: usize, time: f64) -> Result<(), PlateSchemeError> {
    if u.iter().chain(lambda).all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(SchemeError::NonFinite { step, time }.into())
    }
}

pub(crate) fn contact_err(step: usize, time: f64) -> impl Fn(LcpError) -> PlateSchemeError {
    move |source| PlateSchemeError::Contact { step, time, source }
}
