//! L²(0, L) norms of P1 functions and of their error against the exact benchmark solution,
//! integrated exactly.
//!
//! Both u_h (P1 on the mesh) and the exact u(·, t) (affine between its kinks, see
//! [`ImpactingBar::kinks`]) are affine on every piece of the mesh refined by the kinks, so on a
//! piece [p, q] the error e is affine and `∫_p^q e² = (q−p)(e_p² + e_p e_q + e_q²)/3` exactly.
//! No quadrature rule is involved.

use crate::bar::assembly::Bar;
use crate::exact::ImpactingBar;

/// `∫_p^q e² dx` for e affine with end values `ep`, `eq`.
#[inline]
fn affine_square(p: f64, q: f64, ep: f64, eq: f64) -> f64 {
    (q - p) * (ep * ep + ep * eq + eq * eq) / 3.0
}

/// `‖u_h‖_{L²(0,L)}` of the P1 function with values `u` at nodes 0..m−1 and 0 at node m (or
/// at nodes 0..m for a free far end).
pub fn l2_norm_p1(bar: &Bar, u: &[f64]) -> f64 {
    let m = bar.elements;
    let h = bar.h();
    let mut s = 0.0;
    for j in 0..m {
        let a = u[j];
        let b = u.get(j + 1).copied().unwrap_or(0.0); // u_m = 0 when clamped
        s += h * (a * a + a * b + b * b) / 3.0;
    }
    s.sqrt()
}

/// `‖u_h − u(·, t)‖_{L²(0,L)}`, exact (the mesh is split at the kinks of the exact solution).
pub fn l2_error(bar: &Bar, u: &[f64], exact: &ImpactingBar, t: f64) -> f64 {
    let m = bar.elements;
    let mut kinks = [0.0; 3];
    let nk = exact.kinks(t, &mut kinks);
    let kinks = &mut kinks[..nk];
    kinks.sort_by(f64::total_cmp);
    let mut next_kink = 0;
    let mut s = 0.0;
    for j in 0..m {
        let (xa, xb) = (bar.x(j), bar.x(j + 1));
        // u has m values (clamped: u_m = 0) or m + 1 (free far end).
        let (ua, ub) = (u[j], u.get(j + 1).copied().unwrap_or(0.0));
        let uh = |x: f64| ua + (ub - ua) * (x - xa) / (xb - xa);
        let mut p = xa;
        let mut ep = ua - exact.u(xa, t);
        while next_kink < kinks.len() && kinks[next_kink] <= xa {
            next_kink += 1;
        }
        while next_kink < kinks.len() && kinks[next_kink] < xb {
            let q = kinks[next_kink];
            let eq = uh(q) - exact.u(q, t);
            s += affine_square(p, q, ep, eq);
            p = q;
            ep = eq;
            next_kink += 1;
        }
        let eb = ub - exact.u(xb, t);
        s += affine_square(p, xb, ep, eb);
    }
    s.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn norm_of_a_hat_is_exact() {
        // u_h = φ_1 on a 2-element mesh of (0, 2): ∫ φ_1² = 2h/3 with h = 1.
        let bar = Bar { length: 2.0, elements: 2 };
        assert!((l2_norm_p1(&bar, &[0.0, 1.0]) - (2.0f64 / 3.0).sqrt()).abs() < 4.0 * f64::EPSILON);
    }
}
