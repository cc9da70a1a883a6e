//! Repeated timing with the fastest run kept: the clock shared by [`super::perf`] (per-step
//! timings against the bare solves) and [`super::sweep`] (the solve time of each sweep run).

use std::time::Instant;

/// Repeats `run` (which does `work` units) until `min_total` seconds have elapsed or `max_reps`
/// runs are done (at least `min_reps`), and returns the fastest run in ns per unit. The minimum is
/// the estimate least disturbed by other processes on a shared machine.
pub fn best_ns_per_unit(work: f64, min_reps: usize, max_reps: usize, min_total: f64, mut run: impl FnMut()) -> f64 {
    best_timed(work, min_reps, max_reps, min_total, || {
        let t = Instant::now();
        run();
        t.elapsed().as_secs_f64()
    })
}

/// As [`best_ns_per_unit`] for a `run` that returns the seconds of its own timed part.
pub fn best_timed(work: f64, min_reps: usize, max_reps: usize, min_total: f64, mut run: impl FnMut() -> f64) -> f64 {
    let started = Instant::now();
    let mut best = f64::INFINITY;
    let mut reps = 0;
    while reps < min_reps || (reps < max_reps && started.elapsed().as_secs_f64() < min_total) {
        best = best.min(run());
        reps += 1;
    }
    best * 1e9 / work
}
