//! Scene files (TOML): parsed into closed raw structs, validated once into domain types.
//!
//! ```toml
//! [bar]
//! length = 1.0
//! elements = 6
//! initial = "paper"          # u0 = (L-x)/2, v0 = 0 (exact solution known)
//! force = 0.0                # constant body force f (exact solution only for f = 0)
//! [mass]
//! kind = "mod3"              # standard | mod1 | mod2 | mod3 | custom
//! # weights = [0.0, 2.0, 1.0, 1.0, 1.0, 1.0]   # custom only, one per element
//! [scheme]
//! kind = "crank-nicolson"    # crank-nicolson | newmark | backward-euler | paoli-schatzman | hybrid
//! formulation = "full"       # crank-nicolson/newmark: full | reduced (reduced needs w_0 = 0)
//! [time]
//! dt = 0.01
//! end = 3.0                  # end/dt must be an integer (within 1e-9 relative)
//! [output]
//! series = ["u0", "lambda", "energy", "l2_error"]
//! every = 1
//! summary_l2 = true          # exact L² error every step for summary.linf_l2_error (false: null)
//! divergence_factor = 1e6    # stop as diverged when |E| > factor · max(|E⁰|, E_F), in (1, ∞)
//! ```
//!
//! Every error names the key and its allowed range; the resolved scene (all defaults filled in)
//! serialises back to TOML.

mod bar;
mod body;
mod common;

pub use bar::*;
pub use body::*;
pub use common::*;

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Upper bound on `elements`: 10⁷ nodes take ~1 GB of work vectors across a scheme and observers.
pub const MAX_ELEMENTS: usize = 10_000_000;

/// Upper bound on elements × steps: at ~10 ns per node-step (release build) about 2 minutes.
pub const MAX_NODE_STEPS: f64 = 1e10;

/// The default `output.divergence_factor`: six orders of magnitude above any bounded excursion
/// (the standard mass chatters up to about 4 E⁰ by T = 3, Paoli–Schatzman with mod3 drifts to
/// 2.4 E⁰ by T = 3000), and some 300 below overflow (the driver's
/// `DivergenceCriterion::DEFAULT_ENERGY_FACTOR`).
pub const DEFAULT_DIVERGENCE_FACTOR: f64 = 1e6;
/// Upper bound on the values of `series.csv`. It protects the disk, not memory (the series is
/// streamed, memory does not depend on it): at most 25 bytes a value (a shortest round-trip f64
/// has at most 24 characters, e.g. `-2.2250738585072014e-308`, plus a separator), 1.25 GB.
pub const MAX_SERIES_VALUES: f64 = 5e7;

#[derive(Debug, Error)]
pub enum SceneError {
    #[error("cannot read {path}: {source}")]
    Io { path: String, source: std::io::Error },
    #[error("{0}")]
    Parse(String),
    #[error("{key} = {value}: allowed range is {range}")]
    Range { key: &'static str, value: String, range: &'static str },
    #[error("{key} is required{hint}")]
    Missing { key: &'static str, hint: &'static str },
    #[error("{key} does not apply to {context}")]
    Inapplicable { key: &'static str, context: String },
    #[error(
        "time.end / time.dt = {ratio} is not an integer (within 1e-9 relative): choose dt dividing end (end = {end}, dt = {dt})"
    )]
    NotAnInteger { end: f64, dt: f64, ratio: f64 },
    #[error(
        "bar.elements × steps = {work:.3e} node-steps exceeds the limit {limit:.0e} (about 2 minutes of computing in a release build): reduce bar.elements or time.end / time.dt"
    )]
    TooMuchWork { work: f64, limit: f64 },
    #[error("output.series would record {values:.3e} values (limit {limit:.0e}): set output.every to at least {every}")]
    TooManyValues { values: f64, limit: f64, every: usize },
    #[error("output.series lists \"{0}\" twice")]
    DuplicateColumn(String),
    #[error(transparent)]
    Mass(#[from] crate::mass::MassError),
    #[error(transparent)]
    Expr(#[from] crate::expr::ExprError),
}

impl SceneError {
    /// Exit code for the CLI: 2 for anything wrong with the input.
    pub fn exit_code(&self) -> i32 {
        2
    }
}

/// A number written as a TOML integer or float (`end = 3` and `end = 3.0` both work).
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(untagged)]
pub(crate) enum Number {
    Int(i64),
    Float(f64),
}

impl Number {
    pub(crate) fn get(self) -> f64 {
        match self {
            Number::Int(i) => i as f64,
            Number::Float(f) => f,
        }
    }
}

/// A per-step diagnostic that can be recorded in `series.csv`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Column {
    /// Contact-node displacement u_0ⁿ (plates: the contact node at the lowest y).
    U0,
    /// Displacement of node 1 (bars only).
    U1,
    /// Mean of u on Γ_C (plates).
    UMean,
    /// Contact force λⁿ (plates: the mean pressure Σ_c λ_c / |Γ_C|, the 1D λ for y-independent
    /// fields).
    Lambda,
    /// Total contact force Σ_c λ_c (plates).
    ContactForce,
    /// Discrete energy ½VᵀMV + ½UᵀSU − UᵀF.
    Energy,
    /// Exact ‖u_h(t_n) − u(t_n)‖_{L²(0,L)}.
    L2Error,
    /// Exact u(0, t_n).
    ExactU0,
    /// Exact λ(t_n).
    ExactLambda,
    /// Principal pivots of the step's contact solves (plates).
    Pivots,
}

impl Column {
    /// The columns of a bar scene.
    pub const BAR: [Column; 7] =
        [Column::U0, Column::U1, Column::Lambda, Column::Energy, Column::L2Error, Column::ExactU0, Column::ExactLambda];
    /// The columns of a plate scene.
    pub const PLATE: [Column; 9] = [
        Column::U0,
        Column::UMean,
        Column::Lambda,
        Column::ContactForce,
        Column::Energy,
        Column::L2Error,
        Column::ExactU0,
        Column::ExactLambda,
        Column::Pivots,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Column::U0 => "u0",
            Column::U1 => "u1",
            Column::UMean => "u_mean",
            Column::Lambda => "lambda",
            Column::ContactForce => "contact_force",
            Column::Energy => "energy",
            Column::L2Error => "l2_error",
            Column::ExactU0 => "exact_u0",
            Column::ExactLambda => "exact_lambda",
            Column::Pivots => "pivots",
        }
    }

    pub fn needs_exact(self) -> bool {
        matches!(self, Column::L2Error | Column::ExactU0 | Column::ExactLambda)
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

pub(crate) fn finite_in(key: &'static str, v: f64, ok: bool, range: &'static str) -> Result<f64, SceneError> {
    if v.is_finite() && ok { Ok(v) } else { Err(SceneError::Range { key, value: v.to_string(), range }) }
}

pub(crate) fn forbid<T>(key: &'static str, value: &Option<T>, context: &str) -> Result<(), SceneError> {
    match value {
        Some(_) => Err(SceneError::Inapplicable { key, context: context.to_string() }),
        None => Ok(()),
    }
}
