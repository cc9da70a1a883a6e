//! Orders in time at a fixed mesh, against a fine-Δt reference of the same scheme (the
//! semi-discrete solution up to the reference's own error), through impact, contact and release.
//!
//! - Lemma 3.1 of the paper: Crank–Nicolson on the semi-discrete problem (P^mod_U) (w_0 = 0,
//!   the reduced formulation) has a time error of order Δt: G is only Lipschitz (the u_1⁺ term),
//!   so no higher order is claimed. Every observed order must be at least 1.
//! - The hybrid scheme (§5) is second order in time with contact: every order at least 1.8.
//!
//! Data: the paper's bar, m = 6 (h = 1/6), mod1, T = 3 (impact at 0.5, release at 2.5).
//! Error: max over n of max_i |U_i^n − U_ref,i(t_n)|, with Δt = 3/N for N = 150, 300, 600,
//! 1200 and the reference at N_ref = 16 · 1200, so its own error is (1/16)^p of the finest
//! one's (p ≥ 1): at most 6 % of it, which lowers an observed order by at most about 0.03.

mod common;

use common::{CN_REDUCED, trajectory};
use massredist::bar::BarProblem;
use massredist::mass::MassKind;
use massredist::scene::SchemeSpec;

const END: f64 = 3.0;
const STEPS: [usize; 4] = [150, 300, 600, 1200];
const REFINE: usize = 16;

/// The largest nodal error of `spec` at each N of [`STEPS`] against its own run at
/// `REFINE · 1200` steps, and the observed order between successive Δt (log₂ of the ratio of
/// the errors: Δt halves from one to the next).
fn orders(spec: &SchemeSpec) -> (Vec<f64>, Vec<f64>) {
    let problem = BarProblem::benchmark(1.0, 6, &MassKind::Mod1).expect("the paper's bar assembles");
    let fine_steps = REFINE * STEPS[STEPS.len() - 1];
    let fine = trajectory(&problem, spec, END / fine_steps as f64, fine_steps);
    let errors: Vec<f64> = STEPS
        .iter()
        .map(|&n| {
            let run = trajectory(&problem, spec, END / n as f64, n);
            let stride = fine_steps / n;
            run.iter()
                .enumerate()
                .flat_map(|(k, f)| f.u.iter().zip(&fine[k * stride].u).map(|(a, b)| (a - b).abs()))
                .fold(0.0, f64::max)
        })
        .collect();
    let orders = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    (errors, orders)
}

#[test]
fn crank_nicolson_is_at_least_first_order_in_time_at_fixed_h() {
    // Lemma 3.1 (order Δt). Measured: errors 1.29e-2, 5.25e-3, 2.37e-3, 1.09e-3, orders 1.30,
    // 1.15, 1.12 (the reference lowers the last by at most 0.03). Mutation: the reduced
    // formulation's predictor with (½ − β)Δt A instead of (½ − β)Δt² A (an O(Δt) error per
    // step) -> errors 0.64, 2.0e-2, 1.1e-2, 5.8e-3, orders 0.86 and 0.96 after the first -> fails.
    let (errors, p) = orders(&CN_REDUCED);
    assert!(p.iter().all(|&p| p >= 1.0), "orders {p:?}, errors {errors:?}");
    assert!(errors[3] < 2.5e-3, "finest error {:.3e}", errors[3]); // ceiling: 2.3 × the measured 1.09e-3
}

#[test]
fn the_hybrid_scheme_is_second_order_in_time_with_contact() {
    // Second order through impact and release (its contact rows are quasi-static, solved
    // exactly at each step). Measured: errors 8.91e-3, 2.22e-3, 5.58e-4, 1.38e-4, orders 2.00,
    // 1.99, 2.02. Bound 1.8: order 2 less the reference's effect (at most 0.03 here, where
    // (1/16)² makes it 0.4 %) and a margin for the kinks of the solution. Mutation: the
    // predictor Uⁿ + ½ΔtVⁿ replaced by Uⁿ + ΔtVⁿ -> fails.
    let (errors, p) = orders(&SchemeSpec::Hybrid);
    assert!(p.iter().all(|&p| p >= 1.8), "orders {p:?}, errors {errors:?}");
    assert!(errors[3] < 3e-4, "finest error {:.3e}", errors[3]); // ceiling: 2.2 × the measured 1.38e-4
}
