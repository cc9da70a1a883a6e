//! Two elastic bodies in contact (issue 30, `[[solid]]` and `[[pair]]`): the d'Alembert checks
//! of two bars meeting end to end ([`TwoBars`]: duration, force, final momenta, and the rate and
//! overshoot the issue reports), the total momentum of two free bodies through their impact for
//! every scheme, a non-matching interface (node to segment), the reports, and the refusals.

use massredist::models::{TwoBarCase, TwoBars};
use massredist::observe::Column;
use massredist::run::run_scene;
use massredist::scene::SolidScene;

/// mod3 on both bodies, Crank–Nicolson, cΔt/h = 1, at n = 100, 200, 400 cells per unit length.
/// Checked against the exact events: the errors of the contact duration and of the final
/// momenta fall at least like n^-0.4 (the issue's independent run saw n^-0.6; measured here
/// 0.5–0.8 per doubling), the mean force on the plateau is Z V/2 to 1e-5 (measured 1.3e-6 at
/// n = 100, 3e-8 at 400), and the peak overshoots to the same 1.2575 Z V/2 at every n (the
/// issue's "about 1.26 at every resolution": the same value to 1e-9, a property of the
/// discrete interface, not an error that refines away). (c) is released by the force at 2L₁/c
/// (`contact_time`, within 2.5 %), not at 2L₂/c when its ends part.
#[test]
fn two_bars_follow_dalembert_at_the_issues_rate_and_overshoot() {
    // mutation: the coupling's coefficient N_k ν·e_c with the sign flipped (coupling.rs) → the
    // bodies pass through each other: no crossing, this fails.
    for case in TwoBarCase::ALL {
        let runs: Vec<_> = [100, 200, 400]
            .into_iter()
            .map(|n| {
                let bars = TwoBars::new(case, n);
                (bars.clone(), bars.measure(&bars.scene("mod3", "crank-nicolson")).0)
            })
            .collect();
        let (first, last) = (&runs[0].1, &runs[2].1);
        let slowest = 4f64.powf(-0.4);
        for (what, e0, e2) in [("duration", first.duration, last.duration), ("momentum", first.momentum, last.momentum)]
        {
            assert!(e2 <= e0 * slowest, "{}: {what} error {e0:e} at n = 100, {e2:e} at n = 400", case.name());
        }
        for (bars, e) in &runs {
            assert!(e.plateau <= 1e-5, "{} n = {}: plateau {e:?}", case.name(), bars.n);
            assert!((e.peak - first.peak).abs() <= 1e-9 && (1.25..1.27).contains(&e.peak), "{}: {e:?}", case.name());
            // The sum of the steps with Σ R > 0: 2.04, 2.025, 2.015 for (c) at n = 100, 200,
            // 400 (small forces last after the striker stops), 2.01–2.005 for (a), 4.01–4.005
            // for (b); far from 2L₂/c = 4 where (c)'s ends part.
            assert!(
                (e.contact_time - bars.duration()).abs() <= 0.025 * bars.duration(),
                "{} n = {}: contact_time {} against {}",
                case.name(),
                bars.n,
                e.contact_time,
                bars.duration()
            );
        }
    }
}

/// (a) at 1600 cells per unit length: the duration between the half-force crossings, the
/// plateau force and both final momenta to the contract's 1e-3 (measured 7e-4, 1e-9, 7.6e-4
/// with the rate of the test above: 1.2e-3 and 1.5e-3 at n = 800).
#[test]
fn two_bars_onto_a_free_bar_meet_the_contracts_1e_3_at_1600_cells() {
    let bars = TwoBars::new(TwoBarCase::Free, 1600);
    let (e, _) = bars.measure(&bars.scene("mod3", "crank-nicolson"));
    assert!(e.duration <= 1e-3 && e.plateau <= 1e-3 && e.momentum <= 1e-3, "{e:?}");
}

/// Two free bodies with no external force keep their total momentum through the impact, every
/// scheme that takes them, to the contract's 1e-12 relative: on 20 cells per unit length
/// (60 steps). The drift is round-off of S u for the rigid motion u ~ V t, growing like t²
/// and with the stiffness: 1e-11 at 100 cells per unit length (300 steps), as for one free
/// body in free flight (1.1e-11 there, measured with the same mesh): not the pair's coupling.
#[test]
fn two_free_bodies_keep_their_momentum_through_the_impact_with_every_scheme() {
    // mutation: the congruence Tᵀ A T without E's entries (coupling.rs `expand`) → the target
    // feels no force: the momentum breaks by 2 (measured 1.98).
    for (scheme, mass) in [
        ("crank-nicolson", "mod3"),
        ("crank-nicolson", "standard"),
        ("newmark", "mod3"),
        ("backward-euler", "mod3"),
        ("backward-euler", "standard"),
        ("hybrid", "mod3"),
        ("central-difference", "mod3"),
        ("moreau-jean", "standard"),
    ] {
        let bars = TwoBars::new(TwoBarCase::Free, 20);
        let (e, series) = bars.measure(&bars.scene(mass, scheme));
        let p0 = bars.density * bars.height * bars.speed;
        let drift = series.total.iter().map(|p| (p - p0).abs()).fold(0.0, f64::max) / p0;
        assert!(drift <= 1e-12, "{scheme} {mass}: momentum drift {drift:e}");
        assert!(series.force.iter().any(|&f| f > 0.0), "{scheme} {mass}: no impact ({e:?})");
    }
}

/// A scene text of two strips with `ny1` and `ny2` cells across (non-matching when they
/// differ), the striker at speed 1.
fn strips(ny1: usize, ny2: usize, extra: &str) -> String {
    format!(
        "[[solid]]\nname = \"striker\"\nlength = 1.0\nheight = 0.5\nnx = 20\nny = {ny1}\nlame_mu = 0.5\noffset = [-1.0, 0.0]\n\
         initial = {{ velocity = [\"1\", \"0\"] }}\n\
         [[solid]]\nname = \"target\"\nlength = 1.0\nheight = 0.5\nnx = 20\nny = {ny2}\nlame_mu = 0.5\n\
         [[pair]]\nname = \"impact\"\nbodies = [\"striker\", \"target\"]\ngroups = [\"xmax\", \"xmin\"]\n\
         [mass]\nkind = \"mod3\"\n[scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = 0.05\nend = 3.0\n{extra}"
    )
}

/// A non-matching interface (3 against 4 cells across): node to segment. The momentum is kept
/// as on a matching one (1e-12), the pair's reaction equals the force on the target
/// (P_target(t) = ∫ Σ R dt, the trapezoid rule of CN: to 1e-12 of the momentum), and the
/// contact lasts 2L/c to the matching interface's accuracy (the same 20 cells along x: within
/// 3 Δt of it).
#[test]
fn a_non_matching_interface_is_node_to_segment_and_keeps_momentum() {
    let series = "[output]\nseries = [\"momentum_x\", \"impact.contact_force\", \"target.momentum_x\"]\n";
    let run = |ny1, ny2| {
        let s = SolidScene::from_toml(&strips(ny1, ny2, series)).unwrap_or_else(|e| panic!("{e}"));
        run_scene(&s, &mut []).unwrap_or_else(|e| panic!("{e}"))
    };
    let named = |r: &massredist::run::SceneRun<_>, name: &str| {
        let c = *r.series.columns.iter().find(|c: &&Column| c.name() == name).expect("recorded");
        r.series.column(c).expect("recorded")
    };
    let time =
        |r: &massredist::run::SceneRun<_>| r.summary.own["pairs"]["impact"]["contact_time"].as_f64().expect("a number");
    let (matching, other) = (run(3, 3), run(3, 4));
    let p0 = 0.5;
    for r in [&matching, &other] {
        let total = r.series.column(Column::Momentum(0)).expect("recorded");
        let drift = total.iter().map(|p| (p - p0).abs()).fold(0.0, f64::max) / p0;
        assert!(drift <= 1e-12, "momentum drift {drift:e}");
        // Crank–Nicolson's momentum balance of the target: ΔP = Δt (R^n + R^(n+1))/2.
        let (force, target) = (named(r, "impact.contact_force"), named(r, "target.momentum_x"));
        let mut impulse = 0.0;
        for k in 1..force.len() {
            impulse += 0.05 * 0.5 * (force[k - 1] + force[k]);
            assert!((target[k] - impulse).abs() <= 1e-12 * p0, "step {k}: {} against {impulse}", target[k]);
        }
    }
    assert!((time(&matching) - time(&other)).abs() <= 3.0 * 0.05, "{} against {}", time(&matching), time(&other));
}

/// What a multi-body run reports: the nested `pairs` and `bodies` objects, the dotted columns
/// of the default series (every pair's contact force, every body's momentum), and the totals.
#[test]
fn several_bodies_report_per_pair_and_per_body() {
    let s = SolidScene::from_toml(&strips(3, 3, "")).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = s.output.series.iter().map(|c| c.name()).collect();
    assert_eq!(
        names,
        [
            "energy",
            "contact_force",
            "momentum_x",
            "momentum_y",
            "impact.contact_force",
            "striker.momentum_x",
            "striker.momentum_y",
            "target.momentum_x",
            "target.momentum_y"
        ]
    );
    let r = run_scene(&s, &mut []).unwrap_or_else(|e| panic!("{e}"));
    let own = &r.summary.own;
    for key in ["max_contact_force", "min_distance", "final_active_nodes", "contact_time"] {
        assert!(own["pairs"]["impact"][key].is_number(), "pairs.impact.{key}: {own:?}");
    }
    // The bodies' momenta add up to the total, the striker's and the target's each.
    let body = |name: &str| own["bodies"][name]["final_momentum"][0].as_f64().expect("a number");
    let total = own["final_momentum"][0].as_f64().expect("a number");
    assert!((body("striker") + body("target") - total).abs() <= 1e-14, "{own:?}");
    assert!(body("target") > 0.4 && body("striker").abs() < 0.1, "velocities swap: {own:?}");
}

/// `strips` with the pair's own law `law` (`pair.contact`).
fn with_law(text: &str, law: &str) -> String {
    text.replace("groups = [\"xmax\", \"xmin\"]", &format!("groups = [\"xmax\", \"xmin\"]\ncontact = {law}"))
}

/// A pair's own law (`pair.contact`, the contract's optional key) is the scene's law: the exact
/// law written in the pair runs bit for bit as without it, the penalty law written in the pair
/// as the penalty law written in `[contact]` (and the resolved file, which writes it in
/// `[contact]`, reads back to the same run). mutation: the pair's law ignored in
/// src/scene/common.rs (`contact = law` left out) → the penalty pair runs the exact law: the
/// energies differ.
#[test]
fn a_pairs_own_law_is_the_scenes_law() {
    let run = |text: &str| {
        let s = SolidScene::from_toml(text).unwrap_or_else(|e| panic!("{e}"));
        run_scene(&s, &mut []).unwrap_or_else(|e| panic!("{e}")).summary
    };
    let base = strips(3, 3, "");
    let key = |s: &massredist::observe::Summary| (s.energy_final.to_bits(), s.final_contact_force.to_bits());
    assert_eq!(key(&run(&with_law(&base, "{ method = \"exact\" }"))), key(&run(&base)));
    let penalty = "{ method = \"penalty\", penalty = 50.0 }";
    let in_pair = with_law(&base, penalty);
    let in_contact = format!("{base}[contact]\nmethod = \"penalty\"\npenalty = 50.0\n");
    let (a, b) = (run(&in_pair), run(&in_contact));
    assert_eq!(key(&a), key(&b));
    assert_ne!(key(&a), key(&run(&base)), "the penalty law runs as the exact one");
    let resolved = SolidScene::from_toml(&in_pair).unwrap_or_else(|e| panic!("{e}")).resolved_toml();
    assert_eq!(key(&run(&resolved)), key(&a), "{resolved}");
    // Given in every pair and in [contact] alike: accepted.
    assert_eq!(key(&run(&format!("{in_pair}[contact]\nmethod = \"penalty\"\npenalty = 50.0\n"))), key(&a));
}

/// Two blocks stacked on a rigid plane under their weight (`[obstacle]` beside a `[[pair]]`):
/// backward Euler to rest, the pair carries the upper block's weight and the plane both, to
/// round-off of the static balance (1e-10 of the weight: the balance of the curved obstacles'
/// test). "auto" gives the plane the lower block's bottom only: the upper block's bottom faces
/// the plane too, but its nodes are the pair's. mutation: the obstacle's nodes left out of the
/// contact set (bodies.rs `obstacle_contact` returning none) → the stack falls through the
/// plane: refused as no node meeting it, this fails.
#[test]
fn a_stack_on_a_plane_carries_its_weight_through_the_pair_and_the_obstacle() {
    let text = "[[solid]]\nname = \"lower\"\nlength = 1.0\nheight = 0.5\nnx = 4\nny = 2\nlame_lambda = 1.0\nlame_mu = 1.0\n\
        force = [\"0\", \"-1\"]\n\
        [[solid]]\nname = \"upper\"\nlength = 1.0\nheight = 0.5\nnx = 4\nny = 2\nlame_lambda = 1.0\nlame_mu = 1.0\n\
        offset = [0.0, 0.5]\nforce = [\"0\", \"-1\"]\n\
        [[pair]]\nname = \"joint\"\nbodies = [\"upper\", \"lower\"]\ngroups = [\"ymin\", \"ymax\"]\n\
        [obstacle]\nnormal = [0.0, 1.0]\npoint = [0.0, 0.0]\n\
        [mass]\nkind = \"standard\"\n[scheme]\nkind = \"backward-euler\"\n[time]\ndt = 1.0\nend = 400.0\n";
    let s = SolidScene::from_toml(text).unwrap_or_else(|e| panic!("{e}"));
    let system = massredist::run::setup(&s).unwrap_or_else(|e| panic!("{e}")).problem.system;
    // 5 pair nodes (the upper block's bottom) and 5 plane nodes (the lower block's bottom).
    assert_eq!(system.contact_nodes.len(), 10, "{:?}", system.contact_nodes);
    let r = run_scene(&s, &mut []).unwrap_or_else(|e| panic!("{e}"));
    let own = &r.summary.own;
    let pair = own["pairs"]["joint"]["max_contact_force"].as_f64().expect("a number");
    let last = &r.last.lambda;
    let pair_now: f64 = -last[..5].iter().sum::<f64>();
    let plane_now: f64 = -last[5..].iter().sum::<f64>();
    // ρ g |Ω|: 0.5 for the upper block, 1 for both.
    assert!((pair_now - 0.5).abs() <= 1e-10 && (plane_now - 1.0).abs() <= 1e-10, "{pair_now} {plane_now} (max {pair})");
}

/// Refusals name the key and what is allowed.
#[test]
fn refusals_of_several_bodies_name_the_key() {
    let base = strips(3, 3, "");
    let cases: [(String, &str); 11] = [
        (base.replace("bodies = [\"striker\", \"target\"]", "bodies = [\"striker\", \"anvil\"]"), "pair.bodies"),
        (base.replace("groups = [\"xmax\", \"xmin\"]", "groups = [\"xmax\", \"left\"]"), "pair.groups = \"left\""),
        (base.replacen("name = \"striker\"\n", "", 1), "solid.name"),
        (base.replace("name = \"impact\"", "name = \"im.pact\""), "pair.name"),
        (
            base.replace("[mass]\nkind = \"mod3\"", "[mass]\nkind = \"mod3\"\ncontact_directions = \"normal\""),
            "mass.contact_directions",
        ),
        (
            base.replace("[mass]\nkind = \"mod3\"", "[mass]\nkind = \"standard\"")
                .replace("crank-nicolson", "central-difference"),
            "scheme.kind",
        ),
        (
            format!("{base}[obstacle]\nnormal = [1.0, 0.0]\npoint = [-2.0, 0.0]\ncontact = \"nothing\"\n"),
            "obstacle.contact = \"nothing\"",
        ),
        (format!("{base}[obstacle]\nnormal = [1.0, 0.0]\n"), "[obstacle] against body \"striker\""),
        (
            format!("{}[contact]\nmethod = \"exact\"\n", with_law(&base, "{ method = \"penalty\", penalty = 10.0 }")),
            "pair.contact = method = \"penalty\" does not go with [contact] method = \"exact\"",
        ),
        (with_law(&base, "{ method = \"exact\", penalty = 10.0 }"), "pair.contact (the keys of [contact])"),
        (format!("{base}[contact]\nfriction = \"coulomb\"\ncoefficient = 0.3\n"), "friction"),
    ];
    for (text, key) in cases {
        let e = SolidScene::from_toml(&text).expect_err(key).to_string();
        assert!(e.contains(key), "expected {key}: {e}");
    }
    let one = "[solid]\nname = \"x\"\n";
    assert!(SolidScene::from_toml(one).unwrap_err().to_string().contains("solid.name"));
    let pair = "[solid]\n[[pair]]\nname = \"p\"\n";
    assert!(SolidScene::from_toml(pair).unwrap_err().to_string().contains("[[pair]]"));
}
