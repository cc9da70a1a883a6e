//! Per-period energy of a long run: an observer that keeps the energy extremes of every period
//! 3L of the exact solution, the growth of the per-period maximum from the first periods to the
//! last, and the growth above which a run counts as drifting ([`DRIFT_FACTOR`]). Read by the
//! runs ([`super::runs`]) and by the round-off band's verdict ([`super::band`]).

use massredist::driver::{Needs, Observer, Sample};

/// Growth factor of the per-period maximum energy above which a long run counts as drifting.
pub const DRIFT_FACTOR: f64 = 1.05;

/// Energy extremes per period 3L of the exact solution, from every step after the first
/// (t_0 is left out: with w_0 = 0 the first step drops the energy by about h/8, see the report).
/// Period j holds the steps with t_n in [3jL, 3(j+1)L); the last one may be partial.
#[derive(Debug, Clone, Default)]
pub struct PeriodEnergy {
    period: f64,
    dt: f64,
    pub max: Vec<f64>,
    pub min: Vec<f64>,
}

impl PeriodEnergy {
    pub fn new(period: f64, dt: f64) -> Self {
        Self { period, dt, max: Vec::new(), min: Vec::new() }
    }

    /// The end time of period j.
    pub fn end_of(&self, j: usize) -> f64 {
        (j + 1) as f64 * self.period
    }

    /// (max energy over the first k full periods, over the last k, k) with k = min(10, full/2)
    /// of a run to `end`; None with fewer than two full periods.
    pub fn growth(&self, end: f64) -> Option<(f64, f64, usize)> {
        // Full periods: those ending by the final time (the sample at t = end may open a new one).
        let full = (0..self.max.len()).take_while(|&j| self.end_of(j) <= end + 1e-9 * end).count();
        let k = (full / 2).min(10);
        if k == 0 {
            return None;
        }
        let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Some((max(&self.max[..k]), max(&self.max[full - k..full]), k))
    }
}

impl Observer for PeriodEnergy {
    fn needs(&self) -> Needs {
        Needs { energy: true, ..Needs::default() }
    }

    fn observe(&mut self, s: &Sample) {
        if s.state.n == 0 {
            return;
        }
        // Half a step of slack: t_n = n·Δt may round just below a period boundary.
        let j = ((s.state.t + 0.5 * self.dt) / self.period).floor() as usize;
        if self.max.len() <= j {
            self.max.resize(j + 1, f64::NEG_INFINITY);
            self.min.resize(j + 1, f64::INFINITY);
        }
        self.max[j] = self.max[j].max(s.energy);
        self.min[j] = self.min[j].min(s.energy);
    }
}
