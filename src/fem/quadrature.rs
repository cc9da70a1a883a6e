//! Quadrature on the reference simplex `{ξ_k ≥ 0, Σ ξ_k ≤ 1}` of dimension n = 2 or 3: the
//! Grundmann–Möller rule of degree 5 (A. Grundmann, H. M. Möller, "Invariant integration
//! formulas for the n-simplex by combinatorial methods", SIAM J. Numer. Anal. 15 (1978),
//! Theorem 4), whose points and weights are rationals in closed form (no tabulated digits):
//!
//! ```text
//! ∫_T f ≈ Σ_{i=0}^{s} (−1)^i 2^{−2s} (d + n − 2i)^d / (i! (d + n − i)!)
//!              Σ_{|β| = s − i, β ∈ ℕ^{n+1}} f(λ = (2β_0 + 1, …, 2β_n + 1)/(d + n − 2i)),
//! ```
//!
//! with d = 2s + 1 the degree and λ the barycentric coordinates (ξ_k = λ_k, k ≥ 1). For s = 2
//! (degree 5): 10 points on the triangle, 15 on the tetrahedron. Degree 5 covers the P2 mass
//! (φ_a φ_b, degree 4) and stiffness (∇φ_a·∇φ_b, degree 2) on straight-sided cells exactly; on
//! curved cells it is the usual approximation. The weights of the i = 1 points are negative.

/// Largest number of points of a rule here (the tetrahedron's 15).
pub const MAX_POINTS: usize = 15;

/// A rule: points ξ (z = 0 in 2D) and weights on the reference simplex (summing to 1/n!).
#[derive(Debug, Clone)]
pub struct Rule {
    pub n: usize,
    pub points: Vec<[f64; 3]>,
    pub weights: Vec<f64>,
}

fn factorial(k: usize) -> f64 {
    (1..=k).map(|x| x as f64).product()
}

/// All β ∈ ℕ^{len} with |β| = total, in lexicographic order.
fn compositions(total: usize, len: usize, out: &mut Vec<Vec<usize>>, prefix: &mut Vec<usize>) {
    if prefix.len() + 1 == len {
        prefix.push(total);
        out.push(prefix.clone());
        prefix.pop();
        return;
    }
    for first in (0..=total).rev() {
        prefix.push(first);
        compositions(total - first, len, out, prefix);
        prefix.pop();
    }
}

/// The Grundmann–Möller rule of degree 2s + 1 on the n-simplex (module docs).
pub fn grundmann_moller(n: usize, s: usize) -> Rule {
    let d = 2 * s + 1;
    let (mut points, mut weights) = (Vec::new(), Vec::new());
    for i in 0..=s {
        let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
        let denom = (d + n - 2 * i) as f64;
        let w = sign * denom.powi(d as i32) / (factorial(i) * factorial(d + n - i) * 4f64.powi(s as i32));
        let mut betas = Vec::new();
        compositions(s - i, n + 1, &mut betas, &mut Vec::new());
        for beta in betas {
            let mut xi = [0.0; 3];
            for k in 0..n {
                xi[k] = (2 * beta[k + 1] + 1) as f64 / denom;
            }
            points.push(xi);
            weights.push(w);
        }
    }
    Rule { n, points, weights }
}

/// The degree-5 rule of the P2 elements on the n-simplex (cached per dimension).
pub fn p2_rule(n: usize) -> &'static Rule {
    static RULES: std::sync::OnceLock<[Rule; 2]> = std::sync::OnceLock::new();
    &RULES.get_or_init(|| [grundmann_moller(2, 2), grundmann_moller(3, 2)])[n - 2]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫_T ξ^a η^b ζ^c = a! b! c!/(a + b + c + n)! (the Dirichlet integral).
    fn exact(e: [usize; 3], n: usize) -> f64 {
        e.iter().map(|&k| factorial(k)).product::<f64>() / factorial(e.iter().sum::<usize>() + n)
    }

    #[test]
    fn degree_five_rules_integrate_every_monomial_up_to_degree_five() {
        // Every monomial of degree ≤ 5 exactly (the weights alternate in sign, sums of O(0.1)
        // terms: 1e-15 absolute covers their round-off); a degree-6 one not, so the rule is
        // not exact by accident of the test. mutation, as run: the sign of the i = 1 weights
        // made positive -> every monomial fails.
        for n in [2, 3] {
            let r = p2_rule(n);
            assert_eq!(r.points.len(), if n == 2 { 10 } else { 15 });
            let quad = |e: [usize; 3]| -> f64 {
                r.points
                    .iter()
                    .zip(&r.weights)
                    .map(|(p, w)| w * (0..3).map(|k| p[k].powi(e[k] as i32)).product::<f64>())
                    .sum()
            };
            for a in 0..=5 {
                for b in 0..=5 - a {
                    for c in 0..=if n == 3 { 5 - a - b } else { 0 } {
                        let e = [a, b, c];
                        assert!((quad(e) - exact(e, n)).abs() <= 1e-15, "n={n} {e:?}: {} vs {}", quad(e), exact(e, n));
                    }
                }
            }
            assert!((quad([6, 0, 0]) - exact([6, 0, 0], n)).abs() > 1e-6);
        }
    }
}
