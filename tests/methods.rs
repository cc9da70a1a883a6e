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
    assert!((e - e0).abs() <= 1e-12 * e0.abs(), "{e} vs {e0}");
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
