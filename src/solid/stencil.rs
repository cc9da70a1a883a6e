//! The stiffness of a structured Q1 box applied without a matrix (issue 31, item 2).
//!
//! Every cell of the box generator's Q1 mesh ([`crate::fem::Mesh::structured_2d`],
//! [`crate::fem::Mesh::structured_3d`]) is the same rectangle or brick `h = (L/nx, H/ny[, D/nz])`
//! of one material, so every cell has the same element matrix K_e ([`super::columns::stiffness_entry`]
//! on the reference cell `[0, h]`). Summed over the cells around a node, it gives the node's
//! **stencil**: `(K u)_(p, r) = Σ_{o ∈ {−1,0,1}^d} Σ_s S_p(o)_{rs} u_(p+o, s)` with
//! `S_p(o)_{rs} = Σ_{cells c ∋ p, p+o} K_e[(p, r), (p+o, s)]`. S_p depends only on which cells
//! exist around p, that is on whether p lies on the low face, inside or on the high face of
//! each axis: 3^d node classes, each with its list of nonzero terms (153 of 243 in 3D inside:
//! a coupling r ≠ s vanishes for an offset with o_r = 0 or o_s = 0, and such exact
//! cancellations, below 64 ε of the class's largest coefficient, are dropped). Nothing is stored
//! per cell or per node beyond the vectors.
//!
//! **Layout.** The product runs on full node vectors in slabs along the last axis (z in 3D, y
//! in 2D): slab t holds its d components one after the other, `x[(t d + s) P + q]` (P nodes a
//! slab, q = j (nx+1) + i). Inside a slab every term is a shifted copy of a row: the inside
//! nodes of a row share one class and are summed in registers, 32 values at a time ([`interior`];
//! with AVX2 fused multiply–adds where the CPU has them: one rounding per term instead of two, so
//! a machine without them gives other bits at round-off, the same bits run after run); the two
//! ends of each row take their class's terms one by one. The free unknowns (the box's `dofs`: node-major, the
//! clamped face and roller components removed) are scattered into this layout before the
//! product (0 where eliminated) and gathered from it after, slab by slab in parallel (the free
//! unknowns of a slab are contiguous); the slabs of the product run on rayon's threads and each
//! entry is computed in the same order whatever the number of threads (bit for bit).
//!
//! **Against the assembled matrix**: the same operator in exact arithmetic (the assembled entry
//! is the same sum over the same cells, in another order and with each cell's own coordinates),
//! so the two products agree to round-off (`tests/stencil.rs`: within 128 ε of `(|K| |x|)_i`
//! entry by entry on random vectors, trajectories without contact to 1e-12 over 1000 steps).

use crate::fem::element::{CellIntegrals, MAX_VERTS};
use crate::fem::{Cell, Mesh};
use crate::linalg::Operator;
use crate::material::Lame;
use rayon::prelude::*;
use std::sync::Mutex;

/// A stencil's terms for one output component r: `y_(p, r) += c x[p + x_off]`, the offset o
/// and the input component s folded into `x_off` (relative to p's position in the slab layout).
type Terms = Vec<(isize, f64)>;

/// The matrix-free stiffness of a structured Q1 box on its free unknowns (module docs).
#[derive(Debug)]
pub struct BoxStencil {
    d: usize,
    /// Cells per axis `[nx, ny, nz]` (nz = 0 in 2D).
    cells: [usize; 3],
    /// Nodes per slab.
    slab: usize,
    slabs: usize,
    /// The terms of each node class `Σ_axis a_axis 3^axis` (a = 0 low face, 1 inside, 2 high),
    /// by output component r, in the order (o, s).
    classes: Vec<Vec<Terms>>,
    /// The same with each coefficient's absolute value (`|K| x`: the Gershgorin bound).
    abs_classes: Vec<Vec<Terms>>,
    /// Whether the CPU has AVX2 and FMA (the interior then takes fused multiply–adds).
    fma: bool,
    /// The reference cell's vertices and its element matrix `K[(a, r), (b, s)]`, row-major
    /// (k d × k d, k vertices): the element eigenvalue bound ([`Operator::element_bound`]).
    corners: &'static [[usize; 3]],
    element: Vec<f64>,
    /// Whether each full index `node·d + component` is a free unknown.
    free: Vec<bool>,
    /// The first free unknown of each slab (slabs + 1 entries).
    slab_start: Vec<usize>,
    n: usize,
    /// The slab-layout input and output (the scheme's product and its energy share them).
    work: Mutex<(Vec<f64>, Vec<f64>)>,
}

/// The corners of the generator's quadrilateral and hexahedron, in their local vertex order.
const QUAD: [[usize; 3]; 4] = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]];
const HEX: [[usize; 3]; 8] = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]];

impl BoxStencil {
    /// The stencil of `mesh` (a structured quadrilateral or hexahedral mesh of the box
    /// generator; None for any other mesh) with material `lame`, on the free unknowns `free`
    /// (one flag per full index `node·d + component`).
    pub fn new(mesh: &Mesh, lame: &Lame, free: Vec<bool>) -> Option<Self> {
        Self::with_entry(mesh, free, |e, a, b, r, s| super::columns::stiffness_entry(e, lame, a, b, r, s))
    }

    /// The unweighted vector mass with ρ = 1 of the same box (`δ_rs ∫ φ_a φ_b`), for the L²
    /// norms of a run that assembles no mass matrix ([`super::SolidSystem::unit_quad_form`]).
    pub fn unit_mass(mesh: &Mesh, free: Vec<bool>) -> Option<Self> {
        Self::with_entry(mesh, free, |e, a, b, r, s| if r == s { e.mass[a][b] } else { 0.0 })
    }

    /// The stencil of the element matrix `entry(e, a, b, r, s)` = entry ((a, r), (b, s)) on
    /// the reference cell's integrals `e`.
    fn with_entry(
        mesh: &Mesh,
        free: Vec<bool>,
        entry: impl Fn(&CellIntegrals, usize, usize, usize, usize) -> f64,
    ) -> Option<Self> {
        let grid = mesh.grid?;
        let corners: &[[usize; 3]] = match mesh.kind {
            Cell::Quad => &QUAD,
            Cell::Hex => &HEX,
            _ => return None,
        };
        let d = mesh.dim;
        assert_eq!(free.len(), mesh.n_nodes() * d, "one flag per full index");
        let cells = grid;
        let nodes: [usize; 3] = std::array::from_fn(|k| if k < d { cells[k] + 1 } else { 1 });
        let slabs = nodes[d - 1];
        let slab = mesh.n_nodes() / slabs;
        // The reference cell [0, h] and its element matrix K[(a, r), (b, s)].
        let h: [f64; 3] = std::array::from_fn(|k| if k < d { mesh.extent[k] / cells[k] as f64 } else { 0.0 });
        let mut p = [[0.0; 3]; MAX_VERTS];
        for (v, c) in corners.iter().enumerate() {
            p[v] = std::array::from_fn(|k| c[k] as f64 * h[k]);
        }
        let e = CellIntegrals::new(mesh.kind, &p);
        let kd = corners.len() * d;
        let element: Vec<f64> = (0..kd * kd)
            .map(|ij| {
                let ((a, r), (b, s)) = ((ij / kd / d, ij / kd % d), (ij % kd / d, ij % kd % d));
                entry(&e, a, b, r, s)
            })
            .collect();
        // Node strides in the slab layout: along the slab's axes 1 and nx+1, across slabs d·P.
        let stride: [isize; 3] = match d {
            2 => [1, (d * slab) as isize, 0],
            _ => [1, nodes[0] as isize, (d * slab) as isize],
        };
        let classes: Vec<Vec<Terms>> = (0..3usize.pow(d as u32))
            .map(|class| {
                let side: [usize; 3] =
                    std::array::from_fn(|k| if k < d { class / 3usize.pow(k as u32) % 3 } else { 1 });
                // Coefficient (o, r, s), o ∈ {−1,0,1}^d as o + 1 in base 3.
                let mut coef = vec![0.0; 3usize.pow(d as u32) * d * d];
                // The cells around the node: corner offset e_k ∈ {−1, 0}, e_k = −1 absent on a
                // low face, 0 absent on a high face.
                for cell in 0..1usize << d {
                    let off: [isize; 3] = std::array::from_fn(|k| if k < d { -((cell >> k & 1) as isize) } else { 0 });
                    if (0..d).any(|k| (off[k] == -1 && side[k] == 0) || (off[k] == 0 && side[k] == 2)) {
                        continue;
                    }
                    let local = |corner: [isize; 3]| {
                        corners.iter().position(|c| (0..d).all(|k| c[k] as isize == corner[k])).expect("a corner")
                    };
                    let a = local(std::array::from_fn(|k| -off[k]));
                    for (b, c) in corners.iter().enumerate() {
                        let o: usize =
                            (0..d).map(|k| ((off[k] + c[k] as isize + 1) as usize) * 3usize.pow(k as u32)).sum();
                        for r in 0..d {
                            for s in 0..d {
                                coef[(o * d + r) * d + s] += entry(&e, a, b, r, s);
                            }
                        }
                    }
                }
                let largest = coef.iter().fold(0.0f64, |m, c| m.max(c.abs()));
                let mut terms = vec![Vec::new(); d];
                for o in 0..3usize.pow(d as u32) {
                    let shift: isize = (0..d).map(|k| ((o / 3usize.pow(k as u32) % 3) as isize - 1) * stride[k]).sum();
                    for r in 0..d {
                        for s in 0..d {
                            let c = coef[(o * d + r) * d + s];
                            // Exact cancellations (module docs) left at round-off.
                            if c.abs() > 64.0 * f64::EPSILON * largest {
                                terms[r].push((shift + (s * slab) as isize, c));
                            }
                        }
                    }
                }
                terms
            })
            .collect();
        let mut slab_start = Vec::with_capacity(slabs + 1);
        slab_start.push(0);
        for t in 0..slabs {
            let count = free[t * slab * d..(t + 1) * slab * d].iter().filter(|&&f| f).count();
            slab_start.push(slab_start[t] + count);
        }
        let n = slab_start[slabs];
        let full = mesh.n_nodes() * d;
        #[cfg(target_arch = "x86_64")]
        let fma = std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma");
        #[cfg(not(target_arch = "x86_64"))]
        let fma = false;
        let abs_classes = classes
            .iter()
            .map(|by_r| by_r.iter().map(|t| t.iter().map(|&(o, c)| (o, c.abs())).collect()).collect())
            .collect();
        Some(Self {
            d,
            cells,
            slab,
            slabs,
            classes,
            abs_classes,
            fma,
            corners,
            element,
            free,
            slab_start,
            n,
            work: Mutex::new((vec![0.0; full], vec![0.0; full])),
        })
    }

    /// The node class of (i, j[, k]) (module docs).
    fn class(&self, idx: [usize; 3]) -> usize {
        (0..self.d)
            .map(|k| {
                let side = if idx[k] == 0 {
                    0
                } else if idx[k] == self.cells[k] {
                    2
                } else {
                    1
                };
                side * 3usize.pow(k as u32)
            })
            .sum()
    }

    /// `xs` (slab layout) from the free unknowns `x`, 0 where eliminated.
    fn scatter(&self, x: &[f64], xs: &mut [f64]) {
        let (d, p) = (self.d, self.slab);
        xs.par_chunks_mut(d * p).enumerate().for_each(|(t, xt)| {
            let mut i = self.slab_start[t];
            let free = &self.free[t * p * d..(t + 1) * p * d];
            for q in 0..p {
                for s in 0..d {
                    xt[s * p + q] = if free[q * d + s] {
                        i += 1;
                        x[i - 1]
                    } else {
                        0.0
                    };
                }
            }
        });
    }

    /// The free unknowns `y` from `ys` (slab layout).
    fn gather(&self, ys: &[f64], y: &mut [f64]) {
        let (d, p) = (self.d, self.slab);
        // The free unknowns of slab t are y[slab_start[t]..slab_start[t + 1]].
        let mut chunks = Vec::with_capacity(self.slabs);
        let mut rest = y;
        for t in 0..self.slabs {
            let (head, tail) = rest.split_at_mut(self.slab_start[t + 1] - self.slab_start[t]);
            chunks.push(head);
            rest = tail;
        }
        chunks.into_par_iter().enumerate().for_each(|(t, yt)| {
            let (free, yst) = (&self.free[t * p * d..(t + 1) * p * d], &ys[t * p * d..(t + 1) * p * d]);
            let mut i = 0;
            for q in 0..p {
                for s in 0..d {
                    if free[q * d + s] {
                        yt[i] = yst[s * p + q];
                        i += 1;
                    }
                }
            }
        });
    }

    /// `ys = K xs` on full vectors in the slab layout, K given by the terms of its classes
    /// (`self.classes`, or `self.abs_classes` for |K|).
    fn product(&self, classes: &[Vec<Terms>], xs: &[f64], ys: &mut [f64]) {
        let (d, p) = (self.d, self.slab);
        let row = self.cells[0] + 1;
        let rows = p / row;
        ys.par_chunks_mut(d * p).enumerate().for_each(|(t, yt)| {
            let base = (t * d * p) as isize;
            for j in 0..rows {
                let idx = |i: usize| if d == 2 { [i, t, 0] } else { [i, j, t] };
                let q0 = j * row;
                // The row's two ends, value by value.
                for i in [0, row - 1] {
                    let q = q0 + i;
                    for (r, terms) in classes[self.class(idx(i))].iter().enumerate() {
                        let at = base as usize + q;
                        yt[r * p + q] = terms.iter().fold(0.0, |y, &(off, c)| y + c * xs[(at as isize + off) as usize]);
                    }
                }
                // Its inside nodes share one class: summed in registers ([`interior`]).
                let (lo, hi, terms) = (q0 + 1, q0 + row - 1, &classes[self.class(idx(1))]);
                #[cfg(target_arch = "x86_64")]
                if self.fma {
                    // SAFETY: `fma` is set only where the CPU has AVX2 and FMA (`Self::new`).
                    unsafe { interior_fma(terms, xs, yt, base, lo, hi, p) };
                    continue;
                }
                interior::<false>(terms, xs, yt, base, lo, hi, p);
            }
        });
    }
}

/// `y_r[i] = Σ_terms c x[base + off + i]` for i in lo..hi and each component r (`inner[r]`: a
/// class's terms of r, in their order), W values at a time in registers (32: eight AVX2
/// accumulators, enough independent chains to hide the latency of a fused multiply–add; rows
/// shorter than 32 by 8, shorter than 8 one by one), each sum in the terms' order from 0: the
/// same sums whatever the blocking. With
/// `FMA`, each step is a fused multiply–add (one rounding instead of two).
#[inline(always)]
fn interior<const FMA: bool>(
    inner: &[Terms],
    xs: &[f64],
    yt: &mut [f64],
    base: isize,
    lo: usize,
    hi: usize,
    slab: usize,
) {
    for (r, terms) in inner.iter().enumerate() {
        let y = &mut yt[r * slab..(r + 1) * slab];
        let _ = blocks::<32, FMA>(terms, xs, y, base, lo, hi)
            || blocks::<8, FMA>(terms, xs, y, base, lo, hi)
            || blocks::<1, FMA>(terms, xs, y, base, lo, hi);
    }
}

/// The values lo..hi in blocks of W, the last block moved back to end at hi (it recomputes a
/// few values, to the same bits: a latency-bound scalar tail would cost more than the blocks);
/// false, computing nothing, if there are fewer than W values.
#[inline(always)]
fn blocks<const W: usize, const FMA: bool>(
    terms: &[(isize, f64)],
    xs: &[f64],
    y: &mut [f64],
    base: isize,
    lo: usize,
    hi: usize,
) -> bool {
    if hi < lo + W {
        return false;
    }
    let mut i = lo;
    loop {
        let at = i.min(hi - W);
        let mut acc = [0.0; W];
        for &(off, c) in terms {
            let s = (base + off + at as isize) as usize;
            let x: &[f64; W] = xs[s..s + W].try_into().expect("W values");
            for k in 0..W {
                acc[k] = if FMA { c.mul_add(x[k], acc[k]) } else { acc[k] + c * x[k] };
            }
        }
        y[at..at + W].copy_from_slice(&acc);
        if at + W == hi {
            return true;
        }
        i += W;
    }
}

/// [`interior`] compiled for AVX2 with fused multiply–adds.
///
/// # Safety
/// The CPU must have AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn interior_fma(inner: &[Terms], xs: &[f64], yt: &mut [f64], base: isize, lo: usize, hi: usize, slab: usize) {
    interior::<true>(inner, xs, yt, base, lo, hi, slab)
}

impl Operator for BoxStencil {
    fn n(&self) -> usize {
        self.n
    }

    fn apply(&self, x: &[f64], y: &mut [f64]) {
        let mut work = self.work.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let (xs, ys) = &mut *work;
        self.scatter(x, xs);
        self.product(&self.classes, xs, ys);
        self.gather(ys, y);
    }

    fn apply_abs(&self, x: &[f64], y: &mut [f64]) {
        let mut work = self.work.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let (xs, ys) = &mut *work;
        self.scatter(x, xs);
        self.product(&self.abs_classes, xs, ys);
        self.gather(ys, y);
    }

    fn quad_form(&self, x: &[f64]) -> f64 {
        let mut work = self.work.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let (xs, ys) = &mut *work;
        self.scatter(x, xs);
        self.product(&self.classes, xs, ys);
        // The eliminated entries of xs are 0: the full dot product is the free one.
        xs.iter().zip(ys.iter()).map(|(a, b)| a * b).sum()
    }

    fn streamed_bytes(&self) -> usize {
        // scatter: reads x, writes xs; product: reads xs once (neighbouring rows from cache),
        // writes ys; gather: reads ys, writes y; the flags read twice.
        let full = self.free.len();
        8 * (2 * self.n + 4 * full) + 2 * full
    }

    fn name(&self) -> &'static str {
        "the structured Q1 stencil"
    }

    fn is_matrix_free(&self) -> bool {
        true
    }

    /// The element eigenvalue bound: with the lumped mass split into cell parts,
    /// `M_L,II = Σ_c D_c` (`D_c ≥ 0` diagonal, positive on the cell's unknowns in I), every x on
    /// I has `xᵀK x = Σ_c x_cᵀK_c x_c ≤ Σ_c λ_c x_cᵀD_c x_c ≤ (max_c λ_c) xᵀM_L x`, so
    /// `λ_max(M_L,II⁻¹ K_II) ≤ max_c λ_max(D_c⁻¹ K_c)` on each cell's unknowns in I (Irons,
    /// Int. J. Numer. Meth. Eng. 2, 1970; Hughes, *The Finite Element Method*, §9.3). Any such
    /// split gives a bound; here each node's mass is shared equally among its cells (for the
    /// standard mass, each cell's own lumped mass; a split in proportion to the cells' row sums
    /// on I was tried and gave looser bounds on every box of `tests/stencil.rs`). Cells are
    /// grouped by their `D_c` (rounded down to 31 bits of mantissa): a box has a few dozen
    /// kinds (faces, edges, corners, the cells beside a massless layer), each computed once by
    /// faer's symmetric eigenvalue solver and raised by `64 k d ε` relative (its error). Uses the
    /// operator's work space.
    fn element_bound(&self, lumped: &[f64]) -> Option<f64> {
        let (d, kd) = (self.d, self.corners.len() * self.d);
        let mut work = self.work.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let (mass, _) = &mut *work;
        self.scatter(lumped, mass);
        let count: [usize; 3] = std::array::from_fn(|k| if k < d { self.cells[k] } else { 1 });
        let mut kinds: std::collections::HashMap<[u64; 24], f64> = std::collections::HashMap::new();
        let mut bound = 0.0f64;
        for c in 0..count[0] * count[1] * count[2] {
            let (dofs, sharing) = self.cell_dofs(c, count);
            // 0 (left out) where eliminated or massless. Each share rounded down to 31 bits of
            // mantissa (a smaller mass only raises the bound; 2^-31 relative at most): the masses
            // of equal nodes differ at round-off (each cell integrated on its own coordinates),
            // and their kinds would otherwise be as many as the cells.
            let key: [u64; 24] =
                std::array::from_fn(|i| if i < kd { (mass[dofs[i]] / sharing[i]).to_bits() & !SHARE_ULPS } else { 0 });
            let lam = *kinds.entry(key).or_insert_with(|| self.element_eigenvalue(&key[..kd]));
            bound = bound.max(lam);
        }
        Some(bound * (1.0 + 64.0 * kd as f64 * f64::EPSILON))
    }
}

/// The low mantissa bits cleared from a cell's mass shares before they are grouped (a positive
/// value's bits rounded toward zero, 2⁻³¹ relative: [`BoxStencil::element_bound`], and the
/// kernel's [`super::kernel::CellKernel`] with its kinds' keys).
pub(super) const SHARE_ULPS: u64 = (1 << 21) - 1;

impl BoxStencil {
    /// The slab-layout positions of cell c's unknowns `(a, r)` at `a d + r` (cells counted x
    /// fastest; `count` cells per axis, 1 past the dimension), and the number of cells that
    /// share each one's node.
    fn cell_dofs(&self, c: usize, count: [usize; 3]) -> ([usize; 24], [f64; 24]) {
        let (d, p) = (self.d, self.slab);
        let cell = [c % count[0], c / count[0] % count[1], c / count[0] / count[1]];
        let (mut dofs, mut sharing) = ([0usize; 24], [1.0; 24]);
        for (a, corner) in self.corners.iter().enumerate() {
            let node: [usize; 3] = std::array::from_fn(|k| if k < d { cell[k] + corner[k] } else { 0 });
            let (t, q) = if d == 2 { (node[1], node[0]) } else { (node[2], node[1] * (self.cells[0] + 1) + node[0]) };
            let cells: f64 = (0..d).map(|k| if node[k] == 0 || node[k] == self.cells[k] { 1.0 } else { 2.0 }).product();
            for r in 0..d {
                (dofs[a * d + r], sharing[a * d + r]) = ((t * d + r) * p + q, cells);
            }
        }
        (dofs, sharing)
    }

    /// `λ_max(D⁻¹ K_e)` on the unknowns with a positive mass share (`shares`: the bits of
    /// `D`'s diagonal, 0 left out), as the largest eigenvalue of `D^{−½} K_e D^{−½}`.
    fn element_eigenvalue(&self, shares: &[u64]) -> f64 {
        let kd = shares.len();
        let kept: Vec<usize> = (0..kd).filter(|&i| f64::from_bits(shares[i]) > 0.0).collect();
        if kept.is_empty() {
            return 0.0;
        }
        let scale: Vec<f64> = kept.iter().map(|&i| 1.0 / f64::from_bits(shares[i]).sqrt()).collect();
        crate::linalg::largest_eigenvalue(kept.len(), |i, j| scale[i] * self.element[kept[i] * kd + kept[j]] * scale[j])
    }
}

impl BoxStencil {
    /// Whether a scene's solid gets a stencil: the box generator's quadrilaterals or hexahedra
    /// against the plane x = −gap ([`super::Support::Face`]: its unknowns in the world frame).
    pub fn applies(spec: &super::SolidSpec) -> bool {
        matches!(spec.support, super::Support::Face { .. })
            && spec.source == super::MeshSource::Box
            && matches!(spec.cells, Cell::Quad | Cell::Hex)
    }

    /// The stencil of an assembled solid's stiffness, on its free unknowns: None unless it is
    /// such a box ([`Self::applies`]).
    pub fn of_system(system: &super::SolidSystem) -> Option<Self> {
        if system.frame.is_some() || system.bodies.is_some() {
            return None;
        }
        Self::new(&system.mesh, &system.lame, system.dof_of.flags())
    }
}
