//! The limits every scene shares and the readers of its number keys (`Number`,
//! `finite_in`, `length_in`, `forbid`): what every table parser (the shared sections in
//! `crate::scene`, each geometry's table in its folder) reads its keys with.

use super::error::{SceneError, short};
use serde::{Deserialize, Serialize};

// The limits every scene shares, each with what it protects.

/// Upper bound on `bar.elements`: 10⁷ nodes take ~1 GB of work vectors across a scheme and
/// observers.
pub const MAX_ELEMENTS: usize = 10_000_000;

/// Upper bound on unknowns × steps (every geometry), a guard against absurd input rather than
/// a time limit: at ~10 ns per unknown-step it is about 2 minutes of a bar, but an implicit
/// plate or solid step streams its Cholesky factor, whose size grows faster than the unknowns
/// (a 3D scene at this cap takes most of an hour). `check` measures the scene's own step and
/// prints the run's time ([`crate::run::Estimate`]).
pub const MAX_NODE_STEPS: f64 = 1e10;

/// The default `output.divergence_factor` (its reason: the driver's
/// [`crate::driver::DivergenceCriterion::DEFAULT_ENERGY_FACTOR`]).
pub const DEFAULT_DIVERGENCE_FACTOR: f64 = crate::driver::DivergenceCriterion::DEFAULT_ENERGY_FACTOR;
/// Upper bound on the values of `series.csv`. It protects the disk, not memory (the series is
/// streamed, memory does not depend on it): at most 25 bytes a value (a shortest round-trip f64
/// has at most 24 characters, e.g. `-2.2250738585072014e-308`, plus a separator), 1.25 GB.
pub const MAX_SERIES_VALUES: f64 = 5e7;

/// Upper bound on the bytes of the VTU frames a run writes: they are streamed (memory does not
/// depend on them), this protects the disk.
pub const MAX_VTU_BYTES: f64 = 2e10;
/// Bytes per mesh node of one binary VTU frame (`crate::fem::vtu`), an upper bound for the
/// structured meshes: at most 10 Float64 per node (a solid's point, displacement, velocity,
/// pressure: 80 bytes) and 29 bytes per cell (4 Int32 vertices, an Int32 offset, a UInt8 type,
/// a Float64 weight) with at most 6 cells per node (tets: 174 bytes), 254 in all. Measured:
/// 92.6 bytes a node for a 100 × 100 quad plate (944 kB a frame), 112 for triangles, 114 for
/// hexahedra, 204 for 8³ × 6 tets.
pub const VTU_BYTES_PER_NODE: f64 = 260.0;

/// Upper bound on the size of a scene file: a scene is a few hundred bytes (a custom mass with
/// 10⁵ weights about 2 MB); reading stops here, so `/dev/zero` or a binary file fails at once.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// Lengths (`bar.length`, `plate.length`, `plate.height`) lie in [MIN_LENGTH, MAX_LENGTH]:
/// mesh sizes, their squares (stiffness ~ E/h, mass ~ ρh, step matrices M + βΔt²S) and the
/// default `time.end = 3 L` stay far from overflow and underflow.
pub const MIN_LENGTH: f64 = 1e-100;
pub const MAX_LENGTH: f64 = 1e100;
/// The range of `MIN_LENGTH..=MAX_LENGTH`, for messages.
pub const LENGTH_RANGE: &str = "[1e-100, 1e100]";

/// Upper bound on `contact nodes²`: the contact solver ([`crate::contact::Schur`]) keeps the dense
/// Schur complement D = Eᵀ K⁻¹ E, n_c² doubles, and its LCP one more n_c² array for the Cholesky
/// factor of the active block (2.5·10⁷ values is 200 MB each: n_c ≤ 5000; a 4000-row plate has
/// n_c = 4001).
pub const MAX_CONTACT_VALUES: f64 = 2.5e7;

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

pub(crate) fn finite_in(key: &'static str, v: f64, ok: bool, range: &'static str) -> Result<f64, SceneError> {
    if v.is_finite() && ok { Ok(v) } else { Err(SceneError::Range { key, value: short(v), range }) }
}

/// A material constant in (0, ∞) as a normal double: a subnormal one (below
/// `f64::MIN_POSITIVE`, 2.2e-308) has lost digits, and the masses or stiffnesses made of it
/// underflow to 0 (a density of 1e-320 ran with the kinetic energy 0 throughout).
pub(crate) fn positive_normal(key: &'static str, v: f64) -> Result<f64, SceneError> {
    finite_in(key, v, v >= f64::MIN_POSITIVE, POSITIVE_NORMAL)
}

/// The range of [`positive_normal`].
pub(crate) const POSITIVE_NORMAL: &str =
    "(0, ∞), a normal double (≥ 2.2250738585072014e-308; a subnormal one has lost digits)";

/// A length key in [`LENGTH_RANGE`].
pub(crate) fn length_in(key: &'static str, v: f64) -> Result<f64, SceneError> {
    finite_in(key, v, (MIN_LENGTH..=MAX_LENGTH).contains(&v), LENGTH_RANGE)
}

pub(crate) fn forbid<T>(key: &'static str, value: &Option<T>, context: &str) -> Result<(), SceneError> {
    match value {
        Some(_) => Err(SceneError::Inapplicable { key, context: context.to_string() }),
        None => Ok(()),
    }
}

/// The dense contact Schur complement takes contact² values ([`MAX_CONTACT_VALUES`]); `keys`
/// set the contact nodes (a plate's, a solid's).
pub(crate) fn check_contact_memory(contact: usize, keys: &'static str) -> Result<(), SceneError> {
    let values = contact as f64 * contact as f64;
    if values > MAX_CONTACT_VALUES {
        let megabytes = values * 8.0 / 1e6;
        return Err(SceneError::TooManyContactNodes { contact, values, limit: MAX_CONTACT_VALUES, megabytes, keys });
    }
    Ok(())
}
