//! The massless contact layer of central differences with a sparse factor
//! (`massredist::contact::layer::Layer`, issue 31 item 0) against the dense solver it replaced
//! (`QuasiStatic`: the dense Schur complement of the free massless unknowns and Murty's LCP on
//! it), on the layers of solid boxes (2D P1, 3D Q1 and P1; mod1 and mod3: every component of a
//! contact-face node massless, the tangential ones free) with random massive values, loads and
//! obstacle bounds that put part of the face on the obstacle and part off it.

use massredist::contact::QuasiStatic;
use massredist::contact::exact::Split;
use massredist::contact::layer::Layer;
use massredist::fem::Cell;
use massredist::linalg::sparse::{self, SpMat};
use massredist::mass::MassKind;
use massredist::schemes::ContactSystem;
use massredist::solid::SolidSpec;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// A box's explicit system and lumped mass.
fn case(dim: usize, cells: [usize; 3], kind: Cell, mass: MassKind) -> (ContactSystem<SpMat>, Vec<f64>) {
    let mut spec = SolidSpec::paper(dim, cells);
    spec.cells = kind;
    let b = spec.explicit_box(&mass).unwrap();
    (b.system, b.lumped)
}

fn cases() -> Vec<(&'static str, ContactSystem<SpMat>, Vec<f64>)> {
    vec![
        ("2D P1 6×5 mod3", case(2, [6, 5, 0], Cell::Triangle, MassKind::Mod3)),
        ("3D Q1 3×4×3 mod3", case(3, [3, 4, 3], Cell::Hex, MassKind::Mod3)),
        ("3D P1 3×3×4 mod1", case(3, [3, 3, 4], Cell::Tet, MassKind::Mod1)),
    ]
    .into_iter()
    .map(|(n, (s, l))| (n, s, l))
    .collect()
}

/// The layer's unknowns (contact first, then free) and S_LL dense, row-major.
fn dense_block(k: &SpMat, layer: &[usize]) -> Vec<f64> {
    let n = layer.len();
    let mut slot = vec![usize::MAX; k.nrows()];
    layer.iter().enumerate().for_each(|(s, &i)| slot[i] = s);
    let mut d = vec![0.0; n * n];
    for (i, j, v) in sparse::triplets(k) {
        if slot[i] != usize::MAX && slot[j] != usize::MAX {
            d[slot[i] * n + slot[j]] = v;
        }
    }
    d
}

/// κ(S_LL) from its extreme eigenvalues (faer's dense symmetric eigensolver).
fn condition(d: &[f64], n: usize) -> f64 {
    let m = faer::Mat::<f64>::from_fn(n, n, |i, j| d[i * n + j]);
    let ev = m.self_adjoint_eigenvalues(faer::Side::Lower).unwrap();
    assert!(ev[0] > 0.0, "S_LL is SPD");
    ev[n - 1] / ev[0]
}

/// On every case, 40 random draws: the massive values U uniform in [−0.1, 0.1], the load
/// F + a random perturbation, the bounds lb uniform in [−0.05, 0.05]. Checked per draw:
/// - **the same solution as the dense solver**: the same contact set (λ ≠ 0 on the same nodes)
///   and `‖u_sparse − u_dense‖∞ ≤ 16 n_L ε κ(S_LL) ‖u_L‖∞` (each is a backward-stable solve of the
///   same SPD system once the set is right: forward error ≤ c n ε κ ‖u‖, c = 8 for each side);
///   λ the same with ‖S_LL‖∞ for the scale;
/// - **complementarity bit for bit**: u_c ≥ lb_c, λ_c ≤ 0, u_c = lb_c exactly where λ_c ≠ 0 and
///   λ_c = 0 exactly where u_c > lb_c;
/// - **equilibrium**: `S_LL u_L + S_LI U − F_L = −E_C λ` with a residual ≤ 8 n_L ε (‖S‖∞ ‖u‖∞ +
///   ‖F_L‖∞) (the backward error of a Cholesky solve);
/// - **the warm start**: solving again from the solution's set takes no pivot and gives the same
///   bits;
/// - all of this whether the set's matrix is factored again or the reference factor is
///   corrected (`Layer::set_update_limit`).
///
/// Also that the draws cover both states (some nodes on the obstacle, some off).
/// (Mutation, as run: the active set's shift `S_·a lb_a` left out of the right-hand side in
/// `Layer::solve_basis` -> "differs from the dense solver" fails at the first draw with lb ≠ 0.)
#[test]
fn the_sparse_layer_solves_the_dense_solvers_problem_to_round_off() {
    let eps = f64::EPSILON;
    let mut rng = StdRng::seed_from_u64(31);
    for (name, system, lumped) in cases() {
        let split = Split::new(&system, &lumped);
        assert!(!split.free.is_empty(), "{name}: a layer with free massless unknowns");
        let layer_unknowns: Vec<usize> = split.massless.iter().chain(&split.free).copied().collect();
        let nl = layer_unknowns.len();
        let nc = split.massless.len();
        let dense = dense_block(&system.stiffness, &layer_unknowns);
        let kappa = condition(&dense, nl);
        let s_norm = (0..nl).map(|i| (0..nl).map(|j| dense[i * nl + j].abs()).sum::<f64>()).fold(0.0, f64::max);
        let n = system.stiffness.nrows();
        let (mut on, mut off) = (0usize, 0usize);
        let mut dense_layer =
            QuasiStatic::with_free(&system.stiffness, &system.load, &split.massless, &split.free).unwrap();
        // Three layers: the default rule, always factored again (limit 0: every set factored),
        // never (∞: every set a correction of the first, empty one), each warm-started from its
        // last draw; the one with limit 1 factors again only when more than one node changes,
        // so it corrects from references that have nodes on the obstacle.
        let mut layers: Vec<(Option<usize>, Layer)> = [None, Some(0), Some(1), Some(usize::MAX)]
            .into_iter()
            .map(|limit| {
                let mut l = Layer::new(&system.stiffness, &system.load, &split.massless, &split.free).unwrap();
                limit.into_iter().for_each(|k| l.set_update_limit(k));
                (limit, l)
            })
            .collect();
        for (k, draw) in (0..layers.len()).cycle().zip(0..80) {
            let (limit, sparse_layer) = &mut layers[k];
            let name = format!("{name} (limit {limit:?})");
            let u: Vec<f64> = (0..n).map(|_| rng.random_range(-0.1..0.1)).collect();
            let load: Vec<f64> = system.load.iter().map(|f| f + rng.random_range(-0.05..0.05)).collect();
            let lower: Vec<f64> = (0..nc).map(|_| rng.random_range(-0.05..0.05)).collect();
            sparse_layer.set_load(&load);
            dense_layer.set_load(&load);
            let (mut us, mut ud) = (u.clone(), u.clone());
            let (mut ls, mut ld) = (vec![f64::NAN; nc], vec![f64::NAN; nc]);
            sparse_layer.apply(&mut us, &lower, &mut ls).unwrap();
            dense_layer.apply(&mut ud, &lower, &mut ld).unwrap();
            let u_max = layer_unknowns.iter().map(|&i| us[i].abs()).fold(0.0, f64::max);
            let tol_u = 16.0 * nl as f64 * eps * kappa * u_max;
            let du = layer_unknowns.iter().map(|&i| (us[i] - ud[i]).abs()).fold(0.0, f64::max);
            let dl = ls.iter().zip(&ld).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(
                du <= tol_u && dl <= tol_u * s_norm,
                "{name} draw {draw}: differs from the dense solver: u by {du:e} (tol {tol_u:e}), λ by {dl:e}"
            );
            for (c, &i) in split.massless.iter().enumerate() {
                assert_eq!(ls[c] != 0.0, ld[c] != 0.0, "{name} draw {draw}: node {c} in contact in one only");
                assert!(us[i] >= lower[c] && ls[c] <= 0.0, "{name} draw {draw}: node {c} infeasible");
                if ls[c] != 0.0 {
                    assert_eq!(us[i].to_bits(), lower[c].to_bits(), "{name}: u_c = lb_c exactly");
                    on += 1;
                } else {
                    off += 1;
                }
            }
            // Equilibrium of the layer's rows.
            let mut r = vec![0.0; n];
            for (i, j, v) in sparse::triplets(&system.stiffness) {
                r[i] += v * us[j];
            }
            let f_max = layer_unknowns.iter().map(|&i| load[i].abs()).fold(0.0, f64::max);
            let tol_r = 8.0 * nl as f64 * eps * (s_norm * u_max + f_max);
            for (s, &i) in layer_unknowns.iter().enumerate() {
                let lambda = if s < nc { ls[s] } else { 0.0 };
                let res = (r[i] - load[i] + lambda).abs();
                assert!(res <= tol_r, "{name} draw {draw}: row {i} residual {res:e} > {tol_r:e}");
            }
            // Warm start: the same data again.
            let (mut u2, mut l2) = (u.clone(), vec![f64::NAN; nc]);
            let pivots = sparse_layer.apply(&mut u2, &lower, &mut l2).unwrap();
            assert_eq!(pivots, 0, "{name} draw {draw}: the warm start is the solution's set");
            assert!(u2.iter().zip(&us).all(|(a, b)| a.to_bits() == b.to_bits()), "{name}: warm start bits");
            assert!(l2.iter().zip(&ls).all(|(a, b)| a.to_bits() == b.to_bits()), "{name}: warm start λ bits");
        }
        assert!(on > 0 && off > 0, "{name}: the draws put nodes on ({on}) and off ({off}) the obstacle");
    }
}

/// A whole face changing side in one step costs one block pivot, not one pivot per node: the
/// 3D Q1 box's 20 contact nodes pushed onto the obstacle (the start: all off), pulled off and
/// pushed on again take 1 pivot each time; Murty's single-node rule, the dense solver's, takes
/// one per node (20) each time its start is not the answer (it starts with all on).
#[test]
fn a_whole_face_changes_side_in_one_block_pivot() {
    let (system, lumped) = case(3, [3, 4, 3], Cell::Hex, MassKind::Mod3);
    let split = Split::new(&system, &lumped);
    let nc = split.massless.len();
    assert_eq!(nc, 20);
    let n = system.stiffness.nrows();
    let mut layer = Layer::new(&system.stiffness, &system.load, &split.massless, &split.free).unwrap();
    let mut dense = QuasiStatic::with_free(&system.stiffness, &system.load, &split.massless, &split.free).unwrap();
    let mut lambda = vec![0.0; nc];
    // Massive values pushed 0.1 towards the obstacle (−x), then 0.1 away, bounds 0.
    for (k, (shift, on)) in [(-0.1, true), (0.1, false), (-0.1, true)].into_iter().enumerate() {
        let (mut u, mut ud) = (vec![shift; n], vec![shift; n]);
        for i in 0..n {
            if i % 3 != 0 {
                (u[i], ud[i]) = (0.0, 0.0);
            }
        }
        let pivots = layer.apply(&mut u, &vec![0.0; nc], &mut lambda).unwrap();
        assert_eq!(pivots, 1, "one block pivot");
        assert!(lambda.iter().all(|&l| (l < 0.0) == on), "every node {}", if on { "on" } else { "off" });
        let mut ld = vec![0.0; nc];
        let dense_pivots = dense.apply(&mut ud, &vec![0.0; nc], &mut ld).unwrap();
        assert_eq!(dense_pivots, if k == 0 { 0 } else { nc }, "Murty's rule: one pivot per node");
    }
}
