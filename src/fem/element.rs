//! Reference elements for dimension 2 and 3: what an assembler needs of one cell, as numbers
//! (no branches of the assembler per cell type).
//!
//! For a cell with vertices p_a, [`CellIntegrals`] holds
//! - the scalar mass `∫_c φ_a φ_b`,
//! - a quadrature `{(w_q, ∇φ_a(x_q))}` exact for products of gradients, so that any bilinear form
//!   `∫_c Σ C_kl ∂_k φ_a ∂_l φ_b` with constant C is `Σ_q w_q Σ C_kl ∂_k φ_a(x_q) ∂_l φ_b(x_q)`.
//!
//! **P1 simplices** (triangle, tetrahedron): the affine map `x = p_0 + J ξ` with
//! `J = [p_1 − p_0, …, p_d − p_0]`, barycentric basis `φ_0 = 1 − Σ ξ_k`, `φ_a = ξ_a`; gradients
//! `∇φ = J⁻ᵀ ∇_ξ φ` are constant, so one point with weight `|c| = |det J|/d!` is exact; the mass
//! is the closed form `|c| (1 + δ_ab)/((d + 1)(d + 2))`.
//!
//! **Q1 tensor cells** (quadrilateral, hexahedron): reference cell [0, 1]^d with vertex a at the
//! corner r_a (quadrilateral (0,0), (1,0), (1,1), (0,1); hexahedron the same at ζ = 0 then at
//! ζ = 1: VTK order), `φ_a(ξ) = Π_k (r_ak ξ_k + (1 − r_ak)(1 − ξ_k))`, the isoparametric map
//! `x = Σ_a p_a φ_a(ξ)` and the 2^d-point Gauss–Legendre rule (points `(1 ± 1/√3)/2`, weights
//! ½ per direction; degree 3 per direction). On parallelograms and boxes (J constant) the mass
//! (degree 2 per direction) and the gradient products (degree ≤ 2) are integrated exactly;
//! on general quadrilaterals it is the standard 2 × 2 rule.

use super::cell::{Cell, Reference};

/// Largest number of vertices (hexahedron) and of quadrature points.
pub const MAX_VERTS: usize = 8;

/// The integrals of one cell (module docs); only the first `nv` vertices and `nq` points are
/// meaningful.
#[derive(Debug, Clone)]
pub struct CellIntegrals {
    pub nv: usize,
    pub nq: usize,
    /// `∫_c φ_a φ_b`, row-major MAX_VERTS × MAX_VERTS.
    pub mass: [[f64; MAX_VERTS]; MAX_VERTS],
    /// Quadrature weights (|det J| included).
    pub weights: [f64; MAX_VERTS],
    /// `grads[q][a]` = ∇φ_a at point q (z-component 0 in 2D).
    pub grads: [[[f64; 3]; MAX_VERTS]; MAX_VERTS],
}

/// `J⁻ᵀ` and det J of the d × d matrix `j` (j[k][l] = ∂x_k/∂ξ_l), d = 2 or 3.
fn inverse_transpose(j: &[[f64; 3]; 3], d: usize) -> ([[f64; 3]; 3], f64) {
    let mut inv_t = [[0.0; 3]; 3];
    if d == 2 {
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        // J⁻¹ = [[j11, −j01], [−j10, j00]]/det, transposed.
        inv_t[0] = [j[1][1] / det, -j[1][0] / det, 0.0];
        inv_t[1] = [-j[0][1] / det, j[0][0] / det, 0.0];
        return (inv_t, det);
    }
    // Cofactor matrix C: J⁻ᵀ = C/det.
    let c = |r: usize, s: usize| {
        let (r1, r2, s1, s2) = ((r + 1) % 3, (r + 2) % 3, (s + 1) % 3, (s + 2) % 3);
        j[r1][s1] * j[r2][s2] - j[r1][s2] * j[r2][s1]
    };
    let det = j[0][0] * c(0, 0) + j[0][1] * c(0, 1) + j[0][2] * c(0, 2);
    for (r, row) in inv_t.iter_mut().enumerate() {
        for (s, x) in row.iter_mut().enumerate() {
            *x = c(r, s) / det;
        }
    }
    (inv_t, det)
}

/// Reference corners of the Q1 cells (module docs).
const QUAD_CORNERS: [[f64; 3]; 4] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];

fn q1_corner(kind: Cell, a: usize) -> [f64; 3] {
    let mut r = QUAD_CORNERS[a % 4];
    if kind == Cell::Hex && a >= 4 {
        r[2] = 1.0;
    }
    r
}

impl CellIntegrals {
    /// The integrals of a cell of type `kind` with vertices `p` (first `kind.verts()` used).
    pub fn new(kind: Cell, p: &[[f64; 3]; MAX_VERTS]) -> Self {
        let d = kind.dim();
        let nv = kind.verts();
        let mut out = Self {
            nv,
            nq: 0,
            mass: [[0.0; MAX_VERTS]; MAX_VERTS],
            weights: [0.0; MAX_VERTS],
            grads: [[[0.0; 3]; MAX_VERTS]; MAX_VERTS],
        };
        match kind.data().reference {
            Reference::Q1Tensor => out.q1(kind, p),
            Reference::P1Simplex => out.p1(d, p),
        }
        out
    }

    fn p1(&mut self, d: usize, p: &[[f64; 3]; MAX_VERTS]) {
        let mut j = [[0.0; 3]; 3];
        for (k, row) in j.iter_mut().enumerate().take(d) {
            for (l, x) in row.iter_mut().enumerate().take(d) {
                *x = p[l + 1][k] - p[0][k];
            }
        }
        let (inv_t, det) = inverse_transpose(&j, d);
        let measure = det.abs() / if d == 2 { 2.0 } else { 6.0 };
        self.nq = 1;
        self.weights[0] = measure;
        // ∇φ_a = J⁻ᵀ e_a (a ≥ 1), ∇φ_0 = −Σ_a ∇φ_a.
        for a in 1..=d {
            for k in 0..d {
                self.grads[0][a][k] = inv_t[k][a - 1];
                self.grads[0][0][k] -= inv_t[k][a - 1];
            }
        }
        let denom = ((d + 1) * (d + 2)) as f64;
        for a in 0..=d {
            for b in 0..=d {
                self.mass[a][b] = measure * if a == b { 2.0 } else { 1.0 } / denom;
            }
        }
    }

    fn q1(&mut self, kind: Cell, p: &[[f64; 3]; MAX_VERTS]) {
        let d = kind.dim();
        let g = [0.5 - 0.5 / 3f64.sqrt(), 0.5 + 0.5 / 3f64.sqrt()];
        self.nq = 1 << d;
        for q in 0..self.nq {
            let xi = [g[q & 1], g[(q >> 1) & 1], if d == 3 { g[(q >> 2) & 1] } else { 0.0 }];
            let mut phi = [0.0; MAX_VERTS];
            let mut dphi = [[0.0; 3]; MAX_VERTS];
            for a in 0..self.nv {
                let r = q1_corner(kind, a);
                let mut f = [1.0; 3];
                for k in 0..d {
                    f[k] = r[k] * xi[k] + (1.0 - r[k]) * (1.0 - xi[k]);
                }
                phi[a] = f[..d].iter().product();
                for k in 0..d {
                    let others: f64 = (0..d).filter(|&l| l != k).map(|l| f[l]).product();
                    dphi[a][k] = (2.0 * r[k] - 1.0) * others;
                }
            }
            let mut j = [[0.0; 3]; 3];
            for a in 0..self.nv {
                for k in 0..d {
                    for l in 0..d {
                        j[k][l] += p[a][k] * dphi[a][l];
                    }
                }
            }
            let (inv_t, det) = inverse_transpose(&j, d);
            let w = det.abs() / self.nq as f64;
            self.weights[q] = w;
            for a in 0..self.nv {
                for k in 0..d {
                    self.grads[q][a][k] = (0..d).map(|l| inv_t[k][l] * dphi[a][l]).sum();
                }
                // The upper triangle, mirrored below: `w φ_a φ_b` rounds differently from
                // `w φ_b φ_a`, and the matrices must be exactly symmetric.
                for b in a..self.nv {
                    self.mass[a][b] += w * phi[a] * phi[b];
                }
            }
        }
        for a in 0..self.nv {
            for b in 0..a {
                self.mass[a][b] = self.mass[b][a];
            }
        }
    }

    /// `∫_c ∇φ_a · ∇φ_b = Σ_q w_q ∇φ_a(x_q) · ∇φ_b(x_q)`: the scalar stiffness (Laplacian) of
    /// the cell, the form plates assemble (the solid's elasticity combines the same gradients).
    pub fn stiffness(&self, a: usize, b: usize) -> f64 {
        let mut s = 0.0;
        for q in 0..self.nq {
            s += self.weights[q] * self.grad_dot(q, a, b);
        }
        s
    }

    /// `∇φ_a(x_q) · ∇φ_b(x_q)`.
    pub fn grad_dot(&self, q: usize, a: usize, b: usize) -> f64 {
        let (ga, gb) = (&self.grads[q][a], &self.grads[q][b]);
        ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2]
    }

    /// `|c|`, the area or volume of the cell.
    pub fn measure(&self) -> f64 {
        self.weights[..self.nq].iter().sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(v: &[[f64; 3]]) -> [[f64; 3]; MAX_VERTS] {
        let mut p = [[0.0; 3]; MAX_VERTS];
        p[..v.len()].copy_from_slice(v);
        p
    }

    #[test]
    fn gradients_reproduce_linear_functions_and_the_mass_integrates_one() {
        // For g(x) = 1 + 2x − 3y + 5z: Σ_a g(p_a) ∇φ_a = ∇g at every point (P1 and Q1 contain
        // affine functions), and Σ_ab M_ab = |c|. Entries O(1): a few ulps.
        let g = |p: [f64; 3]| 1.0 + 2.0 * p[0] - 3.0 * p[1] + 5.0 * p[2];
        let cases = [
            (Cell::Triangle, pts(&[[0.1, 0.2, 0.0], [1.3, 0.1, 0.0], [0.4, 0.9, 0.0]])),
            (Cell::Quad, pts(&[[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 0.25, 0.0], [0.0, 0.25, 0.0]])),
            (Cell::Tet, pts(&[[0.0, 0.0, 0.0], [1.0, 0.1, 0.0], [0.2, 1.0, 0.1], [0.1, 0.3, 0.8]])),
            (
                Cell::Hex,
                pts(&[
                    [0.0, 0.0, 0.0],
                    [0.5, 0.0, 0.0],
                    [0.5, 0.25, 0.0],
                    [0.0, 0.25, 0.0],
                    [0.0, 0.0, 2.0],
                    [0.5, 0.0, 2.0],
                    [0.5, 0.25, 2.0],
                    [0.0, 0.25, 2.0],
                ]),
            ),
        ];
        for (kind, p) in cases {
            let c = CellIntegrals::new(kind, &p);
            let d = kind.dim();
            let want = [2.0, -3.0, 5.0];
            for q in 0..c.nq {
                for k in 0..d {
                    let s: f64 = (0..c.nv).map(|a| g(p[a]) * c.grads[q][a][k]).sum();
                    assert!((s - want[k]).abs() <= 64.0 * f64::EPSILON, "{kind:?} q{q} ∂{k}: {s}");
                }
            }
            let total: f64 = (0..c.nv).flat_map(|a| (0..c.nv).map(move |b| (a, b))).map(|(a, b)| c.mass[a][b]).sum();
            assert!((total - c.measure()).abs() <= 16.0 * f64::EPSILON, "{kind:?}");
        }
        // Known measures: the box 0.5 × 0.25 × 2 and the rectangle 0.5 × 0.25.
        assert!((CellIntegrals::new(cases[3].0, &cases[3].1).measure() - 0.25).abs() <= 4.0 * f64::EPSILON);
        assert!((CellIntegrals::new(cases[1].0, &cases[1].1).measure() - 0.125).abs() <= 4.0 * f64::EPSILON);
    }

    #[test]
    fn element_masses_are_exactly_symmetric() {
        // The assembled matrices must be (tests/plate.rs compares M[i,j] with M[j,i] bit for
        // bit). mutation, as run: the Q1 mass summed over all (a, b) without the mirror -> fails
        // (on the 6 × 4 quadrilaterals of 1.3 × 0.8, entries one ulp apart).
        use crate::fem::Mesh;
        let meshes = [
            Mesh::structured_2d(1.3, 0.8, 6, 4, Cell::Quad).unwrap(),
            Mesh::structured_2d(1.3, 0.8, 6, 4, Cell::Triangle).unwrap(),
            Mesh::structured_3d([1.3, 0.8, 0.7], [3, 2, 2], Cell::Hex).unwrap(),
            Mesh::structured_3d([1.3, 0.8, 0.7], [3, 2, 2], Cell::Tet).unwrap(),
        ];
        for m in &meshes {
            for c in 0..m.n_cells() {
                let e = m.integrals(c);
                assert!((0..e.nv).all(|a| (0..e.nv).all(|b| e.mass[a][b] == e.mass[b][a])), "{:?} {c}", m.kind);
            }
        }
    }
}
