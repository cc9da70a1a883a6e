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
//!
//! This module is the registry of the geometries (issue 28): [`__geometries!`](crate::__geometries)
//! names each geometry once, one line each, and generates from it [`AnyScene`], the scene
//! aliases ([`BarScene`], …), [`RawScene`] (the tables of a scene file), the parser's dispatch
//! over the geometry tables and [`with_scene!`](crate::with_scene). Each geometry's table is
//! read in its own folder ([`SceneGeometry`]: `bar/table.rs`, `plate/table.rs`,
//! `solid/table/`), over the parser's core in [`crate::spec`] (errors, limits, the
//! compatibility rule), which sits below the geometries; the sections every scene shares are
//! read here (`common.rs`: `[mass]`, `[scheme]`, `[time]`, `[output]`; `contact.rs`:
//! `[contact]`; `tagged.rs`: the reader of the tagged tables).

mod common;
mod contact;
mod registry;
mod tagged;

pub(crate) use common::*;
pub(crate) use contact::RawContact;
// The parser's core (`crate::spec`), at its paths of before.
pub use crate::spec::Offer;
pub use crate::spec::{
    DEFAULT_DIVERGENCE_FACTOR, LENGTH_RANGE, MAX_CONTACT_VALUES, MAX_ELEMENTS, MAX_LENGTH, MAX_NODE_STEPS,
    MAX_SCENE_BYTES, MAX_SERIES_VALUES, MAX_VTU_BYTES, MIN_LENGTH, VTU_BYTES_PER_NODE, short,
};
pub(crate) use crate::spec::{Number, finite_in, forbid};
pub use crate::spec::{OutputSpec, Scene, SceneError, SceneGeometry, TimeSpec};
// The mesh-file readers (`crate::mesh_file`), at their paths of before.
pub use crate::mesh_file::{self, gmsh};
// Public paths of before the registry (a new geometry needs none of these): the specifications
// the tables validate into, and `parse_solid`.
pub use crate::bar::spec::{BarSpec, Initial};
pub use crate::medium::{Force, Medium};
pub use crate::plate::spec::{PlateInitial, PlateSpec};
pub use crate::solid::table::parse_solid;
// The scheme and column vocabularies live with the code that uses them; scenes name them.
pub use crate::observe::Column;
pub use crate::schemes::{Formulation, SchemeSpec};

use crate::mesh_file::MeshInputs;

/// The registry of the geometries: one line each, in the order of [`AnyScene`]'s variants and
/// of messages. A line is `Variant(spec type) as Alias = table`, then `+ table(raw type)` for
/// each table the geometry owns beside its own (its [`SceneGeometry::Extras`], in this order);
/// `default` names the table of a scene file that has none. Everything else of a geometry is
/// in its folder, behind [`SceneGeometry`] and `crate::spec::GeometrySpec`.
///
/// `__geometries!(define)` expands the registry's items here; `__geometries!(with_scene …)`
/// is [`with_scene!`](crate::with_scene) (the machinery: `registry.rs`).
#[doc(hidden)]
#[macro_export]
macro_rules! __geometries {
    ($($mode:tt)*) => {
        $crate::__registry! { [$($mode)*]
            default bar;
            /// A bar scene (`[bar]`, the default table).
            Bar($crate::bar::BarSpec) as BarScene = bar;
            /// A plate scene (`[plate]`).
            Plate($crate::plate::PlateSpec) as PlateScene = plate;
            /// An elastic solid scene (`[solid]`, and a body's `[obstacle]`; or `[[solid]]` bodies and
            /// their `[[pair]]`s).
            Solid($crate::solid::SolidSpec) as SolidScene = solid + obstacle($crate::solid::RawObstacle) + pair(Vec<$crate::solid::RawPair>);
        }
    };
}

crate::__geometries!(define);

/// `with_scene!(any, s => expr)`: `expr` with `s` bound to the scene of whichever geometry
/// `any: &AnyScene` holds (generic code over [`Registered`] and `crate::run::GeometrySpec`).
/// The one dispatch over the geometries, one arm per line of the registry
/// ([`__geometries!`](crate::__geometries)).
#[macro_export]
macro_rules! with_scene {
    ($any:expr, $s:ident => $body:expr) => {
        $crate::__geometries!(with_scene $any, $s => $body)
    };
}

/// A geometry of the registry: its variant of [`AnyScene`] and its tables in [`RawScene`]
/// (implemented by its registry line).
pub trait Registered: SceneGeometry {
    /// The scene of this geometry in `any`, or an error saying which geometry `any` has.
    fn from_any(any: AnyScene) -> Result<Scene<Self>, SceneError>;
    /// The resolved geometry table and the tables it owns ([`SceneGeometry::raw`]), in a
    /// [`RawScene`] otherwise empty.
    fn raw_scene(&self) -> RawScene;
}

impl AnyScene {
    /// Reads (at most [`MAX_SCENE_BYTES`]) and validates a scene file; a mesh file it names is
    /// relative to the scene's folder and read here, once.
    pub fn from_file(path: &std::path::Path) -> Result<AnyScene, SceneError> {
        let text = read_scene_text(path)?;
        AnyScene::parse(&text, MeshInputs::files(path.parent().unwrap_or(std::path::Path::new("."))))
    }

    /// The files a scene file names besides itself (`plate.mesh`, `solid.mesh`, relative to its
    /// folder: each geometry's [`SceneGeometry::FILE_KEYS`]), read from its TOML without
    /// validating it: the inputs that `run --force` must never delete (issue 32, E12). Empty if
    /// the file does not parse (its run is refused then).
    pub fn named_files(path: &std::path::Path) -> Vec<std::path::PathBuf> {
        let Some(table) = read_scene_text(path).ok().and_then(|t| toml::from_str::<toml::Table>(&t).ok()) else {
            return Vec::new();
        };
        let base = path.parent().unwrap_or(std::path::Path::new("."));
        GEOMETRIES
            .iter()
            .flat_map(|(geometry, keys)| keys.iter().map(move |key| (*geometry, *key)))
            // A geometry table, or an array of them (`[[solid]]` bodies).
            .flat_map(|(geometry, key)| {
                let tables = match table.get(geometry) {
                    Some(toml::Value::Array(a)) => a.iter().collect(),
                    Some(t) => vec![t],
                    None => Vec::new(),
                };
                tables.into_iter().filter_map(move |t| t.get(key)?.as_str())
            })
            .filter(|f| *f != mesh_file::ARRAY_MESH)
            .map(|f| base.join(f))
            .collect()
    }

    /// Parses and validates scene text; a mesh file is relative to the current folder.
    pub fn from_toml(text: &str) -> Result<AnyScene, SceneError> {
        AnyScene::parse(text, MeshInputs::files(std::path::Path::new(".")))
    }

    /// Parses and validates scene text; a mesh file is relative to `base` (the folder of the
    /// file the text came from, for the Python package's scenes changed key by key).
    pub fn from_toml_at(text: &str, base: &std::path::Path) -> Result<AnyScene, SceneError> {
        AnyScene::parse(text, MeshInputs::files(base))
    }

    /// Parses and validates scene text whose `mesh` keys name files relative to `inputs.base`
    /// or, as `"<arrays>"`, the arrays given in `inputs` (the Python package's `mesh=`).
    pub fn from_toml_with(text: &str, inputs: MeshInputs) -> Result<AnyScene, SceneError> {
        AnyScene::parse(text, inputs)
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

impl<G: Registered> Scene<G> {
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
        let (mass, scheme, time, output) =
            raw_sections(&self.mass, self.contact_directions, &self.scheme, &self.time, &self.output, G::VTU);
        let contact = contact::raw_contact(&self.contact);
        let raw = RawScene { mass, scheme, contact, time, output, ..self.geometry.raw_scene() };
        let mut text = self.geometry.header(&self.time);
        text.push_str(&toml::to_string(&raw).expect("a resolved scene always serialises"));
        text
    }
}

/// A geometry table validated on the sections every scene shares, if its assembly fits in
/// memory ([`SceneGeometry::assembly_bytes`] against [`crate::linalg::memory_left`], read
/// only for a geometry that states its bytes).
fn validated<G: SceneGeometry>(geometry: G, raw: RawScene) -> Result<Scene<G>, SceneError> {
    // The scheme as written (its errors are `validate_sections`'): central differences set a
    // box up lean.
    let scheme = match &raw.scheme {
        Some(tagged::RawSection::Read(t)) => common::parse_scheme(Some(tagged::RawSection::Read(t.clone()))).ok(),
        Some(tagged::RawSection::Resolved(s)) => Some(*s),
        None => common::parse_scheme(None).ok(),
    };
    let bytes = geometry.assembly_bytes(scheme.as_ref());
    if bytes > 0.0 {
        let limit = crate::linalg::memory_left();
        if bytes > limit as f64 {
            return Err(SceneError::TooMuchMemory { keys: geometry.size_keys(), bytes, limit });
        }
    }
    validate_sections(geometry, raw)
}

/// The error of a scene found in another geometry's place.
pub(crate) fn wrong_geometry(want: &'static str, any: &AnyScene) -> SceneError {
    SceneError::Parse(format!("expected a [{want}] scene, found a [{}] scene", any.table()))
}

/// A table that geometry `owner` owns beside its own (`[obstacle]`), in a scene of another:
/// refused, naming the other geometries and why it is `owner`'s ([`SceneGeometry::EXTRAS_WHY`]).
fn owned_by(key: &'static str, owner: &str, why: &str) -> SceneError {
    let others: Vec<String> = GEOMETRIES.iter().filter(|(g, _)| *g != owner).map(|(g, _)| format!("[{g}]")).collect();
    SceneError::Inapplicable { key, context: format!("{} scenes ({why})", others.join(" and ")) }
}

/// Refuses a scene with more than one geometry table (`present`: each table of the registry,
/// whether the scene has it).
fn one_table(present: &[(bool, &str)]) -> Result<(), SceneError> {
    let tables: Vec<String> = present.iter().filter(|(has, _)| *has).map(|(_, g)| format!("[{g}]")).collect();
    if tables.len() <= 1 {
        return Ok(());
    }
    let mut all: Vec<String> = GEOMETRIES
        .iter()
        .map(|(g, _)| if *g == DEFAULT_TABLE { format!("[{g}] (the default)") } else { format!("[{g}]") })
        .collect();
    let last = all.pop().unwrap_or_default();
    let all = if all.is_empty() { last } else { format!("{} or {last}", all.join(", ")) };
    Err(SceneError::Parse(format!("{}: a scene has one geometry table, {all}", tables.join(" and "))))
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
