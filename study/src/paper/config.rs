//! What `massredist reproduce` runs: the bar, the mesh, Δt and the horizons.

use super::ReproduceError;
use massredist::exact::ImpactingBar;
use serde::Serialize;

/// What to run. [`Config::paper`] is the paper's setting; [`Config::quick`] a reduced one (tests).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Config {
    /// Bar length L (paper: 1).
    pub length: f64,
    /// Number of elements m (paper: 6, Δx = 1/6).
    pub elements: usize,
    /// Time step (paper: 1/100).
    pub dt: f64,
    /// Final times of the solution and energy figures of every scheme (the paper: 3).
    pub horizons: Vec<f64>,
    /// Final times of the long Paoli–Schatzman energy runs.
    pub long_ends: Vec<f64>,
    /// Points per curve in the long runs' raw-energy panel and CSV (the summary and the
    /// per-period extremes see every step).
    pub long_points: usize,
    /// Run the full 2D sensitivity sweep of Table 1 (cells × scheme × Δt × T); else a small one.
    pub full_2d_sweep: bool,
}

impl Config {
    /// Δx = 1/6, Δt = 1/100; T = 3 (the paper's figures) and T = 9 (three periods); the
    /// Paoli–Schatzman energy over 100 periods (T = 300) and 1000 periods (T = 3000).
    pub fn paper() -> Config {
        Config {
            length: 1.0,
            elements: 6,
            dt: 0.01,
            horizons: vec![3.0, 9.0],
            long_ends: vec![300.0, 3000.0],
            long_points: 3000,
            full_2d_sweep: true,
        }
    }

    /// The same experiments with a shorter long run (T = 3 and 9, long run T = 30; the third period
    /// of T = 9 is where the standard mass's events depend on round-off, which
    /// `tests/roundoff_audit.rs` must see) and a small 2D sweep: every kind of
    /// figure, CSV and table of [`Config::paper`] is produced, in less time.
    pub fn quick() -> Config {
        Config { horizons: vec![3.0, 9.0], long_ends: vec![30.0], full_2d_sweep: false, ..Config::paper() }
    }

    /// Recording cadence of a long run: at most `long_points` + 1 samples.
    pub fn long_every(&self, steps: usize) -> usize {
        steps.div_ceil(self.long_points.max(1)).max(1)
    }

    /// Steps to reach `end`, which must be a whole multiple of dt.
    pub fn steps(&self, what: &'static str, end: f64) -> Result<usize, ReproduceError> {
        let ratio = end / self.dt;
        let steps = ratio.round();
        if !(steps >= 1.0 && (steps - ratio).abs() <= 1e-9 * ratio) {
            return Err(ReproduceError::Horizon { what, value: end, dt: self.dt });
        }
        Ok(steps as usize)
    }

    /// The paper's exact solution on this bar (§4.1).
    pub(super) fn exact(&self) -> ImpactingBar {
        ImpactingBar { length: self.length }
    }

    /// Mesh size h = L/m.
    pub(super) fn h(&self) -> f64 {
        self.length / self.elements as f64
    }
}
