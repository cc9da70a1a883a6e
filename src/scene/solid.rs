//! Solid scenes (TOML): a `[solid]` table replaces `[bar]`; the other sections are the ones every
//! scene shares ([`super::validate_sections`]); `[output]` has the plate columns and VTU options.
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
//! key) and validated by [`validate_solid`] (a pure function but for the mesh file it reads:
//! every error names the key, `solid.…`, and its allowed range); the resolved scene writes
//! every key back ([`SceneGeometry::raw`]). The specification itself is `crate::solid::spec`.

use super::*;
use crate::expr::Expr;
use crate::fem::layers::{cell_weights, cell_weights_of, layers, layers_of};
use crate::fem::mesh::{Cell, Mesh};
use crate::mass::MassKind;
use crate::solid::{BodySpec, Lame, Lateral, SolidInitial, SolidSpec};
use std::sync::Arc;

/// The `[solid]` table as written (closed: unknown keys are refused, naming the key).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSolid {
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

/// A number key in (0, ∞).
fn positive(key: &'static str, v: Option<Number>, default: f64) -> Result<f64, SceneError> {
    let v = v.map_or(default, Number::get);
    finite_in(key, v, v > 0.0, "(0, ∞)")
}

/// A number key in [0, ∞).
fn non_negative(key: &'static str, v: Option<Number>) -> Result<f64, SceneError> {
    let v = v.map_or(0.0, Number::get);
    finite_in(key, v, v >= 0.0, "[0, ∞)")
}

/// A cell count in [min, 10000] (default 20).
fn count(key: &'static str, v: Option<i64>, min: i64, range: &'static str) -> Result<usize, SceneError> {
    match v.unwrap_or(20) {
        k if (min..=10_000).contains(&k) => Ok(k as usize),
        k => Err(SceneError::Range { key, value: k.to_string(), range }),
    }
}

/// The `[solid]` table (as a TOML table) validated into a [`SolidSpec`], a mesh file relative to
/// the current folder (library users; scene files go through [`crate::scene::AnyScene`]).
pub fn parse_solid(t: &toml::Table) -> Result<SolidSpec, SceneError> {
    let raw = RawSolid::deserialize(toml::Value::Table(t.clone()))
        .map_err(|e| SceneError::Parse(format!("[solid]: {}", e.to_string().trim_end())))?;
    validate_solid(raw, None, std::path::Path::new("."))
}

/// The `[solid]` table validated into a [`SolidSpec`]: every error names the key (`solid.…`)
/// and its allowed range. The size is checked before any mesh is built (cells, contact nodes,
/// cell aspect ratios), the initial data at the mesh nodes; `mesh = "…"` is relative to `base`
/// (the scene's folder) and read here, once.
pub(crate) fn validate_solid(
    t: RawSolid,
    obstacle: Option<RawObstacle>,
    base: &std::path::Path,
) -> Result<SolidSpec, SceneError> {
    let dim = match t.dim.unwrap_or(2) {
        d @ (2 | 3) => d as usize,
        d => return Err(SceneError::Range { key: "solid.dim", value: d.to_string(), range: "2 | 3" }),
    };
    if dim == 2 {
        forbid("solid.depth", &t.depth, "solid.dim = 2")?;
        forbid("solid.nz", &t.nz, "solid.dim = 2")?;
    }
    if obstacle.is_some() {
        forbid("solid.gap", &t.gap, "a body with an [obstacle] (obstacle.point places the plane)")?;
        forbid("solid.lateral", &t.lateral, "a body with an [obstacle] (its boundary is free but where clamped)")?;
    } else {
        forbid("solid.clamped", &t.clamped, "a box without [obstacle] (clamped on x = L)")?;
    }
    let (extent, n, cells, mesh, mesh_file) = match &t.mesh {
        Some(file) => {
            let path = base.join(file);
            let mesh = if obstacle.is_some() { body_file_mesh(&t, dim, &path)? } else { file_mesh(&t, dim, &path)? };
            (mesh.extent, [0; 3], mesh.kind, Some(Arc::new(mesh)), Some(path))
        }
        None => {
            let (extent, n, cells) = structured(&t, dim)?;
            (extent, n, cells, None, None)
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
    let (mut force, mut body) = ([0.0; 3], None);
    if let Some(o) = obstacle {
        let (vars, consts) = variables(dim, extent);
        let force = parse_body_force(t.force, dim, vars, &consts)?;
        body = Some(BodySpec { obstacle: parse_obstacle(o, dim)?, clamped: t.clamped, force });
    } else if let Some(v) = &t.force {
        force = box_force(v, dim)?;
    }
    let initial = match (&body, t.initial) {
        (Some(_), None) => zero_initial(dim, extent)?,
        (Some(_), Some(RawSolidInitial::Name(s))) => {
            let range = "{ displacement = [...], velocity = [...] } (the paper's data are the box's)";
            return Err(SceneError::Range { key: "solid.initial", value: format!("\"{s}\""), range });
        }
        (_, raw) => parse_initial(raw, dim, extent)?,
    };
    let spec =
        SolidSpec { dim, extent, cells_per_axis: n, cells, lame, gap, lateral, force, initial, mesh_file, mesh, body };
    if let Some(body) = &spec.body {
        check_body(&spec, body)?;
    }
    if let SolidInitial::Fields { displacement, velocity } = &spec.initial {
        let mesh = spec.mesh()?;
        for e in displacement.iter().chain(velocity) {
            e.eval_at_nodes(mesh.points.iter().map(|p| &p[..dim])).map_err(SceneError::from)?;
        }
    }
    Ok(spec)
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
/// ([`crate::solid::body::contact`]), the size of its contact Schur complement, its force
/// finite at the nodes at t = 0.
fn check_body(spec: &SolidSpec, body: &BodySpec) -> Result<(), SceneError> {
    let mesh = spec.mesh()?;
    let contact = crate::solid::body::contact(&mesh, body)?;
    let keys = if spec.mesh_file.is_some() {
        "obstacle.contact, or solid.mesh"
    } else {
        "obstacle.contact, or solid.nx, solid.ny[, solid.nz]"
    };
    check_contact_memory(contact.nodes.len(), keys)?;
    let d = spec.dim;
    for e in &body.force {
        e.eval_at_nodes(mesh.points.iter().map(|p| [&p[..d], &[0.0][..]].concat())).map_err(SceneError::from)?;
    }
    Ok(())
}

/// The mesh of `solid.mesh` for a body: read at the edge, of the table's `dim`; any shape.
fn body_file_mesh(t: &RawSolid, dim: usize, path: &std::path::Path) -> Result<Mesh, SceneError> {
    let context = "solid.mesh (the mesh file gives the geometry)";
    for (key, v) in [("solid.length", &t.length), ("solid.height", &t.height), ("solid.depth", &t.depth)] {
        forbid(key, v, context)?;
    }
    for (key, v) in [("solid.nx", &t.nx), ("solid.ny", &t.ny), ("solid.nz", &t.nz)] {
        forbid(key, v, context)?;
    }
    forbid("solid.cells", &t.cells, context)?;
    Ok(super::mesh_file::read_body("solid.mesh", path, dim)?)
}

/// The structured box of a `[solid]` table without `mesh`: extent, cells per axis, cell kind,
/// its size checked before any mesh is built.
fn structured(t: &RawSolid, dim: usize) -> Result<([f64; 3], [usize; 3], Cell), SceneError> {
    let length = |key, v: Option<Number>| length_in(key, v.map_or(1.0, Number::get));
    let extent =
        [length("solid.length", t.length)?, length("solid.height", t.height)?, length("solid.depth", t.depth)?];
    let n = [
        count("solid.nx", t.nx, 2, "integers in [2, 10000]")?,
        count("solid.ny", t.ny, 1, "integers in [1, 10000]")?,
        count("solid.nz", t.nz, 1, "integers in [1, 10000]")?,
    ];
    let cells = match (dim, t.cells.as_deref().unwrap_or(if dim == 2 { "quad" } else { "hex" })) {
        (2, "quad") => Cell::Quad,
        (2, "triangle") => Cell::Triangle,
        (3, "hex") => Cell::Hex,
        (3, "tet") => Cell::Tet,
        (d, other) => {
            let range = if d == 2 { "quad | triangle (dim = 2)" } else { "hex | tet (dim = 3)" };
            return Err(SceneError::Range { key: "solid.cells", value: format!("\"{other}\""), range });
        }
    };
    check_size(dim, extent, n)?;
    Ok((extent, n, cells))
}

/// The mesh of `solid.mesh`: read by meshio, of the table's `dim`, filling the box
/// (0, L) × (0, H) [× (0, D)] (the contact face x = 0 and the lateral faces are the box's).
fn file_mesh(t: &RawSolid, dim: usize, path: &std::path::Path) -> Result<Mesh, SceneError> {
    let context = "solid.mesh (the mesh file gives the geometry)";
    forbid("solid.length", &t.length, context)?;
    forbid("solid.height", &t.height, context)?;
    forbid("solid.depth", &t.depth, context)?;
    forbid("solid.nx", &t.nx, context)?;
    forbid("solid.ny", &t.ny, context)?;
    forbid("solid.nz", &t.nz, context)?;
    forbid("solid.cells", &t.cells, context)?;
    let mesh = super::mesh_file::read("solid.mesh", path)?;
    let bad = |what: String| SceneError::Range {
        key: "solid.mesh",
        value: format!("\"{}\" ({what})", path.display()),
        range: "a triangle or quad mesh (solid.dim = 2), a tetrahedron or hexahedron mesh (solid.dim = 3), filling the box (0, L) × (0, H) [× (0, D)]",
    };
    if mesh.dim != dim {
        return Err(bad(format!("a {}D mesh", mesh.dim)));
    }
    for axis in 1..dim {
        let lo = mesh.points.iter().map(|p| p[axis]).fold(f64::INFINITY, f64::min);
        if lo.abs() > 1e-12 * mesh.extent[axis] {
            return Err(bad(format!("smallest {} = {}", ["x", "y", "z"][axis], short(lo))));
        }
    }
    mesh.check_fills_box().map_err(|e| bad(e.to_string()))?;
    check_contact_memory((0..mesh.n_nodes()).filter(|&v| mesh.on_contact(v)).count(), "its face x = 0 in solid.mesh")?;
    Ok(mesh)
}

/// Sizes refused before a mesh is built: more than [`MAX_ELEMENTS`] cells, more contact nodes
/// than the dense contact Schur complement allows ([`MAX_CONTACT_VALUES`]), or cells so far from
/// cubes that the stiffness cannot be factored in double precision (as for plates).
fn check_size(dim: usize, extent: [f64; 3], n: [usize; 3]) -> Result<(), SceneError> {
    let axes = if dim == 2 { 2 } else { 3 };
    let cells: f64 = n[..axes].iter().map(|&k| k as f64).product();
    if cells > MAX_ELEMENTS as f64 {
        let keys = if dim == 2 { "solid.nx × solid.ny" } else { "solid.nx × solid.ny × solid.nz" };
        return Err(SceneError::Range {
            key: keys_of(dim),
            value: format!("{cells:e} cells ({keys})"),
            range: "at most 1e7 cells",
        });
    }
    let contact = n[1..axes].iter().map(|&k| k + 1).product::<usize>();
    check_contact_memory(contact, if dim == 2 { "solid.ny" } else { "solid.ny, solid.nz" })?;
    let h: Vec<f64> = (0..axes).map(|a| extent[a] / n[a] as f64).collect();
    let (lo, hi) = h.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &x| (lo.min(x), hi.max(x)));
    if hi / lo > 1e6 {
        return Err(SceneError::Range {
            key: "solid.height",
            value: short(extent[1]),
            range: "cell edges (length/nx, height/ny[, depth/nz]) within a ratio of 1e6 of each other",
        });
    }
    Ok(())
}

fn keys_of(dim: usize) -> &'static str {
    if dim == 2 { "solid.nx, solid.ny" } else { "solid.nx, solid.ny, solid.nz" }
}

/// The series columns of a solid (the body ones need an [obstacle]).
const SOLID_SERIES_NAMES: &str = "any subset of u0, u_mean, lambda, contact_force, energy, l2_error, exact_u0, exact_lambda, pivots, and for bodies active_nodes, min_distance, momentum_x|y|z, mean_u_x|y|z";

impl SceneGeometry for SolidSpec {
    const TABLE: &'static str = "solid";
    const COLUMNS: &'static [Column] = &Column::SOLID;
    const COLUMN_LIST: &'static str = SOLID_SERIES_NAMES;
    const SIZE_KEYS: &'static str = "solid.nx, solid.ny[, solid.nz]";
    const VTU: bool = true;

    fn size_keys(&self) -> &'static str {
        if self.mesh_file.is_some() { "solid.mesh (a coarser mesh)" } else { keys_of(self.dim) }
    }

    /// Free nodes (all but x = L) times the components, less the normal components a roller
    /// face removes.
    fn unknowns(&self) -> usize {
        if let Some(body) = &self.body {
            // Validated: the contact set builds (check_body).
            let mesh = self.mesh().expect("a validated body has its mesh");
            let clamped =
                crate::solid::body::contact(&mesh, body).map_or(0, |c| c.clamped.iter().filter(|&&k| k).count());
            return (mesh.n_nodes() - clamped) * self.dim;
        }
        if let Some(mesh) = &self.mesh {
            let d = self.dim;
            let roller = self.lateral == Lateral::Roller;
            let free = |v: usize| (0..d).filter(|&c| !(c >= 1 && roller && mesh.on_lateral(v, c))).count();
            return (0..mesh.n_nodes()).filter(|&v| !mesh.on_dirichlet(v)).map(free).sum();
        }
        let [nx, ny, nz] = self.cells_per_axis;
        let nz = if self.dim == 2 { 0 } else { nz };
        let (sy, sz) = (ny + 1, nz + 1);
        let mut count = nx * sy * sz * self.dim;
        if self.lateral == Lateral::Roller {
            count -= nx * 2 * sz; // u_y on y = 0, H
            if self.dim == 3 {
                count -= nx * 2 * sy; // u_z on z = 0, D
            }
        }
        count
    }

    fn length(&self) -> f64 {
        self.extent[0]
    }

    /// The largest weight of the cells touching x = 0 (0 iff every component of a contact-face
    /// node is massless).
    fn contact_weight(&self, mass: &MassKind) -> Result<f64, SceneError> {
        let mesh: Mesh = self.mesh()?;
        let (weights, layer) = match &self.body {
            None => (cell_weights(&mesh, mass)?, layers(&mesh)),
            Some(body) => {
                let c = crate::solid::body::contact(&mesh, body)?;
                (cell_weights_of(&mesh, mass, &c.contact, &c.clamped)?, layers_of(&mesh, &c.contact))
            }
        };
        Ok(layer.iter().zip(&weights).filter(|(l, _)| **l == 0).map(|(_, w)| *w).fold(0.0, f64::max))
    }

    fn unavailable(&self, column: Column) -> Option<String> {
        if column.is_body() && self.body.is_none() {
            return Some("a body's columns need an [obstacle] (a body against a rigid plane)".into());
        }
        if column.component().is_some_and(|k| k >= self.dim) {
            return Some("the z component of a 2D body".into());
        }
        if column.needs_exact() && !self.is_plane_wave() {
            return Some(
                "the exact solution (l2_error, exact_u0, exact_lambda) is a plane wave: x-only data, no force, and solid.lame_lambda = 0 or solid.lateral = \"roller\"".into(),
            );
        }
        if column != Column::L2Error {
            return None;
        }
        if self.mesh_file.is_some() {
            return Some("solid.mesh: the exact L² error is integrated on structured quad and hex meshes only".into());
        }
        (!self.cells.is_tensor()).then(|| {
            format!(
                "solid.cells = \"{}\": the exact L² error is integrated on quad and hex cells only",
                self.cells.name()
            )
        })
    }

    fn default_series(&self) -> Vec<Column> {
        if self.body.is_some() {
            let mut series = vec![Column::Energy, Column::ContactForce];
            series.extend(Column::BODY.into_iter().filter(|c| c.component().is_none_or(|k| k < self.dim)));
            return series;
        }
        let mut series = vec![Column::U0, Column::UMean, Column::Lambda, Column::ContactForce, Column::Energy];
        if self.unavailable(Column::L2Error).is_none() {
            series.push(Column::L2Error);
        }
        series
    }

    fn raw(&self) -> RawScene {
        let (f, i) = (|x: f64| Some(Number::Float(x)), |k: usize| Some(k as i64));
        let (three, structured) = (self.dim == 3, self.mesh_file.is_none());
        let initial = match &self.initial {
            SolidInitial::Paper => RawSolidInitial::Name("paper".into()),
            SolidInitial::Fields { displacement, velocity } => {
                let texts = |e: &[Expr]| Some(e.iter().map(|x| RawField::Expr(x.text().into())).collect());
                RawSolidInitial::Fields(RawSolidFields { displacement: texts(displacement), velocity: texts(velocity) })
            }
        };
        let solid = RawSolid {
            dim: i(self.dim),
            mesh: self.mesh_file.as_ref().map(|m| m.display().to_string()),
            length: f(self.extent[0]).filter(|_| structured),
            height: f(self.extent[1]).filter(|_| structured),
            depth: f(self.extent[2]).filter(|_| structured && three),
            nx: i(self.cells_per_axis[0]).filter(|_| structured),
            ny: i(self.cells_per_axis[1]).filter(|_| structured),
            nz: i(self.cells_per_axis[2]).filter(|_| structured && three),
            cells: structured.then(|| self.cells.name().into()),
            lame_lambda: f(self.lame.lambda),
            lame_mu: f(self.lame.mu),
            density: f(self.lame.density),
            gap: f(self.gap).filter(|_| self.body.is_none()),
            lateral: Some(self.lateral.name().into()).filter(|_| self.body.is_none()),
            force: Some(match &self.body {
                None => self.force[..self.dim].iter().map(|&x| RawField::Number(Number::Float(x))).collect(),
                Some(b) => b.force.iter().map(|e| RawField::Expr(e.text().into())).collect(),
            }),
            initial: Some(initial),
            clamped: self.body.as_ref().and_then(|b| b.clamped.clone()),
        };
        let obstacle = self.body.as_ref().map(|b| raw_obstacle(&b.obstacle, self.dim));
        RawScene { solid: Some(solid), obstacle, ..Default::default() }
    }

    fn header(&self, time: &TimeSpec) -> String {
        if self.body.is_some() {
            return format!("# Resolved body scene (every default filled in); {} steps.\n", time.steps);
        }
        if self.mesh_file.is_some() {
            return format!(
                "# Resolved solid scene (every default filled in); {} steps, mesh from a file.\n",
                time.steps
            );
        }
        let [l, h, d] = self.extent;
        let [nx, ny, nz] = self.cells_per_axis;
        let dz = if self.dim == 3 { format!(", dx3 = {:e}", d / nz as f64) } else { String::new() };
        format!(
            "# Resolved solid scene (every default filled in); {} steps, dx1 = {:e}, dx2 = {:e}{dz}.\n",
            time.steps,
            l / nx as f64,
            h / ny as f64
        )
    }

    /// The element triplets of `crate::solid::assembly`: per cell k²·d mass and k²·d²
    /// stiffness triplets (two indices and a value, 24 bytes), each with its value copied out
    /// and the pattern's row index and slot: 48 bytes per triplet, k the cell's vertices
    /// (measured: a 40³ hex, 2.4 GB by this count, peaks at about 2.8 GB before its factor).
    fn assembly_bytes(&self) -> f64 {
        let cells = match &self.mesh {
            Some(m) => m.n_cells() as f64,
            None => {
                let axes = &self.cells_per_axis[..self.dim];
                let boxes: f64 = axes.iter().map(|&n| n as f64).product();
                // The structured meshes split each box into 2 triangles or 6 (Kuhn) tetrahedra.
                boxes
                    * match self.cells {
                        Cell::Triangle => 2.0,
                        Cell::Tet => 6.0,
                        _ => 1.0,
                    }
            }
        };
        let (k, d) = (self.cells.verts() as f64, self.dim as f64);
        cells * k * k * d * (1.0 + d) * 48.0
    }

    fn from_any(any: AnyScene) -> Result<Scene<Self>, SceneError> {
        match any {
            AnyScene::Solid(s) => Ok(s),
            other => Err(wrong_geometry(Self::TABLE, &other)),
        }
    }
}
