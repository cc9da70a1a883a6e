//! The 2D plate: reduction of Q1 to 1D, mass redistribution, matrices against the stored
//! dolfinx/scikit-fem fixtures, exact L² norms, node-wise contact, energy, the schemes on the 1D
//! bar, scenes, VTU read-back and the paper's 2D table.

mod common;

use massredist::bar::assembly::{Bar, BarSystem};
use massredist::driver::{Observer, Sample, integrate};
use massredist::linalg::sparse::{self, SpMat};
use massredist::linalg::tridiag::SymTridiag;
use massredist::mass::MassKind;
use massredist::observe::{EnergyRecorder, SummaryObserver};
use massredist::plate::layers::{cell_weights, layers, total_mass};
use massredist::plate::scene::{PlateInitial, PlateSpec};
use massredist::plate::{CellKind, Mesh2d};
use massredist::run::Problem;
use massredist::run::plate::PlateProblem;
use massredist::scene::{Formulation, SchemeSpec};
use massredist::schemes::{BackwardEuler, Hybrid, Newmark, Scheme};
use massredist::system::ContactSystem;

#[global_allocator]
static GLOBAL: common::alloc::CountingAlloc = common::alloc::CountingAlloc;

const CN: SchemeSpec = SchemeSpec::CrankNicolson { formulation: Formulation::Full };

fn spec(nx: usize, ny: usize, height: f64, cells: CellKind, initial: PlateInitial) -> PlateSpec {
    PlateSpec { length: 1.0, height, nx, ny, cells, initial, body: massredist::scene::Body::default() }
}

/// Max over steps 0..=steps and all nodes of |u_2D(x_i, y_j) − u_1D(x_i)| and the same for v,
/// for Q1 on (0,1) × (0,H) with the paper's data.
fn q1_vs_1d(nx: usize, ny: usize, mass: &MassKind, scheme: &SchemeSpec, dt: f64, steps: usize) -> (f64, f64) {
    let p2 = PlateProblem::new(&spec(nx, ny, 0.5, CellKind::Quad, PlateInitial::Paper), mass).unwrap();
    let p1 = Problem::benchmark(1.0, nx, mass).unwrap();
    let mut s2 = p2.scheme(scheme, dt).unwrap();
    let mut s1 = p1.scheme(scheme, dt).unwrap();
    let (mut du, mut dv) = (0.0f64, 0.0f64);
    for n in 0..=steps {
        let (a, b) = (s2.state(), s1.state());
        for (d, &node) in p2.system.dofs.iter().enumerate() {
            let i = node % (nx + 1);
            du = du.max((a.u[d] - b.u[i]).abs());
            dv = dv.max((a.v[d] - b.v[i]).abs());
        }
        if n < steps {
            s2.step().unwrap();
            s1.step().unwrap();
        }
    }
    (du, dv)
}

#[test]
fn q1_with_paper_data_is_the_1d_solution_extended_in_y() {
    // Q1 on a structured mesh with x-only weights: M = Mx^w ⊗ My, S = Kx ⊗ My + Mx ⊗ Ky, the
    // contact LCP has the y-constant solution λ_c = λ_1D ∫φ_c, so each 2D step is the 1D step.
    let (nx, ny, dt, steps) = (20, 4, 0.01, 300);
    // Each step adds a few ulps per operation of a solve with condition number ≈ 1.1
    // (Δt²/4 · 12/h² ≈ 0.12 beyond M), u and v are O(1): the difference grows at most linearly,
    // steps · 64 ε ≈ 4e-12 for u; v = 2(u_new − u)/Δt − v (hybrid) or a/σ-based (Newmark)
    // amplifies it by up to 2/Δt = 200.
    let tol_u = steps as f64 * 64.0 * f64::EPSILON;
    let tol_v = tol_u * 2.0 / dt;
    let masses = [MassKind::Mod1, MassKind::Mod2, MassKind::Mod3];
    for scheme in [CN, SchemeSpec::BackwardEuler, SchemeSpec::Hybrid] {
        for mass in &masses {
            let (du, dv) = q1_vs_1d(nx, ny, mass, &scheme, dt, steps);
            eprintln!("Q1 vs 1D {} {}: max |du| {du:e}, max |dv| {dv:e}", scheme.name(), mass.name());
            assert!(du <= tol_u && dv <= tol_v, "{} {}: du {du:e} dv {dv:e}", scheme.name(), mass.name());
        }
    }
    let (du, dv) = q1_vs_1d(nx, ny, &MassKind::Standard, &SchemeSpec::BackwardEuler, dt, steps);
    assert!(du <= tol_u && dv <= tol_v, "backward-euler standard: du {du:e} dv {dv:e}");
    // Crank–Nicolson with the standard mass chatters after the impact (the massive contact node
    // bounces each step) and amplifies round-off by ~10 every few steps in 1D as in 2D, so the
    // comparison stops at the first impact (t = 1).
    let (du, dv) = q1_vs_1d(nx, ny, &MassKind::Standard, &CN, dt, 100);
    let tol_u = 100.0 * 64.0 * f64::EPSILON;
    assert!(du <= tol_u && dv <= tol_u * 2.0 / dt, "crank-nicolson standard: du {du:e} dv {dv:e}");
}

#[test]
fn q1_l2_error_equals_the_1d_error_times_sqrt_height() {
    // ‖e‖_{L²((0,1)×(0,H))}² = H ‖e_1D‖²_{L²(0,1)} for a y-independent error.
    let h = 0.5;
    let p2 = PlateProblem::new(&spec(20, 3, h, CellKind::Quad, PlateInitial::Paper), &MassKind::Mod3).unwrap();
    let p1 = Problem::benchmark(1.0, 20, &MassKind::Mod3).unwrap();
    let steps = 300;
    let mut sum2 = SummaryObserver::new(&p2, steps, 0.01, true);
    let mut s2 = p2.scheme(&CN, 0.01).unwrap();
    integrate(&p2, s2.as_mut(), steps, &mut [&mut sum2]).unwrap();
    let mut sum1 = SummaryObserver::new(&p1, steps, 0.01, true);
    let mut s1 = p1.scheme(&CN, 0.01).unwrap();
    integrate(&p1, s1.as_mut(), steps, &mut [&mut sum1]).unwrap();
    let (e2, e1) = (sum2.finish().linf_l2_error.unwrap(), sum1.finish().linf_l2_error.unwrap());
    // Both are exact integrals (kinks split); the states agree to ~1e-12 (test above).
    assert!((e2 - h.sqrt() * e1).abs() <= 1e-10, "{e2} vs {}", h.sqrt() * e1);
}

#[test]
fn exact_l2_norm_of_the_benchmark_on_triangles_and_quads() {
    // With u_h = 0 the error is the exact solution itself: ‖u(t)‖²_{L²(Ω)} = H ‖u_1D(t)‖², and the
    // 1D norm is exact (norms::l2_error with zero values). Times with kinks inside cells.
    let exact = massredist::exact::ImpactingBar { length: 1.0 };
    let bar = Bar { length: 1.0, elements: 7 };
    for kind in [CellKind::Triangle, CellKind::Quad] {
        let p = PlateProblem::new(&spec(7, 3, 0.6, kind, PlateInitial::Paper), &MassKind::Standard).unwrap();
        let zero = vec![0.0; p.system.system.n()];
        for &t in &[0.0, 0.33, 1.21, 1.5, 1.77, 2.4, 2.999] {
            let e2 = massredist::plate::norms::l2_error(&p.system, &zero, &exact, t);
            let e1 = massredist::bar::norms::l2_error(&bar, &vec![0.0; 7], &exact, t);
            // Sums of ~100 exact cell integrals of size ≤ 1: round-off only.
            assert!((e2 - 0.6f64.sqrt() * e1).abs() <= 1e-14, "{kind:?} t={t}: {e2} vs {}", 0.6f64.sqrt() * e1);
        }
        // And with u_h = the interpolant at t = 0 (u⁰ is in the FE space): error 0.
        let e = massredist::plate::norms::l2_error(&p.system, &p.u0, &exact, 0.0);
        assert!(e <= 1e-15, "{kind:?}: {e}");
    }
}

#[test]
fn total_mass_is_kept_where_the_1d_redistribution_keeps_it() {
    // Structured meshes and a perturbed (unstructured) triangle mesh.
    let mut meshes = vec![
        Mesh2d::structured(1.0, 1.0, 20, 20, CellKind::Quad).unwrap(),
        Mesh2d::structured(1.0, 1.0, 20, 20, CellKind::Triangle).unwrap(),
        Mesh2d::structured(2.0, 0.7, 9, 5, CellKind::Triangle).unwrap(),
    ];
    let base = Mesh2d::structured(1.0, 1.0, 8, 8, CellKind::Triangle).unwrap();
    let mut pts = base.points_flat();
    for (k, p) in pts.chunks_mut(2).enumerate() {
        // Move interior nodes by up to h/4 (deterministic pattern), keep the boundary.
        if p[0] > 0.0 && p[0] < 1.0 && p[1] > 0.0 && p[1] < 1.0 {
            p[0] += 0.03 * ((k as f64) * 1.7).sin();
            p[1] += 0.03 * ((k as f64) * 2.3).cos();
        }
    }
    meshes.push(Mesh2d::from_arrays(&pts, &base.cells, 3).unwrap());
    for mesh in &meshes {
        let area = mesh.total_area();
        let a0: f64 = layers(mesh).iter().enumerate().filter(|(_, l)| **l == 0).map(|(c, _)| mesh.area(c)).sum();
        for (kind, expected) in
            [(MassKind::Standard, area), (MassKind::Mod1, area - a0), (MassKind::Mod2, area), (MassKind::Mod3, area)]
        {
            let w = cell_weights(mesh, &kind).unwrap();
            let (m, _) = massredist::plate::assemble(mesh, &w).unwrap();
            // 1ᵀM1 = Σ_c w_c |c| (the basis sums to 1): sums of O(n) terms, a few ulps each.
            let tol = 16.0 * mesh.n_cells() as f64 * f64::EPSILON * area.max(1.0);
            assert!((sparse::total(&m) - expected).abs() <= tol, "{kind:?}: {} vs {expected}", sparse::total(&m));
            assert!((total_mass(mesh, &w) - expected).abs() <= tol);
            // Massless contact nodes for every redistribution (rows of M vanish on x = 0).
            if kind != MassKind::Standard {
                for v in (0..mesh.n_nodes()).filter(|&v| mesh.on_contact(v)) {
                    assert_eq!(sparse::get(&m, v, v), 0.0, "{kind:?}: node {v}");
                }
            }
        }
    }
}

#[test]
fn symmetric_matrices_with_constants_in_the_stiffness_kernel() {
    for kind in [CellKind::Quad, CellKind::Triangle] {
        let mesh = Mesh2d::structured(1.3, 0.8, 6, 4, kind).unwrap();
        let w = cell_weights(&mesh, &MassKind::Mod3).unwrap();
        let (m, s) = massredist::plate::assemble(&mesh, &w).unwrap();
        let ones = vec![1.0; mesh.n_nodes()];
        let mut r = vec![0.0; mesh.n_nodes()];
        sparse::sym_mul_into(&s, &ones, &mut r);
        // S·1 = 0 before boundary conditions (entries O(1), sums of ≤ 6 of them).
        assert!(r.iter().all(|x| x.abs() <= 32.0 * f64::EPSILON), "{kind:?}: {r:?}");
        for (a, name) in [(&m, "M"), (&s, "S")] {
            for (i, j, v) in sparse::triplets(a) {
                assert_eq!(v, sparse::get(a, j, i), "{kind:?} {name}[{i},{j}]");
            }
        }
    }
}

/// Reads a CSR matrix stored by python/gen_fixtures.py.
fn fixture_csr(v: &serde_json::Value) -> (usize, Vec<usize>, Vec<usize>, Vec<f64>) {
    let u =
        |a: &serde_json::Value| a.as_array().unwrap().iter().map(|x| x.as_u64().unwrap() as usize).collect::<Vec<_>>();
    let f = |a: &serde_json::Value| a.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect::<Vec<_>>();
    (v["nrows"].as_u64().unwrap() as usize, u(&v["indptr"]), u(&v["indices"]), f(&v["data"]))
}

#[test]
fn matrices_agree_with_the_dolfinx_and_scikit_fem_fixtures() {
    // fixtures/matrices/2d_*: weighted mass and stiffness assembled by dolfinx 0.5.2 and
    // scikit-fem 12.0.2 on stored points, cells (quads counter-clockwise) and random weights.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/matrices");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).expect("fixtures/matrices exists") {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !name.starts_with("2d_") {
            continue;
        }
        let rec: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let points: Vec<f64> = rec["points"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|p| p.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
            .collect();
        let cells: Vec<Vec<usize>> = rec["cells"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_array().unwrap().iter().map(|x| x.as_u64().unwrap() as usize).collect())
            .collect();
        let k = cells[0].len();
        let flat: Vec<usize> = cells.concat();
        let weights: Vec<f64> = rec["weights"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        let mesh = Mesh2d::from_arrays(&points, &flat, k).unwrap();
        assert_eq!(mesh.cells, flat, "{name}: the fixture's cells are already counter-clockwise");
        let (m, s) = massredist::plate::assemble(&mesh, &weights).unwrap();
        for (mat, key) in [(&m, "mass"), (&s, "stiffness")] {
            let (n, indptr, indices, data) = fixture_csr(&rec[key]);
            assert_eq!(n, mesh.n_nodes());
            let mut dense = vec![vec![0.0; n]; n];
            for i in 0..n {
                for p in indptr[i]..indptr[i + 1] {
                    dense[i][indices[p]] += data[p];
                }
            }
            let ours = sparse::to_dense(mat);
            let scale = data.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            for i in 0..n {
                for j in 0..n {
                    // Different summation orders of ≤ 8 element contributions: a few ulps.
                    assert!(
                        (ours[i][j] - dense[i][j]).abs() <= 32.0 * f64::EPSILON * scale,
                        "{name} {key}[{i},{j}]: {} vs {}",
                        ours[i][j],
                        dense[i][j]
                    );
                }
            }
        }
        checked += 1;
    }
    assert!(checked >= 4, "expected the 2 quad and 2 triangle fixtures (dolfinx, skfem), found {checked}");
}

/// Checks node-wise Signorini complementarity at every step.
struct Complementarity {
    worst: f64,
    min_u: f64,
    max_lambda: f64,
}

impl Observer for Complementarity {
    fn observe(&mut self, s: &Sample) {
        for (c, &i) in s.geometry.contact().iter().enumerate() {
            let (u, l) = (s.state.u[i], s.state.lambda[c]);
            self.worst = self.worst.max((u * l).abs());
            self.min_u = self.min_u.min(u);
            self.max_lambda = self.max_lambda.max(l);
        }
    }
}

#[test]
fn contact_is_solved_exactly_node_by_node() {
    // y-dependent data on triangles: the contact state varies along Γ_C.
    for scheme in [CN, SchemeSpec::BackwardEuler, SchemeSpec::Hybrid] {
        for cells in [CellKind::Triangle, CellKind::Quad] {
            let p = PlateProblem::new(&spec(16, 12, 1.0, cells, PlateInitial::Bump), &MassKind::Mod3).unwrap();
            let mut s = p.scheme(&scheme, 0.01).unwrap();
            let mut c = Complementarity { worst: 0.0, min_u: f64::INFINITY, max_lambda: f64::NEG_INFINITY };
            let mut pressure_seen = PressureSpread::default();
            integrate(&p, s.as_mut(), 300, &mut [&mut c, &mut pressure_seen]).unwrap();
            // Active nodes get u = lower bound exactly, inactive ones λ = 0 exactly.
            assert_eq!(c.worst, 0.0, "{} {cells:?}", scheme.name());
            assert!(c.min_u >= 0.0 && c.max_lambda <= 0.0, "{} {cells:?}: {} {}", scheme.name(), c.min_u, c.max_lambda);
            assert!(
                pressure_seen.mixed_steps > 0,
                "{} {cells:?}: the contact state never varied along Γ_C",
                scheme.name()
            );
        }
    }
}

/// Counts steps where some contact nodes are active and others not.
#[derive(Default)]
struct PressureSpread {
    mixed_steps: usize,
}

impl Observer for PressureSpread {
    fn observe(&mut self, s: &Sample) {
        let active = s.state.lambda.iter().filter(|&&l| l < 0.0).count();
        if active > 0 && active < s.state.lambda.len() {
            self.mixed_steps += 1;
        }
    }
}

/// The bar's tridiagonal matrix as a sparse one (same entries).
fn to_sparse(a: &SymTridiag) -> SpMat {
    let m = a.len();
    let mut t = Vec::with_capacity(3 * m);
    for i in 0..m {
        t.push((i, i, a.diag[i]));
        if i + 1 < m {
            t.push((i, i + 1, a.off[i]));
            t.push((i + 1, i, a.off[i]));
        }
    }
    sparse::from_triplets(m, &t, "bar").unwrap()
}

#[test]
fn the_sparse_back_end_on_the_bar_gives_the_tridiagonal_steps() {
    // The same schemes on the same bar over both back-ends: sparse Cholesky + LCP against the
    // twisted tridiagonal solve + closed form must agree to round-off, with and without a gap.
    let (m, dt, steps) = (12, 0.01, 300);
    for gap in [0.0, 0.1] {
        for mass in [MassKind::Mod1, MassKind::Mod3, MassKind::Standard] {
            let bar = BarSystem::new(Bar { length: 1.0, elements: m }, &mass, 0.0).unwrap().with_gap(gap);
            let tri = &bar.system;
            let sp =
                ContactSystem::new(to_sparse(&tri.mass), to_sparse(&tri.stiffness), tri.load.clone(), vec![0], gap);
            let u0 = bar.interpolate(|x| (1.0 - x) / 2.0);
            let v0 = vec![0.0; m];
            let (u, v) = (|| u0.clone(), || v0.clone());
            let mut pairs: Vec<(Box<dyn Scheme>, Box<dyn Scheme>)> = vec![(
                Box::new(BackwardEuler::new(&sp, dt, u(), v()).unwrap()),
                Box::new(BackwardEuler::new(tri, dt, u(), v()).unwrap()),
            )];
            if mass != MassKind::Standard {
                // (CN with the standard mass chatters and amplifies round-off; see the Q1 test.)
                pairs.push((
                    Box::new(Newmark::new(&sp, 0.3, 0.6, dt, u(), v()).unwrap()),
                    Box::new(Newmark::new(tri, 0.3, 0.6, dt, u(), v()).unwrap()),
                ));
                pairs.push((
                    Box::new(Hybrid::new(&sp, dt, u(), v()).unwrap()),
                    Box::new(Hybrid::new(tri, dt, u(), v()).unwrap()),
                ));
            }
            for (mut a, mut b) in pairs {
                let mut worst = 0.0f64;
                let mut contact_steps = 0;
                for _ in 0..steps {
                    a.step().unwrap();
                    b.step().unwrap();
                    let (sa, sb) = (a.state(), b.state());
                    worst = worst.max(sa.u.iter().zip(sb.u).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max));
                    worst = worst.max((sa.lambda[0] - sb.lambda[0]).abs() * dt * dt);
                    contact_steps += usize::from(sb.lambda[0] < 0.0);
                    assert!(sb.u[0] >= -gap, "{mass:?} gap {gap}: u_0 = {} below the obstacle", sb.u[0]);
                }
                assert!(contact_steps > 0, "{mass:?} gap {gap}: the run must reach the obstacle");
                // As in the Q1 test: linear growth of per-step round-off.
                assert!(worst <= steps as f64 * 64.0 * f64::EPSILON, "{mass:?} gap {gap}: {worst:e}");
            }
        }
    }
}

#[test]
fn backward_euler_energy_never_increases_in_2d() {
    // ΔE = −½δᵀMδ − ½ΔUᵀSΔU + Σ_c λ_c^{n+1} u_cⁿ ≤ 0 node by node (module docs).
    for cells in [CellKind::Triangle, CellKind::Quad] {
        let p = PlateProblem::new(&spec(16, 16, 1.0, cells, PlateInitial::Bump), &MassKind::Mod2).unwrap();
        let mut s = p.scheme(&SchemeSpec::BackwardEuler, 0.01).unwrap();
        let mut e = EnergyRecorder::default();
        integrate(&p, s.as_mut(), 300, &mut [&mut e]).unwrap();
        // E = O(0.1); its evaluation carries a few ulps per term of the quadratic forms.
        let tol = 1e3 * f64::EPSILON;
        let worst = e.energy.windows(2).map(|w| w[1] - w[0]).fold(f64::NEG_INFINITY, f64::max);
        assert!(worst <= tol, "{cells:?}: largest increase {worst:e}");
    }
}

/// Runs the 2D hybrid scheme; per step n → n+1: (ΔE, the three energy terms).
fn hybrid_energy(problem: &PlateProblem, dt: f64, steps: usize) -> Vec<(f64, [f64; 3])> {
    let sys = &problem.system.system;
    let mut h = Hybrid::new(sys, dt, problem.u0.clone(), problem.v0.clone()).unwrap();
    let mut out = Vec::new();
    let mut e = sys.energy(h.state().u, h.state().v);
    for _ in 0..steps {
        h.step().unwrap();
        let e_new = sys.energy(h.state().u, h.state().v);
        out.push((e_new - e, h.energy_terms()));
        e = e_new;
    }
    out
}

#[test]
fn hybrid_energy_never_increases_in_2d() {
    // ΔE = (λ^{n+1})ᵀũ + (u_Cⁿ)ᵀλ̄ − ½‖u_C^{n+1} − ũ‖²_{S_CC} ≤ 0 (hybrid module docs): the 2D
    // form of Lemma 5.1, on y-dependent data (contact state varying along Γ_C), Q1 and P1,
    // several Δt, square and elongated cells, and on the paper's data.
    let cases = [
        (CellKind::Quad, 20, 20, PlateInitial::Bump, 0.01),
        (CellKind::Triangle, 20, 20, PlateInitial::Bump, 0.01),
        (CellKind::Triangle, 20, 20, PlateInitial::Bump, 0.05),
        (CellKind::Triangle, 12, 30, PlateInitial::Bump, 0.002),
        // hx = 0.025, hy = 0.2: S_CC has positive off-diagonal entries (not an M-matrix).
        (CellKind::Quad, 40, 5, PlateInitial::Bump, 0.01),
        (CellKind::Quad, 20, 6, PlateInitial::Paper, 0.01),
        (CellKind::Triangle, 20, 20, PlateInitial::Paper, 0.01),
    ];
    for (cells, nx, ny, init, dt) in cases {
        for mass in [MassKind::Mod1, MassKind::Mod2, MassKind::Mod3] {
            let p = PlateProblem::new(&spec(nx, ny, 1.0, cells, init.clone()), &mass).unwrap();
            let steps = hybrid_energy(&p, dt, (3.0 / dt).round() as usize);
            // E = O(0.1) is a sum of O(n) products: its evaluation error is ~ n ε · 0.1.
            let tol = 1e4 * f64::EPSILON;
            let label = format!("{cells:?} {nx}x{ny} {init:?} dt {dt} {}", mass.name());
            let worst = steps.iter().map(|s| s.0).fold(f64::NEG_INFINITY, f64::max);
            assert!(worst <= tol, "{label}: largest increase {worst:e}");
            // The identity, from the first step on (the scheme starts from the quasi-static
            // u_C⁰ = Φ(U⁰); mutation check: starting from the interpolated u_C⁰ breaks it at n = 0).
            let off = steps.iter().map(|(de, t)| (de - t.iter().sum::<f64>()).abs()).fold(0.0, f64::max);
            assert!(off <= tol, "{label}: identity off by {off:e}");
            // Each term ≤ 0 up to the LCP's round-off allowance (ũ ≥ −O(ε)).
            assert!(steps.iter().all(|(_, t)| t.iter().all(|&x| x <= tol)), "{label}");
            eprintln!("hybrid {label}: largest per-step energy change {worst:e}");
        }
    }
}

#[test]
fn triangles_on_the_paper_data_compared_with_1d() {
    // Not asserted (P1 on one-diagonal meshes is not a tensor product): reported.
    for scheme in [CN, SchemeSpec::Hybrid] {
        let c = massredist::paper::plate_table::compare_with_1d(
            CellKind::Triangle,
            20,
            &MassKind::Mod3,
            &scheme,
            0.01,
            3.0,
        )
        .unwrap();
        eprintln!("P1 20x20 {} mod3 dt 0.01 T 3: {c:?}", scheme.name());
        assert!(c.max_y_variation.is_finite() && c.max_diff_to_1d.is_finite());
    }
}

#[test]
fn every_plate_scene_runs() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !(name.starts_with("plate-") && name.ends_with(".toml")) {
            continue;
        }
        let scene = massredist::plate::scene::PlateScene::from_file(&path).unwrap();
        let again = massredist::plate::scene::PlateScene::from_toml(&scene.resolved_toml()).unwrap();
        assert_eq!(scene, again, "{name}: the resolved scene reads back to itself");
        let run = massredist::run::plate::run_plate_scene(&scene, &mut []).unwrap();
        assert_eq!(run.summary.steps, scene.time.steps);
        assert!(run.summary.min_u0 >= 0.0 && run.summary.max_lambda <= 0.0, "{name}");
        n += 1;
    }
    assert!(n >= 3, "expected the plate scenes, found {n}");
}

#[test]
fn plate_scene_errors_name_the_key() {
    use massredist::plate::scene::{PlateScene, is_plate_scene};
    assert!(is_plate_scene("[plate]\nnx = 4\n"));
    assert!(!is_plate_scene("[bar]\nelements = 4\n"));
    let err = |t: &str| PlateScene::from_toml(t).unwrap_err().to_string();
    assert!(err("[plate]\ncells = \"hex\"\n").contains("plate.cells"));
    assert!(err("[plate]\nnx = 1\n").contains("plate.nx"));
    let e = err("[plate]\n[scheme]\nkind = \"paoli-schatzman\"\n");
    assert!(e.contains("scheme.kind = \"paoli-schatzman\"") && e.contains("bar-only"), "{e}");
    let e = err("[plate]\n[scheme]\nkind = \"crank-nicolson\"\nformulation = \"reduced\"\n");
    assert!(e.contains("scheme.formulation = \"reduced\"") && e.contains("bar-only"), "{e}");
    assert!(err("[plate]\n[mass]\nkind = \"standard\"\n[scheme]\nkind = \"hybrid\"\n").contains("hybrid"));
    assert!(err("[plate]\ninitial = \"bump\"\n[output]\nseries = [\"l2_error\"]\n").contains("exact L² error"));
    assert!(err("[plate]\nnx = 4\nny = 2\n[mass]\nkind = \"custom\"\nweights = [1.0]\n").contains("8 cells"));
    assert!(err("[plate]\n[output]\nvtu_every = 3\n").contains("vtu"));
}

#[test]
fn a_y_dependent_run_writes_vtu_that_reads_back() {
    use massredist::observe::FrameRecorder;
    use massredist::plate::scene::PlateScene;
    use massredist::plate::vtu::{read_pvd, read_vtu};
    use massredist::run::plate::run_plate_scene;
    let text = "[plate]\nnx = 40\nny = 40\ncells = \"triangle\"\ninitial = \"bump\"\n[mass]\nkind = \"mod3\"\n\
                [scheme]\nkind = \"hybrid\"\n[time]\ndt = 0.01\nend = 3.0\n[output]\nvtu = true\nvtu_every = 50\n";
    let scene = PlateScene::from_toml(text).unwrap();
    let run = run_plate_scene(&scene, &mut []).unwrap();
    eprintln!(
        "bump 40x40 P1 hybrid mod3 T=3: energy {} -> {}, min {}, largest step increase {:e} (n >= 1: {:e}), max y-variation {}",
        run.summary.energy_initial,
        run.summary.energy_final,
        run.summary.energy_min,
        run.summary.energy_max_increase,
        run.summary.energy_max_increase_after_first,
        run.summary.max_y_variation.unwrap()
    );
    // The command line's path: series and frames streamed into the folder while computing. The
    // frames and series read back are those the in-memory run recorded, bit for bit.
    // mutation: `FrameWriter::observe` writing the frame before copying the state's u and v into
    // it (each file one frame late) -> fails at the `u` comparison (left: all 0.0).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let prepared = massredist::output::OutputDir::prepare(&out, false, &[]).unwrap();
    let streamed = massredist::run::plate::run_plate_scene_into(&scene, prepared, &mut []).unwrap();
    assert_eq!(streamed.energy_final, run.summary.energy_final);
    let mut series = Vec::new();
    massredist::output::write_series_csv(&run.series, &mut series).unwrap();
    assert_eq!(std::fs::read(out.join("series.csv")).unwrap(), series, "streamed series.csv = the recorded one");
    let frames: &FrameRecorder = run.frames.as_ref().unwrap();
    let pvd = read_pvd(&std::fs::read_to_string(out.join("plate.pvd")).unwrap());
    assert_eq!(pvd.len(), 7); // t = 0, 0.5, …, 3
    let mesh = &run.problem.system.mesh;
    for ((t, file), frame) in pvd.iter().zip(&frames.frames) {
        assert_eq!(*t, frame.t);
        let data = read_vtu(&std::fs::read_to_string(out.join(file)).unwrap()).unwrap();
        assert_eq!((data.n_points, data.n_cells), (mesh.n_nodes(), mesh.n_cells()));
        assert_eq!(data.connectivity, mesh.cells);
        assert!(data.types.iter().all(|&t| t == 5));
        // Shortest round-trip formatting: bit-for-bit equal.
        assert_eq!(data.point_array("u").unwrap().values, frame.u);
        assert_eq!(data.point_array("v").unwrap().values, frame.v);
        assert_eq!(data.cell_array("weight").unwrap().values, run.problem.system.weights);
        let xy: Vec<f64> = data.points.chunks(3).flat_map(|p| [p[0], p[1]]).collect();
        assert_eq!(xy, mesh.points_flat());
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for key in
        ["linf_l2_error", "max_contact_error", "final_u0", "energy_initial", "min_u0", "max_complementarity_product"]
    {
        assert!(summary.get(key).is_some(), "summary.json lacks {key}");
    }
}

#[test]
fn the_judged_table_rows_are_the_1d_errors_with_h_005() {
    // Q1 with the paper's data reduces to 1D (first test), and ‖·‖_{L²((0,1)²)} = ‖·‖_{L²(0,1)}.
    let rows = massredist::paper::plate_table::table_2d(true);
    let judged: Vec<_> = rows.iter().filter(|r| r.judged).collect();
    assert_eq!(judged.len(), 3);
    for r in &judged {
        let mass = match r.mass {
            "mod1" => MassKind::Mod1,
            "mod2" => MassKind::Mod2,
            _ => MassKind::Mod3,
        };
        let p1 = Problem::benchmark(1.0, 20, &mass).unwrap();
        let mut s1 = p1.scheme(&CN, 0.01).unwrap();
        let mut sum = SummaryObserver::new(&p1, 300, 0.01, true);
        integrate(&p1, s1.as_mut(), 300, &mut [&mut sum]).unwrap();
        let e1 = sum.finish().linf_l2_error.unwrap();
        let e2 = r.linf_l2_error.unwrap();
        assert!((e2 - e1).abs() <= 1e-10, "{}: {e2} vs {e1}", r.mass);
        eprintln!("table {}: 2D {e2:.4} (paper {:?})", r.mass, r.paper);
    }
    assert!(rows.iter().all(|r| r.failure.is_none()));
}

#[cfg(feature = "python")]
#[test]
fn a_gmsh_triangle_mesh_runs_through_meshio() {
    // fixtures/meshes/square_4x3_tri.msh (gmsh 2.2) read by meshio: the unit square in 4 × 3
    // squares split in triangles. The hybrid scheme runs on it and keeps its energy lemma.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes/square_4x3_tri.msh");
    let mesh = Mesh2d::read_file(&path).unwrap();
    assert_eq!((mesh.n_nodes(), mesh.n_cells(), mesh.kind), (20, 24, CellKind::Triangle));
    assert!((mesh.total_area() - 1.0).abs() <= 16.0 * f64::EPSILON);
    let p = PlateProblem::from_mesh(mesh, &MassKind::Mod3, &PlateInitial::Bump, &massredist::scene::Body::default())
        .unwrap();
    assert_eq!(p.system.system.contact.len(), 4);
    let steps = hybrid_energy(&p, 0.01, 300);
    let worst = steps.iter().map(|s| s.0).fold(f64::NEG_INFINITY, f64::max);
    assert!(worst <= 1e4 * f64::EPSILON, "largest increase {worst:e}");
}

#[test]
fn stepping_does_not_allocate() {
    // The schemes factor and allocate in `new`; `step` (sparse solve, LCP, updates) must not.
    let p = PlateProblem::new(&spec(12, 12, 1.0, CellKind::Triangle, PlateInitial::Bump), &MassKind::Mod3).unwrap();
    for scheme in [CN, SchemeSpec::BackwardEuler, SchemeSpec::Hybrid] {
        let mut s = p.scheme(&scheme, 0.01).unwrap();
        s.step().unwrap();
        let before = common::alloc::allocations();
        for _ in 0..300 {
            s.step().unwrap();
        }
        let n = common::alloc::allocations() - before;
        assert_eq!(n, 0, "{}: {n} allocations in 300 steps", scheme.name());
    }
}

/// The full sweep of `table_2d(false)`, printed (for the report; run with
/// `cargo test --release --test plate -- --ignored --nocapture print_table_2d`).
#[test]
#[ignore]
fn print_table_2d() {
    let rows = massredist::paper::plate_table::table_2d(false);
    for r in &rows {
        println!(
            "{:5} {:8} {:14} {} dt={:<5} T={:<2} linf_l2={:.5} paper={:?}",
            r.judged,
            r.cells,
            r.scheme,
            r.mass,
            r.dt,
            r.end,
            r.linf_l2_error.unwrap_or(f64::NAN),
            r.paper
        );
    }
    for r in massredist::paper::plate_table::closest_to_paper(&rows) {
        println!("closest to the paper: {r:?}");
    }
    let (group, factor) = massredist::paper::plate_table::best_single_configuration(&rows).unwrap();
    println!("best single configuration (within a factor {factor:.3}): {group:?}");
}

#[test]
fn a_failed_contact_step_names_the_step_and_the_residual() {
    use massredist::contact::lcp::LcpError;
    use massredist::schemes::SchemeError;
    let e =
        SchemeError::Contact { step: 17, time: 0.17, source: LcpError::NotConverged { pivots: 1151, residual: 3e-3 } };
    let msg = e.to_string();
    assert!(msg.contains("step 17") && msg.contains("1151") && msg.contains("3e-3"), "{msg}");
}

#[test]
fn plates_take_the_bar_keys_and_reduce_to_the_bar_with_x_only_data() {
    // The same keys as bars (density, modulus, far_end, gap, expressions): with Q1 cells, x-only
    // weights and y-independent data the plate is the bar extended in y (tensor products, as in
    // the test above), so both scenes built from text must step alike to round-off, for a free
    // far end, a gap, another material and expression data. Mutation check: assembling the
    // plate's density into its stiffness, or ignoring plate.gap, breaks the comparison.
    use massredist::plate::scene::PlateScene;
    use massredist::run::plate::PlateProblem;
    let body = "density = 4.0\nmodulus = 2.25\nfar_end = \"free\"\ngap = 0.05\n\
                initial = { displacement = \"0.1*x\", velocity = \"-1+0.3*x\" }";
    let tail = "[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"KIND\"\n[time]\ndt = 0.01\nend = 2.0\n[output]\nseries = [\"u0\"]\n";
    for kind in ["crank-nicolson", "backward-euler", "hybrid"] {
        let tail = tail.replace("KIND", kind);
        let plate = PlateScene::from_toml(&format!("[plate]\nnx = 20\nny = 3\nheight = 0.5\n{body}\n{tail}")).unwrap();
        let bar = massredist::scene::Scene::from_toml(&format!("[bar]\nelements = 20\n{body}\n{tail}")).unwrap();
        let p2 = PlateProblem::new(&plate.plate, &plate.mass).unwrap();
        let p1 = Problem::from_scene(&bar).unwrap();
        assert_eq!(p2.system.system.lower, vec![-0.05; 4], "the gap on every contact node");
        let (mut s2, mut s1) = (p2.scheme(&plate.scheme, 0.01).unwrap(), p1.scheme(&bar.scheme, 0.01).unwrap());
        let mut worst = 0.0f64;
        let mut contact = 0;
        for _ in 0..200 {
            s2.step().unwrap();
            s1.step().unwrap();
            let (a, b) = (s2.state(), s1.state());
            for (d, &node) in p2.system.dofs.iter().enumerate() {
                worst = worst.max((a.u[d] - b.u[node % 21]).abs());
            }
            contact += usize::from(b.lambda[0] < 0.0);
        }
        assert!(contact > 0, "{kind}: the bar must reach the obstacle");
        // As in the test above: linear growth of per-step round-off, 64 ε per step.
        assert!(worst <= 200.0 * 64.0 * f64::EPSILON, "{kind}: max |u_2D − u_1D| = {worst:e}");
    }
    let err = |t: &str| PlateScene::from_toml(&format!("[plate]\n{t}\n")).unwrap_err().to_string();
    assert!(err("density = 0").contains("plate.density"));
    assert!(err("far_end = \"hinged\"").contains("plate.far_end"));
    assert!(err("gap = -1").contains("plate.gap"));
    assert!(err("force = \"y*t\"").contains("plate.force"));
    assert!(err("initial = { displacement = \"x+\" }").starts_with("plate.initial.displacement"));
    assert!(err("heigth = 2").contains("unknown field `heigth` in [plate]"));
    // One [output] table for every geometry: plates honour summary_l2, bars refuse the VTU keys.
    let text = "[plate]\nnx = 4\nny = 2\n[time]\ndt = 0.05\nend = 1.0\n[output]\nsummary_l2 = false\nseries = []\n";
    let run = massredist::run::plate::run_plate_scene(&PlateScene::from_toml(text).unwrap(), &mut []).unwrap();
    assert!(run.summary.linf_l2_error.is_none() && run.summary.max_contact_error.is_some());
    let e = massredist::scene::Scene::from_toml("[output]\nvtu = true\n").unwrap_err().to_string();
    assert!(e.contains("output.vtu") && e.contains("[bar]"), "{e}");
    // The series-size limit holds for plates too (it did not: a 2×1 plate with Δt = 1e-6 and
    // T = 2000 recorded until memory ran out).
    let e = PlateScene::from_toml(
        "[plate]\nnx = 2\nny = 1\n[time]\ndt = 1e-6\nend = 2000\n[output]\nseries = [\"u0\", \"lambda\"]\n",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("output.series would record") && e.contains("output.every"), "{e}");
}

#[test]
fn y_independent_plates_are_measured_against_the_plane_wave() {
    // Without force and with y-independent data, the plate's reference is the bar's solution by
    // characteristics extended in y: its contact errors equal the bar's (the Q1 plate steps as
    // the bar, test above), its L² error is not offered (null, never a false 0), and exact_u0 is
    // a column. Mutation check: building the plane wave without the plate's gap changes
    // max_contact_error by O(gap).
    use massredist::plate::scene::PlateScene;
    use massredist::run::plate::run_plate_scene;
    let body = "modulus = 4.0\nfar_end = \"free\"\ngap = 0.1\ninitial = { displacement = \"0\", velocity = \"-1\" }";
    let tail = "[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"hybrid\"\n[time]\ndt = 0.005\nend = 1.5\n";
    let plate_text =
        format!("[plate]\nnx = 40\nny = 2\nheight = 0.2\n{body}\n{tail}[output]\nseries = [\"u0\", \"exact_u0\"]\n");
    let plate = PlateScene::from_toml(&plate_text).unwrap();
    let bar = massredist::scene::Scene::from_toml(&format!("[bar]\nelements = 40\n{body}\n{tail}")).unwrap();
    let run = run_plate_scene(&plate, &mut []).unwrap();
    let (summary, _) = massredist::run::run_scene(&bar, &mut []).unwrap();
    let (e2, e1) = (run.summary.max_contact_error.unwrap(), summary.max_contact_error.unwrap());
    assert!((e2 - e1).abs() <= 1e-12, "max contact error: plate {e2} vs bar {e1}");
    let (l2, l1) = (run.summary.l2_lambda_error.unwrap(), summary.l2_lambda_error.unwrap());
    assert!((l2 - l1).abs() <= 1e-10, "λ error: plate {l2} vs bar {l1}");
    assert!(run.summary.linf_l2_error.is_none() && summary.linf_l2_error.is_some());
    // Impact is the first t_n with u_0 ≤ −gap: round-off between the two may move it by a step.
    let (a, b) = (run.summary.impact_time_shift.unwrap(), summary.impact_time_shift.unwrap());
    assert!((a - b).abs() <= 0.005 * (1.0 + 1e-9), "impact shift: plate {a} vs bar {b}");
    let e = PlateScene::from_toml("[plate]\ninitial = \"bump\"\n[output]\nseries = [\"exact_u0\"]\n").unwrap_err();
    assert!(e.to_string().contains("exact_u0"), "{e}");
}
