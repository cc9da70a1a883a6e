//! Chebyshev series `Σ c_k T_k(z)` on z ∈ [−1, 1] and Gauss–Legendre rules: the little
//! polynomial algebra behind [`super::base::Base`].
//!
//! Conventions follow Mason & Handscomb, *Chebyshev Polynomials* (2003): §2.4.5 (Clenshaw),
//! §2.4.4 (derivative and integral recurrences), §6.3 (interpolation at the zeros of T_n).

use std::f64::consts::PI;

/// `Σ_k c_k T_k(z)` by Clenshaw's recurrence `b_k = c_k + 2z b_{k+1} − b_{k+2}`,
/// result `c_0 + z b_1 − b_2`. For a linear series this is `c_0 + z c_1`, one rounding each.
pub(super) fn eval(c: &[f64], z: f64) -> f64 {
    let (mut b1, mut b2) = (0.0, 0.0);
    for &ck in c.iter().skip(1).rev() {
        let b0 = ck + 2.0 * z * b1 - b2;
        b2 = b1;
        b1 = b0;
    }
    c.first().copied().unwrap_or(0.0) + z * b1 - b2
}

/// Coefficients of d/dz of a series, same length (the last is 0):
/// `d_k = d_{k+2} + 2(k+1) c_{k+1}`, then `d_0 /= 2`.
pub(super) fn derivative(c: &[f64]) -> Vec<f64> {
    let n = c.len();
    let mut d = vec![0.0; n];
    for k in (0..n.saturating_sub(1)).rev() {
        let d2 = if k + 2 < n { d[k + 2] } else { 0.0 };
        d[k] = d2 + 2.0 * (k + 1) as f64 * c[k + 1];
    }
    if let Some(d0) = d.first_mut() {
        *d0 *= 0.5;
    }
    d
}

/// Coefficients (one longer) of the antiderivative F with F(−1) = 0:
/// `∫T_0 = T_1`, `∫T_1 = T_2/4`, `∫T_k = T_{k+1}/(2(k+1)) − T_{k−1}/(2(k−1))`, so
/// `F_1 = c_0 − c_2/2` and `F_k = (c_{k−1} − c_{k+1})/(2k)` for k ≥ 2.
pub(super) fn antiderivative(c: &[f64]) -> Vec<f64> {
    let at = |k: usize| c.get(k).copied().unwrap_or(0.0);
    let n = c.len();
    let mut f = vec![0.0; n + 1];
    for (k, fk) in f.iter_mut().enumerate().skip(1) {
        *fk = if k == 1 { at(0) - 0.5 * at(2) } else { (at(k - 1) - at(k + 1)) / (2 * k) as f64 };
    }
    // T_k(−1) = (−1)^k.
    f[0] = -f.iter().enumerate().skip(1).map(|(k, fk)| if k % 2 == 0 { *fk } else { -*fk }).sum::<f64>();
    f
}

/// The n zeros of T_n, `z_j = cos(π(j + ½)/n)`, at which [`interpolate`] wants its samples.
pub(super) fn points(n: usize) -> impl Iterator<Item = f64> {
    (0..n).map(move |j| (PI * (j as f64 + 0.5) / n as f64).cos())
}

/// The degree n−1 interpolant of samples taken at [`points`]`(n)`:
/// `c_k = (2/n) Σ_j f_j cos(πk(j + ½)/n)`, `c_0` halved (discrete orthogonality of T_k).
pub(super) fn interpolate(values: &[f64]) -> Vec<f64> {
    let n = values.len();
    let mut c: Vec<f64> = (0..n)
        .map(|k| {
            let s: f64 = values
                .iter()
                .enumerate()
                .map(|(j, f)| f * (PI * (k * (2 * j + 1)) as f64 / (2 * n) as f64).cos())
                .sum();
            2.0 * s / n as f64
        })
        .collect();
    if let Some(c0) = c.first_mut() {
        *c0 *= 0.5;
    }
    c
}

/// `Σ|c_k|`, a bound on the series over [−1, 1] since |T_k| ≤ 1.
pub(super) fn sup_bound(c: &[f64]) -> f64 {
    c.iter().map(|c| c.abs()).sum()
}

/// The n-point Gauss–Legendre rule on [−1, 1] as (node, weight), exact for degree 2n − 1.
/// Nodes by Newton's method on the three-term recurrence of P_n from the classical first guess
/// `cos(π(i + 3/4)/(n + 1/2))` (Abramowitz & Stegun 22.16.6); weights `2/((1 − x²) P_n'(x)²)`.
pub(super) fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let legendre = |x: f64| {
        // (P_n(x), P_n'(x)) by (k+1) P_{k+1} = (2k+1) x P_k − k P_{k−1}.
        let (mut p0, mut p1) = (1.0, x);
        for k in 1..n {
            let p2 = ((2 * k + 1) as f64 * x * p1 - k as f64 * p0) / (k + 1) as f64;
            p0 = p1;
            p1 = p2;
        }
        (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
    };
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (p, dp) = legendre(x);
                let dx = p / dp;
                x -= dx;
                if dx.abs() <= 2.0 * f64::EPSILON {
                    break;
                }
            }
            let dp = legendre(x).1;
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivative_and_antiderivative_invert_each_other() {
        let c = [0.3, -1.2, 0.5, 0.25, -0.125];
        let back = derivative(&antiderivative(&c));
        for (a, b) in c.iter().zip(&back) {
            assert!((a - b).abs() <= 8.0 * f64::EPSILON, "{a} vs {b}");
        }
        // F(−1) = 0 and F(1) = ∫_{−1}^{1} f = Σ c_k ∫T_k, with ∫T_k = 2/(1 − k²) for even k, 0 for odd k.
        let f = antiderivative(&c);
        assert!(eval(&f, -1.0).abs() <= 4.0 * f64::EPSILON);
        let exact = 2.0 * 0.3 + 0.5 * (-2.0 / 3.0) - 0.125 * (-2.0 / 15.0);
        assert!((eval(&f, 1.0) - exact).abs() <= 8.0 * f64::EPSILON);
    }

    #[test]
    fn interpolation_reproduces_polynomials() {
        // f = 1 + 2z − z³ is T_0 + (2 − 3/4) T_1 − T_3/4.
        let vals: Vec<f64> = points(6).map(|z| 1.0 + 2.0 * z - z * z * z).collect();
        let c = interpolate(&vals);
        let want = [1.0, 1.25, 0.0, -0.25, 0.0, 0.0];
        for (a, b) in c.iter().zip(want) {
            assert!((a - b).abs() <= 8.0 * f64::EPSILON, "{c:?}");
        }
        assert!((eval(&c, 0.3) - (1.0 + 0.6 - 0.027)).abs() <= 8.0 * f64::EPSILON);
    }

    #[test]
    fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
        for n in [3, 8] {
            let rule = gauss_legendre(n);
            for d in 0..2 * n {
                let q: f64 = rule.iter().map(|(x, w)| w * x.powi(d as i32)).sum();
                let exact = if d % 2 == 0 { 2.0 / (d + 1) as f64 } else { 0.0 };
                assert!((q - exact).abs() <= 16.0 * f64::EPSILON, "n={n} degree {d}: {q} vs {exact}");
            }
        }
    }
}
