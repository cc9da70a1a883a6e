//! Bars beyond the paper's benchmark: material, gap, free far end, initial data and force as
//! expressions. Each key's validation; the classic rebounding bar against its exact impact
//! time, contact duration, contact force and departure velocity; complementarity with a gap at
//! every step; the material scaling identity; rigid motion of a free bar.

use massredist::bar::BarProblem;
use massredist::driver::{Observer, Sample, integrate};
use massredist::models::ReboundBar;
use massredist::scene::{BarScene, Column};

mod common;

const SCHEMES: [&str; 3] = ["crank-nicolson", "backward-euler", "hybrid"];

fn bar_scene(bar: &str, scheme: &str, dt: f64, end: f64) -> String {
    format!(
        "[bar]\n{bar}\n[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"{scheme}\"\n[time]\ndt = {dt}\nend = {end}\n\
         [output]\nseries = [\"u0\", \"lambda\", \"energy\"]\n"
    )
}

fn err(bar: &str) -> String {
    BarScene::from_toml(&bar_scene(bar, "crank-nicolson", 0.01, 1.0)).unwrap_err().to_string()
}

#[test]
fn every_new_key_is_validated_naming_the_key_and_the_range() {
    for (bar, key, range) in [
        ("density = 0", "bar.density", "(0, ∞)"),
        ("density = -2.0", "bar.density", "(0, ∞)"),
        ("density = nan", "bar.density", "(0, ∞)"),
        ("density = 1e-320", "bar.density", "a normal double"),
        ("modulus = 0.0", "bar.modulus", "(0, ∞)"),
        ("modulus = inf", "bar.modulus", "(0, ∞)"),
        ("gap = -0.1", "bar.gap", "[0, ∞)"),
        ("far_end = \"hinged\"", "bar.far_end", "\"clamped\""),
        ("initial = \"bump\"", "bar.initial", "\"paper\""),
    ] {
        let e = err(bar);
        assert!(e.contains(key) && e.contains(range), "{bar}: {e}");
    }
    // Unknown keys are refused with the table named (the body keys are a flattened table).
    let e = err("elemnts = 4");
    assert!(e.contains("unknown field `elemnts`") && e.contains("[bar]"), "{e}");
    // Expressions: a parse error names the key and the column, a non-finite value the node.
    let e = err("initial = { displacement = \"sin(x\", velocity = \"0\" }");
    assert!(e.starts_with("bar.initial.displacement") && e.contains("column"), "{e}");
    let e = err("initial = { displacement = \"0\", velocity = \"1/x\" }");
    assert!(e.contains("bar.initial.velocity") && e.contains("node 0"), "{e}");
    let e = err("initial = { displacement = \"y\" }");
    assert!(e.contains("bar.initial.displacement") && e.contains('x'), "{e}");
    // A force in t is a time-dependent load (below); t is the only extra variable.
    let e = err("force = \"sin(y)\"");
    assert!(e.contains("bar.force") && e.contains("x, t"), "{e}");
    // Columns that need an exact solution are refused where none is known.
    let text = "[bar]\ngap = 0.1\nforce = \"x\"\n[output]\nseries = [\"l2_error\"]\n";
    let e = BarScene::from_toml(text).unwrap_err().to_string();
    assert!(e.contains("output.series") && e.contains("l2_error"), "{e}");
}

#[test]
fn new_keys_read_back_from_the_resolved_scene() {
    let text = bar_scene(
        "length = 2.0\nelements = 40\ndensity = 4.0\nmodulus = 2.5\nfar_end = \"free\"\ngap = 0.25\n\
         initial = { displacement = \"0.1*sin(pi*x/L)\", velocity = \"-1\" }\nforce = \"x^2\"",
        "hybrid",
        0.01,
        1.0,
    );
    let scene = BarScene::from_toml(&text).unwrap();
    let again = BarScene::from_toml(&scene.resolved_toml()).unwrap();
    assert_eq!(scene, again);
}

/// Per-step record of the contact node and the energy.
#[derive(Default)]
struct Track {
    t: Vec<f64>,
    u0: Vec<f64>,
    lambda: Vec<f64>,
    v_mean: Vec<f64>,
    energy: Vec<f64>,
}

impl Observer for Track {
    fn needs(&self) -> massredist::driver::Needs {
        massredist::driver::Needs { energy: true, ..Default::default() }
    }
    fn observe(&mut self, s: &Sample) {
        self.t.push(s.state.t);
        self.u0.push(s.u0);
        self.lambda.push(s.state.lambda[0]);
        self.v_mean.push(s.state.v.iter().sum::<f64>() / s.state.v.len() as f64);
        self.energy.push(s.energy);
    }
}

fn track(text: &str) -> (BarProblem, Track) {
    track_scene(&BarScene::from_toml(text).unwrap())
}

fn track_scene(scene: &BarScene) -> (BarProblem, Track) {
    let p = BarProblem::from_scene(scene).unwrap();
    let mut s = p.scheme(&scene.scheme, scene.time.dt).unwrap();
    let mut tr = Track::default();
    integrate(&p, s.as_mut(), scene.time.steps, &mut [&mut tr]).unwrap();
    (p, tr)
}

#[test]
fn the_rebounding_bar_hits_at_t_gap_stays_2l_over_c_and_leaves_with_velocity_one() {
    // The model (models::ReboundBar): u⁰ = 0, v⁰ = −1, free far end, gap g; its exact events and
    // tolerances, each with its reason, are the model's.
    for (density, modulus) in [(1.0, 1.0), (4.0, 1.0), (1.0, 2.25)] {
        let model = ReboundBar { length: 1.0, elements: 200, density, modulus, gap: 0.1 };
        let (exact, gap, dt) = (model.exact(), model.gap, 0.0025);
        for scheme in SCHEMES {
            let (_, tr) = track_scene(&model.scene(scheme, dt));
            let label = format!("{scheme} rho {density} E {modulus}");
            // Complementarity with the gap at every step, bit for bit.
            for n in 0..tr.t.len() {
                assert!(tr.u0[n] >= -gap && tr.lambda[n] <= 0.0, "{label} n={n}");
                assert_eq!((tr.u0[n] + gap) * tr.lambda[n], 0.0, "{label} n={n}");
            }
            let impact = tr.u0.iter().position(|&u| u <= -gap).unwrap();
            let tol = ReboundBar::impact_tolerance(dt);
            assert!(
                approx::relative_eq!(tr.t[impact], exact.impact, epsilon = tol, max_relative = 0.0),
                "{label}: impact at {}",
                tr.t[impact]
            );
            let release = (impact..tr.t.len()).find(|&n| tr.u0[n] > -gap).unwrap();
            let duration = tr.t[release] - tr.t[impact];
            let tol = model.duration_tolerance(dt);
            assert!(
                approx::relative_eq!(duration, exact.contact_duration, epsilon = tol, max_relative = 0.0),
                "{label}: contact {duration}"
            );
            // Mean contact force over the middle half of the contact: −sqrt(Eρ).
            let (a, b) = (impact + (release - impact) / 4, impact + 3 * (release - impact) / 4);
            let mean = tr.lambda[a..b].iter().sum::<f64>() / (b - a) as f64;
            let expect = exact.contact_force;
            assert!(
                approx::relative_eq!(mean, expect, epsilon = ReboundBar::RELATIVE * expect.abs(), max_relative = 0.0),
                "{label}: λ {mean} vs {expect}"
            );
            // Departure: the mean velocity after release is +1 (momentum ρL·1 is restored);
            // backward Euler loses energy at the impact, so only the conservative schemes.
            let v_end = *tr.v_mean.last().unwrap();
            if scheme != "backward-euler" {
                let tol = ReboundBar::RELATIVE * exact.departure_velocity;
                assert!(
                    approx::relative_eq!(v_end, exact.departure_velocity, epsilon = tol, max_relative = 0.0),
                    "{label}: departure velocity {v_end}"
                );
            } else {
                assert!(v_end > 0.0 && v_end < 1.0 + 1e-12, "{label}: departure velocity {v_end}");
            }
        }
    }
}

#[test]
fn density_and_modulus_scale_time_exactly() {
    // ρ = 4, E = 1 (c = ½) with Δt' = 2Δt and v⁰' = v⁰/2 is the unit bar with Δt in the time
    // t' = 2t: K' = 4K and every product by a power of two is exact, so u matches bit for bit at
    // equal step numbers, v' = v/2 and the energies agree (½ v'ᵀ(4M)v' = ½ vᵀMv). Mutation check:
    // assembling ρ into S instead of M breaks the u comparison at the first step.
    for scheme in SCHEMES {
        let base = "far_end = \"free\"\ngap = 0.05\nelements = 50";
        let data = |v: &str| format!("initial = {{ displacement = \"0.1*x\", velocity = \"{v}\" }}");
        let (_, a) = track(&bar_scene(&format!("{base}\n{}", data("-1")), scheme, 0.01, 1.0));
        let (_, b) = track(&bar_scene(&format!("{base}\n{}\ndensity = 4.0", data("-0.5")), scheme, 0.02, 2.0));
        assert_eq!(a.u0, b.u0, "{scheme}");
        for (ea, eb) in a.energy.iter().zip(&b.energy) {
            assert!(
                approx::relative_eq!(ea, eb, epsilon = 8.0 * f64::EPSILON * ea.abs(), max_relative = 0.0),
                "{scheme}: {ea} vs {eb}"
            );
        }
    }
}

#[test]
fn a_free_bar_away_from_the_obstacle_moves_rigidly() {
    // u⁰ = 0, v⁰ = +1, free far end: u = t at every node (S·1 = 0, M·1 carries the mass), so each
    // scheme's state is exact; the energy is ½ ρ L with the redistributed mass ρ ∫ w_h = ρ L for
    // mod3. Mutation check: keeping node m Dirichlet (the clamped system) breaks u = t at once.
    for scheme in ["crank-nicolson", "backward-euler"] {
        let bar =
            "far_end = \"free\"\ndensity = 2.0\ninitial = { displacement = \"0\", velocity = \"1\" }\nelements = 20";
        let scene = BarScene::from_toml(&bar_scene(bar, scheme, 0.01, 1.0)).unwrap();
        let p = BarProblem::from_scene(&scene).unwrap();
        assert_eq!(p.u0.len(), 21, "a free far end keeps node m");
        let mut s = p.scheme(&scene.scheme, 0.01).unwrap();
        for _ in 0..100 {
            s.step().unwrap();
        }
        let st = s.state();
        for &u in st.u {
            // Each step rounds u + Δt v once: linear growth, 64 ε per step.
            assert!(
                approx::relative_eq!(u, st.t, epsilon = 100.0 * 64.0 * f64::EPSILON, max_relative = 0.0),
                "{scheme}: u = {u} at t = {}",
                st.t
            );
        }
        let e = p.energy(st.u, st.v);
        assert!(
            approx::relative_eq!(e, 0.5 * 2.0 * 1.0, epsilon = 100.0 * 64.0 * f64::EPSILON, max_relative = 0.0),
            "{scheme}: energy {e}"
        );
    }
}

#[test]
fn a_force_field_integrates_the_weighted_load() {
    // F_i = ∫ f w_h φ_i: with f = 3 written as an expression the load is the constant one; with
    // f = x, Σ F_i (free end, all nodes) = ∫ x w_h dx, exact by 3-point Gauss.
    let scene = |force: &str| {
        let text = format!(
            "[bar]\nfar_end = \"free\"\nelements = 10\nforce = {force}\n[mass]\nkind = \"standard\"\n[output]\nseries = [\"u0\"]\n"
        );
        BarProblem::from_scene(&BarScene::from_toml(&text).unwrap()).unwrap()
    };
    let (a, b) = (scene("3"), scene("\"1 + 2\""));
    assert_eq!(a.system.system.load, b.system.system.load);
    let p = scene("\"x\"");
    let total: f64 = p.system.system.load.iter().sum();
    assert!(
        approx::relative_eq!(total, 0.5, epsilon = 16.0 * f64::EPSILON, max_relative = 0.0),
        "Σ F = {total}, ∫ x dx = 1/2"
    );
    let p = scene("\"x^2\"");
    let first = p.system.system.load[0];
    // ∫_0^h x² (1 − x/h) dx = h³/12 with h = 1/10.
    assert!(
        approx::relative_eq!(first, 1e-3 / 12.0, epsilon = 16.0 * f64::EPSILON * 1e-3, max_relative = 0.0),
        "F_0 = {first}"
    );
}

/// L∞(0,T; L²) error against the exact solution by characteristics, for m elements and Δt = h/c.
fn linf_l2(bar: &str, scheme: &str, m: usize, c: f64, end: f64) -> f64 {
    let dt = 1.0 / (m as f64 * c);
    let text = format!(
        "[bar]\n{bar}\nelements = {m}\n[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"{scheme}\"\n[time]\ndt = {dt:e}\nend = {end}\n\
         [output]\nseries = []\n"
    );
    let scene = BarScene::from_toml(&text).unwrap();
    let massredist::run::SceneRun { summary, .. } = massredist::run::run_scene(&scene, &mut []).unwrap();
    summary.linf_l2_error.expect("an exact solution is known without body force")
}

#[test]
fn schemes_converge_to_the_exact_solution_by_characteristics_on_three_new_problems() {
    // Three problems the paper does not pose, each with its exact solution by characteristics:
    // the rebounding free bar (gap, piecewise-constant data), a heavier clamped bar released with
    // a smooth displacement and velocity near the obstacle, and a stiffer free bar thrown at it.
    // Contact makes the solution only Lipschitz in time at the obstacle, so the rates of all
    // schemes are below their smooth-problem orders: the convergence results for mass
    // redistribution give h^(1/2), the paper's benchmark shows 1/2 to 1 (docs/bench/rates.md).
    // Asserted: a fitted slope of at least 0.4 over m = 25…200 (Δt = h/c; 1/2 less 0.1 for the
    // pre-asymptotic range of a four-point fit) and an error that at least halves over the sweep. Mutation check: dropping the
    // gap from the exact solution (gap = 0 there) leaves errors of O(gap) and slopes near 0.
    let problems = [
        ("far_end = \"free\"\ngap = 0.1\ninitial = { displacement = \"0\", velocity = \"-1\" }", 1.0, 3.0),
        (
            "density = 4.0\ngap = 0.05\ninitial = { displacement = \"0.1*cos(pi*x/(2*L))\", velocity = \"-0.3*cos(pi*x/(2*L))\" }",
            0.5,
            6.0,
        ),
        (
            "modulus = 4.0\nfar_end = \"free\"\ngap = 0.02\ninitial = { displacement = \"0\", velocity = \"-0.5+0.2*x\" }",
            2.0,
            2.0,
        ),
    ];
    for (k, (bar, c, end)) in problems.iter().enumerate() {
        for scheme in SCHEMES {
            let ms = [25, 50, 100, 200];
            let errs: Vec<f64> = ms.iter().map(|&m| linf_l2(bar, scheme, m, *c, *end)).collect();
            let (lh, le): (Vec<f64>, Vec<f64>) =
                ms.iter().zip(&errs).map(|(&m, &e)| ((1.0 / m as f64).ln(), e.ln())).unzip();
            let n = lh.len() as f64;
            let (mx, my) = (lh.iter().sum::<f64>() / n, le.iter().sum::<f64>() / n);
            let slope = lh.iter().zip(&le).map(|(x, y)| (x - mx) * (y - my)).sum::<f64>()
                / lh.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
            eprintln!("problem {k} {scheme}: errors {errs:?}, fitted slope {slope:.3}");
            assert!(slope >= 0.4, "problem {k} {scheme}: slope {slope} (errors {errs:?})");
            assert!(errs[3] <= 0.5 * errs[0], "problem {k} {scheme}: {errs:?}");
        }
    }
}

#[test]
fn a_time_dependent_force_converges_at_the_schemes_orders() {
    // Manufactured solution without contact: u = cos(πx/2) (1 + sin(t)/2) on (0, 1), ρ = E = 1,
    // clamped at x = 1, u_x(0, t) = 0 and u(0, t) ≥ 1/2 > 0 (never in contact), so
    // f = u_tt − u_xx = cos(πx/2) (−sin(t)/2 + (π/2)² (1 + sin(t)/2)). With the standard mass the
    // semi-discretisation is Galerkin (O(h²) at the nodes), Δt = h: Crank–Nicolson is second
    // order in u(0, t), backward Euler first. Observed slopes over m = 20, 40, 80 (error max over
    // t_n ≤ 2): within 0.25 of the order (the fit of three pre-asymptotic points).
    // Mutation: evaluating F at t_n instead of t_{n+1} in Newmark::step drops CN's slope to ~1.
    let exact = |t: f64| 1.0 + 0.5 * t.sin();
    let bar = "initial = { displacement = \"cos(pi*x/(2*L))\", velocity = \"0.5*cos(pi*x/(2*L))\" }\n\
               force = \"cos(pi*x/(2*L))*(-0.5*sin(t) + (pi/(2*L))^2*(1 + 0.5*sin(t)))\"";
    for (scheme, order) in [("crank-nicolson", 2.0), ("backward-euler", 1.0)] {
        let (mut hs, mut errs) = (Vec::new(), Vec::new());
        for m in [20usize, 40, 80] {
            let h = 1.0 / m as f64;
            let text = format!(
                "[bar]\nelements = {m}\n{bar}\n[mass]\nkind = \"standard\"\n[scheme]\nkind = \"{scheme}\"\n\
                 [time]\ndt = {h}\nend = 2.0\n[output]\nseries = [\"u0\"]\n"
            );
            let scene = BarScene::from_toml(&text).unwrap();
            assert!(!scene.has_exact_solution(), "no closed form with a force");
            let massredist::run::SceneRun { summary, series, .. } =
                massredist::run::run_scene(&scene, &mut []).unwrap();
            assert_eq!(summary.first_impact_time, None, "{scheme}: never in contact");
            let u0 = series.column(Column::U0).unwrap();
            let worst = series.times().iter().zip(&u0).map(|(&t, &u)| (u - exact(t)).abs()).fold(0.0, f64::max);
            hs.push(h);
            errs.push(worst);
        }
        let slope = common::fitted_slope(&hs, &errs);
        eprintln!("{scheme}: errors {errs:?}, slope {slope:.3}");
        assert!(
            approx::relative_eq!(slope, order, epsilon = 0.25, max_relative = 0.0),
            "{scheme}: slope {slope} (order {order}), errors {errs:?}"
        );
    }
}
