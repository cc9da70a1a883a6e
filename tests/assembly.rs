//! The assembled matrices against an independent element-by-element integration of the basis
//! functions of paper §3, and the identities they must satisfy.

mod common;

use massredist::bar::assembly::{Bar, BarSystem};
use massredist::bar::norms::{l2_error, l2_norm_p1};
use massredist::exact::ImpactingBar;
use massredist::mass::MassKind;

/// φ_k(x) of the paper (hat functions on the uniform mesh).
fn phi(k: usize, x: f64, h: f64) -> f64 {
    (1.0 - (x / h - k as f64).abs()).max(0.0)
}

/// ∫ w_h φ_i φ_j and ∫ φ_i' φ_j' by 3-point Gauss per element (exact for these quadratics).
fn reference(bar: &Bar, w: &[f64], i: usize, j: usize) -> (f64, f64) {
    let h = bar.h();
    let (g, gw) = ([-(0.6f64).sqrt(), 0.0, (0.6f64).sqrt()], [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0]);
    let (mut m, mut s) = (0.0, 0.0);
    for e in 0..bar.elements {
        let (a, b) = (e as f64 * h, (e + 1) as f64 * h);
        for q in 0..3 {
            let x = 0.5 * (a + b) + 0.5 * h * g[q];
            m += 0.5 * h * gw[q] * w[e] * phi(i, x, h) * phi(j, x, h);
        }
        // Derivatives are constant per element: ±1/h on the support.
        let d = |k: usize| {
            if k == e {
                -1.0 / h
            } else if k == e + 1 {
                1.0 / h
            } else {
                0.0
            }
        };
        s += h * d(i) * d(j);
    }
    (m, s)
}

#[test]
fn mass_and_stiffness_match_the_integrals() {
    for (l, m) in [(1.0, 6), (2.5, 7), (1.0, 37)] {
        let bar = Bar { length: l, elements: m };
        for kind in common::all_masses(m) {
            let bs = BarSystem::new(bar, &kind, 0.0).unwrap();
            let (sys, w) = (&bs.system, &bs.weights);
            for i in 0..m {
                for j in 0..m {
                    let (mr, sr) = reference(&bar, w, i, j);
                    // Entries are O(h·w) and O(1/h); a few ulps of that scale (the quadrature
                    // sums up to 2×3 terms).
                    let (tm, ts) = (16.0 * f64::EPSILON * l * 2.0, 16.0 * f64::EPSILON / bar.h());
                    assert!(
                        approx::relative_eq!(sys.mass.get(i, j), mr, epsilon = tm, max_relative = 0.0),
                        "{} M[{i}][{j}]",
                        kind.name()
                    );
                    assert!(
                        approx::relative_eq!(sys.stiffness.get(i, j), sr, epsilon = ts, max_relative = 0.0),
                        "S[{i}][{j}]"
                    );
                    assert_eq!(sys.mass.get(i, j), sys.mass.get(j, i));
                }
            }
        }
    }
}

#[test]
fn total_mass_is_preserved_by_mod2_and_mod3_and_reduced_by_h_for_mod1() {
    for (l, m) in [(1.0, 2), (1.0, 6), (2.5, 37), (1.0, 1000)] {
        let bar = Bar { length: l, elements: m };
        let total = |k: MassKind| BarSystem::new(bar, &k, 0.0).unwrap().total_mass();
        // Sum of ~3m entries of size h: rounding ≤ 3m·ε·L.
        let tol = 4.0 * m as f64 * f64::EPSILON * l;
        approx::assert_relative_eq!(total(MassKind::Standard), l, epsilon = tol, max_relative = 0.0);
        assert!(
            approx::relative_eq!(total(MassKind::Mod2), l, epsilon = tol, max_relative = 0.0),
            "mod2 {}",
            total(MassKind::Mod2)
        );
        approx::assert_relative_eq!(total(MassKind::Mod3), l, epsilon = tol, max_relative = 0.0);
        approx::assert_relative_eq!(total(MassKind::Mod1), l - bar.h(), epsilon = tol, max_relative = 0.0);
    }
}

#[test]
fn stiffness_annihilates_constants_away_from_the_dirichlet_node() {
    // S·1 = 0 on rows 0..m−2 (rows with no Dirichlet neighbour); row m−1 gives 1/h.
    let bar = Bar { length: 1.0, elements: 9 };
    let sys = BarSystem::new(bar, &MassKind::Mod3, 0.0).unwrap().system;
    let mut y = vec![0.0; 9];
    sys.stiffness.mul_into(&[1.0; 9], &mut y);
    for v in &y[..8] {
        approx::assert_relative_eq!(*v, 0.0, epsilon = 4.0 * f64::EPSILON / bar.h(), max_relative = 0.0);
    }
    approx::assert_relative_eq!(y[8], 1.0 / bar.h(), epsilon = 4.0 * f64::EPSILON / bar.h(), max_relative = 0.0);
}

#[test]
fn load_vector_integrates_the_weighted_force() {
    // F_i = ∫ f w_h φ_i; Σ_i F_i + F_m = f ∫ w_h, with the Dirichlet node's share f h/2 w_{m−1}.
    let bar = Bar { length: 2.0, elements: 8 };
    let f = 0.7;
    let bs = BarSystem::new(bar, &MassKind::Mod3, f).unwrap();
    let sys = &bs.system;
    let total: f64 = sys.load.iter().sum::<f64>() + f * bar.h() / 2.0 * bs.weights[7];
    approx::assert_relative_eq!(total, f * bs.total_mass(), epsilon = 32.0 * f64::EPSILON, max_relative = 0.0);
    assert_eq!(sys.load[0], 0.0, "f_0 = 0 when w_0 = 0 (paper §3)");
}

#[test]
fn exact_l2_error_of_the_interpolant_matches_fine_quadrature() {
    // At t = 1.3 (three kinks) the interpolant error is computed exactly; a 20000-point
    // midpoint rule converges to it at O(1/n²).
    let bar = Bar { length: 1.0, elements: 7 };
    let e = ImpactingBar { length: 1.0 };
    for t in [0.37, 1.3, 1.5, 2.41] {
        let u: Vec<f64> = (0..7).map(|i| e.u(bar.x(i), t) + 0.01 * (i as f64).sin()).collect();
        let exact = l2_error(&bar, &u, &e, t);
        let n = 20000;
        let h = bar.h();
        let (mut s, mut norm) = (0.0, 0.0);
        for q in 0..n {
            let x = (q as f64 + 0.5) / n as f64;
            let j = ((x / h) as usize).min(6);
            let (a, b) = (u[j], if j + 1 < 7 { u[j + 1] } else { 0.0 });
            let uh = a + (b - a) * (x - j as f64 * h) / h;
            s += (uh - e.u(x, t)).powi(2) / n as f64;
            norm += uh * uh / n as f64;
        }
        // Midpoint rule on kinked integrands: error O(1/n²)·|e'|² ≈ 1e-9 here.
        assert!(
            approx::relative_eq!(exact, s.sqrt(), epsilon = 1e-7, max_relative = 0.0),
            "t={t}: {exact} vs {}",
            s.sqrt()
        );
        approx::assert_relative_eq!(l2_norm_p1(&bar, &u), norm.sqrt(), epsilon = 1e-7, max_relative = 0.0);
    }
}
