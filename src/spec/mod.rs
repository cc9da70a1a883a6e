//! The validated scene and the parser's core: what the parser (`crate::scene`, TOML
//! --validate-->) hands to the geometries and the run path (--assemble--> system), and what
//! each geometry's table parser (in its own folder) reads and answers with. It sits below the
//! geometries, the registry of the geometries (`crate::scene`) and the run path, so that a
//! geometry reads and validates its table without importing the registry; `crate::scene`
//! re-exports every public item here.
//!
//! - this file: [`Scene`], [`TimeSpec`], [`OutputSpec`], [`GeometrySpec`] (a spec's problem),
//!   [`Totals`];
//! - [`geometry`]: [`SceneGeometry`], what a geometry's table is to the parser;
//! - [`error`]: [`SceneError`], the one error of a scene, and its key;
//! - [`limits`]: the limits every scene shares and the readers of its number keys;
//! - [`compat`]: what each geometry offers ([`Offer`]), each scheme and law needs, the one check;
//! - `medium`: the keys a bar's and a plate's table share.

pub mod compat;
pub mod error;
pub mod geometry;
pub mod limits;
pub(crate) mod medium;

pub use compat::Offer;
pub use error::{SceneError, short};
pub use geometry::SceneGeometry;
pub use limits::*;

use crate::observe::Column;
use crate::schemes::SchemeSpec;

/// A validated scene: one geometry (`G`: `BarSpec`, `PlateSpec`, `SolidSpec`) and the sections every
/// scene shares. A scene file is read as a `crate::scene::AnyScene`, whose variant is the geometry table
/// the file has.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene<G> {
    pub geometry: G,
    pub mass: crate::mass::MassKind,
    /// `mass.contact_directions`: which components of the contact layer are redistributed
    /// (solids; bars and plates have only the normal one).
    pub contact_directions: crate::mass::ContactDirections,
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
    /// (the driver's `DivergenceCriterion`); in (1, ∞), default [`DEFAULT_DIVERGENCE_FACTOR`].
    pub divergence_factor: f64,
    /// Steps between VTU frames (plates; None for no VTU output, always None for bars).
    pub vtu_every: Option<usize>,
}

/// What ties a geometry's validated specification to the one core: the problem it poses, the
/// geometry keys of its `summary.json`, and its VTU frames. Each geometry implements it in its
/// own folder (`bar/problem.rs`, `plate/problem.rs`, `solid/problem.rs`), beside its spec
/// (`spec.rs`), its [`Geometry`](crate::problem::Geometry) (`geometry.rs`), its frame writer (`vtu.rs`) and
/// its table parser (`table.rs`, [`SceneGeometry`]). It sits here, below the parser and the
/// run path (`crate::run`), which bound their geometries by it and by `crate::scene::Registered`.
pub trait GeometrySpec: Sized {
    /// The assembled geometry (mesh, contact system, reports).
    type System: crate::problem::Geometry;
    /// Why the problem cannot be built (assembly, mesh, exact solution).
    type Error: std::error::Error + Send + Sync + 'static;
    /// The geometry keys of `summary.json`, written after `scheme`, `mass`, `elements`,
    /// `length` and `end` and before the `Summary` (`crate::observe`).
    type Head: serde::Serialize;
    /// The scene keys that shape the problem, named when it cannot be set up.
    const SETUP_KEYS: &'static str;
    /// Cells along x (`elements` in `summary.json`; 0 for a mesh file).
    fn elements(&self) -> usize;
    /// The problem of a scene: the assembled system, the interpolated initial data and the
    /// exact solution up to `time.end` where one is known.
    fn problem(scene: &Scene<Self>) -> Result<crate::problem::Problem<Self::System>, Self::Error>;
    /// The geometry keys of `summary.json` ([`GeometrySpec::Head`]), with the totals of the
    /// system that ran (a Rust run's, or the FEniCSx engine's own).
    fn summary_head(scene: &Scene<Self>, totals: &Totals) -> Self::Head;
    /// The totals of an assembled system, for [`GeometrySpec::summary_head`].
    fn totals(system: &Self::System) -> Totals;
    /// The VTU frames of this geometry's states (None: it writes none, and its scenes refuse
    /// `output.vtu`: [`SceneGeometry::VTU`]).
    fn frames(_system: &Self::System) -> Option<&dyn crate::fem::frames::VtuFrames> {
        None
    }
}

/// What `summary.json` reports of the system that ran, besides the scene: `∫ ρ w_h` (per
/// component) and the number of unknowns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Totals {
    pub total_mass: f64,
    pub unknowns: usize,
}
