//! The one error of a scene ([`SceneError`]): every variant names its key and allowed range, or
//! carries the error of the layer that refused it (mass, mesh, mesh file, expression, a
//! geometry's own); [`SceneError::key`] is the key the CLI and the Python package report.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum SceneError {
    #[error("cannot read {path}: {source}")]
    Io { path: String, source: std::io::Error },
    #[error("{path} is larger than {limit} bytes: not a scene file (scenes are a few kB)")]
    TooLarge { path: String, limit: u64 },
    #[error("{0}")]
    Parse(String),
    #[error("{key} = {value}: allowed range is {range}")]
    Range { key: &'static str, value: String, range: &'static str },
    #[error("{key} is required{hint}")]
    Missing { key: &'static str, hint: &'static str },
    #[error("{key} does not apply to {context}")]
    Inapplicable { key: &'static str, context: String },
    #[error(
        "time.end / time.dt = {ratio} is not an integer (within 1e-9 relative): choose dt dividing end (end = {end}, dt = {dt})",
        end = short(*end), dt = short(*dt), ratio = short(*ratio)
    )]
    NotAnInteger { end: f64, dt: f64, ratio: f64 },
    #[error(
        "unknowns × steps = {work:.3e} exceeds the limit {limit:.0e} (a bound on the work, not a time: `check` estimates a scene's time): reduce {size} or time.end / time.dt"
    )]
    TooMuchWork { work: f64, limit: f64, size: &'static str },
    #[error("output.series would record {values:.3e} values (limit {limit:.0e}): set output.every to at least {every}")]
    TooManyValues { values: f64, limit: f64, every: usize },
    #[error(
        "output.vtu_every = {given} would write up to {gigabytes:.1} GB of VTU frames (limit {limit_gb:.0} GB): set output.vtu_every to at least {every}"
    )]
    TooManyFrames { given: usize, gigabytes: f64, limit_gb: f64, every: usize },
    #[error("output.series lists \"{0}\" twice")]
    DuplicateColumn(String),
    #[error(transparent)]
    Mass(#[from] crate::mass::MassError),
    #[error(transparent)]
    LayerMass(#[from] crate::fem::layers::LayerMassError),
    #[error(transparent)]
    Mesh(#[from] crate::fem::MeshError),
    #[error(transparent)]
    MeshFile(#[from] crate::mesh_file::MeshFileError),
    #[error(
        "{contact} contact nodes: their dense Schur complement would take {values:.3e} values ({megabytes:.0} MB), over the limit of {limit:.1e}: reduce the nodes of the contact face ({keys})"
    )]
    TooManyContactNodes { contact: usize, values: f64, limit: f64, megabytes: f64, keys: &'static str },
    #[error(
        "{keys}: setting this mesh up takes about {gb:.2} GB before its factors (its assembly buffers times the peak measured over them), over the {limit_gb:.2} GB left of the memory limit (the available memory, or `ulimit -v`): reduce {keys}",
        gb = bytes / 1e9, limit_gb = *limit as f64 / 1e9
    )]
    TooMuchMemory { keys: &'static str, bytes: f64, limit: u64 },
    #[error(transparent)]
    Expr(#[from] crate::expr::ExprError),
    /// A geometry's own error at validation, its message as it is (a body's contact set:
    /// `crate::solid::BodyError`, converted where the solid's table is read).
    #[error(transparent)]
    Geometry(Box<dyn std::error::Error + Send + Sync>),
    /// A geometry, mass, scheme and contact law that do not go together ([`super::compat`]): `key` is
    /// the one key to change, `allowed` its values that go with the rest.
    #[error("{key} = {value} does not go with {with}: {why}; allowed: {allowed}")]
    Conflict { key: &'static str, value: String, with: String, why: String, allowed: String },
    /// The problem a valid-looking scene poses cannot be set up (a matrix that cannot be
    /// factored, an exact solution that cannot be built): found by `check` and by `run` before
    /// stepping.
    #[error("the scene cannot be set up ({keys}): {reason}")]
    Setup { keys: String, reason: String },
}

impl SceneError {
    /// The one key the error names (the CLI prints it first, the Python package's
    /// `SceneError.key`): the key of the variants that carry one, else the dotted key that opens
    /// the message (`bar.colour: unknown field …`, `mass.weights[2] = -1: …` gives
    /// `mass.weights`, `[colour]: …` the table `colour`); None if the message opens with none.
    pub fn key(&self) -> Option<String> {
        use SceneError as E;
        match self {
            E::Range { key, .. } | E::Missing { key, .. } | E::Inapplicable { key, .. } | E::Conflict { key, .. } => {
                Some((*key).to_string())
            }
            E::NotAnInteger { .. } => Some("time.dt".into()),
            E::TooManyValues { .. } => Some("output.every".into()),
            E::TooManyFrames { .. } => Some("output.vtu_every".into()),
            E::DuplicateColumn(_) => Some("output.series".into()),
            E::TooMuchWork { size, .. } => Some((*size).to_string()),
            E::TooMuchMemory { keys, .. } => Some((*keys).to_string()),
            E::Setup { keys, .. } => Some(keys.clone()),
            E::Io { .. } | E::TooLarge { .. } => None,
            // A weight that makes a node massless names no key in its message.
            E::Mass(_) | E::LayerMass(_) => leading_key(&self.to_string()).or_else(|| Some("mass.weights".into())),
            other => leading_key(&other.to_string()),
        }
    }
}

/// The key that opens a message (docs of [`SceneError::key`]).
fn leading_key(message: &str) -> Option<String> {
    let head = message.split([' ', ':', '\n']).next().unwrap_or("");
    if let Some(table) = head.strip_prefix('[').and_then(|h| h.strip_suffix(']')) {
        let ok = !table.is_empty() && table.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        return ok.then(|| table.to_string());
    }
    let head = head.split('[').next().unwrap_or("");
    let is_key = head.contains('.')
        && head.split('.').all(|p| !p.is_empty() && p.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'));
    is_key.then(|| head.to_string())
}

/// A number in the shortest form that reads back to it (`1e308`, not 309 digits).
pub fn short(x: f64) -> String {
    crate::numfmt::fmt_f64(x)
}
