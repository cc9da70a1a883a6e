//! The fine-mesh reference of the elastic Table 1's free-face rows (issue 22, item 2).
//!
//! With λ > 0 and free lateral faces the plane wave is not the solution (the Poisson effect makes
//! the motion two-dimensional), so those rows of [`super::elastic_table`] are measured against a
//! computed solution instead: the same problem on [`REFERENCE_CELLS`]² Q1 cells of (0, 1)²
//! (nested [`REFERENCE_CELLS`]/20 times in the table's 20² mesh), Crank–Nicolson with the uniform
//! redistribution mod2, Δt = h/5. Its own error is estimated by the same run on half as many cells
//! per side (Δt = h/5 there too): [`Reference::self_difference`] is
//! `max_{t_k ≤ T} ‖u_{n/2}(t_k) − u_n(t_k)‖_{L²}` over the snapshot times.
//!
//! **The error of a coarse run** against it is `‖u_H(t) − u_ref(t)‖_{L²((0,1)²)²}`, exact up to
//! round-off: both fields are finite-element functions on one nested mesh family, so the square
//! is `‖u_H‖² − 2 (u_H, u_ref) + ‖u_ref‖²`, three exact integrals ([`Nested`]). For a Q1 coarse
//! mesh u_H lies in the fine Q1 space (its prolongation is nested interpolation, exact); for P1
//! triangles it does not (the coarse diagonal cuts the fine squares it crosses), and it is
//! integrated as it is, piecewise linear, on the two halves of those squares. The reference is
//! kept at the snapshot times t_k = k·[`SNAPSHOT_DT`] (a multiple of every table Δt) as the
//! products `(φ_A, u_ref)` with the coarse basis and `‖u_ref‖²`: 2·21² + 1 numbers per time and
//! cell kind instead of the fine field.

use super::elastic_setup::{ElasticError, Material, spec_on};
use massredist::fem::Cell;
use massredist::mass::MassKind;
use massredist::scene::SchemeSpec;
use massredist::solid::SolidSystem;
use std::sync::{Arc, OnceLock};

/// Snapshot spacing: every Δt of the sweep (0.05, 0.025, 0.02, 0.01, 0.005) is a whole multiple
/// of it, and it is a whole multiple of the reference's step h/5 for h = 1/40, 1/80, 1/160.
pub const SNAPSHOT_DT: f64 = 0.005;

/// Cells per side of the reference in the full `reproduce` (h = 1/160).
pub const REFERENCE_CELLS: usize = 160;

/// Cells per side of the reference in `reproduce --quick` (h = 1/80: the tests' cost).
pub const QUICK_REFERENCE_CELLS: usize = 80;

/// The reference's mass redistribution (mod2, uniform: the w₀ = 0 mass that wins on fine meshes,
/// report section "Scope of mod3 is the most accurate").
pub const REFERENCE_MASS: MassKind = MassKind::Mod2;

/// Two-point Gauss abscissae on [0, 1] (exact to degree 3 per variable).
const GAUSS2: [(f64, f64); 2] = [(0.211_324_865_405_187_1, 0.5), (0.788_675_134_594_812_9, 0.5)];

/// Three-point Gauss on [0, 1] (exact to degree 5).
const GAUSS3: [(f64, f64); 3] =
    [(0.112_701_665_379_258_3, 5.0 / 18.0), (0.5, 8.0 / 18.0), (0.887_298_334_620_741_7, 5.0 / 18.0)];

/// The coarse basis on one cell at local (ξ, η) ∈ [0, 1]², corners [00, 10, 11, 01]: Q1
/// bilinear, or P1 on the structured split along ξ = η ([`massredist::fem::Mesh::structured_2d`]:
/// triangles (00, 10, 11) below, (00, 11, 01) above).
fn coarse_basis(kind: Cell, xi: f64, eta: f64) -> [f64; 4] {
    match kind {
        Cell::Triangle if xi >= eta => [1.0 - xi, xi - eta, eta, 0.0],
        Cell::Triangle => [1.0 - eta, 0.0, xi, eta - xi],
        _ => [(1.0 - xi) * (1.0 - eta), xi * (1.0 - eta), xi * eta, (1.0 - xi) * eta],
    }
}

/// A coarse `coarse`² mesh of (0, 1)² (Q1 or P1) nested `r` times in the fine Q1 mesh of
/// (r·coarse)² cells: the exact products of their nodal functions (module docs).
#[derive(Debug, Clone)]
pub struct Nested {
    pub coarse: usize,
    pub r: usize,
    pub kind: Cell,
    /// `∫ φ_a ψ_k` over one coarse cell of unit size, per fine node k (local, row-major over
    /// (r+1)²) and coarse corner a.
    cross: Vec<[f64; 4]>,
    /// `∫ φ_a φ_b` over one coarse cell of unit size.
    mass: [[f64; 4]; 4],
}

impl Nested {
    /// The local products by quadrature on the fine pieces of a coarse cell: each fine square
    /// with 2×2 Gauss (φ is bilinear or linear there, ψ bilinear: degree ≤ 2 per variable), or,
    /// for triangles on the squares the coarse diagonal cuts, each half with the collapsed
    /// (Duffy) 3×3 Gauss rule (φψ of total degree 3 becomes degree ≤ 4 in u and 3 in v).
    pub fn new(coarse: usize, r: usize, kind: Cell) -> Nested {
        let side = r + 1;
        let mut cross = vec![[0.0; 4]; side * side];
        let mut mass = [[0.0; 4]; 4];
        let mut add = |a: usize, b: usize, s: f64, t: f64, w: f64| {
            // Fine local (s, t) in square (a, b); coarse local (ξ, η); weight w in coarse units.
            let (xi, eta) = ((a as f64 + s) / r as f64, (b as f64 + t) / r as f64);
            let phi = coarse_basis(kind, xi, eta);
            let psi = [(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t];
            let nodes = [b * side + a, b * side + a + 1, (b + 1) * side + a + 1, (b + 1) * side + a];
            for (&k, &p) in nodes.iter().zip(&psi) {
                for (c, &f) in cross[k].iter_mut().zip(&phi) {
                    *c += w * p * f;
                }
            }
            for (row, &f) in mass.iter_mut().zip(&phi) {
                for (m, &g) in row.iter_mut().zip(&phi) {
                    *m += w * f * g;
                }
            }
        };
        let cell = 1.0 / (r * r) as f64;
        for b in 0..r {
            for a in 0..r {
                if kind == Cell::Triangle && a == b {
                    // Lower half 0 ≤ t ≤ s ≤ 1: s = u, t = u·v (Jacobian u); upper: t = u, s = u·v.
                    for &(u, wu) in &GAUSS3 {
                        for &(v, wv) in &GAUSS3 {
                            add(a, b, u, u * v, cell * wu * wv * u);
                            add(a, b, u * v, u, cell * wu * wv * u);
                        }
                    }
                } else {
                    for &(s, ws) in &GAUSS2 {
                        for &(t, wt) in &GAUSS2 {
                            add(a, b, s, t, cell * ws * wt);
                        }
                    }
                }
            }
        }
        Nested { coarse, r, kind, cross, mass }
    }

    /// The coarse node of corner a of coarse cell (i, j) (numbering of `structured_2d`).
    fn coarse_node(&self, i: usize, j: usize, a: usize) -> usize {
        let (di, dj) = [(0, 0), (1, 0), (1, 1), (0, 1)][a];
        (j + dj) * (self.coarse + 1) + i + di
    }

    /// `(φ_A, f)_{L²}` for every coarse node A, f a scalar nodal field of the fine Q1 mesh.
    pub fn cross_products(&self, fine: &[f64]) -> Vec<f64> {
        let (n, r) = (self.coarse, self.r);
        let (side, fine_side) = (r + 1, n * r + 1);
        let area = 1.0 / (n * n) as f64;
        let mut out = vec![0.0; (n + 1) * (n + 1)];
        for j in 0..n {
            for i in 0..n {
                let mut acc = [0.0; 4];
                for (k, c) in self.cross.iter().enumerate() {
                    let f = fine[(j * r + k / side) * fine_side + i * r + k % side];
                    for (x, &w) in acc.iter_mut().zip(c) {
                        *x += w * f;
                    }
                }
                for (a, x) in acc.iter().enumerate() {
                    out[self.coarse_node(i, j, a)] += area * x;
                }
            }
        }
        out
    }

    /// `‖c‖²_{L²}` of a scalar nodal field c of the coarse mesh.
    pub fn coarse_square(&self, c: &[f64]) -> f64 {
        let n = self.coarse;
        let area = 1.0 / (n * n) as f64;
        let mut sum = 0.0;
        for j in 0..n {
            for i in 0..n {
                let v: [f64; 4] = std::array::from_fn(|a| c[self.coarse_node(i, j, a)]);
                for (row, x) in self.mass.iter().zip(&v) {
                    sum += x * row.iter().zip(&v).map(|(m, y)| m * y).sum::<f64>();
                }
            }
        }
        area * sum
    }

    /// `‖c − f‖_{L²}` of scalar nodal fields, from `‖c‖²`, `(φ, f)` and `‖f‖²` (module docs).
    pub fn distance_squared(&self, c: &[f64], cross: &[f64], fine_square: f64) -> f64 {
        let dot: f64 = c.iter().zip(cross).map(|(x, y)| x * y).sum();
        self.coarse_square(c) - 2.0 * dot + fine_square
    }
}

/// `‖f‖²_{L²}` of a scalar nodal field of the `n`² Q1 mesh of (0, 1)²: the element mass
/// (h²/36)·[4 2 1 2; 2 4 2 1; 1 2 4 2; 2 1 2 4] (exact).
pub fn q1_square(n: usize, f: &[f64]) -> f64 {
    const M: [[f64; 4]; 4] = [[4.0, 2.0, 1.0, 2.0], [2.0, 4.0, 2.0, 1.0], [1.0, 2.0, 4.0, 2.0], [2.0, 1.0, 2.0, 4.0]];
    let side = n + 1;
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..n {
            let v = [f[j * side + i], f[j * side + i + 1], f[(j + 1) * side + i + 1], f[(j + 1) * side + i]];
            for (row, x) in M.iter().zip(&v) {
                sum += x * row.iter().zip(&v).map(|(m, y)| m * y).sum::<f64>();
            }
        }
    }
    sum / (36.0 * (n * n) as f64)
}

/// The nodal values of component `comp` of a 2D solid's free unknowns `u` (0 where eliminated).
pub fn component(solid: &SolidSystem, u: &[f64], comp: usize) -> Vec<f64> {
    let nodes = solid.mesh.points.len();
    (0..nodes).map(|v| solid.dof_of.get(v * 2 + comp).map_or(0.0, |k| u[k])).collect()
}

/// The reference at one snapshot time, seen from the table's 20² meshes.
#[derive(Debug, Clone)]
struct Snapshot {
    /// `(φ_A, u_ref,x)`, `(φ_A, u_ref,y)` per coarse kind (quad, triangle).
    cross: [[Vec<f64>; 2]; 2],
    /// `‖u_ref‖²`.
    square: f64,
}

/// The fine-mesh reference (module docs).
#[derive(Debug, Clone)]
pub struct Reference {
    /// Cells per side of the reference (its check run has half as many).
    pub cells: usize,
    pub dt: f64,
    pub end: f64,
    /// `max_{t_k ≤ t} ‖u_{n/2}(t_k) − u_n(t_k)‖_{L²}` at each snapshot k.
    self_difference: Vec<f64>,
    snapshots: Vec<Snapshot>,
    /// The coarse meshes seen by the table: quad, triangle (20² in `r` = cells/20).
    nested: [Nested; 2],
}

impl Reference {
    fn index(&self, t: f64) -> Option<usize> {
        let k = (t / SNAPSHOT_DT).round();
        ((t - k * SNAPSHOT_DT).abs() <= 1e-9 && (k as usize) < self.snapshots.len()).then_some(k as usize)
    }

    /// `‖u_H(t) − u_ref(t)‖_{L²((0,1)²)²}` of a 20² coarse solid (quad or triangle) at a snapshot
    /// time t; None at other times or beyond the reference's end.
    pub fn error(&self, solid: &SolidSystem, u: &[f64], t: f64) -> Option<f64> {
        let snap = &self.snapshots[self.index(t)?];
        let kind = usize::from(solid.mesh.kind == Cell::Triangle);
        let nested = &self.nested[kind];
        let mut sum = snap.square;
        for comp in 0..2 {
            let c = component(solid, u, comp);
            sum +=
                nested.coarse_square(&c) - 2.0 * c.iter().zip(&snap.cross[kind][comp]).map(|(x, y)| x * y).sum::<f64>();
        }
        Some(sum.max(0.0).sqrt())
    }

    /// The reference's own error estimate up to t: `max_{t_k ≤ t} ‖u_{n/2} − u_n‖`.
    pub fn self_difference(&self, t: f64) -> Option<f64> {
        self.index(t).map(|k| self.self_difference[k])
    }
}

/// Runs the reference on `cells`² Q1 cells up to `end` (a multiple of [`SNAPSHOT_DT`]), and
/// beside it, in lockstep, its check on (cells/2)² cells (module docs). `cells` must be a
/// multiple of 40 (so that h/5 divides [`SNAPSHOT_DT`] on both meshes and 20 divides it).
pub fn reference(cells: usize, end: f64) -> Result<Reference, ElasticError> {
    let snapshots = (end / SNAPSHOT_DT).round() as usize;
    let cn = SchemeSpec::CRANK_NICOLSON;
    let run = |n: usize| -> Result<_, ElasticError> {
        let dt = 1.0 / (5 * n) as f64;
        let problem = spec_on(Cell::Quad, Material::PoissonFree, n).problem(&REFERENCE_MASS, end * (1.0 + 1e-9))?;
        let scheme = problem.scheme(&cn, dt)?;
        Ok((problem, scheme, (SNAPSHOT_DT / dt).round() as usize))
    };
    let (fine, mut fine_scheme, fine_steps) = run(cells)?;
    let (check, mut check_scheme, check_steps) = run(cells / 2)?;
    let nested = [Nested::new(20, cells / 20, Cell::Quad), Nested::new(20, cells / 20, Cell::Triangle)];
    let check_nested = Nested::new(cells / 2, 2, Cell::Quad);
    let mut out = Vec::with_capacity(snapshots + 1);
    let (mut self_difference, mut running) = (Vec::with_capacity(snapshots + 1), 0.0_f64);
    for k in 0..=snapshots {
        if k > 0 {
            for _ in 0..fine_steps {
                fine_scheme.step()?;
            }
            for _ in 0..check_steps {
                check_scheme.step()?;
            }
        }
        let f = [0, 1].map(|c| component(&fine.system, fine_scheme.state().u, c));
        let square = f.iter().map(|x| q1_square(cells, x)).sum::<f64>();
        let cross = nested.each_ref().map(|m| [m.cross_products(&f[0]), m.cross_products(&f[1])]);
        let coarse = [0, 1].map(|c| component(&check.system, check_scheme.state().u, c));
        let d2: f64 = (0..2)
            .map(|c| {
                check_nested.distance_squared(&coarse[c], &check_nested.cross_products(&f[c]), q1_square(cells, &f[c]))
            })
            .sum();
        running = running.max(d2.max(0.0).sqrt());
        self_difference.push(running);
        out.push(Snapshot { cross, square });
    }
    Ok(Reference { cells, dt: 1.0 / (5 * cells) as f64, end, self_difference, snapshots: out, nested })
}

/// The reference of a `reproduce` run, computed once per process: [`REFERENCE_CELLS`] up to
/// T = 10 for the full sweep, [`QUICK_REFERENCE_CELLS`] up to T = 3 for `--quick`.
pub fn cached_reference(quick: bool) -> Arc<Result<Reference, String>> {
    static CACHE: [OnceLock<Arc<Result<Reference, String>>>; 2] = [OnceLock::new(), OnceLock::new()];
    let (cells, end) = if quick { (QUICK_REFERENCE_CELLS, 3.0) } else { (REFERENCE_CELLS, 10.0) };
    CACHE[usize::from(quick)].get_or_init(|| Arc::new(reference(cells, end).map_err(|e| e.to_string()))).clone()
}
