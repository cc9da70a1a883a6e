//! The 2D plate: reduction of Q1 to 1D, mass redistribution, matrices against the stored
//! dolfinx/scikit-fem fixtures, exact L² norms, node-wise contact, energy, the schemes on the 1D
//! bar, scenes, VTU read-back and the paper's 2D table.

#[path = "../../tests/common/mod.rs"]
mod common;

use massredist::bar::BarProblem;
use massredist::bar::assembly::{Bar, BarSystem};
use massredist::driver::{Observer, Sample, integrate};
use massredist::fem::layers::{cell_weights, layers, total_mass};
use massredist::fem::{Cell, Mesh};
use massredist::linalg::sparse::{self, SpMat};
use massredist::linalg::tridiag::SymTridiag;
use massredist::mass::MassKind;
use massredist::models::{PaperPlate, PlateBump, RoundOffGrowth};
use massredist::observe::{EnergyRecorder, SummaryObserver};
use massredist::plate::PlateProblem;
use massredist::scene::{Formulation, SchemeSpec};
use massredist::scene::{PlateInitial, PlateSpec};
use massredist::schemes::{BackwardEuler, Beta, Gamma, Hybrid, Newmark, Scheme};
use massredist::system::ContactSystem;

#[global_allocator]
static GLOBAL: common::alloc::CountingAlloc = common::alloc::CountingAlloc;

const CN: SchemeSpec = SchemeSpec::CrankNicolson { formulation: Formulation::Full };

fn spec(nx: usize, ny: usize, height: f64, cells: Cell, initial: PlateInitial) -> PlateSpec {
    PlateSpec::structured(1.0, height, nx, ny, cells, initial)
}

/// Max over steps 0..=steps and all nodes of |u_2D(x_i, y_j) − u_1D(x_i)| and the same for v,
/// for Q1 on (0,1) × (0,H) with the paper's data (the model [`PaperPlate`]) against its
/// reference bar.
fn q1_vs_1d(nx: usize, ny: usize, mass: &MassKind, scheme: &SchemeSpec, dt: f64, steps: usize) -> (f64, f64) {
    let plate = PaperPlate { height: 0.5, nx, ny, cells: Cell::Quad };
    let p2 = plate.problem(mass).unwrap();
    let p1 = plate.reference().problem(mass).unwrap();
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
    // The model's reduction (models::PaperPlate): each 2D step is the 1D step, to round-off
    // growing at most linearly (its tolerance, models::RoundOffGrowth, says why).
    let (nx, ny, dt, steps) = (20, 4, 0.01, 300);
    let RoundOffGrowth { u: tol_u, v: tol_v } = PaperPlate::tolerance(steps, dt);
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
    let tol = PaperPlate::tolerance(100, dt);
    assert!(du <= tol.u && dv <= tol.v, "crank-nicolson standard: du {du:e} dv {dv:e}");
}

#[test]
fn q1_l2_error_equals_the_1d_error_times_sqrt_height() {
    // ‖e‖_{L²((0,1)×(0,H))}² = H ‖e_1D‖²_{L²(0,1)} for a y-independent error.
    let h = 0.5;
    let plate = PaperPlate { height: h, nx: 20, ny: 3, cells: Cell::Quad };
    let p2 = plate.problem(&MassKind::Mod3).unwrap();
    let p1 = plate.reference().problem(&MassKind::Mod3).unwrap();
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
    for kind in [Cell::Triangle, Cell::Quad] {
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
fn the_plane_wave_l2_error_equals_the_closed_form_one() {
    // The paper's data by characteristics is the closed form (tests/characteristics.rs), so the
    // plane-wave L² error (cut cells integrated in y exactly, in x by the 1D solution's own rule)
    // must equal the closed form's exact cell rules, for u_h = 0 and for a state that is not the
    // solution (the initial interpolant at t > 0), at times with kinks inside cells.
    use massredist::characteristics::InitialData;
    use massredist::exact::{ImpactingBar, by_characteristics, paper_data};
    use massredist::material::{FarEnd, Material};
    let closed = ImpactingBar { length: 1.0 };
    let (x, u, v) = paper_data(1.0);
    let data = InitialData::PiecewiseLinear { x: &x, u: &u, v: &v };
    let general = by_characteristics(1.0, Material::UNIT, FarEnd::Clamped, 0.0, data, 3.0).unwrap();
    for kind in [Cell::Triangle, Cell::Quad] {
        let p = PlateProblem::new(&spec(7, 3, 0.6, kind, PlateInitial::Paper), &MassKind::Standard).unwrap();
        let zero = vec![0.0; p.system.system.n()];
        for &t in &[0.0, 0.33, 1.21, 1.5, 1.77, 2.4, 2.999] {
            for state in [&zero, &p.u0] {
                let a = massredist::plate::norms::l2_error(&p.system, state, &closed, t);
                let b = massredist::plate::norms::l2_error_plane_wave(&p.system, state, &general, t);
                // Both exact up to round-off: sums of ~100 cell integrals of size ≤ 1, and the
                // characteristics solution equals the closed form to ~1e-15.
                assert!((a - b).abs() <= 1e-13, "{kind:?} t={t}: closed form {a} vs plane wave {b}");
            }
        }
    }
}

#[test]
fn total_mass_is_kept_where_the_1d_redistribution_keeps_it() {
    // Structured meshes and a perturbed (unstructured) triangle mesh.
    let mut meshes = vec![
        Mesh::structured_2d(1.0, 1.0, 20, 20, Cell::Quad).unwrap(),
        Mesh::structured_2d(1.0, 1.0, 20, 20, Cell::Triangle).unwrap(),
        Mesh::structured_2d(2.0, 0.7, 9, 5, Cell::Triangle).unwrap(),
    ];
    let base = Mesh::structured_2d(1.0, 1.0, 8, 8, Cell::Triangle).unwrap();
    let mut pts = base.flat_points();
    for (k, p) in pts.chunks_mut(2).enumerate() {
        // Move interior nodes by up to h/4 (deterministic pattern), keep the boundary.
        if p[0] > 0.0 && p[0] < 1.0 && p[1] > 0.0 && p[1] < 1.0 {
            p[0] += 0.03 * ((k as f64) * 1.7).sin();
            p[1] += 0.03 * ((k as f64) * 2.3).cos();
        }
    }
    meshes.push(Mesh::from_arrays(Cell::Triangle, &pts, &base.cells).unwrap());
    for mesh in &meshes {
        let area = mesh.total_measure();
        let a0: f64 = layers(mesh).iter().enumerate().filter(|(_, l)| **l == 0).map(|(c, _)| mesh.measure(c)).sum();
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
    for kind in [Cell::Quad, Cell::Triangle] {
        let mesh = Mesh::structured_2d(1.3, 0.8, 6, 4, kind).unwrap();
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

/// Reads a CSR matrix stored by python/scripts/gen_fixtures.py.
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
    let dir = massredist_study::repo::root().join("fixtures/matrices");
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
        let mesh = Mesh::from_arrays(if k == 3 { Cell::Triangle } else { Cell::Quad }, &points, &flat).unwrap();
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
        for cells in [Cell::Triangle, Cell::Quad] {
            let p = PlateBump::unit(16, 12, cells).problem(&MassKind::Mod3).unwrap();
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
                    Box::new(Newmark::new(&sp, Beta::new(0.3), Gamma::new(0.6), dt, u(), v()).unwrap()),
                    Box::new(Newmark::new(tri, Beta::new(0.3), Gamma::new(0.6), dt, u(), v()).unwrap()),
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
    for cells in [Cell::Triangle, Cell::Quad] {
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
        (Cell::Quad, 20, 20, PlateInitial::Bump, 0.01),
        (Cell::Triangle, 20, 20, PlateInitial::Bump, 0.01),
        (Cell::Triangle, 20, 20, PlateInitial::Bump, 0.05),
        (Cell::Triangle, 12, 30, PlateInitial::Bump, 0.002),
        // hx = 0.025, hy = 0.2: S_CC has positive off-diagonal entries (not an M-matrix).
        (Cell::Quad, 40, 5, PlateInitial::Bump, 0.01),
        (Cell::Quad, 20, 6, PlateInitial::Paper, 0.01),
        (Cell::Triangle, 20, 20, PlateInitial::Paper, 0.01),
    ];
    for (cells, nx, ny, init, dt) in cases {
        for mass in [MassKind::Mod1, MassKind::Mod2, MassKind::Mod3] {
            let p = PlateProblem::new(&spec(nx, ny, 1.0, cells, init.clone()), &mass).unwrap();
            let steps = hybrid_energy(&p, dt, (3.0 / dt).round() as usize);
            let tol = PlateBump::ENERGY_ROUND_OFF; // (its reason there)
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
        let c = massredist_study::paper::plate_table::compare_with_1d(
            Cell::Triangle,
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
fn the_judged_table_rows_are_the_1d_errors_with_h_005() {
    // Q1 with the paper's data reduces to 1D (first test), and ‖·‖_{L²((0,1)²)} = ‖·‖_{L²(0,1)}.
    let rows = massredist_study::paper::plate_table::table_2d(true);
    let judged: Vec<_> = rows.iter().filter(|r| r.judged).collect();
    assert_eq!(judged.len(), 3);
    for r in &judged {
        let mass = match r.mass {
            "mod1" => MassKind::Mod1,
            "mod2" => MassKind::Mod2,
            _ => MassKind::Mod3,
        };
        let p1 = BarProblem::benchmark(1.0, 20, &mass).unwrap();
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

#[test]
fn stepping_does_not_allocate() {
    // The schemes factor and allocate in `new`; `step` (sparse solve, LCP, updates) must not.
    let p = PlateProblem::new(&spec(12, 12, 1.0, Cell::Triangle, PlateInitial::Bump), &MassKind::Mod3).unwrap();
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

#[test]
fn a_failed_contact_step_names_the_step_and_the_residual() {
    use massredist::contact::lcp::LcpError;
    use massredist::schemes::SchemeError;
    let e =
        SchemeError::Contact { step: 17, time: 0.17, source: LcpError::NotConverged { pivots: 1151, residual: 3e-3 } };
    let msg = e.to_string();
    assert!(msg.contains("step 17") && msg.contains("1151") && msg.contains("3e-3"), "{msg}");
}

#[cfg(feature = "python")]
#[test]
fn a_gmsh_triangle_mesh_runs_through_meshio() {
    // fixtures/meshes/square_4x3_tri.msh (gmsh 2.2) read by meshio: the unit square in 4 × 3
    // squares split in triangles. The hybrid scheme runs on it and keeps its energy lemma.
    let path = massredist_study::repo::root().join("fixtures/meshes/square_4x3_tri.msh");
    let mesh = massredist::scene::mesh_file::read("plate.mesh", &path).unwrap();
    assert_eq!((mesh.n_nodes(), mesh.n_cells(), mesh.kind), (20, 24, Cell::Triangle));
    assert!((mesh.total_measure() - 1.0).abs() <= 16.0 * f64::EPSILON);
    let p = PlateProblem::from_mesh(mesh, &MassKind::Mod3, &PlateInitial::Bump, &massredist::scene::Medium::default())
        .unwrap();
    assert_eq!(p.system.system.contact.len(), 4);
    let steps = hybrid_energy(&p, 0.01, 300);
    let worst = steps.iter().map(|s| s.0).fold(f64::NEG_INFINITY, f64::max);
    assert!(worst <= 1e4 * f64::EPSILON, "largest increase {worst:e}");
}
