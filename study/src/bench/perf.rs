//! Time per node-step of each scheme next to the floor of an implicit 1D step: one bare
//! tridiagonal solve of the same size (LDLᵀ, and the two-sided [`massredist::linalg::tridiag::TwistedFactor`]).
//!
//! A 1D implicit step costs at least one forward and one backward substitution; each is a
//! chain of dependent multiply–subtracts, so on one core the solve is bound by the latency of
//! that chain, not by arithmetic or memory. The schemes hide their O(m) streaming work (the
//! right-hand side, the update of U, V, A) inside the chains of a two-sided solve, which halves
//! the chain length. This module measures both with the same clock in the same process.
//!
//! Timing is at the edge by nature: nothing here is used by a test.

use super::timing::{best_ns_per_unit, best_timed};
use massredist::driver::integrate;
use massredist::linalg::tridiag::SymTridiag;
use massredist::mass::MassKind;
use massredist::models::{PaperBar, PaperPlate};
use massredist::scene::SchemeSpec;
use serde::Serialize;
use std::hint::black_box;
use std::time::Instant;

/// The Crank–Nicolson iteration matrix `M + Δt²/4 S` of the standard mass with Δt = h: an SPD
/// tridiagonal matrix of the size of a step, used for the bare-solve floor.
pub fn floor_matrix(elements: usize) -> SymTridiag {
    let problem = PaperBar::unit(elements).problem(&MassKind::Standard).expect("standard mass assembles");
    let h = problem.system.h();
    let s = &problem.system.system;
    s.mass.combine(1.0, &s.stiffness, h * h / 4.0)
}

/// Which bare solve to time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Solver {
    /// One-sided LDLᵀ: one forward and one backward chain of length n.
    Ldlt,
    /// Two-sided (twisted) factorisation: two interleaved chains of length n/2 per sweep, with
    /// fused multiply-add where the CPU has it (what the schemes use).
    Twisted,
    /// The same without fused multiply-add.
    TwistedNoFma,
}

/// ns per unknown of one solve `A x = b` (the right-hand side is restored by a copy before
/// each solve, so that repeated solves neither overflow nor underflow; the copy is counted).
pub fn time_solve(solver: Solver, elements: usize, min_total: f64) -> f64 {
    let a = floor_matrix(elements);
    let b: Vec<f64> = (0..elements).map(|i| (i as f64 * 0.37).sin()).collect();
    let mut x = b.clone();
    let solves = (2_000_000 / elements).max(1);
    let work = (solves * elements) as f64;
    match solver {
        Solver::Ldlt => {
            let f = a.factor().expect("SPD");
            best_ns_per_unit(work, 3, 200, min_total, || {
                for _ in 0..solves {
                    x.copy_from_slice(&b);
                    f.solve_in_place(black_box(&mut x));
                }
            })
        }
        Solver::Twisted => {
            let f = a.factor_twisted().expect("SPD");
            best_ns_per_unit(work, 3, 200, min_total, || {
                for _ in 0..solves {
                    x.copy_from_slice(&b);
                    f.solve_in_place(black_box(&mut x));
                }
            })
        }
        Solver::TwistedNoFma => {
            let f = a.factor_twisted().expect("SPD");
            best_ns_per_unit(work, 3, 200, min_total, || {
                for _ in 0..solves {
                    x.copy_from_slice(&b);
                    f.solve_in_place_without_fma(black_box(&mut x));
                }
            })
        }
    }
}

/// ns per node-step of `spec` on the benchmark with `elements` elements and Δt = h / `divisor`,
/// through the public driver with no observer (the scheme is built once, outside the clock;
/// each timed run restarts from a fresh clone so that every run steps the same states).
pub fn time_scheme(spec: &SchemeSpec, mass: &MassKind, elements: usize, divisor: usize, min_total: f64) -> Option<f64> {
    let problem = PaperBar::unit(elements).problem(mass).ok()?;
    let dt = problem.system.h() / divisor as f64;
    // About 2·10⁶ node-steps per timed run, at least 64 steps; never past one period (3L).
    let steps = (2_000_000 / elements).clamp(64, 3 * elements * divisor);
    let work = (steps * elements) as f64;
    problem.scheme(spec, dt).ok()?;
    let mut failed = false;
    let ns = best_timed(work, 3, 100, min_total, || {
        // Construction (factorisation) is outside the per-step figure: it is O(m) once.
        let mut scheme = problem.scheme(spec, dt).expect("built once already");
        let t = Instant::now();
        failed |= integrate(&problem, scheme.as_mut(), steps, &mut []).is_err();
        t.elapsed().as_secs_f64()
    });
    (!failed).then_some(ns)
}

/// ns per node-step of each scheme at one size, next to the bare solves.
#[derive(Debug, Clone, Serialize)]
pub struct SizeTimings {
    pub elements: usize,
    /// Bare one-sided LDLᵀ solve, ns per unknown: the naive floor of an implicit step.
    pub ldlt_ns: f64,
    /// Bare two-sided (twisted) solve, ns per unknown (FMA where available, as the schemes).
    pub twisted_ns: f64,
    /// The same without fused multiply-add.
    pub twisted_no_fma_ns: f64,
    pub schemes: Vec<SchemeTiming>,
}

#[derive(Debug, Clone, Serialize)]
pub struct SchemeTiming {
    pub scheme: &'static str,
    pub mass: &'static str,
    /// None if the run failed.
    pub ns_per_node_step: Option<f64>,
}

/// Times every scheme of [`super::sweep::scheme_cases`] (standard mass, or Mod 3 where w_0 = 0
/// is needed) and the two bare solves at `elements`, Δt = h, sequentially.
pub fn time_size(elements: usize, min_total: f64) -> SizeTimings {
    let ldlt_ns = time_solve(Solver::Ldlt, elements, min_total);
    let twisted_ns = time_solve(Solver::Twisted, elements, min_total);
    let twisted_no_fma_ns = time_solve(Solver::TwistedNoFma, elements, min_total);
    let schemes = super::sweep::scheme_cases()
        .into_iter()
        .map(|c| {
            let mass = if c.needs_massless { MassKind::Mod3 } else { MassKind::Standard };
            SchemeTiming {
                scheme: c.label,
                mass: mass.name(),
                ns_per_node_step: time_scheme(&c.spec, &mass, elements, 1, min_total),
            }
        })
        .collect();
    SizeTimings { elements, ldlt_ns, twisted_ns, twisted_no_fma_ns, schemes }
}

/// Seconds per step of `spec` on the benchmark over exactly `steps` steps of Δt = h (fastest of
/// repeated runs), and the final displacement (to compare with another implementation).
pub fn time_steps(
    spec: &SchemeSpec,
    mass: &MassKind,
    elements: usize,
    steps: usize,
    min_total: f64,
) -> Option<(f64, Vec<f64>)> {
    let problem = PaperBar::unit(elements).problem(mass).ok()?;
    let dt = problem.system.h();
    let mut last = Vec::new();
    let mut failed = false;
    let s_per_step = best_timed(steps as f64, 3, 50, min_total, || {
        let mut scheme = problem.scheme(spec, dt).expect("valid benchmark scheme");
        let t = Instant::now();
        failed |= integrate(&problem, scheme.as_mut(), steps, &mut []).is_err();
        let secs = t.elapsed().as_secs_f64();
        last = scheme.state().u.to_vec();
        secs
    }) * 1e-9;
    (!failed).then_some((s_per_step, last))
}

/// 2D: time per step of each plate scheme against one sparse triangular solve pair (forward and
/// backward substitution with the sparse Cholesky factor of the same iteration matrix).
#[derive(Debug, Clone, Serialize)]
pub struct PlateTimings {
    pub nx: usize,
    pub ny: usize,
    pub unknowns: usize,
    /// One `L Lᵀ` solve of the Crank–Nicolson matrix `M + Δt²/4 S` (Mod 3, Δt = h), µs.
    pub solve_pair_us: f64,
    pub schemes: Vec<(&'static str, Option<f64>)>,
}

/// Times the plate schemes (Crank–Nicolson, backward Euler, hybrid; Mod 3, quad mesh nx × ny of
/// (0,1) × (0, ny/nx), Δt = 1/nx, the paper's initial data) and the bare sparse solve pair.
pub fn time_plate(nx: usize, ny: usize, min_total: f64) -> Option<PlateTimings> {
    use massredist::fem::Cell;
    use massredist::linalg::sparse;
    let plate = PaperPlate { height: ny as f64 / nx as f64, nx, ny, cells: Cell::Quad };
    let problem = plate.problem(&MassKind::Mod3).ok()?;
    let dt = 1.0 / nx as f64;
    let sys = &problem.system.system;
    let k = sparse::combine(&sys.mass, 1.0, &sys.stiffness, dt * dt / 4.0, "M + Δt²/4 S").ok()?;
    let mut llt = sparse::SparseLlt::new(&k, "M + Δt²/4 S").ok()?;
    let n = sys.mass.nrows();
    let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
    let mut x = b.clone();
    let solve_pair_us = best_ns_per_unit(1.0, 5, 2000, min_total, || {
        x.copy_from_slice(&b);
        llt.solve_in_place(black_box(&mut x));
    }) * 1e-3;
    let steps = 3 * nx; // one period
    let schemes = super::sweep::scheme_cases()
        .into_iter()
        .filter(|c| {
            matches!(
                c.spec,
                SchemeSpec::CrankNicolson { formulation: massredist::scene::Formulation::Full }
                    | SchemeSpec::BackwardEuler
                    | SchemeSpec::Hybrid
            )
        })
        .map(|c| {
            let mut failed = false;
            let us = best_timed(steps as f64, 2, 20, min_total, || {
                let Ok(mut s) = problem.scheme(&c.spec, dt) else {
                    failed = true;
                    return f64::NAN;
                };
                let t = Instant::now();
                failed |= integrate(&problem, s.as_mut(), steps, &mut []).is_err();
                t.elapsed().as_secs_f64()
            }) * 1e-3;
            (c.label, (!failed && us.is_finite()).then_some(us))
        })
        .collect();
    Some(PlateTimings { nx, ny, unknowns: n, solve_pair_us, schemes })
}
