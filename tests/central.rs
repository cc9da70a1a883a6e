//! Central differences with a lumped redistributed mass (issue 20): d'Alembert at Courant 1,
//! order 2 in Δt, the quasi-static contact node, the forward-increment multipliers of massive
//! contact nodes, and the refusals.

mod common;

use massredist::bar::assembly::{Bar, BarSystem, Load};
use massredist::contact::law::ContactLaw;
use massredist::material::{FarEnd, Material};
use massredist::problem::Problem;
use massredist::scene::SchemeSpec;
use massredist::schemes::{CentralDifference, SchemeError};

const CD: SchemeSpec = SchemeSpec::CENTRAL_DIFFERENCE;

/// A clamped bar (0, 1) of m elements, ρ = 2, E = 8 (c = 2), weights `w`, obstacle `gap` away.
fn bar(weights: Vec<f64>, gap: f64) -> BarSystem {
    let bar = Bar { length: 1.0, elements: weights.len() };
    let material = Material { density: 2.0, modulus: 8.0 };
    BarSystem::assemble(bar, weights, material, FarEnd::Clamped, &Load::Constant(0.0)).with_gap(gap)
}

fn problem(system: BarSystem, u0: impl Fn(f64) -> f64) -> Problem<BarSystem> {
    let u = system.interpolate(&u0);
    let v = vec![0.0; u.len()];
    Problem { system, u0: u, v0: v, exact: None }
}

/// The initial displacement: any f with f(1) = 0 (clamped end).
fn f(x: f64) -> f64 {
    (std::f64::consts::FRAC_PI_2 * x).cos() * (1.0 + x) + 0.3 * (1.0 - x).powi(3) * x
}

/// d'Alembert's solution of u_tt = c² u_xx on (0, 1), u_x(0) = 0, u(1) = 0, u(·, 0) = f,
/// u_t(·, 0) = 0: ½ (F(x − ct) + F(x + ct)) with F the extension of f even about 0, odd
/// about 1 (period 4).
fn dalembert(x: f64, t: f64, c: f64) -> f64 {
    let ext = |y: f64| {
        let y = y.rem_euclid(4.0);
        match y {
            y if y <= 1.0 => f(y),
            y if y <= 2.0 => -f(2.0 - y),
            y if y <= 3.0 => -f(y - 2.0),
            y => f(4.0 - y),
        }
    };
    0.5 * (ext(x - c * t) + ext(x + c * t))
}

/// At Δt = h/c the lumped P1 scheme is the exact characteristic scheme on the lattice: the free
/// node's half mass reflects evenly (u_0^{n+1} = 2u_1ⁿ − u_0^{n−1}), the clamped end oddly, and
/// the first step from V⁰ = 0 is ½(U_{i+1} + U_{i−1}): the nodal values equal d'Alembert's to
/// round-off for all time (two periods here; 1e-12 ≈ 800 steps × a few ulps of values ≤ 2).
/// Standard mass, no contact (gap 10). dt = h/c is below the stable limit (accepted).
/// (Mutation: the half-step velocity `Vⁿ + ½ΔtAⁿ` -> `Vⁿ + ΔtAⁿ` in `step` -> error 5.7e180.)
#[test]
fn courant_one_reproduces_dalembert_at_the_nodes() {
    let m = 40;
    let p = problem(bar(vec![1.0; m], 10.0), f);
    let (h, c) = (1.0 / m as f64, 2.0);
    let dt = h / c;
    let mut s = p.scheme(&CD, dt).expect("Δt = h/c is below the stable limit");
    let mut worst: f64 = 0.0;
    for _ in 0..8 * m {
        s.step().unwrap();
        let st = s.state();
        for (i, &u) in st.u.iter().enumerate() {
            worst = worst.max((u - dalembert(i as f64 * h, st.t, c)).abs());
        }
    }
    assert!(worst < 1e-12, "largest nodal error {worst:e}");
}

/// Max nodal distance after `steps` steps of Δt between two runs.
fn run_u(p: &Problem<BarSystem>, dt: f64, steps: usize) -> Vec<f64> {
    let mut s = p.scheme(&CD, dt).unwrap();
    for _ in 0..steps {
        s.step().unwrap();
    }
    s.state().u.to_vec()
}

/// Order 2 in Δt against the same space discretisation at Δt/64 (no contact: gap 10), with a
/// massless contact node (mod1: w_0 = 0, solved quasi-statically each step) and with the
/// standard mass. Observed slopes in [1.9, 2.1]. (Mutation: the half-step velocity
/// `Vⁿ + ½ΔtAⁿ` -> `Vⁿ + ΔtAⁿ` -> slope 1.49 for w0 = 0.)
#[test]
fn order_two_in_dt_without_contact() {
    let m = 20;
    for w0 in [0.0, 1.0] {
        let mut w = vec![1.0; m];
        w[0] = w0;
        let p = problem(bar(w, 10.0), f);
        let t = 0.8;
        let dt0 = 0.5 / (m as f64 * 2.0); // Courant ½
        let reference = run_u(&p, dt0 / 64.0, 64 * (t / dt0).round() as usize);
        let mut errs = Vec::new();
        let mut dts = Vec::new();
        for k in 0..4 {
            let dt = dt0 / 2f64.powi(k);
            let u = run_u(&p, dt, (t / dt).round() as usize);
            errs.push(common::max_abs_diff(&u, &reference));
            dts.push(dt);
        }
        let slope = common::fitted_slope(&dts, &errs);
        assert!((1.9..=2.1).contains(&slope), "w0 = {w0}: slope {slope}, errors {errs:?}");
    }
}

/// With a massless contact node (mod1), every step's u_0 is the quasi-static Signorini value
/// `max(−gap, (F_0 − K_01 u_1)/K_00) = max(−gap, u_1)` (F = 0); with the standard mass the
/// forward-increment multiplier keeps u_0 ≥ −gap; λ ≤ 0 and λ (u_0 + gap) = 0 in both. The paper's
/// bar's data: u⁰ = (1 − x)/2, here with gap 0.1 (u_0 would swing to −½).
/// (Mutation: `.min(0.0)` dropped from the forward-increment multiplier -> "w0 = 1: λ = 69.48 > 0".)
#[test]
fn contact_is_exact_with_both_masses() {
    let m = 40;
    let gap = 0.1;
    for w0 in [0.0, 1.0] {
        let mut w = vec![1.0; m];
        w[0] = w0;
        let p = problem(bar(w, gap), |x| (1.0 - x) / 2.0);
        let mut s = p.scheme(&CD, 0.9 / (2.0 * m as f64)).unwrap();
        let mut contacts = 0;
        for _ in 0..400 {
            s.step().unwrap();
            let st = s.state();
            let (u0, l) = (st.u[0], st.lambda[0]);
            assert!(u0 >= -gap - 1e-14, "w0 = {w0}: penetration {u0} at t = {}", st.t);
            assert!(l <= 0.0, "w0 = {w0}: λ = {l} > 0");
            if w0 == 0.0 {
                assert!(
                    approx::relative_eq!(u0, st.u[1].max(-gap), epsilon = 1e-14, max_relative = 0.0),
                    "quasi-static u0 {u0} vs u1 {}",
                    st.u[1]
                );
                assert!(l == 0.0 || (u0 + gap).abs() <= 1e-14, "complementarity");
            }
            contacts += (l < 0.0) as usize;
        }
        assert!(contacts > 10, "w0 = {w0}: the bar never touched ({contacts} contact steps)");
    }
}

/// `dt` just below Δt_c is accepted, `dt = Δt_c` (not stable: issue 32, E7) and above it refused
/// naming `time.dt` and Δt_c; for the standard
/// mass the lumped uniform bar's λ_max is below 4c²/h², so Δt_c > h/c, and within 1% of it.
#[test]
fn the_stable_limit_is_computed_and_enforced() {
    let m = 40;
    let p = problem(bar(vec![1.0; m], 10.0), f);
    let s = &p.system.system;
    let lumped = p.system.lumped.clone();
    let cd = CentralDifference::new(s, lumped, &ContactLaw::Exact, 1e-3, p.u0.clone(), p.v0.clone()).unwrap();
    let (limit, _) = cd.stable_limit();
    let hc = 1.0 / (m as f64 * 2.0);
    assert!(limit > hc && limit < 1.01 * hc, "Δt_c = {limit}, h/c = {hc}");
    assert!(p.scheme(&CD, limit * (1.0 - 1e-9)).is_ok(), "dt below Δt_c must be accepted");
    for dt in [limit, limit * (1.0 + 1e-9)] {
        let e = p.scheme(&CD, dt).err().expect("at or above the limit");
        assert!(matches!(e, SchemeError::AboveStableLimit { .. }), "{e}");
    }
    let e = p.scheme(&CD, limit * (1.0 + 1e-9)).err().expect("above the limit");
    let text = e.to_string();
    assert!(text.starts_with("time.dt = ") && text.contains(&massredist::numfmt::fmt_f64(limit)), "{text}");
}

/// Central differences refuse what is not built, naming the key: Nitsche contact with
/// γ₀ ≤ 1 (Verlet with Nitsche is built for γ₀ > 1, `tests/nitsche.rs`). (Solids, refused here
/// until they had a lumped mass, are tests/central_solid.rs's.)
#[test]
fn refusals_name_the_key() {
    let p = problem(bar(vec![1.0; 10], 10.0), f);
    let law = ContactLaw::Nitsche { theta: 1, gamma0: 1.0 };
    let e = p.scheme_with(&CD, &law, 1e-3).err().expect("Nitsche with γ₀ = 1 refused");
    assert!(e.to_string().contains("contact.nitsche_gamma0 = 1"), "{e}");
}

/// The reported energy is `½V·M_L V + ½U·KU − F·U` (what `Scheme::energy` gives the run):
/// without contact its largest drift over a period is O(Δt²) (the scheme conserves a shadow
/// energy): measured ratios of the drift at Courant ½ and ¼ about 4, asserted in [3.5, 4.5];
/// and once V ≠ 0 it is not the consistent-mass energy.
/// (Mutation: the kinetic term `m * v * v` -> `1.0 * v * v` -> drifts 19.73, 19.77: ratio 1.)
#[test]
fn the_energy_drift_is_second_order() {
    let m = 40;
    let p = problem(bar(vec![1.0; m], 10.0), f);
    let drift = |courant: f64| {
        let dt = courant / (2.0 * m as f64);
        let mut s = p.scheme(&CD, dt).unwrap();
        let e0 = s.energy().expect("central differences report their energy");
        let mut worst: f64 = 0.0;
        for _ in 0..(2.0 / dt).round() as usize {
            s.step().unwrap();
            worst = worst.max((s.energy().unwrap() - e0).abs() / e0);
        }
        worst
    };
    let (a, b) = (drift(0.5), drift(0.25));
    assert!((3.5..=4.5).contains(&(a / b)), "drifts {a:e}, {b:e}");
    let mut s = p.scheme(&CD, 0.01).unwrap();
    for _ in 0..20 {
        s.step().unwrap(); // V ≠ 0: the kinetic energies differ
    }
    let consistent = p.energy(s.state().u, s.state().v);
    assert!((s.energy().unwrap() - consistent).abs() > 1e-6, "the lumped energy is its own");
}

/// `check` prints the stable limit as a TOML comment before the resolved scene.
#[test]
fn check_prints_the_stable_limit() {
    let scene = "[bar]\nlength = 1.0\nelements = 100\ninitial = \"paper\"\n[mass]\nkind = \"standard\"\n[scheme]\nkind = \"central-difference\"\n[time]\ndt = 0.005\nend = 0.1\n";
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cd.toml");
    std::fs::write(&path, scene).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_massredist")).arg("check").arg(&path).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{}", common::stderr(&o));
    assert!(out.starts_with("# central-difference: stable limit Δt_c = 0.0100"), "{out}");
    assert!(toml::from_str::<toml::Table>(&out).is_ok(), "still TOML: {out}");
}

/// On plates (sparse back-end, Q1 quads), y-independent data reduce exactly to the bar: the
/// lumped Q1 mass is `L_x ⊗ L_y` and `L_y 1 = M_y 1`, so `M_L⁻¹ K (u ⊗ 1) = (L_x⁻¹ K_x u) ⊗ 1`.
/// Central differences on the paper's data with the standard mass (forward-increment
/// multipliers on the 4 contact nodes) and mod1 (quasi-static contact column) give the bar's
/// u_0 at every step to 1e-10, through contact. The plate's stable limit is below the bar's (its
/// y-modes): dt = 0.04 is below both. (Mutation: the plate's row sums without the Dirichlet
/// columns -> "standard: plate vs bar u_0 differ by 1.48e-2".)
#[test]
fn plates_with_y_independent_data_are_the_bar() {
    use massredist::problem::GeometryView;
    use massredist::scene::{BarScene, PlateScene};
    for mass in ["standard", "mod1"] {
        let tail = format!(
            "initial = \"paper\"\n[mass]\nkind = \"{mass}\"\n[scheme]\nkind = \"central-difference\"\n[time]\ndt = 0.04\nend = 4.0\n"
        );
        let bar = BarScene::from_toml(&format!("[bar]\nlength = 1.0\nelements = 10\n{tail}")).unwrap();
        let plate = PlateScene::from_toml(&format!(
            "[plate]\nlength = 1.0\nheight = 0.5\nnx = 10\nny = 3\ncells = \"quad\"\n{tail}"
        ))
        .unwrap();
        let mut b = massredist::run::setup(&bar).unwrap();
        let mut p = massredist::run::setup(&plate).unwrap();
        let (mut worst, mut touched): (f64, bool) = (0.0, false);
        for _ in 0..100 {
            b.scheme.step().unwrap();
            p.scheme.step().unwrap();
            let (sb, sp) = (b.scheme.state(), p.scheme.state());
            worst = worst.max((sb.u[0] - p.problem.system.u0(sp.u)).abs());
            touched |= sb.lambda[0] < 0.0;
        }
        assert!(touched, "{mass}: no contact");
        assert!(worst < 1e-10, "{mass}: plate vs bar u_0 differ by {worst:e}");
    }
}

/// The stated accuracy of Δt_c on a large mesh (n = 2001 unknowns > the 300 Lanczos steps): a
/// free–free uniform chain with the standard lumped mass has λ_max = 4c²/h² exactly (the mode
/// (−1)^i), so Δt_c = h/c. Lanczos stops unconverged there (its Ritz value gave Δt_c 8.6e-6
/// above h/c: not conservative), so the Gershgorin bound is used, which the uniform chain attains:
/// Δt_c = h/c to 1e-12. (Mutation: the Gershgorin fallback removed -> "relative excess 8.6e-6".)
#[test]
fn the_stable_limit_accuracy_on_a_large_mesh() {
    let m = 2000;
    let bar = Bar { length: 1.0, elements: m };
    let system =
        BarSystem::assemble(bar, vec![1.0; m], Material::UNIT, FarEnd::Free, &Load::Constant(0.0)).with_gap(10.0);
    let n = system.n();
    let cd = CentralDifference::new(
        &system.system,
        system.lumped.clone(),
        &ContactLaw::Exact,
        1e-5,
        vec![0.0; n],
        vec![0.0; n],
    )
    .unwrap();
    let (limit, steps) = cd.stable_limit();
    let h = 1.0 / m as f64;
    eprintln!("Δt_c = {limit:e}, h/c = {h:e}, relative {:e}, {steps} Lanczos steps", limit / h - 1.0);
    assert!(
        approx::relative_eq!(limit / h, 1.0, epsilon = 1e-12, max_relative = 0.0),
        "relative excess {:e}",
        limit / h - 1.0
    );
}

/// E7 (issue 32): Δt = Δt_c is not stable: there the highest mode's amplification matrix has the
/// double eigenvalue −1, its amplitude grows linearly and the energy quadratically (0.5 → 637 in
/// 20,000 steps on a free rod at Courant 1, status "ok"). The free–free uniform chain with the
/// standard lumped mass has Δt_c = h/c exactly (the mode (−1)^i). Unfixed: Δt = h/c was accepted
/// (the refusal was `dt > Δt_c (1 + 1e-12)`). Now Δt ≥ Δt_c (1 − 1e-12) is refused, the margin
/// being the estimator's stated accuracy ([`massredist::schemes::stable_limit::REL_TOL`]), and
/// the message says so; Δt = (1 − 1e-9) h/c is accepted.
#[test]
fn dt_at_the_stable_limit_is_refused_with_the_estimators_margin() {
    let m = 40;
    let bar = Bar { length: 1.0, elements: m };
    let system =
        BarSystem::assemble(bar, vec![1.0; m], Material::UNIT, FarEnd::Free, &Load::Constant(0.0)).with_gap(10.0);
    let p = problem(system, |_| 0.0);
    let h = 1.0 / m as f64;
    let e = p.scheme(&CD, h).err().expect("Δt = Δt_c = h/c is refused");
    let SchemeError::AboveStableLimit { limit, .. } = e else { panic!("{e}") };
    assert!((limit / h - 1.0).abs() <= 1e-12, "Δt_c = h/c: {limit:e}");
    let text = e.to_string();
    assert!(text.starts_with("time.dt = ") && text.contains("1e-12") && text.contains("not stable"), "{text}");
    assert!(p.scheme(&CD, h * (1.0 - 1e-9)).is_ok(), "below Δt_c by more than the margin");
}

/// Contact events are read off the force (issue 32, item 1). The rebounding free bar (m = 100,
/// standard mass, c = 1) with central differences at 0.9 h/c: the forward-increment multiplier
/// keeps λ < 0 over the whole contact while u_0 sits at −gap ± a few ulps, so some steps with
/// force have u_0 above −gap (the reason a displacement test counts "releases" there). The
/// summary's contact, read off the force, is one episode lasting the exact 2L/c = 2 to within
/// the 0.8 % the method comparison prints (0.00800, `bench --methods` (b)), 2 % here.
/// mutation: `s.touching |= u[i] <= lower[c]` in ContactStats::of -> the first release comes a
/// few steps after the impact (duration ≈ 0), fails.
#[test]
fn a_massive_contact_node_is_in_contact_while_it_pushes() {
    use massredist::column::Column;
    use massredist::scene::BarScene;
    let scene = BarScene::from_toml(
        "[bar]\nlength = 1.0\nelements = 100\nfar_end = \"free\"\ngap = 0.1\n\
         initial = { displacement = \"0\", velocity = \"-1\" }\n[mass]\nkind = \"standard\"\n\
         [scheme]\nkind = \"central-difference\"\n[time]\ndt = 0.009\nend = 2.7\n[output]\nseries = [\"u0\", \"lambda\"]\n",
    )
    .unwrap();
    let run = massredist::run::run_scene(&scene, &mut []).unwrap();
    let (u0, lambda) = (run.series.column(Column::U0).unwrap(), run.series.column(Column::Lambda).unwrap());
    let pushing_above = u0.iter().zip(&lambda).filter(|&(&u, &l)| l < 0.0 && u > -0.1).count();
    assert!(pushing_above > 0, "no step pushes with u_0 above −gap: the case no longer tells the two readings apart");
    let episodes = (0..lambda.len()).filter(|&n| lambda[n] < 0.0 && (n == 0 || lambda[n - 1] >= 0.0)).count();
    assert_eq!(episodes, 1);
    let (impact, release) = (run.summary.first_impact_time.unwrap(), run.summary.first_release_time.unwrap());
    assert!(((release - impact) - 2.0).abs() <= 0.02 * 2.0, "contact {impact} .. {release}");
}

/// The summary says which estimator gave Δt_c (issue 32, item 3): on the free–free uniform chain
/// with the standard lumped mass (Δt_c = h/c exactly, the mode (−1)^i) Lanczos converges at
/// m = 20 (21 unknowns: it exhausts the space; ~1e-12 relative) and stops unconverged at
/// m = 2000, where the Gershgorin bound is taken (attained here: h/c to 1e-12); an implicit
/// scheme has neither key. mutation: "lanczos" for both estimators in
/// CentralDifference::stable_limit -> the m = 2000 case fails.
#[test]
fn the_summary_names_the_stable_limits_estimator() {
    use massredist::scene::BarScene;
    let summary = |m: usize, scheme: &str| {
        let h = 1.0 / m as f64;
        let text = format!(
            "[bar]\nlength = 1.0\nelements = {m}\nfar_end = \"free\"\ngap = 10.0\n\
             initial = {{ displacement = \"0\", velocity = \"0\" }}\n[mass]\nkind = \"standard\"\n\
             [scheme]\nkind = \"{scheme}\"\n[time]\ndt = {}\nend = {}\n",
            0.5 * h,
            h
        );
        massredist::run::run_scene(&BarScene::from_toml(&text).unwrap(), &mut []).unwrap().summary
    };
    for (m, estimator) in [(20, "lanczos"), (2000, "gershgorin")] {
        let s = summary(m, "central-difference");
        assert_eq!(s.stable_step_method, Some(estimator), "m = {m}");
        let limit = s.stable_step.unwrap();
        assert!(approx::relative_eq!(limit * m as f64, 1.0, epsilon = 1e-11, max_relative = 0.0), "m = {m}: {limit:e}");
    }
    let s = summary(20, "crank-nicolson");
    assert_eq!((s.stable_step, s.stable_step_method), (None, None));
}

/// Lanczos runs to convergence on the comparison's bars (issue 32, item 3): up to
/// [`massredist::schemes::stable_limit::EXHAUST`] interior unknowns it is not capped, so the
/// uniform bar of m = 400 elements (whose clustered top spectrum kept it unconverged at 300
/// steps, and the Gershgorin fallback then set Verlet-with-Nitsche's step to 0.126 h/c) has
/// Δt_c from Lanczos for every law and mass. Checked: the standard mass's is h/c (the free–free
/// chain's exact value, the mode (−1)^i) to 1e-11; with mod3 the massless contact node leaves the
/// free bar's Δt_c slightly above h/c (1 + O(1/m²): measured 1.0000319, 1.0000078, 1.0000019 h/c
/// at m = 100, 200, 400, a ratio of 4 per doubling), and Nitsche's term on the massless node does
/// not lower it (measured equal to 4e-12 relative, within REL_TOL's stated accuracy times the
/// window). mutation: EXHAUST = 0 -> "gershgorin" at m = 400, fails.
#[test]
fn lanczos_converges_on_the_comparisons_bars() {
    use massredist::scene::BarScene;
    let m = 400;
    let summary = |mass: &str, law: &str| {
        let text = format!(
            "[bar]\nlength = 1.0\nelements = {m}\nfar_end = \"free\"\ngap = 0.1\n\
             initial = {{ displacement = \"0\", velocity = \"-1\" }}\n[mass]\nkind = \"{mass}\"\n\
             [scheme]\nkind = \"central-difference\"\n[contact]\n{law}\n[time]\ndt = 1e-4\nend = 1e-3\n"
        );
        let s = massredist::run::run_scene(&BarScene::from_toml(&text).unwrap(), &mut []).unwrap().summary;
        assert_eq!(s.stable_step_method, Some("lanczos"), "{mass} {law}");
        s.stable_step.unwrap() * m as f64
    };
    let standard = summary("standard", "method = \"exact\"");
    assert!(approx::relative_eq!(standard, 1.0, epsilon = 1e-11, max_relative = 0.0), "{standard}");
    let exact = summary("mod3", "method = \"exact\"");
    let nitsche = summary("mod3", "method = \"nitsche\"\nnitsche_theta = 1\nnitsche_gamma0 = 100.0");
    assert!(exact > 1.0 && exact < 1.0 + 1.0 / (m * m) as f64, "mod3: {exact}");
    assert!((nitsche - exact).abs() <= 1e-10 * exact, "Nitsche {nitsche} against exact {exact}");
}
