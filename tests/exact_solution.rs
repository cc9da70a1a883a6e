//! The exact solution of the impacting bar satisfies the wave equation, both boundary
//! conditions, complementarity, the energy identity and periodicity; and the paper's sign typo
//! in region I of the contact phase is corrected.

use massredist::exact::ImpactingBar;

/// A few ulps of O(L) values.
fn tol(l: f64) -> f64 {
    16.0 * f64::EPSILON * l.max(1.0)
}

fn grid(n: usize, a: f64, b: f64) -> impl Iterator<Item = f64> {
    (0..=n).map(move |i| a + (b - a) * i as f64 / n as f64)
}

#[test]
fn wave_equation_holds_on_characteristic_parallelograms() {
    // d'Alembert: u solves u_tt = u_xx iff u(P) + u(R) = u(Q) + u(S) on every characteristic
    // parallelogram P=(x,t), Q=(x+a,t+a), R=(x+a−b,t+a+b), S=(x−b,t+b). Checked well inside
    // (0,L)×(0,3L) over several periods, including parallelograms across every kink.
    for l in [1.0, 2.5] {
        let e = ImpactingBar { length: l };
        for x in grid(40, 0.3 * l, 0.7 * l) {
            for t in grid(97, 0.0, 8.0 * l) {
                for (a, b) in [(0.1, 0.05), (0.2, 0.13), (0.05, 0.27)] {
                    let (a, b) = (a * l, b * l);
                    let lhs = e.u(x, t) + e.u(x + a - b, t + a + b);
                    let rhs = e.u(x + a, t + a) + e.u(x - b, t + b);
                    assert!(
                        approx::relative_eq!(lhs, rhs, epsilon = tol(l), max_relative = 0.0),
                        "L={l} x={x} t={t}: {lhs} vs {rhs}"
                    );
                }
            }
        }
    }
}

#[test]
fn boundary_conditions_and_complementarity() {
    for l in [1.0, 2.5] {
        let e = ImpactingBar { length: l };
        for t in grid(3000, 0.0, 9.0 * l) {
            assert_eq!(e.u(l, t), 0.0, "Dirichlet at x = L, t = {t}");
            let (u0, lam) = (e.u0(t), e.lambda(t));
            assert!(u0 >= 0.0 && lam <= 0.0 && u0 * lam == 0.0, "t = {t}: u0 = {u0}, λ = {lam}");
            // λ = u_x(0+, t) away from the switching times.
            let tau = (t / l).rem_euclid(3.0);
            if tau > 1e-9 && (tau - 1.0).abs() > 1e-9 && (tau - 2.0).abs() > 1e-9 {
                assert_eq!(lam, e.u_x(0.0, t), "t = {t}");
            }
        }
        // Contact exactly on (L, 2L) with λ = −1/2; free flight with u(0,t) > 0 elsewhere.
        assert_eq!(e.lambda(1.5 * l), -0.5);
        assert!(e.u0(0.5 * l) > 0.0 && e.u0(2.5 * l) > 0.0);
        assert_eq!(e.u0(1.5 * l), 0.0);
    }
}

#[test]
fn initial_data_periodicity_and_continuity() {
    for l in [1.0, 2.5] {
        let e = ImpactingBar { length: l };
        for x in grid(50, 0.0, l) {
            assert!(
                approx::relative_eq!(e.u(x, 0.0), (l - x) / 2.0, epsilon = tol(l), max_relative = 0.0),
                "u(x, 0) = (L − x)/2 at x = {x}"
            );
            if x > 0.0 {
                assert_eq!(e.u_t(x, 0.0), 0.0);
            }
            for t in grid(60, 0.0, 3.0 * l) {
                assert!(
                    approx::relative_eq!(e.u(x, t + 3.0 * l), e.u(x, t), epsilon = tol(l), max_relative = 0.0),
                    "period 3L at x={x} t={t}"
                );
                // Lipschitz with constant 1/2 in x and t (|u_x|, |u_t| ≤ 1/2): continuity across kinks.
                let d = 1e-7 * l;
                approx::assert_relative_eq!(e.u(x, t + d), e.u(x, t), epsilon = 0.5 * d + tol(l), max_relative = 0.0);
                approx::assert_relative_eq!(
                    e.u((x + d).min(l), t),
                    e.u(x, t),
                    epsilon = 0.5 * d + tol(l),
                    max_relative = 0.0
                );
            }
        }
    }
}

/// ½∫₀ᴸ (u_t² + u_x²) dx, exact: u_t and u_x are constant between consecutive kinks.
fn energy(e: &ImpactingBar, t: f64) -> f64 {
    let mut k = [0.0; 3];
    let n = e.kinks(t, &mut k);
    let mut pts: Vec<f64> = k[..n].to_vec();
    pts.push(0.0);
    pts.push(e.length);
    pts.sort_by(f64::total_cmp);
    pts.windows(2)
        .map(|w| {
            let mid = 0.5 * (w[0] + w[1]);
            0.5 * (w[1] - w[0]) * (e.u_t(mid, t).powi(2) + e.u_x(mid, t).powi(2))
        })
        .sum()
}

#[test]
fn energy_is_l_over_8_at_all_times() {
    for l in [1.0, 2.5] {
        let e = ImpactingBar { length: l };
        for t in grid(901, 0.0, 9.0 * l) {
            assert!(
                approx::relative_eq!(energy(&e, t), l / 8.0, epsilon = tol(l), max_relative = 0.0),
                "L={l} t={t}: {}",
                energy(&e, t)
            );
        }
    }
}

#[test]
fn u_t_and_u_x_are_the_derivatives_of_u() {
    // Centred differences of the affine pieces reproduce u_t and u_x away from kinks.
    let e = ImpactingBar { length: 1.0 };
    let d = 1e-6;
    for x in grid(23, 0.013, 0.987) {
        for t in grid(71, 0.011, 5.99) {
            // Skip points within a few d of a kink line or of a phase switch (t ∈ ℤ).
            let near_kink = [t - d, t, t + d].iter().any(|&s| {
                let mut k = [0.0; 3];
                let n = e.kinks(s, &mut k);
                k[..n].iter().any(|&q| (q - x).abs() < 4.0 * d)
            });
            let f = t.rem_euclid(1.0);
            if near_kink || f < 4.0 * d || f > 1.0 - 4.0 * d {
                continue;
            }
            let ut = (e.u(x, t + d) - e.u(x, t - d)) / (2.0 * d);
            let ux = (e.u(x + d, t) - e.u(x - d, t)) / (2.0 * d);
            // Rounding of a difference quotient of O(1) values: ~ε/d ≈ 2e-10.
            assert!(
                approx::relative_eq!(ut, e.u_t(x, t), epsilon = 1e-8, max_relative = 0.0),
                "u_t at x={x} t={t}: {ut} vs {}",
                e.u_t(x, t)
            );
            assert!(
                approx::relative_eq!(ux, e.u_x(x, t), epsilon = 1e-8, max_relative = 0.0),
                "u_x at x={x} t={t}: {ux} vs {}",
                e.u_x(x, t)
            );
        }
    }
}

#[test]
fn contact_phase_region_one_is_minus_t_minus_t1_over_two() {
    // Region I of the contact phase (t₁ < t < 1.5, t − t₁ < x < 1 − (t − t₁)): the paper's (4.2)
    // prints (t − t₁)/2; the solution is −(t − t₁)/2.
    let e = ImpactingBar { length: 1.0 };
    let t1 = 1.0;
    for t in grid(20, 1.01, 1.45) {
        for x in grid(20, t - t1 + 0.01, 1.0 - (t - t1) - 0.01) {
            assert_eq!(e.u(x, t), -(t - t1) / 2.0);
        }
        // The printed sign would jump against region II (−x/2) on the line x = t − t₁.
        let x = t - t1;
        let paper = (t - t1) / 2.0;
        assert!((paper - (-x / 2.0)).abs() > 0.0);
        approx::assert_relative_eq!(e.u(x, t), -x / 2.0, epsilon = tol(1.0), max_relative = 0.0);
    }
}
