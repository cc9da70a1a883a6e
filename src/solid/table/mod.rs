//! Solid scenes (TOML): a `[solid]` table replaces `[bar]`; the other sections are the ones every
//! scene shares (`crate::scene`'s sections); `[output]` has the plate columns and VTU options.
//! A body's `[obstacle]` is the solid's too ([`obstacle`]): a table of its own beside
//! `[solid]`, refused in the scenes of other geometries.
//!
//! ```toml
//! [solid]
//! dim = 2                  # 2 (plane strain) | 3
//! length = 1.0             # x: contact face x = 0, clamped face x = L
//! height = 1.0             # y
//! depth = 1.0              # z, dim = 3 only
//! nx = 20                  # >= 2
//! ny = 20                  # >= 1
//! nz = 20                  # >= 1, dim = 3 only
//! cells = "quad"           # dim 2: quad | triangle;  dim 3: hex | tet
//! lame_lambda = 0.0        # >= 0
//! lame_mu = 0.5            # > 0
//! density = 1.0            # > 0
//! gap = 0.0                # >= 0: u_x >= -gap on x = 0
//! lateral = "free"         # free | roller
//! force = [0.0, 0.0]       # constant body force, one number per component
//! initial = "paper"        # u = ((L-x)/2, 0[, 0]), v = 0; or per-component expressions in
//! # x, y[, z] and L, H[, D], pi:
//! # initial = { displacement = ["(1-x)/2", "0"], velocity = ["0", "0"] }
//! ```
//!
//! The table is read by serde into a closed [`RawSolid`] (unknown keys are refused, naming the
//! key) and validated by `validate_solid` (a pure function but for the mesh file it reads:
//! every error names the key, `solid.…`, and its allowed range); the resolved scene writes
//! every key back ([`crate::spec::SceneGeometry::raw`]). The specification itself is [`super::spec`].

pub mod bodies;
mod geometry;
mod mesh;
pub mod obstacle;

use super::assembly::{Lame, Lateral};
use super::body::BodyError;
use super::spec::{BodySpec, BuildError, MeshSource, SolidInitial, SolidSpec, Support};
use crate::column::Column;
use crate::expr::Expr;
use crate::fem::mesh::{Cell, Mesh};
use crate::mesh_file::{MeshInput, MeshInputs};
use crate::spec::medium::RawField;
use crate::spec::{MAX_ELEMENTS, Number, SceneError, check_contact_memory, finite_in, forbid, length_in, short};
use mesh::{body_file_mesh, file_mesh, structured};
use obstacle::{RawObstacle, parse_body_force, parse_obstacle, raw_obstacle};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The `[solid]` table as written (closed: unknown keys are refused, naming the key).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawSolid {
    #[serde(skip_serializing_if = "Option::is_none")]
    dim: Option<i64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    mesh: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    length: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    height: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    depth: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    nx: Option<i64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    ny: Option<i64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    nz: Option<i64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    cells: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    lame_lambda: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    lame_mu: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    density: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    gap: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    lateral: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    force: Option<Vec<RawField>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    initial: Option<RawSolidInitial>,
    #[serde(skip_serializing_if = "Option::is_none")]
    clamped: Option<String>,
    /// A `[[solid]]` body's name ([`bodies`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    name: Option<String>,
    /// A `[[solid]]` box's lowest corner.
    #[serde(skip_serializing_if = "Option::is_none")]
    offset: Option<Vec<Number>>,
}

/// `[solid]` (one body or the box) or `[[solid]]` (several bodies, [`bodies`]): read through
/// the scene's own deserializer either way, so that an unknown key is refused with its position.
#[derive(Debug)]
pub enum RawSolids {
    One(RawSolid),
    Many(Vec<RawSolid>),
}

impl Default for RawSolids {
    fn default() -> Self {
        RawSolids::One(RawSolid::default())
    }
}

impl Serialize for RawSolids {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            RawSolids::One(t) => t.serialize(s),
            RawSolids::Many(v) => v.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for RawSolids {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Either;
        impl<'de> serde::de::Visitor<'de> for Either {
            type Value = RawSolids;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a [solid] table or [[solid]] tables")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<RawSolids, A::Error> {
                RawSolid::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(RawSolids::One)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<RawSolids, A::Error> {
                Vec::<RawSolid>::deserialize(serde::de::value::SeqAccessDeserializer::new(seq)).map(RawSolids::Many)
            }
        }
        d.deserialize_any(Either)
    }
}

/// `solid.initial`: `"paper"` or a table of per-component fields.
#[derive(Debug, Deserialize, Serialize)]
#[serde(untagged)]
pub(crate) enum RawSolidInitial {
    Name(String),
    Fields(RawSolidFields),
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSolidFields {
    #[serde(skip_serializing_if = "Option::is_none")]
    displacement: Option<Vec<RawField>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    velocity: Option<Vec<RawField>>,
}

/// `solid.dim` (2 | 3), with the keys a 2D solid refuses.
fn dim_of(t: &RawSolid) -> Result<usize, SceneError> {
    let dim = match t.dim.unwrap_or(2) {
        d @ (2 | 3) => d as usize,
        d => return Err(SceneError::Range { key: "solid.dim", value: d.to_string(), range: "2 | 3" }),
    };
    if dim == 2 {
        forbid("solid.depth", &t.depth, "solid.dim = 2")?;
        forbid("solid.nz", &t.nz, "solid.dim = 2")?;
    }
    Ok(dim)
}

/// A material constant in (0, ∞), a normal double.
fn positive(key: &'static str, v: Option<Number>, default: f64) -> Result<f64, SceneError> {
    crate::spec::limits::positive_normal(key, v.map_or(default, Number::get))
}

/// A number key in [0, ∞).
fn non_negative(key: &'static str, v: Option<Number>) -> Result<f64, SceneError> {
    let v = v.map_or(0.0, Number::get);
    finite_in(key, v, v >= 0.0, "[0, ∞)")
}

/// The `[solid]` table (as a TOML table) validated into a [`SolidSpec`], a mesh file relative to
/// the current folder (library users; scene files go through `crate::scene::AnyScene`).
pub fn parse_solid(t: &toml::Table) -> Result<SolidSpec, SceneError> {
    let raw = RawSolid::deserialize(toml::Value::Table(t.clone()))
        .map_err(|e| SceneError::Parse(format!("[solid]: {}", e.to_string().trim_end())))?;
    validate_solid(raw, None, MeshInputs::files(std::path::Path::new(".")))
}

/// The `[solid]` table validated into a [`SolidSpec`]: every error names the key (`solid.…`)
/// and its allowed range. The size is checked before any mesh is built (cells, contact nodes,
/// cell aspect ratios), the initial data at the mesh nodes; `mesh = "…"` is relative to
/// `inputs.base` (the scene's folder), or the arrays given for `"<arrays>"`, and read here, once.
pub(crate) fn validate_solid(
    t: RawSolid,
    obstacle: Option<RawObstacle>,
    inputs: MeshInputs,
) -> Result<SolidSpec, SceneError> {
    let dim = dim_of(&t)?;
    let one = "a single [solid] table (several bodies are [[solid]] tables)";
    forbid("solid.name", &t.name, one)?;
    forbid("solid.offset", &t.offset, one)?;
    if obstacle.is_some() {
        forbid("solid.gap", &t.gap, "a body with an [obstacle] (obstacle.point places the plane)")?;
        forbid("solid.lateral", &t.lateral, "a body with an [obstacle] (its boundary is free but where clamped)")?;
    } else {
        forbid("solid.clamped", &t.clamped, "a box without [obstacle] (clamped on x = L)")?;
    }
    let (extent, n, cells, source) = match &t.mesh {
        Some(file) => {
            let input = inputs.resolve(file);
            let path = inputs.base.join(file);
            let mesh = match obstacle.is_some() {
                true => body_file_mesh(&t, dim, &input)?,
                false => file_mesh(&t, dim, &input, &path)?,
            };
            let (extent, cells, mesh) = (mesh.extent, mesh.kind, Arc::new(mesh));
            let source = match input {
                MeshInput::Arrays(_) => MeshSource::Arrays(mesh),
                MeshInput::File(_) => MeshSource::File { path, mesh },
            };
            (extent, [0; 3], cells, source)
        }
        None => {
            let (extent, n, cells) = structured(&t, dim)?;
            (extent, n, cells, MeshSource::Box)
        }
    };
    let lame = Lame {
        lambda: non_negative("solid.lame_lambda", t.lame_lambda)?,
        mu: positive("solid.lame_mu", t.lame_mu, 0.5)?,
        density: positive("solid.density", t.density, 1.0)?,
    };
    let gap = non_negative("solid.gap", t.gap)?;
    let lateral = match t.lateral.as_deref().unwrap_or("free") {
        "free" => Lateral::Free,
        "roller" => Lateral::Roller,
        other => {
            let range = "\"free\" (traction-free) | \"roller\" (u·n = 0)";
            return Err(SceneError::Range { key: "solid.lateral", value: format!("\"{other}\""), range });
        }
    };
    let support = match obstacle {
        Some(o) => {
            let (vars, consts) = variables(dim, extent);
            let force = parse_body_force(t.force, dim, vars, &consts)?;
            Support::Plane(BodySpec { obstacle: parse_obstacle(o, dim)?, clamped: t.clamped, force })
        }
        None => Support::Face { gap, lateral, force: t.force.as_deref().map_or(Ok([0.0; 3]), |v| box_force(v, dim))? },
    };
    let initial = match (&support, t.initial) {
        (Support::Plane(_), None) => zero_initial(dim, extent)?,
        (Support::Plane(_), Some(RawSolidInitial::Name(s))) => {
            let range = "{ displacement = [...], velocity = [...] } (the paper's data are the box's)";
            return Err(SceneError::Range { key: "solid.initial", value: format!("\"{s}\""), range });
        }
        (_, raw) => parse_initial(raw, dim, extent)?,
    };
    let cache = Default::default();
    let spec = SolidSpec { dim, extent, cells_per_axis: n, cells, lame, initial, source, support, cache };
    if let Support::Plane(body) = &spec.support {
        check_body(&spec, body)?;
    }
    if let SolidInitial::Fields { displacement, velocity } = &spec.initial {
        let built = spec.built().map_err(setup_error)?;
        for e in displacement.iter().chain(velocity) {
            e.eval_at_nodes(built.mesh.points.iter().map(|p| &p[..dim])).map_err(SceneError::from)?;
        }
    }
    Ok(spec)
}

/// A solid's build error at validation (its mesh, or a body's contact set) as a scene error.
fn setup_error(e: BuildError) -> SceneError {
    match e {
        BuildError::Mesh(m) => SceneError::Mesh(m),
        BuildError::Body(b) => b.into(),
        BuildError::Bodies(b) => SceneError::Geometry(Box::new(b)),
    }
}

/// A body's contact set refused at validation: the solid's own error, its message as it is.
impl From<BodyError> for SceneError {
    fn from(e: BodyError) -> Self {
        SceneError::Geometry(Box::new(e))
    }
}

/// `initial = "paper"` or `{ displacement = [..], velocity = [..] }` (one entry per component,
/// a number or an expression; a missing array is all zeros). A number is kept exactly (its
/// shortest round-trip text).
fn parse_initial(v: Option<RawSolidInitial>, dim: usize, extent: [f64; 3]) -> Result<SolidInitial, SceneError> {
    let range = "\"paper\" or { displacement = [...], velocity = [...] } with one expression per component";
    let fields = match v {
        None => return Ok(SolidInitial::Paper),
        Some(RawSolidInitial::Name(s)) if s == "paper" => return Ok(SolidInitial::Paper),
        Some(RawSolidInitial::Name(s)) => {
            return Err(SceneError::Range { key: "solid.initial", value: format!("\"{s}\""), range });
        }
        Some(RawSolidInitial::Fields(f)) => f,
    };
    let (vars, consts) = variables(dim, extent);
    let consts = &consts[..];
    let field = |key: &'static str, raw: Option<Vec<RawField>>| -> Result<Vec<Expr>, SceneError> {
        let Some(a) = raw else {
            return Ok((0..dim).map(|_| Expr::parse(key, "0", vars, consts).expect("0 parses")).collect());
        };
        if a.len() != dim {
            let value = format!("{} entries", a.len());
            return Err(SceneError::Range { key, value, range: "one expression per component (solid.dim of them)" });
        }
        a.into_iter()
            .map(|x| {
                let text = match x {
                    RawField::Expr(s) => s,
                    RawField::Number(n) => finite_in(key, n.get(), true, "finite numbers or expressions").map(short)?,
                };
                Ok(Expr::parse(key, &text, vars, consts)?)
            })
            .collect()
    };
    Ok(SolidInitial::Fields {
        displacement: field("solid.initial.displacement", fields.displacement)?,
        velocity: field("solid.initial.velocity", fields.velocity)?,
    })
}

/// A box's `solid.force`: one finite number per component (expressions need an [obstacle]).
fn box_force(v: &[RawField], dim: usize) -> Result<[f64; 3], SceneError> {
    let range = "an array of one finite number per component (expressions: bodies with an [obstacle])";
    let numbers: Vec<Option<f64>> =
        v.iter().map(|x| if let RawField::Number(n) = x { Some(n.get()) } else { None }).collect();
    if v.len() != dim || numbers.iter().any(|x| !x.is_some_and(f64::is_finite)) {
        let shown = |x: &RawField| match x {
            RawField::Number(n) => short(n.get()),
            RawField::Expr(e) => format!("\"{e}\""),
        };
        let value = format!("[{}]", v.iter().map(shown).collect::<Vec<_>>().join(", "));
        return Err(SceneError::Range { key: "solid.force", value, range });
    }
    let mut force = [0.0; 3];
    for (f, x) in force.iter_mut().zip(numbers) {
        *f = x.unwrap_or(0.0);
    }
    Ok(force)
}

/// The variables x, y[, z] and constants L, H[, D], pi of a solid's expressions.
fn variables(dim: usize, extent: [f64; 3]) -> (&'static [&'static str], Vec<(&'static str, f64)>) {
    let vars: &[&str] = if dim == 2 { &["x", "y"] } else { &["x", "y", "z"] };
    let pi = std::f64::consts::PI;
    let consts = [("L", extent[0]), ("H", extent[1]), ("D", extent[2]), ("pi", pi)];
    (vars, if dim == 2 { vec![consts[0], consts[1], consts[3]] } else { consts.to_vec() })
}

/// A body's default initial data: u = v = 0.
fn zero_initial(dim: usize, extent: [f64; 3]) -> Result<SolidInitial, SceneError> {
    let zeros = || Some((0..dim).map(|_| RawField::Number(Number::Int(0))).collect());
    parse_initial(
        Some(RawSolidInitial::Fields(RawSolidFields { displacement: zeros(), velocity: zeros() })),
        dim,
        extent,
    )
}

/// A body's checks at validation (exit 2, nothing written): its contact set, gaps and groups
/// ([`crate::solid::body::contact`]) and its force finite at the nodes at t = 0. The size of
/// its contact Schur complement is the compatibility rule's ([`crate::spec::compat`]: not
/// checked for central differences with the exact law, which form none).
fn check_body(spec: &SolidSpec, body: &BodySpec) -> Result<(), SceneError> {
    let built = spec.built().map_err(setup_error)?;
    let d = spec.dim;
    for e in &body.force {
        e.eval_at_nodes(built.mesh.points.iter().map(|p| [&p[..d], &[0.0][..]].concat())).map_err(SceneError::from)?;
    }
    Ok(())
}
