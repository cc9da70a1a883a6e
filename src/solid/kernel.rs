//! The stiffness of any mesh applied cell by cell, without a matrix (issue 31, item 2): P1
//! triangles and tetrahedra, Q1 quadrilaterals and hexahedra of any shape, P2 triangles and
//! tetrahedra (straight or curved).
//!
//! For each cell c and quadrature point q (weight w_q, physical basis gradients g_a = ∇φ_a(x_q)),
//! with u_c the cell's nodal displacements,
//!
//! ```text
//! H = Σ_b u_b ⊗ g_b  (H_jk = ∂_k u_j),   σ = λ tr(H) I + μ (H + Hᵀ),   f_(a,i) += w_q Σ_k g_a,k σ_ik,
//! ```
//!
//! which is `Σ_(b,j) S_(a,i),(b,j) u_(b,j)` with the assembled element entry
//! `S = Σ_q w_q (λ g_a,i g_b,j + μ (δ_ij g_a·g_b + g_a,j g_b,i))`
//! ([`super::columns::stiffness_entry`]): the same operator, each product associated otherwise
//! (round-off apart). Nothing is stored per cell but one flag; the geometry is mapped again at
//! every product from the mesh's own points and connectivity, which the run holds anyway:
//! - **affine cells** (every P1 simplex; a P2 simplex whose edge nodes are their edges'
//!   midpoints to round-off, `64 ε (max |p| + h)`): one `J = [p_1 − p_0, …, p_d − p_0]`, and the
//!   P1 gradients at one point (exact: they are constant) or the P2 gradients at a rule exact
//!   for degree 2 (the products of the P2 gradients are of degree 2: 3 points in 2D, the
//!   symmetric 4-point rule in 3D, Keast, *Comput. Methods Appl. Mech. Engrg.* 55, 1986); a Q1
//!   parallelogram or parallelepiped (each vertex at `p_0 + J r_a` to the same round-off): J
//!   from the edges at vertex 0 and the assembler's 2^d Gauss points;
//! - **every other cell** (other Q1 cells, curved P2 cells): the assembler's own rule
//!   ([`crate::fem::element::reference_rule`]) with J mapped at each point, so the two integrate
//!   the same rational integrand at the same points.
//!
//! Cost per cell and point: Ĥ = Σ_b u_b ⊗ ∇_ξ φ_b (k d² multiply–adds), H and σ J⁻ᵀ (2 d³), the
//! force (k d²); P1 tetrahedra 1 point, tetra10 4 (affine), hexahedra 8 (J at each point, k d²
//! more, unless affine).
//!
//! **Layout and threads.** The free unknowns (in the body's frames: [`super::body::Frames`]) are
//! scattered onto full world vectors (0 where eliminated), the cells run in two fixed halves
//! (each into its own full output; rayon runs them on two threads where it has them), the
//! halves' outputs are added and rotated back, and the free entries gathered: each entry is the
//! same sum in the same order whatever the number of threads (bit for bit). Runs of four affine
//! cells are computed at once, one cell a lane ([`CellKernel::lanes`], compiled for AVX2 where
//! the CPU has it, without fused multiply–adds), each lane with the one-cell path's operations in
//! its order: the same bits on any CPU. Working memory: three full vectors (24 bytes per
//! unknown) and a byte a cell.

use super::body::Frames;
use super::dof_map::DofMap;
use super::stencil::SHARE_ULPS;
use crate::fem::cell::Reference;
use crate::fem::element::{MAX_VERTS, jacobian_inverse_transpose, reference_rule};
use crate::fem::{Cell, Mesh};
use crate::linalg::{Operator, largest_eigenvalue};
use crate::material::Lame;
use std::sync::{Arc, Mutex};

/// Points and ξ-gradients of one rule (reference weights: det J not included).
#[derive(Debug, Clone)]
struct Rule {
    weights: Vec<f64>,
    grads: Vec<[[f64; 3]; MAX_VERTS]>,
}

/// The P2 simplex rule exact for degree 2 (module docs): points ξ and weights (summing to 1/d!).
fn affine_p2_rule(d: usize) -> Rule {
    let points: Vec<[f64; 3]> = if d == 2 {
        let (a, b) = (2.0 / 3.0, 1.0 / 6.0);
        vec![[b, b, 0.0], [a, b, 0.0], [b, a, 0.0]]
    } else {
        // Barycentric (a, b, b, b) and its permutations, a = (5 + 3√5)/20, b = (5 − √5)/20.
        let s5 = 5f64.sqrt();
        let (a, b) = ((5.0 + 3.0 * s5) / 20.0, (5.0 - s5) / 20.0);
        vec![[b, b, b], [a, b, b], [b, a, b], [b, b, a]]
    };
    let w = if d == 2 { 1.0 / 6.0 } else { 1.0 / 24.0 };
    let weights = vec![w; points.len()];
    let grads = points.iter().map(|xi| crate::fem::element::p2_basis(d, xi).1).collect();
    Rule { weights, grads }
}

/// The stiffness of a mesh on its free unknowns, applied cell by cell (module docs).
#[derive(Debug)]
pub struct CellKernel {
    mesh: Arc<Mesh>,
    lame: Lame,
    /// The free unknowns' full indices `node·d + component`, increasing.
    dofs: Vec<u32>,
    /// The frames of the unknowns (None: the world's).
    frames: Option<Frames>,
    /// Per cell: whether its map is affine (module docs).
    affine: Vec<bool>,
    /// The rule of affine cells and the assembler's rule of the others.
    affine_rule: Rule,
    general_rule: Rule,
    /// Two halves' outputs and the scattered input, full world vectors.
    work: Mutex<[Vec<f64>; 3]>,
    /// Whether the CPU has AVX2 ([`Self::lanes`] is then compiled for it).
    avx2: bool,
    /// Whether runs of affine cells go through [`Self::lanes`] (always; the unit test compares
    /// with one cell at a time).
    lanes: bool,
}

impl CellKernel {
    /// The kernel of `mesh` (world coordinates) with material `lame` on the free unknowns of
    /// `dof_of` (full indices), in `frames` (None: the world's).
    pub fn new(mesh: Arc<Mesh>, lame: Lame, dof_of: &DofMap, frames: Option<Frames>) -> Self {
        let kind = mesh.kind;
        let d = mesh.dim;
        let dofs: Vec<u32> = (0..dof_of.len())
            .filter(|&g| dof_of.is_free(g))
            .map(|g| u32::try_from(g).expect("fewer than 2³² unknowns (DofMap)"))
            .collect();
        let general = reference_rule(kind);
        let general_rule = Rule { weights: general.0, grads: general.1 };
        let (affine_rule, affine) = match kind {
            Cell::Triangle | Cell::Tet => (general_rule.clone(), vec![true; mesh.n_cells()]),
            Cell::Triangle6 | Cell::Tet10 => {
                (affine_p2_rule(d), (0..mesh.n_cells()).map(|c| straight(&mesh, c)).collect())
            }
            Cell::Quad | Cell::Hex => (general_rule.clone(), (0..mesh.n_cells()).map(|c| parallel(&mesh, c)).collect()),
        };
        let full = mesh.n_nodes() * d;
        let work = Mutex::new([vec![0.0; full], vec![0.0; full], vec![0.0; full]]);
        #[cfg(target_arch = "x86_64")]
        let avx2 = std::arch::is_x86_feature_detected!("avx2");
        #[cfg(not(target_arch = "x86_64"))]
        let avx2 = false;
        CellKernel { mesh, lame, dofs, frames, affine, affine_rule, general_rule, work, avx2, lanes: true }
    }

    /// `ys = K xs` on full world vectors over the cells `cells`, with the cell kind's sizes.
    fn product<const D: usize, const K: usize>(&self, cells: std::ops::Range<usize>, xs: &[f64], ys: &mut [f64]) {
        let mesh = &*self.mesh;
        let (lambda, mu) = (self.lame.lambda, self.lame.mu);
        // The rules' ξ-gradients at the kind's sizes (once per product).
        let sized = |r: &Rule| -> Vec<(f64, [[f64; D]; K])> {
            let at = |g: &[[f64; 3]; MAX_VERTS]| std::array::from_fn(|a| std::array::from_fn(|l| g[a][l]));
            r.weights.iter().zip(&r.grads).map(|(&w, g)| (w, at(g))).collect()
        };
        let (affine_rule, general_rule) = (sized(&self.affine_rule), sized(&self.general_rule));
        let q1 = mesh.kind.data().reference == Reference::Q1Tensor;
        let mut c = cells.start;
        while c < cells.end {
            // LANES affine cells at once (each lane the scalar path's operations in its order:
            // the same bits), else one cell.
            if self.lanes && c + LANES <= cells.end && self.affine[c..c + LANES].iter().all(|&a| a) {
                #[cfg(target_arch = "x86_64")]
                if self.avx2 {
                    // SAFETY: the CPU has AVX2 (checked in `new`).
                    unsafe { self.lanes_avx2::<D, K>(c, xs, ys, &affine_rule, q1) };
                    c += LANES;
                    continue;
                }
                self.lanes::<D, K>(c, xs, ys, &affine_rule, q1);
                c += LANES;
                continue;
            }
            let v = &mesh.cells[c * K..(c + 1) * K];
            let mut u = [[0.0; D]; K];
            for (ua, &node) in u.iter_mut().zip(v) {
                ua.copy_from_slice(&xs[node * D..node * D + D]);
            }
            let mut f = [[0.0; D]; K];
            let p = |a: usize| &mesh.points[v[a]];
            if self.affine[c] {
                let (inv_t, det) = affine_map::<D>(mesh, v, q1);
                for (w, dphi) in &affine_rule {
                    point(&u, &mut f, (lambda, mu), w * det, &inv_t, dphi);
                }
            } else {
                for (w, dphi) in &general_rule {
                    let mut j = [[0.0; 3]; 3];
                    for (a, da) in dphi.iter().enumerate() {
                        for k in 0..D {
                            for l in 0..D {
                                j[k][l] += p(a)[k] * da[l];
                            }
                        }
                    }
                    let (inv_t, det) = jacobian_inverse_transpose(&j, D);
                    point(&u, &mut f, (lambda, mu), w * det.abs(), &inv_t, dphi);
                }
            }
            for (fa, &node) in f.iter().zip(v) {
                for (y, x) in ys[node * D..node * D + D].iter_mut().zip(fa) {
                    *y += x;
                }
            }
            c += 1;
        }
    }

    /// [`Self::lanes`] compiled for AVX2 (no fused multiply–adds: the same bits as without).
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn lanes_avx2<const D: usize, const K: usize>(
        &self,
        c0: usize,
        xs: &[f64],
        ys: &mut [f64],
        rule: &[(f64, [[f64; D]; K])],
        q1: bool,
    ) {
        self.lanes::<D, K>(c0, xs, ys, rule, q1)
    }

    /// The affine cells `c0 .. c0 + LANES` at once: [`point`]'s operations on each lane (its
    /// values, its order), vectorised across the lanes by the compiler; scattered in cell order.
    #[inline(always)]
    fn lanes<const D: usize, const K: usize>(
        &self,
        c0: usize,
        xs: &[f64],
        ys: &mut [f64],
        rule: &[(f64, [[f64; D]; K])],
        q1: bool,
    ) {
        let mesh = &*self.mesh;
        let cell = |s: usize| &mesh.cells[(c0 + s) * K..(c0 + s + 1) * K];
        let mut u = [[[0.0; LANES]; D]; K];
        let mut g = [[[0.0; LANES]; 3]; 3];
        let mut det = [0.0; LANES];
        for s in 0..LANES {
            let v = cell(s);
            for (a, &node) in v.iter().enumerate() {
                for j in 0..D {
                    u[a][j][s] = xs[node * D + j];
                }
            }
            let (inv_t, d) = affine_map::<D>(mesh, v, q1);
            for k in 0..3 {
                for l in 0..3 {
                    g[k][l][s] = inv_t[k][l];
                }
            }
            det[s] = d;
        }
        let mut f = [[[0.0; LANES]; D]; K];
        let (lambda, mu) = (self.lame.lambda, self.lame.mu);
        for (w, dphi) in rule {
            let mut hr = [[[0.0; LANES]; D]; D];
            for (ub, db) in u.iter().zip(dphi) {
                for j in 0..D {
                    for l in 0..D {
                        for s in 0..LANES {
                            hr[j][l][s] += ub[j][s] * db[l];
                        }
                    }
                }
            }
            let mut h = [[[0.0; LANES]; D]; D];
            for j in 0..D {
                for k in 0..D {
                    for l in 0..D {
                        for s in 0..LANES {
                            h[j][k][s] += hr[j][l][s] * g[k][l][s];
                        }
                    }
                }
            }
            let mut tr = [0.0; LANES];
            for hj in h.iter().enumerate().map(|(j, row)| &row[j]) {
                for s in 0..LANES {
                    tr[s] += hj[s];
                }
            }
            let mut sg = [[[0.0; LANES]; D]; D];
            for i in 0..D {
                for k in 0..D {
                    for s in 0..LANES {
                        let diagonal = if i == k { lambda * tr[s] } else { 0.0 };
                        sg[i][k][s] = w * det[s] * (mu * (h[i][k][s] + h[k][i][s]) + diagonal);
                    }
                }
            }
            let mut pr = [[[0.0; LANES]; D]; D];
            for i in 0..D {
                for l in 0..D {
                    for k in 0..D {
                        for s in 0..LANES {
                            pr[i][l][s] += sg[i][k][s] * g[k][l][s];
                        }
                    }
                }
            }
            for (fa, da) in f.iter_mut().zip(dphi) {
                for i in 0..D {
                    for l in 0..D {
                        for s in 0..LANES {
                            fa[i][s] += da[l] * pr[i][l][s];
                        }
                    }
                }
            }
        }
        for s in 0..LANES {
            for (a, &node) in cell(s).iter().enumerate() {
                for j in 0..D {
                    ys[node * D + j] += f[a][j][s];
                }
            }
        }
    }

    /// `ys = K xs` on full world vectors: the two halves (module docs), added into `ys`.
    fn full_product(&self, xs: &[f64], ys: &mut [f64], other: &mut [f64]) {
        let n_cells = self.mesh.n_cells();
        let half = n_cells / 2;
        let run = |cells: std::ops::Range<usize>, out: &mut [f64]| {
            out.fill(0.0);
            match self.mesh.kind {
                Cell::Triangle => self.product::<2, 3>(cells, xs, out),
                Cell::Quad => self.product::<2, 4>(cells, xs, out),
                Cell::Triangle6 => self.product::<2, 6>(cells, xs, out),
                Cell::Tet => self.product::<3, 4>(cells, xs, out),
                Cell::Hex => self.product::<3, 8>(cells, xs, out),
                Cell::Tet10 => self.product::<3, 10>(cells, xs, out),
            }
        };
        rayon::join(|| run(0..half, ys), || run(half..n_cells, other));
        ys.iter_mut().zip(other.iter()).for_each(|(y, o)| *y += o);
    }

    /// `xs` = the free values `x` on full world vectors (0 where eliminated).
    fn scatter(&self, x: &[f64], xs: &mut [f64]) {
        xs.fill(0.0);
        for (&g, &x) in self.dofs.iter().zip(x) {
            xs[g as usize] = x;
        }
        self.rotate(xs, false);
    }

    /// `y` = the free entries of `ys` (world) in the frames.
    fn gather(&self, ys: &mut [f64], y: &mut [f64]) {
        self.rotate(ys, true);
        for (&g, y) in self.dofs.iter().zip(y.iter_mut()) {
            *y = ys[g as usize];
        }
    }

    /// Each node's `x ← R x` (frame to world) or, `back`, `x ← Rᵀ x`.
    fn rotate(&self, xs: &mut [f64], back: bool) {
        let Some(frames) = &self.frames else { return };
        let d = self.mesh.dim;
        for (node, x) in xs.chunks_exact_mut(d).enumerate() {
            let r = frames.of(node);
            let old = [x[0], x[1], if d == 3 { x[2] } else { 0.0 }];
            for (i, xi) in x.iter_mut().enumerate() {
                *xi = (0..d).map(|k| if back { r[k][i] * old[k] } else { r[i][k] * old[k] }).sum();
            }
        }
    }

    /// `y = |K_c| x` summed over the cells (the entries' absolute values cell by cell, in the
    /// frames): entry by entry at least `|K| x` for x ≥ 0 (the triangle inequality), so that the
    /// Gershgorin bound it gives is a bound.
    fn abs_product(&self, x: &[f64], y: &mut [f64]) {
        let mesh = &*self.mesh;
        let d = mesh.dim;
        let k = mesh.kind.verts();
        let mut xs = vec![0.0; mesh.n_nodes() * d];
        for (&g, &x) in self.dofs.iter().zip(x) {
            xs[g as usize] = x;
        }
        let mut ys = vec![0.0; xs.len()];
        let mut kc = vec![0.0; k * d * k * d];
        for c in 0..mesh.n_cells() {
            let v = mesh.cell(c);
            self.cell_matrix(c, &mut kc);
            for (r, row) in kc.chunks_exact(k * d).enumerate() {
                for (col, s) in row.iter().enumerate() {
                    ys[v[r / d] * d + r % d] += s.abs() * xs[v[col / d] * d + col % d];
                }
            }
        }
        for (&g, y) in self.dofs.iter().zip(y.iter_mut()) {
            *y = ys[g as usize];
        }
    }

    /// Cell c's stiffness in the frames, `(R_aᵀ S_ab R_b)_ij` at row `a d + i`, column `b d + j`
    /// of `kc` (k d × k d, row-major), from the assembler's blocks.
    fn cell_matrix(&self, c: usize, kc: &mut [f64]) {
        let mesh = &*self.mesh;
        let (d, k) = (mesh.dim, mesh.kind.verts());
        let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let e = mesh.integrals(c);
        let v = mesh.cell(c);
        for a in 0..k {
            for b in 0..k {
                let s = super::columns::stiffness_block(&e, &self.lame, a, b, d);
                let (ra, rb) = match &self.frames {
                    Some(f) => (f.of(v[a]), f.of(v[b])),
                    None => (&identity, &identity),
                };
                for i in 0..d {
                    for j in 0..d {
                        let mut sum = 0.0;
                        for kk in 0..d {
                            for l in 0..d {
                                sum += ra[kk][i] * s[kk][l] * rb[l][j];
                            }
                        }
                        kc[(a * d + i) * k * d + b * d + j] = sum;
                    }
                }
            }
        }
    }

    /// The element eigenvalue bound ([`Operator::element_bound`]; the inequality as for the
    /// box's stencil, [`super::stencil::BoxStencil`]): with each unknown's lumped mass shared
    /// equally among the cells at its node (`D_c`, 0 where eliminated or massless),
    /// `λ_max(M_L,II⁻¹ K_II) ≤ max_c λ_max(A_c)`, `A_c = D_c^{−½} K_c D_c^{−½}` on the cell's
    /// unknowns with a positive share (Irons 1970; Hughes, *The Finite Element Method*, §9.3),
    /// `K_c` in the frames. Each share is rounded down to 31 bits of mantissa (a smaller mass
    /// only raises the bound). Cells are grouped by kind: the same rounded shares, and their
    /// points' differences from their first one (and their frames) the same to 31 bits. The
    /// first cell of a kind gets its eigenvalue from faer's symmetric solver (raised by
    /// `64 k d ε` relative for its error) and keeps `A_c`; every other cell of the kind is
    /// bounded by Weyl's inequality, `λ_max(A_c) ≤ λ_max(A_first) + ‖A_c − A_first‖_F` (its
    /// matrix made, not its eigenvalues: a structured mesh's cells differ from their kind's first
    /// at round-off). At most [`KINDS`] kinds are kept; a cell of another kind is solved alone.
    fn bound(&self, lumped: &[f64]) -> f64 {
        let mesh = &*self.mesh;
        let (d, k) = (mesh.dim, mesh.kind.verts());
        let kd = k * d;
        let mut mass = vec![0.0; mesh.n_nodes() * d];
        for (&g, &m) in self.dofs.iter().zip(lumped) {
            mass[g as usize] = m;
        }
        let mut cells_at = vec![0u32; mesh.n_nodes()];
        mesh.cells.iter().for_each(|&v| cells_at[v] += 1);
        let rounded = |x: f64| x.to_bits() & !SHARE_ULPS;
        // Per kind: the first cell's eigenvalue and its A_c (kd × kd, 0 outside the kept set).
        let mut kinds: std::collections::HashMap<Vec<u64>, (f64, Vec<f64>)> = std::collections::HashMap::new();
        let (mut kc, mut bound) = (vec![0.0; kd * kd], 0.0f64);
        let slack = 1.0 + 64.0 * kd as f64 * f64::EPSILON;
        for c in 0..mesh.n_cells() {
            let v = mesh.cell(c);
            let share = |i: usize| {
                let m = mass[v[i / d] * d + i % d] / f64::from(cells_at[v[i / d]]);
                f64::from_bits(rounded(m))
            };
            let p0 = mesh.points[v[0]];
            let mut key: Vec<u64> = (0..kd).map(|i| share(i).to_bits()).collect();
            key.extend(v[1..].iter().flat_map(|&a| (0..d).map(move |i| rounded(mesh.points[a][i] - p0[i]))));
            if let Some(f @ Frames::Nodes(_)) = &self.frames {
                key.extend(v.iter().flat_map(|&a| f.of(a).iter().flatten().map(|&x| rounded(x)).collect::<Vec<_>>()));
            }
            self.cell_matrix(c, &mut kc);
            let scale: Vec<f64> = (0..kd).map(|i| if share(i) > 0.0 { 1.0 / share(i).sqrt() } else { 0.0 }).collect();
            for (i, row) in kc.chunks_exact_mut(kd).enumerate() {
                for (j, x) in row.iter_mut().enumerate() {
                    *x *= scale[i] * scale[j];
                }
            }
            let lam = match kinds.get(&key) {
                Some((first, a)) => {
                    let gap: f64 = a.iter().zip(&kc).map(|(p, q)| (p - q) * (p - q)).sum::<f64>().sqrt();
                    first + gap * slack
                }
                None => {
                    let kept: Vec<usize> = (0..kd).filter(|&i| scale[i] > 0.0).collect();
                    let lam = largest_eigenvalue(kept.len(), |i, j| kc[kept[i] * kd + kept[j]]) * slack;
                    if kinds.len() < KINDS {
                        kinds.insert(key, (lam, kc.clone()));
                    }
                    lam
                }
            };
            bound = bound.max(lam);
        }
        bound * slack
    }
}

/// The cell kinds [`CellKernel::bound`] keeps (each a key of at most 147 numbers and a 30 × 30
/// matrix: 8.4 kB, at most 8.6 MB).
const KINDS: usize = 1024;

/// Cells computed at once by [`CellKernel::lanes`] (AVX-512 holds 8 values, AVX2 4).
const LANES: usize = 4;

/// `J⁻ᵀ` and |det J| of an affine cell with nodes `v` (J's columns from [`AXES`]; `q1`: a Q1
/// cell).
#[inline(always)]
fn affine_map<const D: usize>(mesh: &Mesh, v: &[usize], q1: bool) -> ([[f64; 3]; 3], f64) {
    let axes = AXES[usize::from(q1)];
    let p = |a: usize| &mesh.points[v[a]];
    let mut j = [[0.0; 3]; 3];
    for (k, row) in j.iter_mut().enumerate().take(D) {
        for (l, x) in row.iter_mut().enumerate().take(D) {
            *x = p(axes[l])[k] - p(0)[k];
        }
    }
    let (inv_t, det) = jacobian_inverse_transpose(&j, D);
    (inv_t, det.abs())
}

/// One quadrature point of a cell (weight w, `g = J⁻ᵀ`, the ξ-gradients `dphi`): the reference
/// gradient `Ĥ = Σ_b u_b ⊗ ∇_ξ φ_b`, `H = Ĥ J⁻¹` (`H_jk = Σ_l Ĥ_jl g_kl`), σ, and
/// `f_a += w ∇_ξ φ_a · (σ g)` (the physical gradient is `g ∇_ξ φ_a`).
#[inline(always)]
fn point<const D: usize, const K: usize>(
    u: &[[f64; D]; K],
    f: &mut [[f64; D]; K],
    (lambda, mu): (f64, f64),
    w: f64,
    g: &[[f64; 3]; 3],
    dphi: &[[f64; D]; K],
) {
    let mut hr = [[0.0; D]; D];
    for (ub, db) in u.iter().zip(dphi) {
        for j in 0..D {
            for l in 0..D {
                hr[j][l] += ub[j] * db[l];
            }
        }
    }
    let mut h = [[0.0; D]; D];
    for j in 0..D {
        for k in 0..D {
            h[j][k] = (0..D).map(|l| hr[j][l] * g[k][l]).sum();
        }
    }
    let tr: f64 = (0..D).map(|j| h[j][j]).sum();
    let mut s = [[0.0; D]; D];
    for i in 0..D {
        for k in 0..D {
            s[i][k] = w * (mu * (h[i][k] + h[k][i]) + if i == k { lambda * tr } else { 0.0 });
        }
    }
    let mut pr = [[0.0; D]; D];
    for i in 0..D {
        for l in 0..D {
            pr[i][l] = (0..D).map(|k| s[i][k] * g[k][l]).sum();
        }
    }
    for (fa, da) in f.iter_mut().zip(dphi) {
        for i in 0..D {
            for l in 0..D {
                fa[i] += da[l] * pr[i][l];
            }
        }
    }
}

/// The vertices whose differences from vertex 0 are an affine cell's J columns: a simplex's
/// 1, 2, 3; a Q1 cell's neighbours of vertex 0 along ξ_1, ξ_2, ξ_3 (VTK order).
const AXES: [[usize; 3]; 2] = [[1, 2, 3], [1, 3, 4]];

/// `64 ε (max |p| + h)` over the points `p` of a cell (module docs), h its largest distance
/// from its first point.
fn tolerance(p: &[[f64; 3]]) -> f64 {
    let norm = |x: [f64; 3]| x.iter().map(|x| x * x).sum::<f64>().sqrt();
    let size = p.iter().map(|&q| norm(q)).fold(0.0, f64::max);
    let h = p.iter().map(|q| norm(std::array::from_fn(|k| q[k] - p[0][k]))).fold(0.0, f64::max);
    64.0 * f64::EPSILON * (size + h)
}

/// Whether Q1 cell c is a parallelogram or parallelepiped: each vertex a at
/// `p_0 + J r_a` within [`tolerance`], J's columns from [`AXES`] (its map then affine, J
/// constant).
fn parallel(mesh: &Mesh, c: usize) -> bool {
    let (d, v) = (mesh.dim, mesh.cell(c));
    let p: Vec<[f64; 3]> = v.iter().map(|&a| mesh.points[a]).collect();
    let tol = tolerance(&p);
    let axes = AXES[1];
    // Corner r_a in VTK order: (0,0,0), (1,0,0), (1,1,0), (0,1,0), then the same at ζ = 1.
    let corner = |a: usize| {
        [f64::from(u8::from(a % 4 == 1 || a % 4 == 2)), f64::from(u8::from(a % 4 >= 2)), f64::from(u8::from(a >= 4))]
    };
    (0..v.len()).all(|a| {
        let r = corner(a);
        let at: [f64; 3] =
            std::array::from_fn(|k| p[0][k] + (0..d).map(|l| (p[axes[l]][k] - p[0][k]) * r[l]).sum::<f64>());
        (0..3).map(|k| (p[a][k] - at[k]).powi(2)).sum::<f64>().sqrt() <= tol
    })
}

/// Whether P2 cell c is straight: each edge node at its edge's midpoint within
/// `64 ε (max |p| + h)` (module docs), h the cell's longest edge.
fn straight(mesh: &Mesh, c: usize) -> bool {
    let (d, v) = (mesh.dim, mesh.cell(c));
    let edges: &[[usize; 2]] =
        if d == 2 { &[[0, 1], [1, 2], [2, 0]] } else { &[[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]] };
    let p = |a: usize| mesh.points[v[a]];
    let norm = |x: [f64; 3]| x.iter().map(|x| x * x).sum::<f64>().sqrt();
    let scale = (0..=d).map(|a| norm(p(a))).fold(0.0, f64::max)
        + edges.iter().map(|&[a, b]| norm(std::array::from_fn(|k| p(a)[k] - p(b)[k]))).fold(0.0, f64::max);
    let tol = 64.0 * f64::EPSILON * scale;
    edges.iter().enumerate().all(|(e, &[a, b])| {
        let mid: [f64; 3] = std::array::from_fn(|k| 0.5 * (p(a)[k] + p(b)[k]));
        norm(std::array::from_fn(|k| p(d + 1 + e)[k] - mid[k])) <= tol
    })
}

impl Operator for CellKernel {
    fn n(&self) -> usize {
        self.dofs.len()
    }

    fn apply(&self, x: &[f64], y: &mut [f64]) {
        let mut work = self.work.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let [xs, ys, other] = &mut *work;
        self.scatter(x, xs);
        self.full_product(xs, ys, other);
        self.gather(ys, y);
    }

    fn quad_form(&self, x: &[f64]) -> f64 {
        let mut y = vec![0.0; x.len()];
        self.apply(x, &mut y);
        x.iter().zip(&y).map(|(a, b)| a * b).sum()
    }

    fn apply_abs(&self, x: &[f64], y: &mut [f64]) {
        self.abs_product(x, y);
    }

    fn streamed_bytes(&self) -> usize {
        // x read and y written (n each); the three full vectors: scatter writes xs, the cells
        // read it and write both halves, the sum reads two and writes one, the gather reads one;
        // the connectivity (8 bytes an index), the points (24 bytes a node), the flags and the
        // free indices (4 bytes) read once.
        let mesh = &*self.mesh;
        let full = mesh.n_nodes() * mesh.dim;
        8 * (2 * self.dofs.len() + 7 * full)
            + 8 * mesh.cells.len()
            + 24 * mesh.n_nodes()
            + self.affine.len()
            + 4 * self.dofs.len()
    }

    fn name(&self) -> &'static str {
        "the cell-by-cell kernel"
    }

    fn is_matrix_free(&self) -> bool {
        true
    }

    fn element_bound(&self, lumped: &[f64]) -> Option<f64> {
        Some(self.bound(lumped))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lanes (compiled for AVX2 or not) give the bits of one cell at a time: each lane does
    /// the scalar path's operations in its order, without fused multiply–adds (a zero's sign
    /// aside, which `==` does not see). A straight tetra10 mesh (every cell affine) and a sheared
    /// hexahedral one. (Mutation, as run: the lanes' σ as `w (det (…))` instead of `(w det) (…)`
    /// -> differs in the last bit, fails.)
    #[test]
    fn the_lanes_give_the_bits_of_one_cell_at_a_time() {
        let tet10 = Mesh::structured_3d([1.0, 0.7, 0.5], [3, 2, 2], Cell::Tet).unwrap().quadratic().unwrap();
        let mut hex = Mesh::structured_3d([1.0, 0.7, 0.5], [3, 2, 2], Cell::Hex).unwrap();
        for p in hex.points.iter_mut() {
            *p = [p[0], p[1] + 0.3 * p[0], p[2] + 0.2 * p[1]];
        }
        for mesh in [tet10, hex] {
            let n = mesh.n_nodes() * 3;
            let dof_of = DofMap::identity(n);
            let lame = Lame { lambda: 0.7, mu: 0.45, density: 1.0 };
            let mut op = CellKernel::new(Arc::new(mesh), lame, &dof_of, None);
            assert!(op.affine.iter().all(|&a| a));
            let x: Vec<f64> = (0..n).map(|i| ((i as f64 + 1.0) * 0.618_033_988_749_895).fract() - 0.5).collect();
            let mut products = Vec::new();
            for (lanes, avx2) in [(true, op.avx2), (true, false), (false, false)] {
                (op.lanes, op.avx2) = (lanes, avx2);
                let mut y = vec![0.0; n];
                op.apply(&x, &mut y);
                products.push(y);
            }
            assert!(products[0] == products[2] && products[1] == products[2]);
        }
    }
}
