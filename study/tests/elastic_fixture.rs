//! The elastic table's fixture (`fixtures/elastic-reference.json`, module docs of
//! `massredist_study::paper::elastic_fixture`): its coarse set, recomputed here by the code that
//! wrote it (a 40² reference up to T = 3 and the quick grid's free-face runs against it), must
//! match what is stored; a change to the reference, the solid, the schemes or the error that
//! would change the full set changes the coarse one too, and this test says to regenerate.

use approx::assert_relative_eq;
use massredist_study::paper::elastic_fixture::{self, COARSE};

#[test]
fn the_coarse_set_matches_a_fresh_computation() {
    let stored = elastic_fixture::load().expect("fixtures/elastic-reference.json reads");
    let fresh = elastic_fixture::compute_set(COARSE.0, COARSE.1, true).expect("the coarse set computes");
    let old = &stored.coarse;
    assert_eq!((fresh.cells, fresh.end, &fresh.ends), (old.cells, old.end, &old.ends));
    assert_eq!(fresh.runs.len(), old.runs.len(), "the same runs");
    // The stored perturbed copies (U⁰ moved by ≤ 1e-13) move these errors by a relative spread
    // s; another evaluation order of the same arithmetic (another CPU or compiler) moves them by
    // round-off of that order, so 10 s (at least 1e-12) separates round-off from a change.
    let spread = old
        .runs
        .iter()
        .filter_map(|r| {
            let base = old.runs.iter().find(|b| {
                b.copy.is_none() && (&b.cells, &b.scheme, b.dt, &b.mass) == (&r.cells, &r.scheme, r.dt, &r.mass)
            })?;
            let (a, b) = (r.errors.as_ref().ok()?, base.errors.as_ref().ok()?);
            a.iter()
                .zip(b)
                .filter_map(|(x, y)| Some(((x.as_ref()? - y.as_ref()?) / y.as_ref()?).abs()))
                .reduce(f64::max)
        })
        .fold(0.0, f64::max);
    let tol = (10.0 * spread).max(1e-12);
    for (f, o) in fresh.runs.iter().zip(&old.runs) {
        assert_eq!((&f.cells, &f.scheme, f.dt, &f.mass, f.copy), (&o.cells, &o.scheme, o.dt, &o.mass, o.copy));
        let (fe, oe) = (f.errors.as_ref().expect("fresh run"), o.errors.as_ref().expect("stored run"));
        for (x, y) in fe.iter().zip(oe) {
            let (x, y) = (x.expect("fresh value"), y.expect("stored value"));
            assert_relative_eq!(x, y, epsilon = 1e-15, max_relative = tol);
        }
    }
    for (x, y) in fresh.self_difference.iter().zip(&old.self_difference) {
        assert_relative_eq!(x.expect("fresh"), y.expect("stored"), epsilon = 1e-15, max_relative = tol);
    }
}

#[test]
fn the_full_set_covers_every_free_face_run_of_the_table() {
    let stored = elastic_fixture::load().expect("fixtures/elastic-reference.json reads");
    // 2 cells × 3 schemes × 5 Δt × 3 masses, each unperturbed and in 4 copies; T = 1, 2, 3, 10.
    assert_eq!(stored.full.runs.len(), 2 * 3 * 5 * 3 * 5);
    assert_eq!(stored.full.ends, [1.0, 2.0, 3.0, 10.0]);
    assert_eq!((stored.full.cells, stored.full.end), (160, 10.0));
    assert!(stored.full.runs.iter().all(|r| r.errors.as_ref().is_ok_and(|e| e.len() == 4)));
}
