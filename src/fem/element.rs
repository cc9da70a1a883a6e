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
//! on general quadrilaterals it is the standard 2 × 2 rule. The map is general (any convex
//! quadrilateral or hexahedron with positive det J): only the box scenes' contact-face areas
//! (`solid/assembly.rs`) and [`super::Mesh::from_arrays`] ask for boxes.
//!
//! **P2 simplices** (triangle6, tetra10; node order in [`super::cell`]): with barycentric
//! λ_0 = 1 − Σ ξ_k, λ_k = ξ_k, the basis `φ_a = λ_a (2λ_a − 1)` at vertex a and `φ_e = 4 λ_a λ_b`
//! at the node of edge e = (a, b); the isoparametric map `x = Σ_a p_a φ_a(ξ)` (curved sides
//! allowed) and the degree-5 Grundmann–Möller rule ([`super::quadrature`]). On straight-sided
//! cells (J constant) the mass (degree 4) and the gradient products (degree 2) are exact.

use super::cell::{Cell, Reference};
use super::quadrature::{MAX_POINTS, p2_rule};

/// Largest number of nodes of a cell (tetra10).
pub const MAX_VERTS: usize = 10;
/// Largest number of quadrature points (the tetra10's degree-5 rule).
pub const MAX_QUAD: usize = MAX_POINTS;

/// The edges of the P2 cells, in the order of their nodes after the vertices ([`super::cell`]).
const TRIANGLE_EDGES: [[usize; 2]; 3] = [[0, 1], [1, 2], [2, 0]];
const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]];

/// The integrals of one cell (module docs); only the first `nv` vertices and `nq` points are
/// meaningful.
#[derive(Debug, Clone)]
pub struct CellIntegrals {
    pub nv: usize,
    pub nq: usize,
    /// `∫_c φ_a φ_b`, row-major MAX_VERTS × MAX_VERTS.
    pub mass: [[f64; MAX_VERTS]; MAX_VERTS],
    /// Quadrature weights (|det J| included).
    pub weights: [f64; MAX_QUAD],
    /// `grads[q][a]` = ∇φ_a at point q (z-component 0 in 2D).
    pub grads: [[[f64; 3]; MAX_VERTS]; MAX_QUAD],
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

/// `J[k][l] = Σ_a p_a[k] ∂φ_a/∂ξ_l` over the first `nv` nodes.
fn jacobian(d: usize, nv: usize, p: &[[f64; 3]; MAX_VERTS], dphi: &[[f64; 3]; MAX_VERTS]) -> [[f64; 3]; 3] {
    let mut j = [[0.0; 3]; 3];
    for a in 0..nv {
        for k in 0..d {
            for l in 0..d {
                j[k][l] += p[a][k] * dphi[a][l];
            }
        }
    }
    j
}

/// The P2 basis on the reference simplex of dimension d at ξ (module docs): values and
/// reference gradients ∂φ/∂ξ_l.
pub fn p2_basis(d: usize, xi: &[f64; 3]) -> ([f64; MAX_VERTS], [[f64; 3]; MAX_VERTS]) {
    let mut lam = [0.0; 4];
    let mut dlam = [[0.0; 3]; 4];
    lam[0] = 1.0 - xi[..d].iter().sum::<f64>();
    for k in 0..d {
        lam[k + 1] = xi[k];
        dlam[0][k] = -1.0;
        dlam[k + 1][k] = 1.0;
    }
    let (mut phi, mut dphi) = ([0.0; MAX_VERTS], [[0.0; 3]; MAX_VERTS]);
    for a in 0..=d {
        phi[a] = lam[a] * (2.0 * lam[a] - 1.0);
        for l in 0..d {
            dphi[a][l] = (4.0 * lam[a] - 1.0) * dlam[a][l];
        }
    }
    let edges: &[[usize; 2]] = if d == 2 { &TRIANGLE_EDGES } else { &TET_EDGES };
    for (e, &[a, b]) in edges.iter().enumerate() {
        phi[d + 1 + e] = 4.0 * lam[a] * lam[b];
        for l in 0..d {
            dphi[d + 1 + e][l] = 4.0 * (lam[b] * dlam[a][l] + lam[a] * dlam[b][l]);
        }
    }
    (phi, dphi)
}

/// Q1 basis at ξ: values and reference gradients (module docs).
fn q1_basis(kind: Cell, xi: &[f64; 3]) -> ([f64; MAX_VERTS], [[f64; 3]; MAX_VERTS]) {
    let d = kind.dim();
    let mut phi = [0.0; MAX_VERTS];
    let mut dphi = [[0.0; 3]; MAX_VERTS];
    for a in 0..kind.verts() {
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
    (phi, dphi)
}

/// The smallest and largest det J of the map of a cell of `kind` with nodes `p`, over its
/// quadrature points and its nodes' reference positions: both > 0 for a valid cell with the
/// orientation of the reference cell, both < 0 for a mirrored one; opposite signs for a
/// tangled (self-overlapping) one. For P1 the constant det J (twice the signed area, six times
/// the signed volume).
pub fn det_range(kind: Cell, p: &[[f64; 3]; MAX_VERTS]) -> [f64; 2] {
    let d = kind.dim();
    let mut at: Vec<[f64; 3]> = Vec::new();
    match kind.data().reference {
        Reference::P1Simplex => at.push([0.0; 3]),
        Reference::Q1Tensor => {
            let g = [0.5 - 0.5 / 3f64.sqrt(), 0.5 + 0.5 / 3f64.sqrt()];
            for q in 0..1 << d {
                at.push([g[q & 1], g[(q >> 1) & 1], if d == 3 { g[(q >> 2) & 1] } else { 0.0 }]);
            }
            at.extend((0..kind.verts()).map(|a| q1_corner(kind, a)));
        }
        Reference::P2Simplex => {
            at.extend(p2_rule(d).points.iter().copied());
            // The vertices and edge midpoints of the reference simplex.
            let mut corners = vec![[0.0; 3]];
            corners.extend((0..d).map(|k| {
                let mut e = [0.0; 3];
                e[k] = 1.0;
                e
            }));
            let edges: &[[usize; 2]] = if d == 2 { &TRIANGLE_EDGES } else { &TET_EDGES };
            let mids: Vec<[f64; 3]> =
                edges.iter().map(|&[a, b]| std::array::from_fn(|k| 0.5 * (corners[a][k] + corners[b][k]))).collect();
            at.extend(corners);
            at.extend(mids);
        }
    }
    let mut range = [f64::INFINITY, f64::NEG_INFINITY];
    for xi in &at {
        let dphi = match kind.data().reference {
            Reference::P1Simplex => {
                let mut g = [[0.0; 3]; MAX_VERTS];
                for k in 0..d {
                    g[0][k] = -1.0;
                    g[k + 1][k] = 1.0;
                }
                g
            }
            Reference::Q1Tensor => q1_basis(kind, xi).1,
            Reference::P2Simplex => p2_basis(d, xi).1,
        };
        let det = inverse_transpose(&jacobian(d, kind.verts(), p, &dphi), d).1;
        range = [range[0].min(det), range[1].max(det)];
    }
    range
}

/// The quadrature [`CellIntegrals`] takes for `kind`'s gradient products, on the reference
/// cell: the reference weights (det J not included: P1 one point of weight 1/d!, Q1 the 2^d
/// Gauss points of weight 1/2^d, P2 the degree-5 rule) and the basis's ξ-gradients at each
/// point. A matrix-free product ([`crate::solid::kernel`]) maps them itself.
pub fn reference_rule(kind: Cell) -> (Vec<f64>, Vec<[[f64; 3]; MAX_VERTS]>) {
    let d = kind.dim();
    match kind.data().reference {
        Reference::P1Simplex => {
            let mut g = [[0.0; 3]; MAX_VERTS];
            for k in 0..d {
                g[0][k] = -1.0;
                g[k + 1][k] = 1.0;
            }
            (vec![if d == 2 { 0.5 } else { 1.0 / 6.0 }], vec![g])
        }
        Reference::Q1Tensor => {
            let g = [0.5 - 0.5 / 3f64.sqrt(), 0.5 + 0.5 / 3f64.sqrt()];
            let nq = 1 << d;
            let grads = (0..nq)
                .map(|q| q1_basis(kind, &[g[q & 1], g[(q >> 1) & 1], if d == 3 { g[(q >> 2) & 1] } else { 0.0 }]).1)
                .collect();
            (vec![1.0 / nq as f64; nq], grads)
        }
        Reference::P2Simplex => {
            let rule = p2_rule(d);
            (rule.weights.clone(), rule.points.iter().map(|xi| p2_basis(d, xi).1).collect())
        }
    }
}

/// `J⁻ᵀ` and det J of the d × d matrix `j` (`j[k][l] = ∂x_k/∂ξ_l`): what [`CellIntegrals`]
/// maps its gradients with.
pub fn jacobian_inverse_transpose(j: &[[f64; 3]; 3], d: usize) -> ([[f64; 3]; 3], f64) {
    inverse_transpose(j, d)
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
            weights: [0.0; MAX_QUAD],
            grads: [[[0.0; 3]; MAX_VERTS]; MAX_QUAD],
        };
        match kind.data().reference {
            Reference::Q1Tensor => out.q1(kind, p),
            Reference::P1Simplex => out.p1(d, p),
            Reference::P2Simplex => out.p2(kind, p),
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
            let (phi, dphi) = q1_basis(kind, &xi);
            // |det J|/nq = |det J| × (1/nq): the same float (a power of 2).
            self.accumulate(q, d, p, &phi, &dphi, 1.0 / self.nq as f64);
        }
        self.mirror_mass();
    }

    /// Point q of an isoparametric element: J = Σ_a p_a ⊗ ∇_ξ φ_a, the weight `w_ref |det J|`,
    /// the gradients `J⁻ᵀ ∇_ξ φ_a` and the mass's upper triangle `+= w φ_a φ_b`.
    fn accumulate(
        &mut self,
        q: usize,
        d: usize,
        p: &[[f64; 3]; MAX_VERTS],
        phi: &[f64; MAX_VERTS],
        dphi: &[[f64; 3]; MAX_VERTS],
        w_ref: f64,
    ) {
        let (inv_t, det) = inverse_transpose(&jacobian(d, self.nv, p, dphi), d);
        let w = det.abs() * w_ref;
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

    fn mirror_mass(&mut self) {
        for a in 0..self.nv {
            for b in 0..a {
                self.mass[a][b] = self.mass[b][a];
            }
        }
    }

    fn p2(&mut self, kind: Cell, p: &[[f64; 3]; MAX_VERTS]) {
        let d = kind.dim();
        let rule = p2_rule(d);
        self.nq = rule.points.len();
        for (q, (xi, &w_ref)) in rule.points.iter().zip(&rule.weights).enumerate() {
            let (phi, dphi) = p2_basis(d, xi);
            self.accumulate(q, d, p, &phi, &dphi, w_ref);
        }
        self.mirror_mass();
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

    /// Reference positions of the P2 nodes in VTK order (vertices, then the midpoints of the
    /// edges listed in `super::cell`), written out independently of TET_EDGES.
    fn p2_nodes(d: usize) -> Vec<[f64; 3]> {
        let (o, h) = (0.0, 0.5);
        if d == 2 {
            return vec![[o, o, o], [1.0, o, o], [o, 1.0, o], [h, o, o], [h, h, o], [o, h, o]];
        }
        let v = [[o, o, o], [1.0, o, o], [o, 1.0, o], [o, o, 1.0]];
        let e = [[h, o, o], [h, h, o], [o, h, o], [o, o, h], [h, o, h], [o, h, h]];
        [&v[..], &e[..]].concat()
    }

    /// The P2 mass and stiffness on straight-sided cells x = A ξ + b against closed forms:
    /// with q(ξ) = ξ η interpolated exactly (u_a = q(ξ_a)), uᵀ M u = |det A| ∫_T ξ² η²
    /// (= |det A| 2! 2!/(4 + n)!) and uᵀ K u = |det A| ∫_T (η, ξ) B (η, ξ)ᵀ with B = A⁻¹A⁻ᵀ
    /// (∫ξ² = 2/(n + 2)!, ∫ξη = 1/(n + 2)!); the basis is a partition of unity and ∫φ_a is 0
    /// at triangle6 vertices, |c|/3 at its edge nodes, −|c|/20 and |c|/5 for tetra10.
    /// Entries O(1): 1e-14. mutations, as run: the edge basis `4 λ_a λ_b` -> `2 λ_a λ_b`
    /// -> fails (uᵀ M u); the tetra10 edges (1,3), (2,3) swapped in TET_EDGES -> fails
    /// (uᵀ M u: the node positions here are written out, not taken from TET_EDGES).
    #[test]
    fn p2_mass_and_stiffness_are_exact_on_straight_cells() {
        let a2 = [[2.0, 0.5, 0.0], [0.3, 1.5, 0.0], [0.0, 0.0, 1.0]];
        let a3 = [[2.0, 0.5, 0.1], [0.3, 1.5, -0.2], [0.4, 0.1, 0.7]];
        for (kind, a) in [(Cell::Triangle6, a2), (Cell::Tet10, a3)] {
            let d = kind.dim();
            let nodes = p2_nodes(d);
            let map = |xi: &[f64; 3]| -> [f64; 3] {
                std::array::from_fn(|k| 0.3 + (0..3).map(|l| a[k][l] * xi[l]).sum::<f64>())
            };
            let p = pts(&nodes.iter().map(map).collect::<Vec<_>>());
            let e = CellIntegrals::new(kind, &p);
            let (inv_t, det) = inverse_transpose(&a, d);
            let fact = |k: usize| (1..=k).map(|x| x as f64).product::<f64>();
            let u: Vec<f64> = nodes.iter().map(|x| x[0] * x[1]).collect();
            let um: f64 =
                (0..e.nv).flat_map(|i| (0..e.nv).map(move |j| (i, j))).map(|(i, j)| u[i] * e.mass[i][j] * u[j]).sum();
            assert!((um - det.abs() * 4.0 / fact(4 + d)).abs() <= 1e-14, "{kind:?}: {um}");
            // B = A⁻¹ A⁻ᵀ = (J⁻ᵀ)ᵀ J⁻ᵀ.
            let b = |k: usize, l: usize| (0..d).map(|r| inv_t[r][k] * inv_t[r][l]).sum::<f64>();
            let want = det.abs() * ((b(0, 0) + b(1, 1)) * 2.0 + 2.0 * b(0, 1)) / fact(d + 2);
            let uk: f64 = (0..e.nv)
                .flat_map(|i| (0..e.nv).map(move |j| (i, j)))
                .map(|(i, j)| u[i] * e.stiffness(i, j) * u[j])
                .sum();
            assert!((uk - want).abs() <= 1e-14, "{kind:?}: {uk} vs {want}");
            let measure = det.abs() / fact(d);
            assert!((e.measure() - measure).abs() <= 1e-14);
            let (v_int, e_int) = if d == 2 { (0.0, 1.0 / 3.0) } else { (-1.0 / 20.0, 1.0 / 5.0) };
            for i in 0..e.nv {
                let row: f64 = e.mass[i][..e.nv].iter().sum();
                let want = measure * if i <= d { v_int } else { e_int };
                assert!((row - want).abs() <= 1e-14, "{kind:?} node {i}: {row} vs {want}");
            }
            for xi in &p2_rule(d).points {
                let (phi, dphi) = p2_basis(d, xi);
                assert!((phi[..e.nv].iter().sum::<f64>() - 1.0).abs() <= 1e-15);
                assert!((0..d).all(|l| dphi[..e.nv].iter().map(|g| g[l]).sum::<f64>().abs() <= 1e-14));
            }
            assert!(det_range(kind, &p)[0] > 0.0);
        }
    }

    /// A curved triangle6: the unit right triangle with the midside node of its hypotenuse
    /// pushed out by δ along the normal. The isoparametric side is a parabola: the area gains
    /// the parabolic segment, 2/3 × chord × δ (det J is quadratic: the rule is exact);
    /// affine functions are still reproduced. Pushed past the opposite vertex, the cell tangles
    /// and det J changes sign (`det_range`).
    #[test]
    fn a_curved_triangle6_has_the_area_of_its_parabolic_side() {
        let delta = 0.1;
        let s = delta / 2f64.sqrt();
        let p = pts(&[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.0, 0.0],
            [0.5 + s, 0.5 + s, 0.0],
            [0.0, 0.5, 0.0],
        ]);
        let e = CellIntegrals::new(Cell::Triangle6, &p);
        let want = 0.5 + 2.0 / 3.0 * 2f64.sqrt() * delta;
        assert!((e.measure() - want).abs() <= 1e-15, "{}", e.measure());
        let g = |p: [f64; 3]| 1.0 + 2.0 * p[0] - 3.0 * p[1];
        for q in 0..e.nq {
            for (k, want) in [2.0, -3.0].into_iter().enumerate() {
                let s: f64 = (0..6).map(|a| g(p[a]) * e.grads[q][a][k]).sum();
                assert!((s - want).abs() <= 1e-13, "q{q}: {s}");
            }
        }
        let [lo, hi] = det_range(Cell::Triangle6, &p);
        assert!(lo > 0.0 && hi > lo);
        let mut tangled = p;
        tangled[4] = [-0.6, -0.6, 0.0];
        let [lo, hi] = det_range(Cell::Triangle6, &tangled);
        assert!(lo < 0.0 && hi > 0.0, "{lo} {hi}");
    }
}
