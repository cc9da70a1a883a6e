//! The validated scene: what the parser (`crate::scene`, TOML --validate-->) hands to the
//! geometries and the run path (--assemble--> system). It sits below both, so that a geometry
//! reads its scene without importing the parser; `crate::scene` re-exports every type here.

use crate::observe::Column;
use crate::schemes::SchemeSpec;

/// A validated scene: one geometry (`G`: `BarSpec`, `PlateSpec`, `SolidSpec`) and the sections every
/// scene shares. A scene file is read as a `crate::scene::AnyScene`, whose variant is the geometry table
/// the file has.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene<G> {
    pub geometry: G,
    pub mass: crate::mass::MassKind,
    pub scheme: SchemeSpec,
    /// The contact law (`[contact]`; default exact).
    pub contact: crate::contact::law::ContactLaw,
    pub time: TimeSpec,
    pub output: OutputSpec,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeSpec {
    pub dt: f64,
    pub end: f64,
    pub steps: usize,
}

impl TimeSpec {
    /// Where an exact solution must be defined: up to the last step's time as the schemes
    /// compute it, `steps · dt`, which may pass `end` by a rounding (Δt = 0.1·0.1 and end = 3
    /// give 300·Δt = 3.0000000000000004). The run ends at step `steps`, an index; its time is
    /// never compared with `end` (issue 32, E5).
    pub fn exact_end(&self) -> f64 {
        self.end.max(self.steps as f64 * self.dt)
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct OutputSpec {
    pub series: Vec<Column>,
    pub every: usize,
    /// Compute the exact L² error at every step for the summary's `linf_l2_error` (one O(m) pass
    /// per step, about the cost of a step); false leaves those summary keys null.
    pub summary_l2: bool,
    /// The run stops as diverged when its energy exceeds this factor times its reference
    /// (the driver's `DivergenceCriterion`); in (1, ∞), default `crate::scene::DEFAULT_DIVERGENCE_FACTOR`.
    pub divergence_factor: f64,
    /// Steps between VTU frames (plates; None for no VTU output, always None for bars).
    pub vtu_every: Option<usize>,
}
