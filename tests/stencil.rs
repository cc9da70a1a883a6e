//! The matrix-free stiffness of a structured Q1 box (issue 31, item 2; `solid::stencil`): the
//! same operator as the assembled stiffness, checked product by product and over 1000 steps of
//! central differences without contact; `scheme.operator` chosen, reported and refused by name.

mod common;

use massredist::linalg::sparse;
use massredist::linalg::{Operator, SymMatrix};
use massredist::scene::SolidScene;
use massredist::solid::SolidSystem;
use massredist::solid::stencil::BoxStencil;

fn scene(text: &str) -> SolidScene {
    SolidScene::from_toml(text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// A box (L, H[, D]) = (1, 0.6[, 0.4]) on `n` Q1 cells, λ = 0.7, μ = 0.45, ρ = 1.3, clamped at
/// x = 1, its lateral faces `lateral`, the obstacle `gap` below x = 0, a smooth initial
/// displacement and velocity in every component (so every coupling of K acts), central
/// differences with `operator` at dt.
fn boxed(dim: usize, n: [usize; 3], lateral: &str, gap: f64, operator: &str, dt: f64) -> String {
    let (cells, depth, fields) = if dim == 2 {
        (
            "quad",
            String::new(),
            "initial = { displacement = [\"0.01*(1-x)*y\", \"0.02*(1-x)*x\"], velocity = [\"0.05*(1-x)\", \"-0.03*(1-x)*y\"] }",
        )
    } else {
        (
            "hex",
            format!("depth = 0.4\nnz = {}\n", n[2]),
            "initial = { displacement = [\"0.01*(1-x)*y*z\", \"0.02*(1-x)*x\", \"0.01*(1-x)*(y-z)\"], velocity = [\"0.05*(1-x)\", \"-0.03*(1-x)*y\", \"0.04*(1-x)*z\"] }",
        )
    };
    format!(
        "[solid]\ndim = {dim}\nlength = 1.0\nheight = 0.6\n{depth}nx = {}\nny = {}\ncells = \"{cells}\"\nlame_lambda = 0.7\nlame_mu = 0.45\ndensity = 1.3\nlateral = \"{lateral}\"\ngap = {gap}\n{fields}\n[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"central-difference\"\noperator = \"{operator}\"\n[time]\ndt = {dt}\nend = {}\n",
        n[0],
        n[1],
        1000.0 * dt
    )
}

const CASES: [(usize, [usize; 3], &str); 4] =
    [(2, [5, 3, 0], "free"), (2, [4, 2, 0], "roller"), (3, [4, 3, 2], "free"), (3, [3, 2, 3], "roller")];

/// `K x` by the stencil against the assembled stiffness on random vectors, entry by entry:
/// `|y_free − y_assembled|_i ≤ 128 ε (|K| |x|)_i`. Derivation: a stencil coefficient is the
/// assembled entry's sum of at most 2^d cell contributions in another order and on the
/// reference cell instead of each cell's own coordinates (which differ from it by a few ulps:
/// `x_k = L k/n`), so it differs by ≤ 16 ε relative; each product row sums at most 81 terms
/// (≤ 81 ε of `(|K||x|)_i` either way). (Mutation, as run: the coupling (r, s) stored as (s, r)
/// in `BoxStencil::new` -> fails; a face class's terms dropped -> fails.)
#[test]
fn the_stencil_is_the_assembled_stiffness_to_round_off() {
    for (dim, n, lateral) in CASES {
        let s = scene(&boxed(dim, n, lateral, 0.0, "auto", 1e-3));
        let problem = common::whole_problem(&s);
        let sys: &SolidSystem = &problem.system;
        let k = &sys.system.stiffness;
        let op = BoxStencil::of_system(sys).expect("a structured Q1 box has a stencil");
        assert_eq!(op.n(), k.nrows());
        let mut state = 0x2545F4914F6CDD1Du64;
        let mut rand = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..3 {
            let x: Vec<f64> = (0..k.nrows()).map(|_| rand()).collect();
            let (mut y, mut z) = (vec![0.0; k.nrows()], vec![0.0; k.nrows()]);
            op.apply(&x, &mut y);
            k.mul_into(&x, &mut z);
            let ax: Vec<f64> = x.iter().map(|v| v.abs()).collect();
            let mut bound = vec![0.0; k.nrows()];
            for (i, j, v) in sparse::triplets(k) {
                bound[i] += v.abs() * ax[j];
            }
            for i in 0..k.nrows() {
                assert!(
                    (y[i] - z[i]).abs() <= 128.0 * f64::EPSILON * bound[i],
                    "{dim}D {lateral} {n:?}: row {i}: stencil {} vs assembled {} (|K||x| = {})",
                    y[i],
                    z[i],
                    bound[i]
                );
            }
            let (q, qk) = (op.quad_form(&x), k.quad_form(&x));
            let scale: f64 = ax.iter().zip(&bound).map(|(a, b)| a * b).sum();
            assert!((q - qk).abs() <= 256.0 * f64::EPSILON * scale, "{dim}D {lateral}: xᵀKx {q} vs {qk}");
        }
    }
}

/// Without contact (the obstacle 10 below, never reached: λ = 0 at every step), central
/// differences with the stencil and with the assembled matrix follow the same trajectory: 1000
/// steps at 0.9 Δt_c agree to 1e-12 relative to the largest |u| and |v| (the bound; a
/// linear, stable recurrence carries a round-off difference of the product, ~1e-16, with growth
/// at most linear in the steps; measured: at most 3.2e-13, 3D free). Both schemes say in their
/// note which product they use. (Mutation, as run: the interior terms scaled by 1 + 1e-9 -> 2D
/// free fails with |Δu| = 2.7e-9 of 3.0e-2.)
#[test]
fn without_contact_the_matrix_free_and_assembled_trajectories_agree_over_1000_steps() {
    for (dim, n, lateral) in CASES {
        let probe = massredist::run::setup(&scene(&boxed(dim, n, lateral, 10.0, "assembled", 1e-6))).unwrap();
        let (limit, _) = probe.scheme.stable_limit().unwrap();
        let dt = 0.9 * limit;
        let mut runs = ["assembled", "matrix-free"]
            .map(|op| massredist::run::setup(&scene(&boxed(dim, n, lateral, 10.0, op, dt))).unwrap());
        let notes: Vec<String> = runs.iter().map(|r| r.scheme.note().unwrap()).collect();
        assert!(!notes[0].contains("matrix-free") && notes[1].contains("K u matrix-free"), "{notes:?}");
        let [du, dv, su, sv] = common::contact_free_lockstep(&mut runs, 1000, &format!("{dim}D {lateral}"));
        eprintln!("{dim}D {lateral}: |Δu| {du:e} of {su:e}, |Δv| {dv:e} of {sv:e}");
        assert!(du <= 1e-12 * su && dv <= 1e-12 * sv, "{dim}D {lateral}: |Δu| {du:e} of {su:e}, |Δv| {dv:e} of {sv:e}");
    }
}

/// `scheme.operator`: refused by name where there is no matrix-free stiffness (several bodies in
/// contact, a bar) and on a scheme it does not apply to; `assembled` and `auto` run anywhere.
#[test]
fn the_operator_key_is_refused_by_name_where_it_cannot_apply() {
    // A tetrahedral box takes the cell-by-cell kernel (`solid::kernel`); several bodies in
    // contact have no matrix-free stiffness.
    let tet = boxed(3, [3, 2, 2], "free", 0.0, "matrix-free", 1e-3).replace("\"hex\"", "\"tet\"");
    assert!(SolidScene::from_toml(&tet).is_ok());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let bodies = std::fs::read_to_string(root.join("scenes/bodies-two-bars-free.toml"))
        .unwrap()
        .replace("kind = \"crank-nicolson\"", "kind = \"central-difference\"\noperator = \"matrix-free\"");
    let e = SolidScene::from_toml(&bodies).unwrap_err().to_string();
    assert!(e.starts_with("scheme.operator = \"matrix-free\""), "{e}");
    assert!(e.contains("several bodies in contact") && e.contains("auto | assembled"), "{e}");
    assert!(SolidScene::from_toml(&bodies.replace("matrix-free", "auto")).is_ok());
    let bar = "[bar]\nelements = 10\n[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"central-difference\"\noperator = \"matrix-free\"\n[time]\ndt = 0.05\n";
    let e = massredist::scene::BarScene::from_toml(bar).unwrap_err().to_string();
    assert!(e.starts_with("scheme.operator = \"matrix-free\""), "{e}");
    assert!(massredist::scene::BarScene::from_toml(&bar.replace("matrix-free", "assembled")).is_ok());
    let cn = boxed(2, [4, 2, 0], "free", 0.0, "auto", 1e-3).replace("central-difference", "crank-nicolson");
    let e = SolidScene::from_toml(&cn).unwrap_err().to_string();
    assert!(e.starts_with("scheme.operator does not apply to scheme.kind = \"crank-nicolson\""), "{e}");
    let e = SolidScene::from_toml(&boxed(2, [4, 2, 0], "free", 0.0, "stencil", 1e-3)).unwrap_err().to_string();
    assert!(e.contains("scheme.operator = \"stencil\": allowed range is auto | assembled | matrix-free"), "{e}");
}

/// Δt_c without a matrix (`stable_limit_of_operator`): by Lanczos on the stencil it is the
/// assembled Lanczos's to 1e-12 relative (both stop when θ changes by less than `REL_TOL` =
/// 1e-12 over five steps); the Gershgorin fallback from the stencil's `|K| 1_I` is the matrix's
/// row-sum bound to 128 ε (each row sums at most 81 absolute values, in another order). Boxes
/// with the standard mass and with mod1 (massless contact layer, left out of I).
/// (Mutation, as run: `apply_abs` taking the signed coefficients -> the Gershgorin check fails.)
#[test]
fn the_stable_limit_from_the_stencil_is_the_assembled_one() {
    use massredist::schemes::central_difference::{stable_limit_of, stable_limit_of_operator};
    use massredist::schemes::stable_limit::{gershgorin, gershgorin_of};
    for (dim, n, lateral) in CASES {
        for mass in ["standard", "mod1"] {
            let s = scene(&boxed(dim, n, lateral, 0.0, "auto", 1e-3).replace("\"mod3\"", &format!("\"{mass}\"")));
            let problem = common::whole_problem(&s);
            let sys: &SolidSystem = &problem.system;
            let op = BoxStencil::of_system(sys).unwrap();
            let lumped = sys.lumped_mass();
            let (a, _, ca) = stable_limit_of(&sys.system, &lumped, None);
            let (b, _, cb) = stable_limit_of_operator(&op, &lumped, None);
            let lanczos = massredist::schemes::stable_limit::Method::Lanczos;
            assert!(
                ca == lanczos && cb == lanczos && (a - b).abs() <= 1e-12 * a,
                "{dim}D {lateral} {mass}: Δt_c {a} vs {b}"
            );
            let d: Vec<f64> = lumped.iter().map(|&m| if m > 0.0 { (1.0 / m).sqrt() } else { 0.0 }).collect();
            let (ga, gb) = (
                gershgorin(&sys.system.stiffness, &d, &[], 0.0),
                gershgorin_of(|x, y| op.apply_abs(x, y), &d, &[], 0.0),
            );
            assert!((ga - gb).abs() <= 128.0 * f64::EPSILON * ga, "{dim}D {lateral} {mass}: Gershgorin {ga} vs {gb}");
        }
    }
}

/// The element eigenvalue bound of the stencil (`Operator::element_bound`, issue 31 item 3) is
/// an upper bound of λ_max(M_L,II⁻¹ K_II): above the converged Lanczos value (its error,
/// 1e-12 relative, below) on every box, with the standard mass and with the massless layers
/// of mod1 and mod3. It is not always tighter than Gershgorin's row-sum bound (on the 2D boxes
/// with a massless layer it is looser), but on a 3D box with the standard mass it is (measured
/// on 12 × 8 × 6 free: 1.526 λ_max against 1.722), and a run whose Lanczos does not converge
/// takes the smaller and names it: the summary of a 3D box above `LARGE` unknowns says
/// `stable_step_method = "element"`, its `stable_step` 2/√(element bound).
/// (Mutation, as run: a node's mass shared among twice too few cells (`2.0` -> `1.0` in
/// `cell_dofs`) -> the upper bound fails.)
#[test]
fn the_element_bound_is_an_upper_bound_of_the_stable_limits_eigenvalue() {
    use massredist::schemes::stable_limit::{gershgorin_of, lambda_max_of};
    let cases = CASES.iter().copied().chain([(3, [12, 8, 6], "free")]);
    for (dim, n, lateral) in cases {
        for mass in ["standard", "mod1", "mod3"] {
            let s = scene(&boxed(dim, n, lateral, 0.0, "auto", 1e-3).replace("\"mod3\"", &format!("\"{mass}\"")));
            let problem = common::whole_problem(&s);
            let sys: &SolidSystem = &problem.system;
            let op = BoxStencil::of_system(sys).unwrap();
            let lumped = sys.lumped_mass();
            let d: Vec<f64> = lumped.iter().map(|&m| if m > 0.0 { (1.0 / m).sqrt() } else { 0.0 }).collect();
            let (lam, _, converged) = lambda_max_of(|x, y| op.apply(x, y), &d);
            assert!(converged);
            let element = op.element_bound(&lumped).expect("a box has the element bound");
            assert!(
                lam * (1.0 - 1e-12) <= element,
                "{dim}D {lateral} {mass}: λ_max {lam:e} above the element bound {element:e}"
            );
            if (dim, n[0], mass) == (3, 12, "standard") {
                let gershgorin = gershgorin_of(|x, y| op.apply_abs(x, y), &d, &[], 0.0);
                assert!(element < 0.9 * gershgorin, "element bound {element:e}, Gershgorin {gershgorin:e}");
            }
        }
    }
}

/// The lean matrix-free set-up (`SolidSpec::explicit_box_matrix_free`, the benches' path: no
/// global matrix) keeps of the stiffness exactly the rows and columns of the massless unknowns,
/// bit for bit (`columns::stiffness_touching`), none for the standard mass; central differences
/// on it (the stencil's product and Δt_c) follow the assembled run through contact: a mod1
/// box, the paper's data, 300 steps, u and v within 1e-11 of their scale (measured: 8.1e-14; the contact
/// layer's active set is the same at every step here; the products differ at round-off).
/// (Mutation, as run: `kept` keeping only entries whose row and column are both marked ->
/// the pattern check fails.)
#[test]
fn the_lean_matrix_free_box_holds_only_the_layer_rows_and_follows_the_assembled_run() {
    use massredist::contact::law::ContactLaw;
    use massredist::mass::MassKind;
    use massredist::schemes::{CentralDifference, Scheme};
    use massredist::solid::SolidSpec;
    for dim in [2, 3] {
        let mut spec = SolidSpec::paper(dim, if dim == 2 { [8, 3, 0] } else { [6, 3, 2] });
        spec.lame = massredist::solid::Lame { lambda: 0.7, mu: 0.45, density: 1.3 };
        for mass in [MassKind::Standard, MassKind::Mod1] {
            let full = spec.explicit_box(&mass).unwrap();
            let (lean, op) = spec.explicit_box_matrix_free(&mass).unwrap();
            let massless: Vec<bool> = full.lumped.iter().map(|&m| m <= 0.0).collect();
            let want = common::bits_of(&full.system.stiffness, |i, j| massless[i] || massless[j]);
            let got = common::bits_of(&lean.system.stiffness, |_, _| true);
            assert_eq!(got, want, "{dim}D {mass:?}: the layer's rows and columns");
            assert_eq!(want.is_empty(), mass == MassKind::Standard);
            let (limit, _, _) =
                massredist::schemes::central_difference::stable_limit_of(&full.system, &full.lumped, None);
            let dt = 0.9 * limit;
            let mut a =
                CentralDifference::new(&full.system, full.lumped, &ContactLaw::Exact, dt, full.u0, full.v0).unwrap();
            let mut b = CentralDifference::with_operator(
                &lean.system,
                Some(Box::new(op)),
                lean.lumped,
                &ContactLaw::Exact,
                dt,
                || (lean.u0, lean.v0),
            )
            .unwrap();
            let (mut worst, mut scale, mut contact) = (0.0f64, 0.0f64, false);
            for _ in 0..300 {
                a.step().unwrap();
                b.step().unwrap();
                let (x, y) = (a.state(), b.state());
                contact |= x.lambda.iter().any(|&l| l < 0.0);
                for (p, q) in x.u.iter().chain(x.v).zip(y.u.iter().chain(y.v)) {
                    worst = worst.max((p - q).abs());
                    scale = scale.max(p.abs());
                }
            }
            assert!(contact, "{dim}D {mass:?}: the run meets the obstacle");
            assert!(worst <= 1e-11 * scale, "{dim}D {mass:?}: {worst:e} of {scale:e}");
            eprintln!("{dim}D {mass:?}: {worst:e} of {scale:e}");
        }
    }
}
