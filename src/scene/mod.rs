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
//!                            # | central-difference | moreau-jean (contact law: [contact], scene/contact.rs)
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
mod common;
mod compat;
mod contact;
mod medium;
mod obstacle;
mod plate;
mod solid;
mod tagged;

pub(crate) use common::*;
pub use compat::Offer;
// The mesh-file readers (`crate::mesh_file`), at their paths of before.
pub use crate::mesh_file::{self, gmsh};
pub(crate) use contact::RawContact;
pub(crate) use medium::*;
pub(crate) use obstacle::*;
pub use plate::*;
pub use solid::*;
// The geometries' specifications, which the tables validate into.
pub use crate::bar::spec::{BarSpec, Initial};
pub use crate::medium::{Force, Medium};
pub use crate::plate::spec::{PlateInitial, PlateSpec};
// The scheme and column vocabularies live with the code that uses them; scenes name them.
pub use crate::observe::Column;
pub use crate::schemes::{Formulation, SchemeSpec};
pub use crate::spec::{OutputSpec, Scene, TimeSpec};

use serde::{Deserialize, Serialize};
use thiserror::Error;

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
    MeshFile(#[from] mesh_file::MeshFileError),
    #[error(
        "{contact} contact nodes: their dense Schur complement would take {values:.3e} values ({megabytes:.0} MB), over the limit of {limit:.1e}: reduce the nodes of the contact face ({keys})"
    )]
    TooManyContactNodes { contact: usize, values: f64, limit: f64, megabytes: f64, keys: &'static str },
    #[error(
        "{keys}: assembling this mesh takes at least {gb:.2} GB, over the memory limit of {limit_gb:.2} GB (the available memory, or `ulimit -v`): reduce {keys}",
        gb = bytes / 1e9, limit_gb = *limit as f64 / 1e9
    )]
    TooMuchMemory { keys: &'static str, bytes: f64, limit: u64 },
    #[error(transparent)]
    Expr(#[from] crate::expr::ExprError),
    #[error(transparent)]
    Body(#[from] crate::solid::BodyError),
    /// A geometry, mass, scheme and contact law that do not go together ([`compat`]): `key` is
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

/// A bar scene (`[bar]`).
pub type BarScene = Scene<BarSpec>;
/// A plate scene (`[plate]`).
pub type PlateScene = Scene<PlateSpec>;
/// An elastic solid scene (`[solid]`).
pub type SolidScene = Scene<crate::solid::SolidSpec>;

/// `with_scene!(any, s => expr)`: `expr` with `s` bound to the scene of whichever geometry
/// `any: &AnyScene` holds (generic code over [`SceneGeometry`] and `crate::run::GeometrySpec`).
/// The one dispatch over the geometries: a new geometry adds its variant here.
#[macro_export]
macro_rules! with_scene {
    ($any:expr, $s:ident => $body:expr) => {
        match $any {
            $crate::scene::AnyScene::Bar($s) => $body,
            $crate::scene::AnyScene::Plate($s) => $body,
            $crate::scene::AnyScene::Solid($s) => $body,
        }
    };
}

/// A scene file of any geometry: the geometry table it has (`[bar]`, the default, `[plate]` or
/// `[solid]`) decides the variant.
#[derive(Debug, Clone, PartialEq)]
pub enum AnyScene {
    Bar(BarScene),
    Plate(PlateScene),
    Solid(SolidScene),
}

/// The tables of a scene file (one geometry table at most), as read and as resolved (opaque
/// outside the crate).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawScene {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) bar: Option<bar::RawBar>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) plate: Option<RawPlate>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) solid: Option<solid::RawSolid>,
    /// The rigid plane of a body (`[solid]` scenes only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) obstacle: Option<obstacle::RawObstacle>,
    pub(crate) mass: Option<RawMass>,
    pub(crate) scheme: Option<RawScheme>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) contact: Option<RawContact>,
    pub(crate) time: Option<RawTime>,
    pub(crate) output: Option<RawOutput>,
}

/// What the shared sections need of a geometry: its table, its columns, its unknowns and
/// contact weight, and the exact solutions it offers.
pub trait SceneGeometry: Sized {
    /// The geometry's table: "bar" or "plate".
    const TABLE: &'static str;
    /// The columns `output.series` accepts, and their list for messages.
    const COLUMNS: &'static [Column];
    const COLUMN_LIST: &'static str;
    /// The keys that set the number of unknowns (named when the work limit is exceeded).
    const SIZE_KEYS: &'static str;
    /// [`Self::SIZE_KEYS`] of this scene: the keys it has (a mesh file's scene has no `nx`;
    /// issue 32, E16).
    fn size_keys(&self) -> &'static str {
        Self::SIZE_KEYS
    }
    /// Whether the geometry writes VTU frames (`output.vtu`).
    const VTU: bool;
    /// Whether the contact nodes carry unknowns without a contact condition (a solid's
    /// tangential components), massless with them when w_0 = 0: a contact layer ([`Offer`]).
    const MASSLESS_TANGENTS: bool = false;
    /// Unknowns per step (the work limit's measure).
    fn unknowns(&self) -> usize;
    /// The extent along x (the default `time.end` is 3 L).
    fn length(&self) -> f64;
    /// The mass weights validated on this geometry; returns the largest weight of the cells at
    /// the contact boundary (0 iff the contact unknowns are massless).
    fn contact_weight(&self, mass: &crate::mass::MassKind) -> Result<f64, SceneError>;
    /// What the geometry offers the schemes and laws with this mass (the compatibility rule,
    /// [`compat`]). The default: many contact nodes over a sparse back-end, a lumped mass, the
    /// contact weight of [`SceneGeometry::contact_weight`].
    fn offer(&self, mass: &crate::mass::MassKind) -> Result<Offer, SceneError> {
        let w0 = self.contact_weight(mass)?;
        Ok(Offer {
            one_node_system: false,
            lumped_mass: true,
            w0,
            contact_layer: Self::MASSLESS_TANGENTS && w0 == 0.0,
            one_cell_contact_row: false,
            zero_gap: false,
        })
    }
    /// Why `column` cannot be recorded for this geometry's data (None if it can).
    fn unavailable(&self, column: Column) -> Option<String>;
    /// The series recorded without `output.series`.
    fn default_series(&self) -> Vec<Column>;
    /// The resolved geometry table, in a [`RawScene`] otherwise empty.
    fn raw(&self) -> RawScene;
    /// The first line of the resolved file (a comment).
    fn header(&self, time: &TimeSpec) -> String;
    /// The scene of this geometry in `any`, or an error saying which geometry `any` has.
    fn from_any(any: AnyScene) -> Result<Scene<Self>, SceneError>;
    /// A lower bound of the memory, in bytes, that assembling this geometry's matrices takes
    /// (its element-matrix buffers), checked against [`crate::linalg::memory_limit`] before any
    /// mesh is assembled; the factor is checked, exactly, after its symbolic analysis.
    fn assembly_bytes(&self) -> f64 {
        0.0
    }
}

impl AnyScene {
    /// Reads (at most [`MAX_SCENE_BYTES`]) and validates a scene file; a mesh file it names is
    /// relative to the scene's folder and read here, once.
    pub fn from_file(path: &std::path::Path) -> Result<AnyScene, SceneError> {
        let text = read_scene_text(path)?;
        AnyScene::parse(&text, mesh_file::MeshInputs::files(path.parent().unwrap_or(std::path::Path::new("."))))
    }

    /// The files a scene file names besides itself (`plate.mesh`, `solid.mesh`, relative to its
    /// folder), read from its TOML without validating it: the inputs that `run --force` must
    /// never delete (issue 32, E12). Empty if the file does not parse (its run is refused then).
    pub fn named_files(path: &std::path::Path) -> Vec<std::path::PathBuf> {
        let Some(table) = read_scene_text(path).ok().and_then(|t| toml::from_str::<toml::Table>(&t).ok()) else {
            return Vec::new();
        };
        let base = path.parent().unwrap_or(std::path::Path::new("."));
        ["plate", "solid"]
            .iter()
            .filter_map(|g| table.get(*g)?.get("mesh")?.as_str())
            .filter(|f| *f != mesh_file::ARRAY_MESH)
            .map(|f| base.join(f))
            .collect()
    }

    /// Parses and validates scene text; a mesh file is relative to the current folder.
    pub fn from_toml(text: &str) -> Result<AnyScene, SceneError> {
        AnyScene::parse(text, mesh_file::MeshInputs::files(std::path::Path::new(".")))
    }

    /// Parses and validates scene text; a mesh file is relative to `base` (the folder of the
    /// file the text came from, for the Python package's scenes changed key by key).
    pub fn from_toml_at(text: &str, base: &std::path::Path) -> Result<AnyScene, SceneError> {
        AnyScene::parse(text, mesh_file::MeshInputs::files(base))
    }

    /// Parses and validates scene text whose `mesh` keys name files relative to `inputs.base`
    /// or, as `"<arrays>"`, the arrays given in `inputs` (the Python package's `mesh=`).
    pub fn from_toml_with(text: &str, inputs: mesh_file::MeshInputs) -> Result<AnyScene, SceneError> {
        AnyScene::parse(text, inputs)
    }

    fn parse(text: &str, inputs: mesh_file::MeshInputs) -> Result<AnyScene, SceneError> {
        let mut raw: RawScene = toml::from_str(text).map_err(|e| toml_error(text, &e))?;
        if raw.obstacle.is_some() && raw.solid.is_none() {
            let context = "[bar] and [plate] scenes (a [solid] body meets a plane)".into();
            return Err(SceneError::Inapplicable { key: "[obstacle]", context });
        }
        match (raw.bar.take(), raw.plate.take(), raw.solid.take()) {
            (b, p, s) if b.is_some() as u8 + p.is_some() as u8 + s.is_some() as u8 > 1 => {
                let tables: Vec<&str> = [(b.is_some(), "[bar]"), (p.is_some(), "[plate]"), (s.is_some(), "[solid]")]
                    .into_iter()
                    .filter_map(|(has, name)| has.then_some(name))
                    .collect();
                Err(SceneError::Parse(format!(
                    "{}: a scene has one geometry table, [bar] (the default), [plate] or [solid]",
                    tables.join(" and ")
                )))
            }
            (None, Some(p), None) => {
                Ok(AnyScene::Plate(validate_sections(fits(PlateSpec::validate(p, inputs)?)?, raw)?))
            }
            (None, None, Some(s)) => {
                let solid = validate_solid(s, raw.obstacle.take(), inputs)?;
                Ok(AnyScene::Solid(validate_sections(fits(solid)?, raw)?))
            }
            (b, _, _) => Ok(AnyScene::Bar(validate_sections(BarSpec::validate(b.unwrap_or_default())?, raw)?)),
        }
    }

    /// The scene with every default filled in, as TOML.
    pub fn resolved_toml(&self) -> String {
        crate::with_scene!(self, s => s.resolved_toml())
    }

    pub fn time(&self) -> &TimeSpec {
        crate::with_scene!(self, s => &s.time)
    }

    /// The geometry table's name.
    pub fn table(&self) -> &'static str {
        fn table<G: SceneGeometry>(_: &Scene<G>) -> &'static str {
            G::TABLE
        }
        crate::with_scene!(self, s => table(s))
    }
}

impl<G: SceneGeometry> Scene<G> {
    /// Reads and validates a scene file of this geometry.
    pub fn from_file(path: &std::path::Path) -> Result<Self, SceneError> {
        G::from_any(AnyScene::from_file(path)?)
    }

    /// Parses and validates scene text of this geometry.
    pub fn from_toml(text: &str) -> Result<Self, SceneError> {
        G::from_any(AnyScene::from_toml(text)?)
    }

    /// The scene with every default filled in, as TOML.
    pub fn resolved_toml(&self) -> String {
        let (mass, scheme, time, output) = raw_sections(&self.mass, &self.scheme, &self.time, &self.output, G::VTU);
        let contact = contact::raw_contact(&self.contact);
        let raw = RawScene { mass, scheme, contact, time, output, ..self.geometry.raw() };
        let mut text = self.geometry.header(&self.time);
        text.push_str(&toml::to_string(&raw).expect("a resolved scene always serialises"));
        text
    }
}

/// The geometry, if its assembly fits in memory ([`SceneGeometry::assembly_bytes`] against
/// [`crate::linalg::memory_limit`]).
fn fits<G: SceneGeometry>(geometry: G) -> Result<G, SceneError> {
    let (bytes, limit) = (geometry.assembly_bytes(), crate::linalg::memory_limit());
    if bytes > limit as f64 {
        return Err(SceneError::TooMuchMemory { keys: geometry.size_keys(), bytes, limit });
    }
    Ok(geometry)
}

/// The error of a scene found in another geometry's place.
pub(crate) fn wrong_geometry(want: &'static str, any: &AnyScene) -> SceneError {
    SceneError::Parse(format!("expected a [{want}] scene, found a [{}] scene", any.table()))
}

/// The text of a scene file, read up to [`MAX_SCENE_BYTES`].
fn read_scene_text(path: &std::path::Path) -> Result<String, SceneError> {
    use std::io::Read;
    let io = |source| SceneError::Io { path: path.display().to_string(), source };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(MAX_SCENE_BYTES + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(SceneError::TooLarge { path: path.display().to_string(), limit: MAX_SCENE_BYTES });
    }
    String::from_utf8(bytes)
        .map_err(|e| io(std::io::Error::new(std::io::ErrorKind::InvalidData, format!("not UTF-8 text ({e})"))))
}

/// A TOML error with the key it concerns on the first line (`plate.cells`, found from the span:
/// the key on the span's line under the last table header above it), then its position and the
/// parser's own report.
fn toml_error(text: &str, e: &toml::de::Error) -> SceneError {
    let Some(span) = e.span() else { return SceneError::Parse(e.to_string()) };
    let before = &text[..span.start.min(text.len())];
    let line_no = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    let line = text.lines().nth(line_no - 1).unwrap_or("");
    let table = before
        .lines()
        .rev()
        .map(str::trim)
        .find_map(|l| l.strip_prefix('[').and_then(|l| l.strip_suffix(']')))
        .map(|t| t.trim_matches(|c| c == '[' || c == ']').trim().to_string());
    let key = line.split_once('=').map(|(k, _)| k.trim().trim_matches('"').to_string()).filter(|k| !k.is_empty());
    let what = match (table, key) {
        _ if line.trim_start().starts_with('[') => line.trim().to_string(),
        (Some(t), Some(k)) => format!("{t}.{k}"),
        (Some(t), None) => format!("[{t}]"),
        (None, Some(k)) => k,
        (None, None) => "the scene".into(),
    };
    SceneError::Parse(format!("{what}: {} (line {line_no}, column {column})\n{e}", e.message().trim_end()))
}
