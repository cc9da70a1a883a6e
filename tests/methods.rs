//! Moreau–Jean (issue 20): orders without contact (2 for θ = ½, 1 for θ = 1), energy of the
//! midpoint rule, the impact law solved exactly, penetration O(Δt), the refusal of a massless
//! contact node.

mod common;

use massredist::bar::assembly::{Bar, BarSystem, Load};
use massredist::material::{FarEnd, Material};
use massredist::problem::Problem;
use massredist::scene::SchemeSpec;
use massredist::schemes::{ImpactRestitution, SchemeError, Theta};

fn mj(theta: f64, e: f64) -> SchemeSpec {
    SchemeSpec::MoreauJean { theta: Theta::new(theta), restitution: ImpactRestitution::new(e) }
}

/// A bar (0, 1) of m elements, unit material, weights `w`, obstacle `gap` away.
fn bar(weights: Vec<f64>, far_end: FarEnd, gap: f64) -> BarSystem {
    let bar = Bar { length: 1.0, elements: weights.len() };
    BarSystem::assemble(bar, weights, Material::UNIT, far_end, &Load::Constant(0.0)).with_gap(gap)
}

/// Clamped bar, no contact (gap 10), smooth data.
fn smooth(m: usize) -> Problem<BarSystem> {
    let system = bar(vec![1.0; m], FarEnd::Clamped, 10.0);
    let u0 = system.interpolate(|x| (1.0 - x) * (1.0 + (3.0 * x).sin()));
    let v0 = system.interpolate(|x| (1.0 - x) * x);
    Problem { system, u0, v0, exact: None }
}

/// The free rebounding bar: u⁰ = 0, v⁰ = −1, gap 0.1, standard mass.
fn rebound(m: usize) -> Problem<BarSystem> {
    let system = bar(vec![1.0; m], FarEnd::Free, 0.1);
    let n = system.n();
    Problem { system, u0: vec![0.0; n], v0: vec![-1.0; n], exact: None }
}

fn run(p: &Problem<BarSystem>, spec: &SchemeSpec, dt: f64, t: f64) -> (Vec<f64>, Vec<(f64, f64, f64, f64)>) {
    let mut s = p.scheme(spec, dt).unwrap();
    let mut trace = Vec::new();
    for _ in 0..(t / dt).round() as usize {
        let v0_old = s.state().v[0];
        s.step().unwrap();
        let st = s.state();
        trace.push((st.u[0], st.v[0], v0_old, st.lambda[0]));
    }
    (s.state().u.to_vec(), trace)
}

/// Order 2 for θ = ½ and 1 for θ = 1 against the θ = ½ run at 0.01/256 (same mesh, no contact).
/// Observed slopes: θ = ½ in [1.9, 2.1], θ = 1 in [0.9, 1.1]. (Mutation: U^{n+θ} taken as Uⁿ in
/// the right-hand side (`th * (1.0 - th)` -> 0) -> θ = ½ slope 1.46.)
#[test]
fn orders_without_contact() {
    let p = smooth(20);
    let (t, dt0) = (0.6, 0.01);
    let (reference, _) = run(&p, &mj(0.5, 0.0), dt0 / 256.0, t);
    // θ = 1 damps the mesh's high modes by O(1) until ω_max Δt ≪ 1 (ω_max ≈ 2c/h = 40 here):
    // its asymptotic range starts near Δt = 2.5e-4 (ratios 1.69, 1.82, 1.90 from 1e-3).
    for (theta, start, lo, hi) in [(0.5, dt0, 1.9, 2.1), (1.0, dt0 / 40.0, 0.9, 1.1)] {
        let (mut dts, mut errs) = (Vec::new(), Vec::new());
        for k in 0..4 {
            let dt = start / 2f64.powi(k);
            let (u, _) = run(&p, &mj(theta, 0.0), dt, t);
            dts.push(dt);
            errs.push(common::max_abs_diff(&u, &reference));
        }
        let slope = common::fitted_slope(&dts, &errs);
        assert!((lo..=hi).contains(&slope), "θ = {theta}: slope {slope}, errors {errs:?}");
    }
}

/// θ = ½ without contact is the midpoint rule: `½V·MV + ½U·KU` is conserved to round-off
/// (1e-12 relative over 200 steps).
#[test]
fn midpoint_conserves_the_energy() {
    let p = smooth(30);
    let mut s = p.scheme(&mj(0.5, 0.0), 0.01).unwrap();
    let e0 = p.energy(s.state().u, s.state().v);
    for _ in 0..200 {
        s.step().unwrap();
    }
    let e = p.energy(s.state().u, s.state().v);
    assert!(approx::relative_eq!(e, e0, epsilon = 1e-12 * e0.abs(), max_relative = 0.0), "{e} vs {e0}");
}

/// The impact law holds exactly on the contact node: λ ≤ 0, `v_0^{n+1} + e v_0ⁿ ≥ 0` whenever
/// a contact force acts, and `= 0` to round-off there (complementarity), for e = 0 and ½, θ = ½
/// and 1; the rebounding bar touches (some λ < 0). (Mutation: the bound `−e v_cⁿ` -> `+e v_cⁿ`
/// -> "θ = 0.5, e = 0.5, step 10: v + e v_old = -1.0000000000000004".)
#[test]
fn the_impact_law_is_solved_exactly() {
    let p = rebound(50);
    for (theta, e) in [(0.5, 0.0), (0.5, 0.5), (1.0, 0.0), (1.0, 0.5)] {
        let (_, trace) = run(&p, &mj(theta, e), 0.01, 3.0);
        let mut touched = false;
        for (n, &(_, v, v_old, l)) in trace.iter().enumerate() {
            assert!(l <= 0.0, "θ = {theta}, e = {e}, step {n}: λ = {l}");
            if l < 0.0 {
                touched = true;
                assert!(
                    (v + e * v_old).abs() <= 1e-12,
                    "θ = {theta}, e = {e}, step {n}: v + e v_old = {}",
                    v + e * v_old
                );
            }
        }
        assert!(touched, "θ = {theta}, e = {e}: no contact");
    }
}

/// Penetration is O(Δt): the largest `−gap − u_0` on the rebounding bar (fixed mesh) at Δt,
/// Δt/2, Δt/4, Δt/8 has a fitted slope in [0.8, 1.2].
#[test]
fn penetration_is_first_order() {
    let p = rebound(50);
    let (mut dts, mut pens) = (Vec::new(), Vec::new());
    for k in 0..4 {
        let dt = 0.01 / 2f64.powi(k);
        let (_, trace) = run(&p, &mj(0.5, 0.0), dt, 2.5);
        let pen = trace.iter().map(|t| -0.1 - t.0).fold(0.0, f64::max);
        dts.push(dt);
        pens.push(pen);
    }
    let slope = common::fitted_slope(&dts, &pens);
    assert!((0.8..=1.2).contains(&slope), "slope {slope}, penetrations {pens:?}");
}

/// A massless contact node (mod1: w_0 = 0) is refused, naming the key and why.
#[test]
fn a_massless_contact_node_is_refused() {
    let mut w = vec![1.0; 10];
    w[0] = 0.0;
    let system = bar(w, FarEnd::Clamped, 0.0);
    let n = system.n();
    let p = Problem { system, u0: vec![0.0; n], v0: vec![0.0; n], exact: None };
    let e = p.scheme(&mj(0.5, 0.0), 0.01).err().expect("refused");
    assert!(matches!(e, SchemeError::Needs { key: "mass.kind", .. }), "{e}");
    assert!(e.to_string().contains("inertia"), "{e}");
}

// ---- The penalty law (Newmark/CN, backward Euler, central differences) ----

use massredist::contact::law::ContactLaw;
use massredist::schemes::{BackwardEuler, CentralDifference, Scheme};

const CN: SchemeSpec = SchemeSpec::CRANK_NICOLSON;

fn penalty(k: f64) -> ContactLaw {
    ContactLaw::penalty(k).unwrap()
}

/// The paper's bar (u⁰ = (1 − x)/2, v⁰ = 0, gap 0, clamped) with w_0 = `w0`, other weights 1.
fn paper(m: usize, w0: f64) -> Problem<BarSystem> {
    let mut w = vec![1.0; m];
    w[0] = w0;
    let system = bar(w, FarEnd::Clamped, 0.0);
    let u0 = system.interpolate(|x| (1.0 - x) / 2.0);
    let n = system.n();
    Problem { system, u0, v0: vec![0.0; n], exact: None }
}

fn trajectory(s: &mut Box<dyn Scheme>, steps: usize) -> Vec<Vec<f64>> {
    (0..steps)
        .map(|_| {
            s.step().unwrap();
            s.state().u.to_vec()
        })
        .collect()
}

/// CN with the penalty law is order 2 without contact (gap 10: the springs never engage), against
/// its own run at 0.01/256; slopes in [1.9, 2.1].
#[test]
fn crank_nicolson_penalty_is_second_order_without_contact() {
    let p = smooth(20);
    let law = penalty(1e4);
    let (t, dt0) = (0.6, 0.01);
    let end = |dt: f64| {
        let mut s = p.scheme_with(&CN, &law, dt).unwrap();
        trajectory(&mut s, (t / dt).round() as usize).pop().unwrap()
    };
    let reference = end(dt0 / 256.0);
    let dts: Vec<f64> = (0..4).map(|k| dt0 / 2f64.powi(k)).collect();
    let errs: Vec<f64> = dts.iter().map(|&dt| common::max_abs_diff(&end(dt), &reference)).collect();
    let slope = common::fitted_slope(&dts, &errs);
    assert!((1.9..=2.1).contains(&slope), "slope {slope}, errors {errs:?}");
}

/// Penalty → ∞ converges to exact contact: the penalty law with κ = 10², …, 10⁶ against exact
/// contact (same scheme, mesh m = 40, Δt = 1/80, to t = 3: two impacts), the largest nodal
/// distance over the run; CN for the massless contact node (w_0 = 0), backward Euler for the
/// standard mass (CN's standard-mass impacts are round-off sensitive, README: its trajectories do
/// not compare). Measured: errors 7.1e-3 … 7.5e-7 and 5.0e-3 … 5.8e-7, rates 0.995 and 0.984 in
/// 1/κ (the penetration of a spring is R/κ). Asserted: rate in [0.8, 1.2], error at 10⁶ < 1e-5.
/// (Mutation: `d[a * nc + a] += 1.0 / (sigma * kappa)` dropped in `PenaltySolver::new` -> the
/// step is the exact one: errors 1.2e-14 for every κ, rate 0: fails.)
#[test]
fn penalty_converges_to_exact_contact() {
    for (w0, spec, lo, hi) in [(0.0, CN, 0.8, 1.2), (1.0, SchemeSpec::BackwardEuler, 0.8, 1.2)] {
        let p = paper(40, w0);
        let (dt, steps) = (1.0 / 80.0, 240);
        let exact = trajectory(&mut p.scheme(&spec, dt).unwrap(), steps);
        let kappas = [1e2, 1e3, 1e4, 1e5, 1e6];
        let errs: Vec<f64> = kappas
            .iter()
            .map(|&k| {
                let pen = trajectory(&mut p.scheme_with(&spec, &penalty(k), dt).unwrap(), steps);
                pen.iter().zip(&exact).map(|(a, b)| common::max_abs_diff(a, b)).fold(0.0, f64::max)
            })
            .collect();
        let inv: Vec<f64> = kappas.iter().map(|k| 1.0 / k).collect();
        let slope = common::fitted_slope(&inv, &errs);
        eprintln!("w0 = {w0}: errors {errs:?}, rate {slope}");
        assert!((lo..=hi).contains(&slope) && errs[4] < 1e-5, "w0 = {w0}: rate {slope}, errors {errs:?}");
    }
}

/// Backward Euler with the penalty: its energy with the spring term, `½V·MV + ½U·SU + Σ ½κ
/// (d⁻)²`, never increases (BE on a convex potential), through impacts (w_0 = 1 and 0).
#[test]
fn backward_euler_penalty_dissipates() {
    for w0 in [1.0, 0.0] {
        let p = paper(30, w0);
        let s = &p.system.system;
        let mut be = BackwardEuler::with_law(s, &penalty(1e3), 0.02, p.u0.clone(), p.v0.clone()).unwrap();
        let mut e = be.energy().expect("the penalty law has an energy");
        let mut touched = false;
        for _ in 0..150 {
            be.step().unwrap();
            let e1 = be.energy().unwrap();
            assert!(e1 <= e + 1e-13 * e.abs(), "w0 = {w0}: energy rose {e} -> {e1}");
            touched |= be.state().lambda[0] < 0.0;
            e = e1;
        }
        assert!(touched, "no contact");
    }
}

/// Central differences with the penalty: the springs of massive contact nodes lower the stable
/// limit (Δt_c for K + κ e_0 e_0ᵀ), those of massless ones do not; the spring is active on
/// contact and λ = κ min(0, u_0 + gap) holds at every step (massless node: on the quasi-static
/// row; massive node: the force of the current displacement).
#[test]
fn central_differences_with_the_penalty() {
    let limit = |p: &Problem<BarSystem>, law: &ContactLaw| {
        let s = &p.system.system;
        CentralDifference::new(s, p.system.lumped.clone(), law, 1e-4, p.u0.clone(), p.v0.clone())
            .unwrap()
            .stable_limit()
            .0
    };
    let (standard, massless) = (paper(40, 1.0), paper(40, 0.0));
    assert!(limit(&standard, &penalty(1e4)) < 0.5 * limit(&standard, &ContactLaw::Exact));
    assert_eq!(limit(&massless, &penalty(1e4)), limit(&massless, &ContactLaw::Exact));
    for p in [&standard, &massless] {
        let dt = 0.9 * limit(p, &penalty(1e3));
        let mut s = p.scheme_with(&SchemeSpec::CENTRAL_DIFFERENCE, &penalty(1e3), dt).unwrap();
        let mut touched = false;
        for _ in 0..(2.0 / dt) as usize {
            s.step().unwrap();
            let st = s.state();
            let expect = 1e3 * st.u[0].min(0.0);
            assert!(
                approx::relative_eq!(st.lambda[0], expect, epsilon = 1e-9 * (1.0 + expect.abs()), max_relative = 0.0),
                "λ {} vs {expect}",
                st.lambda[0]
            );
            touched |= st.lambda[0] < 0.0;
        }
        assert!(touched, "no contact");
    }
}

/// Refusals through the command line (exit 2, the key named): a non-positive penalty, Nitsche
/// with a scheme that treats contact itself, Moreau–Jean with a massless contact node, a dt above
/// the stable limit.
#[test]
fn refusals_exit_2_naming_the_key() {
    // h = 0.005 < dt = 0.01 = 2h/c (Δt_c ≈ h/c for the standard mass).
    let base = "[bar]\nlength = 1.0\nelements = 200\ninitial = \"paper\"\n[time]\ndt = 0.01\nend = 0.1\n";
    let cases = [
        ("[contact]\nmethod = \"penalty\"\npenalty = -1\n", vec!["contact.penalty = -1", "(0, ∞)"]),
        (
            "[scheme]\nkind = \"paoli-schatzman\"\n[contact]\nmethod = \"nitsche\"\n",
            vec!["contact.method = \"nitsche\"", "treats contact itself", "allowed: exact"],
        ),
        ("[mass]\nkind = \"mod1\"\n[scheme]\nkind = \"moreau-jean\"\n", vec!["mass.kind", "inertia"]),
        (
            "[mass]\nkind = \"standard\"\n[scheme]\nkind = \"central-difference\"\n",
            vec!["time.dt = 0.01", "stable limit"],
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (i, (extra, needles)) in cases.iter().enumerate() {
        let path = dir.path().join(format!("s{i}.toml"));
        std::fs::write(&path, format!("{base}{extra}")).unwrap();
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_massredist")).arg("check").arg(&path).output().unwrap();
        common::assert_refused(&o, needles);
    }
}

/// On plates (the sparse back-end: the Schur contact solver, one factor per active set for
/// Moreau–Jean, the penalty LCP on (K⁻¹)_CC + I/(σκ)), Q1 quads with y-independent data are the
/// 1D bar: Moreau–Jean (θ = ½, e = ½) and Crank–Nicolson with the penalty give the bar's u_0 at
/// every step to 1e-10 (round-off of two different factorisations over 150 steps), through
/// impacts and releases (the contact column acts as one node; ny = 3 for Moreau–Jean). The penalty is a spring per node,
/// unscaled: the plate (height H = ½, ny = 1: two contact nodes, each standing for H/2 of the
/// section) takes κ_plate = κ_bar H/2 = 25 for κ_bar = 100.
#[test]
fn plates_with_y_independent_data_are_the_bar() {
    use massredist::problem::GeometryView;
    use massredist::scene::{BarScene, PlateScene};
    let tail = |extra: &str| {
        format!("initial = \"paper\"\n[mass]\nkind = \"standard\"\n{extra}[time]\ndt = 0.02\nend = 3.0\n")
    };
    let mj = "[scheme]\nkind = \"moreau-jean\"\ntheta = 0.5\nrestitution = 0.5\n";
    let penalty = |k: f64| format!("[contact]\nmethod = \"penalty\"\npenalty = {k:?}\n");
    for (ny, extra, plate_extra) in [(3, mj.to_string(), mj.to_string()), (1, penalty(100.0), penalty(25.0))] {
        let bar = BarScene::from_toml(&format!("[bar]\nlength = 1.0\nelements = 10\n{}", tail(&extra))).unwrap();
        let plate = PlateScene::from_toml(&format!(
            "[plate]\nlength = 1.0\nheight = 0.5\nnx = 10\nny = {ny}\ncells = \"quad\"\n{}",
            tail(&plate_extra)
        ))
        .unwrap();
        let mut b = massredist::run::setup(&bar).unwrap();
        let mut p = massredist::run::setup(&plate).unwrap();
        let (mut worst, mut touched): (f64, bool) = (0.0, false);
        for _ in 0..150 {
            b.scheme.step().unwrap();
            p.scheme.step().unwrap();
            let (sb, sp) = (b.scheme.state(), p.scheme.state());
            worst = worst.max((sb.u[0] - p.problem.system.u0(sp.u)).abs());
            touched |= sb.lambda[0] < 0.0;
        }
        assert!(touched, "{extra}: no contact");
        assert!(worst < 1e-10, "{extra}: plate vs bar u_0 differ by {worst:e}");
    }
}

/// Moreau–Jean on a plate whose contact nodes touch at different times (velocity −(1 + 2y),
/// gap 0.05, free far end): every step is finite, λ ≤ 0, the impact law `v_c^{n+1} = 0` (e = 0)
/// holds to 1e-12 on the nodes with λ < 0, and steps with some nodes active and others not
/// occur (the factor of each active set). (Mutation: the solver of every contact node with
/// bounds −∞ on the inactive ones -> fails: "no step with mixed contact states".)
#[test]
fn moreau_jean_on_a_plate_with_mixed_contact_states() {
    use massredist::scene::PlateScene;
    let plate = PlateScene::from_toml(
        "[plate]\nlength = 1.0\nheight = 0.5\nnx = 10\nny = 4\ncells = \"quad\"\nfar_end = \"free\"\ngap = 0.05\n\
         initial = { displacement = \"0\", velocity = \"-(1 + 2*y)\" }\n[mass]\nkind = \"standard\"\n\
         [scheme]\nkind = \"moreau-jean\"\n[time]\ndt = 0.01\nend = 1.0\n",
    )
    .unwrap();
    let mut p = massredist::run::setup(&plate).unwrap();
    let contact = p.problem.system.system.contact.clone();
    let mut mixed = 0;
    for n in 0..100 {
        p.scheme.step().unwrap();
        let st = p.scheme.state();
        assert!(st.u.iter().chain(st.v).all(|x| x.is_finite()), "step {n}: not finite");
        let active = st.lambda.iter().filter(|&&l| l < 0.0).count();
        mixed += (active > 0 && active < contact.len()) as usize;
        for (&c, &l) in contact.iter().zip(st.lambda) {
            assert!(l <= 0.0, "step {n}: λ = {l}");
            if l < 0.0 {
                assert!(
                    approx::relative_eq!(st.v[c], 0.0, epsilon = 1e-12, max_relative = 0.0),
                    "step {n}: node {c} v = {}",
                    st.v[c]
                );
            }
        }
    }
    assert!(mixed > 0, "no step with mixed contact states");
}

/// The fenicsx engine runs exact contact only: a plate scene with the penalty law is refused
/// before anything starts (an engine run would otherwise ignore `[contact]`). (Mutation: the
/// check disabled -> `unwrap_err` on Ok: fails.)
#[test]
fn the_engine_refuses_other_contact_laws() {
    let plate = massredist::scene::PlateScene::from_toml(
        "[plate]\nnx = 4\nny = 2\ninitial = \"paper\"\n[contact]\nmethod = \"penalty\"\npenalty = 10.0\n[time]\ndt = 0.01\nend = 0.1\n",
    )
    .unwrap();
    let e = massredist::engine::validate(&plate).unwrap_err();
    assert!(e.to_string().contains("contact.method = \"penalty\""), "{e}");
    assert!(e.is_invalid(), "exit 2");
}

/// A scene with a `[contact]` law resolves to a file that reads back to the same scene, and
/// `massredist run` runs it (Moreau–Jean and central differences too), writing its series.
/// (Mutation: the resolved file without its `[contact]` table -> the read-back scene differs.)
#[test]
fn contact_scenes_resolve_and_run() {
    use massredist::scene::BarScene;
    let base = "[bar]\nlength = 1.0\nelements = 50\ninitial = \"paper\"\n[mass]\nkind = \"standard\"\n[time]\ndt = 0.01\nend = 1.0\n";
    let dir = tempfile::tempdir().unwrap();
    for (i, extra) in [
        "[contact]\nmethod = \"penalty\"\npenalty = 1000.0\n",
        "[scheme]\nkind = \"moreau-jean\"\ntheta = 1\nrestitution = 0.5\n",
        "[scheme]\nkind = \"central-difference\"\n[contact]\nmethod = \"penalty\"\npenalty = 10.0\n",
    ]
    .iter()
    .enumerate()
    {
        let text = format!("{base}{extra}");
        let scene = BarScene::from_toml(&text).unwrap();
        assert_eq!(BarScene::from_toml(&scene.resolved_toml()).unwrap(), scene, "{}", scene.resolved_toml());
        let path = dir.path().join(format!("s{i}.toml"));
        std::fs::write(&path, &text).unwrap();
        let out = dir.path().join(format!("out{i}"));
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_massredist"))
            .args(["run", path.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{extra}: {}", common::stderr(&o));
        let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
        assert_eq!(series.lines().count(), 102, "{extra}: header + 101 states");
    }
}
