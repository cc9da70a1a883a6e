//! One contact node's 3 × 3 frictional problem of the isotropic cone ([`super::cone`], issue
//! 29): open, stick or slide, solved to round-off ([`node_cone`]); a slide's direction is the
//! root of one smooth function of the angle ([`slide_direction`]).

use super::{Friction, NodeState, Tangent};

/// Node's 3 × 3 problem `y = r + [[a, bᵀ], [b, C]] f` with the disc `|f_t| ≤ g` solved to
/// round-off: the first candidate whose inequalities hold (open, stick, slide: the order of
/// the 2D [`super::planar::local_solve`]), else the one that violates them least. `tresca` is Tresca's
/// bound (0 for Coulomb); `guess` the last slide direction.
#[allow(clippy::too_many_arguments)]
pub(super) fn node_cone(
    a: f64,
    b: [f64; 2],
    c: [[f64; 2]; 2],
    rn: f64,
    rt: [f64; 2],
    friction: Friction,
    tresca: f64,
    guess: Option<[f64; 2]>,
) -> ([f64; 3], NodeState) {
    let dot = |u: [f64; 2], v: [f64; 2]| u[0] * v[0] + u[1] * v[1];
    let times_c = |e: [f64; 2]| [c[0][0] * e[0] + c[0][1] * e[1], c[1][0] * e[0] + c[1][1] * e[1]];
    let neg = |x: f64| (-x).max(0.0);
    let state = |closed: bool, tangent: Tangent| NodeState { closed, tangent };
    let mut best = (f64::INFINITY, ([0.0; 3], state(false, Tangent::Zero)));
    let mut offer = |f: [f64; 3], st: NodeState, violation: f64| {
        if violation < best.0 {
            best = (violation, (f, st));
        }
        violation <= 0.0
    };
    let stick = solve3([[a, b[0], b[1]], [b[0], c[0][0], c[0][1]], [b[1], c[1][0], c[1][1]]], [-rn, -rt[0], -rt[1]]);
    // The slide is against the force that would stick it.
    let away = |ft: [f64; 2]| {
        let n = ft[0].hypot(ft[1]);
        (n > 0.0).then(|| [-ft[0] / n, -ft[1] / n])
    };
    let guess = guess.or_else(|| away([stick[1], stick[2]])).unwrap_or([1.0, 0.0]);
    match friction {
        Friction::Tresca { .. } => {
            let g = tresca;
            if g == 0.0 {
                let (fn_, closed) = super::planar::normal_alone(a, rn);
                return ([fn_, 0.0, 0.0], state(closed, Tangent::Zero));
            }
            // Open: f_n = 0 and the tangential problem on the disc alone.
            let det = c[0][0] * c[1][1] - c[0][1] * c[1][0];
            let ft = [(-rt[0] * c[1][1] + rt[1] * c[0][1]) / det, (-rt[1] * c[0][0] + rt[0] * c[1][0]) / det];
            if ft[0].hypot(ft[1]) <= g {
                if offer([0.0, ft[0], ft[1]], state(false, Tangent::Stick), neg(rn + dot(b, ft))) {
                    return best.1;
                }
            } else {
                let open_guess = away(ft).unwrap_or(guess);
                let yt = |e: [f64; 2]| {
                    let ce = times_c(e);
                    Some([rt[0] - g * ce[0], rt[1] - g * ce[1]])
                };
                if let Some(e) = slide_direction(yt, open_guess) {
                    let ft = [-g * e[0], -g * e[1]];
                    if offer([0.0, ft[0], ft[1]], state(false, Tangent::Slide(e)), neg(rn + dot(b, ft))) {
                        return best.1;
                    }
                }
            }
            let size = stick[1].hypot(stick[2]);
            if offer(stick, state(true, Tangent::Stick), neg(stick[0]) + neg(g - size)) {
                return best.1;
            }
            let normal = |e: [f64; 2]| -(rn - g * dot(b, e)) / a;
            let yt = |e: [f64; 2]| {
                let (fn_, ce) = (normal(e), times_c(e));
                Some([rt[0] + b[0] * fn_ - g * ce[0], rt[1] + b[1] * fn_ - g * ce[1]])
            };
            if let Some(e) = slide_direction(yt, guess) {
                let fn_ = normal(e);
                let y = yt(e).unwrap_or([0.0; 2]);
                offer([fn_, -g * e[0], -g * e[1]], state(true, Tangent::Slide(e)), neg(fn_) + neg(dot(e, y)));
            }
        }
        Friction::Coulomb { mu } => {
            if offer([0.0; 3], state(false, Tangent::Zero), neg(rn)) {
                return best.1;
            }
            let size = stick[1].hypot(stick[2]);
            if offer(stick, state(true, Tangent::Stick), neg(stick[0]) + neg(mu * stick[0] - size)) {
                return best.1;
            }
            let normal = |e: [f64; 2]| {
                let den = a - mu * dot(b, e);
                (den > 0.0).then(|| -rn / den)
            };
            let yt = |e: [f64; 2]| {
                let fn_ = normal(e)?;
                let ce = times_c(e);
                Some([rt[0] + b[0] * fn_ - mu * fn_ * ce[0], rt[1] + b[1] * fn_ - mu * fn_ * ce[1]])
            };
            if let Some(e) = slide_direction(yt, guess)
                && let (Some(fn_), Some(y)) = (normal(e), yt(e))
            {
                let g = mu * fn_;
                offer([fn_, -g * e[0], -g * e[1]], state(true, Tangent::Slide(e)), neg(fn_) + neg(dot(e, y)));
            }
        }
    }
    best.1
}

/// The slide direction e = (cos θ, sin θ): a root of `h(θ) = e⊥ · y_t(e)` (y_t parallel to e)
/// with `e · y_t ≥ 0` (the slip along e), `yt(e)` the values of the state sliding along e (None
/// where that state has no solution). Newton's method from the guess (its slope by central
/// differences), else a scan of 96 angles and bisection of every sign change, the admissible
/// root nearest the guess. None if there is none.
fn slide_direction(yt: impl Fn([f64; 2]) -> Option<[f64; 2]>, guess: [f64; 2]) -> Option<[f64; 2]> {
    let unit = |th: f64| [th.cos(), th.sin()];
    let h = |th: f64| {
        let (e, y) = (unit(th), yt(unit(th))?);
        Some((-e[1] * y[0] + e[0] * y[1], e[0] * y[0] + e[1] * y[1]))
    };
    let th0 = guess[1].atan2(guess[0]);
    let mut th = th0;
    for _ in 0..50 {
        let Some((hv, _)) = h(th) else { break };
        let (Some((hp, _)), Some((hm, _))) = (h(th + 1e-6), h(th - 1e-6)) else { break };
        let slope = (hp - hm) / 2e-6;
        if !(slope.is_finite() && slope != 0.0) {
            break;
        }
        let step = (hv / slope).clamp(-0.5, 0.5);
        th -= step;
        if step.abs() <= 1e-14 {
            if let Some((_, along)) = h(th)
                && along >= 0.0
            {
                return Some(unit(th));
            }
            break;
        }
    }
    // The scan: 96 angles from the guess, each sign change bisected.
    const N: usize = 96;
    let at = |k: usize| th0 + std::f64::consts::TAU * k as f64 / N as f64;
    let mut found: Option<(f64, f64)> = None;
    for k in 0..N {
        let (mut lo, mut hi) = (at(k), at(k + 1));
        let (Some((mut hlo, _)), Some((hhi, _))) = (h(lo), h(hi)) else { continue };
        if hlo * hhi > 0.0 {
            continue;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            let Some((hm, _)) = h(mid) else { break };
            if hm * hlo > 0.0 {
                (lo, hlo) = (mid, hm);
            } else {
                hi = mid;
            }
        }
        let root = 0.5 * (lo + hi);
        let Some((_, along)) = h(root) else { continue };
        // The angular distance to the guess.
        let dist = (root - th0).min(th0 + std::f64::consts::TAU - root);
        if along >= 0.0 && found.is_none_or(|(_, d)| dist < d) {
            found = Some((root, dist));
        }
    }
    found.map(|(root, _)| unit(root))
}

/// The 3 × 3 system `A x = r` by Cramer's rule (A symmetric positive definite: a node's block
/// of D).
fn solve3(a: [[f64; 3]; 3], r: [f64; 3]) -> [f64; 3] {
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let det = det3(a);
    let mut x = [0.0; 3];
    for (k, xk) in x.iter_mut().enumerate() {
        let mut m = a;
        for row in 0..3 {
            m[row][k] = r[row];
        }
        *xk = det3(m) / det;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With D = I, r = (−1, t₁, t₂), Coulomb μ = ½: the node sticks for |t| ≤ ½ (f = −r) and
    /// beyond slides along t/|t| with f_t = −½ t/|t| (isotropic: the direction is r_t's, not a
    /// pyramid's corner); open for r_n > 0.
    #[test]
    fn one_node_sticks_inside_the_disc_and_slides_on_its_rim() {
        let (id_b, id_c) = ([0.0; 2], [[1.0, 0.0], [0.0, 1.0]]);
        let coulomb = Friction::Coulomb { mu: 0.5 };
        let (f, st) = node_cone(1.0, id_b, id_c, -1.0, [0.3, 0.2], coulomb, 0.0, None);
        assert_eq!((f, st.tangent), ([1.0, -0.3, -0.2], Tangent::Stick));
        let (f, st) = node_cone(1.0, id_b, id_c, -1.0, [0.6, 0.8], coulomb, 0.0, None);
        let Tangent::Slide(e) = st.tangent else { panic!("{st:?}") };
        assert!((e[0] - 0.6).abs() <= 4.0 * f64::EPSILON && (e[1] - 0.8).abs() <= 4.0 * f64::EPSILON, "{e:?}");
        assert!((f[1] + 0.3).abs() <= 4.0 * f64::EPSILON && (f[2] + 0.4).abs() <= 4.0 * f64::EPSILON, "{f:?}");
        let (f, st) = node_cone(1.0, id_b, id_c, 0.2, [0.6, 0.8], coulomb, 0.0, None);
        assert_eq!((f, st.closed), ([0.0; 3], false));
    }

    /// An anisotropic block (coupled normal and tangential, C not a multiple of I): the slide
    /// found satisfies its equations to round-off, y_n = 0, |f_t| = μ f_n and y_t ∥ e, e·y_t > 0.
    #[test]
    fn a_coupled_node_slides_with_y_t_along_its_force() {
        let (a, b, c) = (2.0, [0.3, -0.2], [[1.5, 0.4], [0.4, 0.7]]);
        let (rn, rt) = (-1.0, [0.9, -1.3]);
        let (f, st) = node_cone(a, b, c, rn, rt, Friction::Coulomb { mu: 0.4 }, 0.0, None);
        let Tangent::Slide(e) = st.tangent else { panic!("{st:?}") };
        let yn = rn + a * f[0] + b[0] * f[1] + b[1] * f[2];
        let yt = [
            rt[0] + b[0] * f[0] + c[0][0] * f[1] + c[0][1] * f[2],
            rt[1] + b[1] * f[0] + c[1][0] * f[1] + c[1][1] * f[2],
        ];
        let tol = 16.0 * f64::EPSILON;
        assert!(yn.abs() <= tol, "y_n {yn:e}");
        assert!((f[1].hypot(f[2]) - 0.4 * f[0]).abs() <= tol, "on the rim");
        assert!((-e[1] * yt[0] + e[0] * yt[1]).abs() <= tol, "y_t ∥ e");
        assert!(e[0] * yt[0] + e[1] * yt[1] > 0.0);
        assert!((f[1] + 0.4 * f[0] * e[0]).abs() <= tol && (f[2] + 0.4 * f[0] * e[1]).abs() <= tol);
    }
}
