//! L²(Ω) norms on the plate, and the exact L² error against the y-independent benchmark
//! solution `u(x, y, t) = u_1D(x, t)` ([`ImpactingBar`]), integrated exactly.
//!
//! The exact solution is affine in x between its kinks ([`ImpactingBar::kinks`], at most 3
//! vertical lines x = k) and constant in y. Each cell is cut along those lines; on each piece
//! - P1 triangles: u_h and u are affine, so the error e is affine on every convex piece (a
//!   triangle clipped by vertical lines, fanned into triangles) and
//!   `∫_T e² = |T|/6 (e_1² + e_2² + e_3² + e_1e_2 + e_2e_3 + e_3e_1)` exactly;
//! - Q1 rectangles: u_h is bilinear, u affine in x and constant in y, so e is bilinear on each
//!   sub-rectangle [p, q] × [y_a, y_b] and `∫ e² = Σ (M_x)_{ac} (M_y)_{bd} e_{ab} e_{cd}` with
//!   the 1D mass matrices `(len/6)[[2,1],[1,2]]`, exactly.
//!
//! No quadrature rule is involved: the only error is round-off.

use super::assembly::PlateSystem;
use super::cells::QuadCells;
use crate::characteristics::Characteristics;
use crate::exact::ImpactingBar;
use crate::fem::Cell;
use crate::fem::columns::Columns;
use crate::linalg::sparse;

/// `‖u_h‖_{L²(Ω)} = (Uᵀ M₁ U)^{1/2}` (M₁ the unweighted mass matrix; u_h = 0 on Γ_D).
pub fn l2_norm(plate: &PlateSystem, u: &[f64]) -> f64 {
    let q = sparse::quad_form(&plate.mass_unit, u);
    (if q < 0.0 { 0.0 } else { q }).sqrt()
}

/// `∫_T e²` for e affine on the triangle with corners p and values e.
fn triangle_square(p: [[f64; 2]; 3], e: [f64; 3]) -> f64 {
    let area = 0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1])).abs();
    area / 6.0 * (e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[0] * e[1] + e[1] * e[2] + e[2] * e[0])
}

/// Clips the convex polygon `poly` (≤ 7 vertices) to `lo ≤ x ≤ hi`, into `out`; returns its
/// vertex count.
fn clip_strip(poly: &[[f64; 2]], lo: f64, hi: f64, out: &mut [[f64; 2]; 8]) -> usize {
    let mut a = [[0.0; 2]; 8];
    let mut na = 0;
    // x ≥ lo
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let (pin, qin) = (p[0] >= lo, q[0] >= lo);
        if pin {
            a[na] = p;
            na += 1;
        }
        if pin != qin {
            let s = (lo - p[0]) / (q[0] - p[0]);
            a[na] = [lo, p[1] + s * (q[1] - p[1])];
            na += 1;
        }
    }
    let mut nb = 0;
    // x ≤ hi
    for k in 0..na {
        let (p, q) = (a[k], a[(k + 1) % na]);
        let (pin, qin) = (p[0] <= hi, q[0] <= hi);
        if pin {
            out[nb] = p;
            nb += 1;
        }
        if pin != qin {
            let s = (hi - p[0]) / (q[0] - p[0]);
            out[nb] = [hi, p[1] + s * (q[1] - p[1])];
            nb += 1;
        }
    }
    nb
}

/// `∫ e²` over `[a, b] × [y0, y0 + hy]` for e bilinear with values `bottom` at (a, y0), (b, y0)
/// and `top` at (a, y1), (b, y1): `(b − a) hy / 36 · (2 BᵀAB + 2 TᵀAT + 2 BᵀAT)`, A = [[2,1],[1,2]]
/// (the tensor product of the 1D mass matrices), exactly.
#[inline]
fn rectangle_square(len: f64, hy: f64, bottom: [f64; 2], top: [f64; 2]) -> f64 {
    let form = |u: [f64; 2], v: [f64; 2]| 2.0 * u[0] * v[0] + u[0] * v[1] + u[1] * v[0] + 2.0 * u[1] * v[1];
    len * hy / 18.0 * (form(bottom, bottom) + form(top, top) + form(bottom, top))
}

/// The Q1 part of [`l2_error`]: every cell from [`QuadCells`], split at the kinks strictly
/// inside it.
fn quad_error_squared(plate: &PlateSystem, u: &[f64], exact: &ImpactingBar, t: f64, kinks: &[f64]) -> f64 {
    let quads = plate.quad_cells.get_or_init(|| QuadCells::new(&plate.mesh, &plate.node_dof));
    let ue: Vec<f64> = quads.xs.iter().map(|&x| exact.u(x, t)).collect();
    let val = |d: usize| if d == usize::MAX { 0.0 } else { u[d] };
    let mut total = 0.0;
    for q in &quads.cells {
        let [x0, x1, y0, y1] = q.bbox;
        let c = [val(q.dof[0]), val(q.dof[1]), val(q.dof[2]), val(q.dof[3])];
        let hy = y1 - y0;
        if !kinks.iter().any(|&k| k > x0 && k < x1) {
            let (ua, ub) = (ue[q.ix[0]], ue[q.ix[1]]);
            total += rectangle_square(x1 - x0, hy, [c[0] - ua, c[1] - ub], [c[3] - ua, c[2] - ub]);
            continue;
        }
        // u_h along the bottom and top edges, and u affine between consecutive cuts.
        let uh = |x: f64, bottom: bool| {
            let s = (x - x0) / (x1 - x0);
            if bottom { c[0] + s * (c[1] - c[0]) } else { c[3] + s * (c[2] - c[3]) }
        };
        let mut a = x0;
        for b in kinks.iter().copied().filter(|&k| k > x0 && k < x1).chain([x1]) {
            if b <= a {
                continue; // a repeated kink
            }
            let (ua, ub) = (exact.u(a, t), exact.u(b, t));
            total += rectangle_square(
                b - a,
                hy,
                [uh(a, true) - ua, uh(b, true) - ub],
                [uh(a, false) - ua, uh(b, false) - ub],
            );
            a = b;
        }
    }
    total
}

/// `‖u_h − u(·, t)‖_{L²(Ω)}` for the y-independent benchmark solution, exact (module docs).
/// Q1 cells: [`quad_error_squared`]; P1 triangles: each cell clipped at the kinks and fanned.
/// `u` holds the values on the free unknowns of `plate`.
pub fn l2_error(plate: &PlateSystem, u: &[f64], exact: &ImpactingBar, t: f64) -> f64 {
    let mesh = &plate.mesh;
    let mut kinks = [0.0; 3];
    let nk = exact.kinks(t, &mut kinks);
    let kinks = &mut kinks[..nk];
    kinks.sort_by(f64::total_cmp);
    if mesh.kind == Cell::Quad {
        let total = quad_error_squared(plate, u, exact, t, kinks);
        return (if total < 0.0 { 0.0 } else { total }).sqrt();
    }
    let val = |v: usize| plate.node_dof[v].map_or(0.0, |d| u[d]);
    let mut total = 0.0;
    let mut cuts = [0.0; 5];
    for c in 0..mesh.n_cells() {
        let cell = mesh.cell(c);
        let [x0, x1, _, _] = mesh.cell_box(c);
        // Strip boundaries: the cell's x-range cut at the kinks strictly inside it.
        let mut nc = 0;
        cuts[nc] = x0;
        nc += 1;
        for &k in kinks.iter() {
            // Sorted, and repeated kinks (t = 1.5 L has three at L/2) give one cut.
            if k > cuts[nc - 1] && k < x1 {
                cuts[nc] = k;
                nc += 1;
            }
        }
        cuts[nc] = x1;
        nc += 1;
        match mesh.kind {
            Cell::Triangle => {
                let xy = |v: usize| [mesh.points[v][0], mesh.points[v][1]];
                let p = [xy(cell[0]), xy(cell[1]), xy(cell[2])];
                let uv = [val(cell[0]), val(cell[1]), val(cell[2])];
                // u_h(x, y) = Σ uv_i λ_i(x, y) (barycentric coordinates).
                let det = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
                let uh = |q: [f64; 2]| {
                    let l1 = ((q[0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (q[1] - p[0][1])) / det;
                    let l2 = ((p[1][0] - p[0][0]) * (q[1] - p[0][1]) - (q[0] - p[0][0]) * (p[1][1] - p[0][1])) / det;
                    uv[0] * (1.0 - l1 - l2) + uv[1] * l1 + uv[2] * l2
                };
                let mut piece = [[0.0; 2]; 8];
                for s in 0..nc - 1 {
                    let np = clip_strip(&p, cuts[s], cuts[s + 1], &mut piece);
                    if np < 3 {
                        continue;
                    }
                    // u is affine on the strip: its values at the strip ends define it there.
                    let (a, b) = (cuts[s], cuts[s + 1]);
                    let (ua, ub) = (exact.u(a, t), exact.u(b, t));
                    let ue = |x: f64| ua + (ub - ua) * (x - a) / (b - a);
                    let e = |q: [f64; 2]| uh(q) - ue(q[0]);
                    for k in 1..np - 1 {
                        let tri = [piece[0], piece[k], piece[k + 1]];
                        total += triangle_square(tri, [e(tri[0]), e(tri[1]), e(tri[2])]);
                    }
                }
            }
            _ => unreachable!("quad meshes take quad_error_squared; plates have no 3D cells"),
        }
    }
    // A sum of positive semi-definite quadratic forms; NaN stays NaN.
    (if total < 0.0 { 0.0 } else { total }).sqrt()
}

/// The segment where the vertical line at abscissa x meets cell c, as `(y_lo, u_h(x, y_lo),
/// y_hi, u_h(x, y_hi))`: u_h is linear along every edge of a P1 triangle or an axis-aligned Q1
/// rectangle, so the ends are found on the edges crossing x, exactly.
fn vertical_cut(plate: &PlateSystem, u: &[f64], c: usize, x: f64) -> (f64, f64, f64, f64) {
    let mesh = &plate.mesh;
    let cell = mesh.cell(c);
    let val = |v: usize| plate.node_dof[v].map_or(0.0, |d| u[d]);
    let (mut lo, mut hi) = ((f64::INFINITY, 0.0), (f64::NEG_INFINITY, 0.0));
    for a in 0..cell.len() {
        let (p, q) = (cell[a], cell[(a + 1) % cell.len()]);
        let (pp, qp) = (mesh.points[p], mesh.points[q]);
        let (xmin, xmax) = (pp[0].min(qp[0]), pp[0].max(qp[0]));
        if pp[0] == qp[0] || x < xmin || x > xmax {
            continue;
        }
        let s = (x - pp[0]) / (qp[0] - pp[0]);
        let (y, w) = (pp[1] + s * (qp[1] - pp[1]), val(p) + s * (val(q) - val(p)));
        if y < lo.0 {
            lo = (y, w);
        }
        if y > hi.0 {
            hi = (y, w);
        }
    }
    (lo.0, lo.1, hi.0, hi.1)
}

/// `‖u_h − u(·, t)‖_{L²(Ω)}` against a plane wave `u(x, y, t) = u_1D(x, t)` given by
/// characteristics (y-independent data without force).
///
/// At fixed x the error `e = u_h − u` is affine in y on each cell (P1 triangles, and Q1
/// rectangles whose u_h is bilinear), so `∫ e² dy = ℓ (e_lo² + e_lo e_hi + e_hi²)/3` over the
/// cell's vertical cut of length ℓ exactly (`vertical_cut`). What is left is an integral in x
/// over the 1D mesh of the distinct vertex abscissae, which the 1D solution integrates split at
/// its own breakpoints ([`Characteristics::integrate`]): exactly for piecewise-linear data (the
/// integrand is a polynomial of degree ≤ 5 per piece), to the smooth rule's accuracy otherwise.
pub fn l2_error_plane_wave(plate: &PlateSystem, u: &[f64], exact: &Characteristics, t: f64) -> f64 {
    let columns = plate.columns.get_or_init(|| Columns::new(&plate.mesh));
    exact
        .integrate(&columns.xs, t, |j, x, ue| {
            columns
                .of(j)
                .iter()
                .map(|&c| {
                    let (ylo, elo, yhi, ehi) = vertical_cut(plate, u, c, x);
                    let (elo, ehi) = (elo - ue, ehi - ue);
                    (yhi - ylo) * (elo * elo + elo * ehi + ehi * ehi) / 3.0
                })
                .sum()
        })
        .max(0.0)
        .sqrt()
}
