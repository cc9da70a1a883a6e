//! The rebounding bar of `massredist reproduce` (its section): the exact facts the section takes
//! from the solution by characteristics, and the schemes' rebound on the paper's mesh.

use massredist::bar::BarProblem;
use massredist::mass::MassKind;
use massredist::scene::BarScene;
use massredist_study::paper::{self, Config, Experiment};

#[test]
fn the_rebounding_bar_s_exact_facts_hold_to_round_off() {
    // What the section takes from the exact solution by characteristics: one contact phase
    // [gap, gap + 2L/c), λ = −sqrt(Eρ)·|v⁰| at every t_n inside it, u(0, t) = −gap there, the
    // rebound velocity +|v⁰| = 1 and the energy ½ρL — for the section's bar and two other
    // materials. Mutation check: letting `exact_rebound` sample λ on the closed interval
    // [start, end] takes λ(end) = 0 (the contact is over) and fails the force assertion.
    let config = Config::quick();
    for (density, modulus) in [(1.0_f64, 1.0_f64), (4.0, 1.0), (1.0, 2.25)] {
        let text = paper::rebound_scene_text(&config, Experiment::CrankNicolson, &MassKind::Mod3)
            .replace("density = 1.0", &format!("density = {density:?}"))
            .replace("modulus = 1.0", &format!("modulus = {modulus:?}"));
        let c = (modulus / density).sqrt();
        // T covers the contact, 2L/c = 4 for the slow bar, and the window after it.
        let text = text.replace("end = 3.0", &format!("end = {:?}", (0.1 + 2.0 / c + 1.0).ceil()));
        let scene = BarScene::from_toml(&text).unwrap();
        let exact = BarProblem::from_scene(&scene).unwrap().exact.expect("exact by characteristics");
        let (gap, l) = (scene.geometry.gap, scene.geometry.length);
        let facts = paper::exact_rebound(&exact, config.elements, config.dt, scene.time.end).unwrap();
        let label = format!("rho {density} E {modulus}");
        eprintln!("{label}: {facts:?}");
        // Round-off: the waves are piecewise linear (v⁰ constant), each reflection and switch a
        // few ulps of O(1) quantities (module docs of characteristics); 64 ε of the scale.
        let tol = 64.0 * f64::EPSILON;
        assert_eq!(facts.contacts.len(), 1, "{label}: {:?}", facts.contacts);
        let (start, end) = facts.contacts[0];
        assert!((start - gap).abs() <= tol * gap, "{label}: impact {start}");
        assert!((end - (gap + 2.0 * l / c)).abs() <= tol * end, "{label}: release {end}");
        let force = -(modulus * density).sqrt();
        for f in [facts.force.0, facts.force.1] {
            assert!((f - force).abs() <= tol * force.abs(), "{label}: λ {f} vs {force}");
        }
        assert!((facts.rebound_velocity - 1.0).abs() <= tol, "{label}: {}", facts.rebound_velocity);
        assert!((facts.energy - 0.5 * density * l).abs() <= tol * facts.energy, "{label}: {}", facts.energy);
        for n in 0..=scene.time.steps {
            let t = n as f64 * config.dt;
            if t > start && t < end {
                assert!((exact.u0(t) + gap).abs() <= tol, "{label}: u(0, {t}) = {}", exact.u0(t));
            }
        }
    }
}

#[test]
fn crank_nicolson_and_hybrid_with_mod3_rebound_at_plus_one_and_impact_on_time() {
    // On the paper's mesh (m = 6, Δt = 0.01): the bar leaves with velocity +1 within 2 % (the
    // conservative schemes with the mass-conserving redistribution; the discrete contact lasts a
    // few steps more or less than 2L/c, which the momentum balance turns into a velocity error
    // of a few per cent at h = 1/6), and the first impact is within one Δt of t = gap (events
    // are read on the grid; u(0, gap) = −gap is met only up to the rounding of n·Δt). Mutation
    // check: measuring the velocity over [0.5, T] instead of [T − 0.5, T] in `BarMotion`
    // averages over the contact (CN: 0.477) and fails the first assertion.
    let config = Config::quick();
    for e in [Experiment::CrankNicolson, Experiment::Hybrid] {
        let r = paper::run_rebound(&config, e, &MassKind::Mod3).unwrap();
        assert!(r.failure.is_none());
        let v = r.rebound_velocity.unwrap();
        assert!((v - 1.0).abs() <= 0.02, "{e:?}: rebound velocity {v}");
        let shift = r.summary.impact_time_shift.unwrap();
        assert!(shift.abs() <= config.dt * (1.0 + 1e-9), "{e:?}: impact shift {shift}");
    }
}

#[test]
fn the_chattering_rebound_row_is_rerun_from_perturbed_velocities() {
    // Crank–Nicolson with the standard mass chatters: `run_rebound` reruns it from v⁰ changed by
    // ±1e-13 and ±2e-13 (the report then shows bands). Each rerun is an independent `run_scene`
    // of the section's scene with `velocity = "-1-2e-13"` etc., to the last bit, and the five
    // errors spread by far more than round-off (so the unperturbed digits are no result).
    // Mutation check: ignoring `dv` in the scene text makes every rerun the unperturbed run and
    // fails the first assertion.
    let config = Config::paper();
    let r = paper::run_rebound(&config, Experiment::CrankNicolson, &MassKind::Standard).unwrap();
    assert_eq!(r.copies.len(), paper::REBOUND_DV.len());
    let base = paper::rebound_scene_text(&config, Experiment::CrankNicolson, &MassKind::Standard);
    for (dv, copy) in paper::REBOUND_DV.iter().zip(&r.copies) {
        let text = base.replace("velocity = \"-1\"", &format!("velocity = \"-1{dv:+e}\""));
        assert_ne!(text, base);
        let scene = BarScene::from_toml(&text).unwrap();
        let run = massredist::run::run_scene(&scene, &mut []).unwrap();
        assert_eq!(copy.summary.linf_l2_error, run.summary.linf_l2_error, "dv = {dv:e}");
    }
    let errors: Vec<f64> = r.over_runs(|s, _, _, _| s.linf_l2_error.unwrap());
    let (lo, hi) = errors.iter().fold((f64::INFINITY, 0.0_f64), |(a, b), &e| (a.min(e), b.max(e)));
    // Round-off alone would move a 4-digit error by ~1e-12; the chatter moves it by tens of %.
    assert!(hi / lo > 1.1, "{errors:?}");
    // No other case is rerun.
    let mod3 = paper::run_rebound(&config, Experiment::CrankNicolson, &MassKind::Mod3).unwrap();
    assert!(mod3.copies.is_empty());
}
