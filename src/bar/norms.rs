//! L²(0, L) norms of P1 functions and of their error against the exact benchmark solution,
//! integrated exactly.
//!
//! Both u_h (P1 on the mesh) and the exact u(·, t) (affine between its kinks, see
//! [`ImpactingBar::kinks`]) are affine on every piece of the mesh refined by the kinks, so on a
//! piece [p, q] the error e is affine and `∫_p^q e² = (q−p)(e_p² + e_p e_q + e_q²)/3` exactly.
//! No quadrature rule is involved.

use crate::bar::assembly::Bar;
use crate::exact::ImpactingBar;
use crate::linalg::tridiag::SymTridiag;

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

/// Independent partial sums of the element sums below: breaking the one long chain of
/// dependent additions lets them vectorise and overlap (a serial sum costs an add latency per
/// term). The lanes, not the vector width, fix the order of the additions, so the result does
/// not depend on the CPU.
const LANES: usize = 4;

/// `Σ_j f(x_j, x_{j+1}, y_j, y_{j+1}, p_j, q_j)` over the elements j = 0..p.len() (two sums at
/// once), for node arrays x, y (at least p.len() + 1 values) and element arrays p, q, in
/// [`LANES`] interleaved partial sums: a few ulps of the sum from the serial order.
#[inline(always)]
fn element_sums(x: &[f64], y: &[f64], p: &[f64], q: &[f64], f: impl Fn([f64; 6]) -> [f64; 2]) -> [f64; 2] {
    let e = p.len();
    let (xa, xb, ya, yb, q) = (&x[..e], &x[1..=e], &y[..e], &y[1..=e], &q[..e]);
    // One array per sum, one entry per lane: the lanes of a sum are contiguous, so they pack
    // into one vector register.
    let (mut s0, mut s1) = ([0.0; LANES], [0.0; LANES]);
    let chunks = xa
        .chunks_exact(LANES)
        .zip(xb.chunks_exact(LANES))
        .zip(ya.chunks_exact(LANES).zip(yb.chunks_exact(LANES)))
        .zip(p.chunks_exact(LANES).zip(q.chunks_exact(LANES)));
    for (((xa, xb), (ya, yb)), (p, q)) in chunks {
        for k in 0..LANES {
            let [r0, r1] = f([xa[k], xb[k], ya[k], yb[k], p[k], q[k]]);
            s0[k] += r0;
            s1[k] += r1;
        }
    }
    for j in e - e % LANES..e {
        let [r0, r1] = f([xa[j], xb[j], ya[j], yb[j], p[j], q[j]]);
        s0[0] += r0;
        s1[0] += r1;
    }
    let total = |a: [f64; LANES]| (a[0] + a[1]) + (a[2] + a[3]);
    [total(s0), total(s1)]
}

/// Runs `f` compiled for AVX2 where the CPU has it (the lanes of [`element_sums`] then fill one
/// 256-bit register; the result is the same, see [`LANES`]).
macro_rules! with_avx2 {
    ($impl:ident($($arg:expr),*)) => {{
        #[cfg(target_arch = "x86_64")]
        {
            #[target_feature(enable = "avx2")]
            unsafe fn avx2<R>(f: impl FnOnce() -> R) -> R {
                f()
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU supports AVX2 (checked on the line above).
                return unsafe { avx2(|| $impl($($arg),*)) };
            }
        }
        $impl($($arg),*)
    }};
}

/// The discrete energy `½VᵀMV + ½UᵀSU − UᵀF` of tridiagonal M and S, in one pass over the
/// unknowns, as a sum of element energies (without the cancellation of `ContactSystem::energy`).
///
/// For a symmetric tridiagonal A with `a_i = A_{i,i+1}` and the diagonal residuals
/// `r_i = A_ii − c(a_{i−1} + a_i)` (c = 2 for M, −1 for S), the identities
///
/// ```text
/// ½VᵀMV = Σ_i m_i (v_i² + v_i v_{i+1} + v_{i+1}²) + ½ Σ_i r^M_i v_i²,    m_i = M_{i,i+1},
/// ½UᵀSU = ½ Σ_i k_i (u_i − u_{i+1})² + ½ Σ_i r^S_i u_i²,                 k_i = −S_{i,i+1},
/// ```
///
/// hold exactly; for a bar the residuals vanish except at a clamped end (the element to the
/// eliminated node) and the element terms are the element energies `(ρ w h/6)(v_a² + v_a v_b
/// + v_b²)` and `(E/2h)(u_a − u_b)²`. The row form `½Σ S_ii u_i² + Σ S_{i,i+1} u_i u_{i+1}` adds
/// terms of size `|u|²/h` that cancel to O(|u_x|²): its round-off grows like m^{3/2} ε
/// (8e−14 of E = 1/8 at m = 10³, 2e−10 at m = 10⁵ on the paper's benchmark), which is then what
/// the per-step energy increase of a long run shows; the element form is accurate to a few ulps
/// of E. One pass reads M's and S's off-diagonals, u and v (and F if non-zero): four streams
/// instead of the seven of three row-form passes.
#[derive(Debug, Clone)]
pub struct Energy {
    /// The non-zero diagonal residuals `(i, r^M_i, r^S_i)`.
    residuals: Vec<(usize, f64, f64)>,
}

impl Energy {
    pub fn new(mass: &SymTridiag, stiffness: &SymTridiag) -> Self {
        let off = |a: &SymTridiag, i: usize| a.off.get(i).copied().unwrap_or(0.0);
        let adjacent = |a: &SymTridiag, i: usize| off(a, i) + if i > 0 { off(a, i - 1) } else { 0.0 };
        let residuals = (0..mass.diag.len())
            .map(|i| (i, mass.diag[i] - 2.0 * adjacent(mass, i), stiffness.diag[i] + adjacent(stiffness, i)))
            .filter(|&(_, rm, rs)| rm != 0.0 || rs != 0.0)
            .collect();
        Self { residuals }
    }

    /// The energy of (u, v); `load = None` for F = 0.
    pub fn energy(&self, mass: &SymTridiag, stiffness: &SymTridiag, load: Option<&[f64]>, u: &[f64], v: &[f64]) -> f64 {
        with_avx2!(energy_impl(self, mass, stiffness, load, u, v))
    }
}

#[inline(always)]
fn energy_impl(
    kernel: &Energy,
    mass: &SymTridiag,
    stiffness: &SymTridiag,
    load: Option<&[f64]>,
    u: &[f64],
    v: &[f64],
) -> f64 {
    let n = u.len();
    let (mo, so) = (&mass.off[..n - 1], &stiffness.off[..n - 1]);
    let ends: f64 = kernel.residuals.iter().map(|&(i, rm, rs)| 0.5 * (rm * v[i] * v[i] + rs * u[i] * u[i])).sum();
    let [kinetic, strain] = element_sums(u, v, mo, so, |[ua, ub, va, vb, m, k]| {
        let du = ua - ub;
        [m * (va * va + va * vb + vb * vb), k * du * du]
    });
    // Σ F_i u_i as an element sum over (u_i, F_i) pairs of the n unknowns: pad with the last.
    let work = load.map_or(0.0, |f| {
        let [w, _] = element_sums(u, u, &f[..n - 1], &f[..n - 1], |[ua, _, _, _, fa, _]| [fa * ua, 0.0]);
        w + f[n - 1] * u[n - 1]
    });
    ends + kinetic - 0.5 * strain - work
}

/// `(‖u_h − u(·, t)‖, ‖I_h u(·, t)‖)` in L²(0, L) against the paper's closed form: what
/// [`l2_error`] and [`l2_norm_p1`] of the interpolant give, in one pass over the nodes, with the
/// exact values at the nodes `nodes` (x_0 … x_m, [`Bar::x`]) computed once
/// ([`ImpactingBar::nodal_values`], into `nodal`) and the pass free of divisions and branches. The ≤ 3 elements that hold a kink are first summed
/// as if unsplit, then corrected: their unsplit term is replaced by the split one of
/// [`l2_error`]. Agrees with the two separate functions to a few ulps of the sums.
pub fn l2_error_and_interp_norm(
    bar: &Bar,
    u: &[f64],
    exact: &ImpactingBar,
    t: f64,
    nodes: &[f64],
    nodal: &mut Vec<f64>,
) -> (f64, f64) {
    with_avx2!(l2_impl(bar, u, exact, t, nodes, nodal))
}

#[inline(always)]
fn l2_impl(bar: &Bar, u: &[f64], exact: &ImpactingBar, t: f64, nodes: &[f64], nodal: &mut Vec<f64>) -> (f64, f64) {
    let m = bar.elements;
    let h = bar.h();
    // u has m values (clamped: u_m = 0) or m + 1 (free far end); so has the interpolant.
    nodal.resize(m + 1, 0.0);
    exact.nodal_values(t, &nodes[..=m], nodal);
    let free = u.len() > m;
    let ex = &nodal[..];
    let (uh, ue) = (&u[..m], if free { u[m] } else { 0.0 });
    let (e_last, i_last) = (ue - ex[m], if free { ex[m] } else { 0.0 });
    let tri = |a: f64, b: f64| a * a + a * b + b * b;
    let e = |j: usize| uh[j] - ex[j];
    let [err, interp] =
        element_sums(uh, ex, &ex[..m - 1], &ex[..m - 1], |[ua, ub, xa, xb, _, _]| [tri(ua - xa, ub - xb), tri(xa, xb)]);
    let mut err = err + tri(e(m - 1), e_last);
    let interp = interp + tri(ex[m - 1], i_last);
    // The kink elements: x_j < kink < x_{j+1}.
    let mut kinks = [0.0; 3];
    let nk = exact.kinks(t, &mut kinks);
    let mut done = [usize::MAX; 3];
    for (k, &q) in kinks[..nk].iter().enumerate() {
        let mut j = (((q / bar.length) * m as f64) as usize).min(m - 1);
        while j > 0 && bar.x(j) >= q {
            j -= 1;
        }
        while j + 1 < m && bar.x(j + 1) <= q {
            j += 1;
        }
        if !(bar.x(j) < q && q < bar.x(j + 1)) || done.contains(&j) {
            continue;
        }
        done[k] = j;
        let (ea, eb) = (e(j), if j + 1 < m { e(j + 1) } else { e_last });
        let ub = if j + 1 < m { uh[j + 1] } else { ue };
        err += 3.0 / h * split_element(bar, j, uh[j], ub, exact, t, &kinks[..nk]) - tri(ea, eb);
    }
    ((h * err.max(0.0) / 3.0).sqrt(), (h * interp / 3.0).sqrt())
}

/// `∫ (u_h − u)²` over element j split at the kinks inside it (the loop body of [`l2_error`]).
fn split_element(bar: &Bar, j: usize, ua: f64, ub: f64, exact: &ImpactingBar, t: f64, kinks: &[f64]) -> f64 {
    let (xa, xb) = (bar.x(j), bar.x(j + 1));
    let uh = |x: f64| ua + (ub - ua) * (x - xa) / (xb - xa);
    let mut inside: [f64; 3] = [f64::INFINITY; 3];
    let mut n = 0;
    for &q in kinks {
        if xa < q && q < xb {
            inside[n] = q;
            n += 1;
        }
    }
    inside[..n].sort_by(f64::total_cmp);
    let (mut p, mut ep, mut s) = (xa, ua - exact.u(xa, t), 0.0);
    for &q in &inside[..n] {
        let eq = uh(q) - exact.u(q, t);
        s += affine_square(p, q, ep, eq);
        (p, ep) = (q, eq);
    }
    s + affine_square(p, xb, ep, ub - exact.u(xb, t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bar::assembly::{BarSystem, FarEnd, Load, Material};
    use crate::mass::MassKind;

    /// A deterministic state with sign changes between neighbours (so the row form's terms
    /// cancel) and of size O(1).
    fn wiggle(n: usize, phase: f64) -> Vec<f64> {
        (0..n).map(|i| (i as f64 * 0.37 + phase).sin() + 0.3 * (i as f64 * 2.9).cos()).collect()
    }

    #[test]
    fn element_energy_is_the_row_form_energy() {
        // The element form is an identity for every symmetric tridiagonal M, S: it must give
        // `ContactSystem::energy` (row form) up to the row form's round-off, which is bounded by
        // n ε times the sum of the absolute values of its terms (three serial sums of them).
        // mutation: `va * vb` -> `va * va` in the kinetic element term -> fails (6.18 vs 6.07).
        let masses = [MassKind::Standard, MassKind::Mod3, MassKind::Custom(vec![0.0, 2.0, 0.5, 1.5, 1.0, 1.0, 3.0])];
        for mass in &masses {
            for far_end in [FarEnd::Clamped, FarEnd::Free] {
                for force in [0.0, 0.7] {
                    let bar = Bar { length: 2.5, elements: 7 };
                    let w = BarSystem::weights(bar, mass).unwrap();
                    let material = Material { density: 1.3, modulus: 2.2 };
                    let b = BarSystem::assemble(bar, w, material, far_end, &Load::Constant(force));
                    let s = &b.system;
                    let (u, v) = (wiggle(s.n(), 0.1), wiggle(s.n(), 1.7));
                    let kernel = Energy::new(&s.mass, &s.stiffness);
                    let load = (force != 0.0).then_some(&s.load[..]);
                    let e = kernel.energy(&s.mass, &s.stiffness, load, &u, &v);
                    let row = s.energy(&u, &v);
                    let abs = |a: &SymTridiag, x: &[f64]| {
                        (0..x.len()).map(|i| (a.diag[i] * x[i] * x[i]).abs()).sum::<f64>()
                            + 2.0 * a.off.iter().enumerate().map(|(i, o)| (o * x[i] * x[i + 1]).abs()).sum::<f64>()
                    };
                    let scale = abs(&s.mass, &v)
                        + abs(&s.stiffness, &u)
                        + u.iter().zip(&s.load).map(|(a, b)| (a * b).abs()).sum::<f64>();
                    let tol = 4.0 * s.n() as f64 * f64::EPSILON * scale;
                    assert!((e - row).abs() <= tol, "{mass:?} {far_end:?} f={force}: {e} vs {row} (tol {tol:e})");
                }
            }
        }
    }

    #[test]
    fn one_pass_l2_error_and_interpolant_norm_match_the_separate_ones() {
        // Against `l2_error` (split at the kinks element by element) and `l2_norm_p1` of the
        // interpolant (exact values from `ImpactingBar::u`), at times in every phase, with
        // kinks inside elements and on nodes, for clamped (m values) and free (m + 1) vectors.
        // Tolerance: the sums of positive terms in another order (m ε relative, 16 m ε with
        // the kink correction's cancellation); the exact nodal values are the same numbers.
        // mutation: the kink correction (`err += 3.0 / h * split_element(…) − tri(ea, eb)`)
        // removed -> fails at t = 0.337 (0.0079651 vs 0.0079599).
        let exact = ImpactingBar { length: 1.5 };
        let bar = Bar { length: exact.length, elements: 40 };
        let m = bar.elements;
        let (mut nodal, nodes) = (Vec::new(), (0..=m).map(|i| bar.x(i)).collect::<Vec<_>>());
        for t in [0.0, 0.337, 1.5, 1.9001, 2.25, 2.6, 3.3, 3.75, 4.4, 6.0] {
            for n in [m, m + 1] {
                let u: Vec<f64> = (0..n).map(|i| exact.u(bar.x(i), t) + 0.01 * (i as f64 * 0.9).sin()).collect();
                let (err, interp) = l2_error_and_interp_norm(&bar, &u, &exact, t, &nodes, &mut nodal);
                let want_err = l2_error(&bar, &u, &exact, t);
                assert!(nodal.iter().zip(&nodes).all(|(&v, &x)| v == exact.u(x, t)), "t={t}: nodal values are u(x, t)");
                let iu: Vec<f64> = (0..n).map(|i| exact.u(bar.x(i), t)).collect();
                let want_interp = l2_norm_p1(&bar, &iu);
                let tol = |a: f64, b: f64| 16.0 * m as f64 * f64::EPSILON * a.max(b);
                assert!((err - want_err).abs() <= tol(err, want_err), "t={t} n={n}: error {err} vs {want_err}");
                assert!(
                    (interp - want_interp).abs() <= tol(interp, want_interp),
                    "t={t} n={n}: {interp} vs {want_interp}"
                );
            }
        }
    }

    #[test]
    fn norm_of_a_hat_is_exact() {
        // u_h = φ_1 on a 2-element mesh of (0, 2): ∫ φ_1² = 2h/3 with h = 1.
        let bar = Bar { length: 2.0, elements: 2 };
        assert!((l2_norm_p1(&bar, &[0.0, 1.0]) - (2.0f64 / 3.0).sqrt()).abs() < 4.0 * f64::EPSILON);
    }
}
