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
//! The table is read as a TOML table and validated by [`parse_solid`] (a pure function: every
//! error names the key, `solid.…`, and its allowed range; unknown keys are refused); the
//! resolved scene writes every key back ([`SceneGeometry::raw`]).

use super::*;
use crate::expr::Expr;
use crate::fem::layers::{cell_weights, layers};
use crate::fem::mesh::{Cell, Mesh};
use crate::mass::MassKind;
use crate::solid::{Lame, Lateral, SolidInitial, SolidSpec};
use std::sync::Arc;

/// The keys of `[solid]`, for the unknown-key message.
const KEYS: &str =
    "dim, length, height, depth, nx, ny, nz, cells, mesh, lame_lambda, lame_mu, density, gap, lateral, force, initial";

fn number(t: &toml::Table, key: &str, full: &'static str, default: f64) -> Result<f64, SceneError> {
    match t.get(key) {
        None => Ok(default),
        Some(toml::Value::Integer(i)) => Ok(*i as f64),
        Some(toml::Value::Float(f)) => Ok(*f),
        Some(v) => Err(SceneError::Range { key: full, value: v.to_string(), range: "a number" }),
    }
}

fn positive(t: &toml::Table, key: &str, full: &'static str, default: f64) -> Result<f64, SceneError> {
    let v = number(t, key, full, default)?;
    finite_in(full, v, v > 0.0, "(0, ∞)")
}

fn length(t: &toml::Table, key: &str, full: &'static str) -> Result<f64, SceneError> {
    length_in(full, number(t, key, full, 1.0)?)
}

fn count(t: &toml::Table, key: &str, full: &'static str, min: i64, range: &'static str) -> Result<usize, SceneError> {
    match t.get(key) {
        None => Ok(20),
        Some(toml::Value::Integer(i)) if *i >= min && *i <= 10_000 => Ok(*i as usize),
        Some(v) => Err(SceneError::Range { key: full, value: v.to_string(), range }),
    }
}

fn string<'a>(t: &'a toml::Table, key: &str, full: &'static str, default: &'a str) -> Result<&'a str, SceneError> {
    match t.get(key) {
        None => Ok(default),
        Some(toml::Value::String(s)) => Ok(s),
        Some(v) => Err(SceneError::Range { key: full, value: v.to_string(), range: "a string" }),
    }
}

/// The `[solid]` table validated into a [`SolidSpec`]: every error names the key (`solid.…`)
/// and its allowed range; unknown keys are refused. The size is checked before any mesh is
/// built (cells, contact nodes, cell aspect ratios), the initial data at the mesh nodes.
pub fn parse_solid(t: &toml::Table) -> Result<SolidSpec, SceneError> {
    parse_solid_at(t, std::path::Path::new("."))
}

/// [`parse_solid`] with `mesh = "…"` relative to `base` (the scene's folder), read here, once.
pub(crate) fn parse_solid_at(t: &toml::Table, base: &std::path::Path) -> Result<SolidSpec, SceneError> {
    if let Some(key) = t.keys().find(|k| !KEYS.split(", ").any(|x| x == k.as_str())) {
        return Err(SceneError::Parse(format!("unknown field `{key}` in [solid], expected one of {KEYS}")));
    }
    let dim = match t.get("dim") {
        None => 2,
        Some(toml::Value::Integer(d @ (2 | 3))) => *d as usize,
        Some(v) => return Err(SceneError::Range { key: "solid.dim", value: v.to_string(), range: "2 | 3" }),
    };
    if dim == 2 {
        for key in ["depth", "nz"] {
            if t.contains_key(key) {
                let key = if key == "depth" { "solid.depth" } else { "solid.nz" };
                return Err(SceneError::Inapplicable { key, context: "solid.dim = 2".into() });
            }
        }
    }
    let (extent, n, cells, mesh, mesh_file) = match t.get("mesh") {
        Some(file) => {
            let file = file.as_str().ok_or_else(|| SceneError::Range {
                key: "solid.mesh",
                value: file.to_string(),
                range: "a mesh file name (a string, relative to the scene file)",
            })?;
            let path = base.join(file);
            let mesh = file_mesh(t, dim, &path)?;
            (mesh.extent, [0; 3], mesh.kind, Some(Arc::new(mesh)), Some(path))
        }
        None => {
            let (extent, n, cells) = structured(t, dim)?;
            (extent, n, cells, None, None)
        }
    };
    let lambda = number(t, "lame_lambda", "solid.lame_lambda", 0.0)?;
    let lambda = finite_in("solid.lame_lambda", lambda, lambda >= 0.0, "[0, ∞)")?;
    let lame = Lame {
        lambda,
        mu: positive(t, "lame_mu", "solid.lame_mu", 0.5)?,
        density: positive(t, "density", "solid.density", 1.0)?,
    };
    let gap = number(t, "gap", "solid.gap", 0.0)?;
    let gap = finite_in("solid.gap", gap, gap >= 0.0, "[0, ∞)")?;
    let lateral = match string(t, "lateral", "solid.lateral", "free")? {
        "free" => Lateral::Free,
        "roller" => Lateral::Roller,
        other => {
            let range = "\"free\" (traction-free) | \"roller\" (u·n = 0)";
            return Err(SceneError::Range { key: "solid.lateral", value: format!("\"{other}\""), range });
        }
    };
    let mut force = [0.0; 3];
    if let Some(v) = t.get("force") {
        let range = "an array of one finite number per component";
        let bad = || SceneError::Range { key: "solid.force", value: v.to_string(), range };
        let a = v.as_array().filter(|a| a.len() == dim).ok_or_else(bad)?;
        for (f, x) in force.iter_mut().zip(a) {
            *f = x.as_float().or_else(|| x.as_integer().map(|i| i as f64)).filter(|f| f.is_finite()).ok_or_else(bad)?;
        }
    }
    let initial = parse_initial(t.get("initial"), dim, extent)?;
    let spec = SolidSpec { dim, extent, cells_per_axis: n, cells, lame, gap, lateral, force, initial, mesh_file, mesh };
    if let SolidInitial::Fields { displacement, velocity } = &spec.initial {
        let mesh = spec.mesh()?;
        for e in displacement.iter().chain(velocity) {
            e.eval_at_nodes(mesh.points.iter().map(|p| &p[..dim])).map_err(SceneError::from)?;
        }
    }
    Ok(spec)
}

/// `initial = "paper"` or `{ displacement = [..], velocity = [..] }` (one entry per component;
/// a missing array is all zeros).
fn parse_initial(v: Option<&toml::Value>, dim: usize, extent: [f64; 3]) -> Result<SolidInitial, SceneError> {
    let range = "\"paper\" or { displacement = [...], velocity = [...] } with one expression per component";
    let bad = |v: &toml::Value| SceneError::Range { key: "solid.initial", value: v.to_string(), range };
    let table = match v {
        None => return Ok(SolidInitial::Paper),
        Some(toml::Value::String(s)) if s == "paper" => return Ok(SolidInitial::Paper),
        Some(toml::Value::Table(t)) => t,
        Some(v) => return Err(bad(v)),
    };
    if let Some(k) = table.keys().find(|k| *k != "displacement" && *k != "velocity") {
        return Err(SceneError::Parse(format!(
            "unknown field `{k}` in solid.initial, expected one of displacement, velocity"
        )));
    }
    let vars: &[&str] = if dim == 2 { &["x", "y"] } else { &["x", "y", "z"] };
    let pi = std::f64::consts::PI;
    let consts = [("L", extent[0]), ("H", extent[1]), ("D", extent[2]), ("pi", pi)];
    let consts = if dim == 2 { &[consts[0], consts[1], consts[3]][..] } else { &consts[..] };
    let field = |key: &'static str, name: &str| -> Result<Vec<Expr>, SceneError> {
        let Some(v) = table.get(name) else {
            return Ok((0..dim).map(|_| Expr::parse(key, "0", vars, consts).expect("0 parses")).collect());
        };
        let a = v.as_array().filter(|a| a.len() == dim).ok_or_else(|| bad(v))?;
        a.iter()
            .map(|x| {
                let text = match x {
                    toml::Value::String(s) => s.clone(),
                    toml::Value::Integer(i) => i.to_string(),
                    toml::Value::Float(f) if f.is_finite() => crate::expr::sci(*f),
                    other => return Err(bad(other)),
                };
                Ok(Expr::parse(key, &text, vars, consts)?)
            })
            .collect()
    };
    Ok(SolidInitial::Fields {
        displacement: field("solid.initial.displacement", "displacement")?,
        velocity: field("solid.initial.velocity", "velocity")?,
    })
}

/// The structured box of a `[solid]` table without `mesh`: extent, cells per axis, cell kind,
/// its size checked before any mesh is built.
fn structured(t: &toml::Table, dim: usize) -> Result<([f64; 3], [usize; 3], Cell), SceneError> {
    let extent = [
        length(t, "length", "solid.length")?,
        length(t, "height", "solid.height")?,
        length(t, "depth", "solid.depth")?,
    ];
    let n = [
        count(t, "nx", "solid.nx", 2, "integers in [2, 10000]")?,
        count(t, "ny", "solid.ny", 1, "integers in [1, 10000]")?,
        count(t, "nz", "solid.nz", 1, "integers in [1, 10000]")?,
    ];
    let cells = match (dim, string(t, "cells", "solid.cells", if dim == 2 { "quad" } else { "hex" })?) {
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
fn file_mesh(t: &toml::Table, dim: usize, path: &std::path::Path) -> Result<Mesh, SceneError> {
    let context = "solid.mesh (the mesh file gives the geometry)";
    for key in ["solid.length", "solid.height", "solid.depth", "solid.nx", "solid.ny", "solid.nz", "solid.cells"] {
        if t.contains_key(&key[6..]) {
            return Err(SceneError::Inapplicable { key, context: context.into() });
        }
    }
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
    check_contact_memory((0..mesh.n_nodes()).filter(|&v| mesh.on_contact(v)).count())?;
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
    check_contact_memory(contact)?;
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

impl SceneGeometry for SolidSpec {
    const TABLE: &'static str = "solid";
    const COLUMNS: &'static [Column] = &Column::PLATE;
    const COLUMN_LIST: &'static str = SERIES_NAMES;
    const SIZE_KEYS: &'static str = "solid.nx, solid.ny[, solid.nz]";
    const VTU: bool = true;

    /// Free nodes (all but x = L) times the components, less the normal components a roller
    /// face removes.
    fn unknowns(&self) -> usize {
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
        let weights = cell_weights(&mesh, mass)?;
        Ok(layers(&mesh).iter().zip(&weights).filter(|(l, _)| **l == 0).map(|(_, w)| *w).fold(0.0, f64::max))
    }

    fn unavailable(&self, column: Column) -> Option<String> {
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
        let mut series = vec![Column::U0, Column::UMean, Column::Lambda, Column::ContactForce, Column::Energy];
        if self.unavailable(Column::L2Error).is_none() {
            series.push(Column::L2Error);
        }
        series
    }

    fn raw(&self) -> RawScene {
        let mut t = toml::Table::new();
        let f = |x: f64| toml::Value::Float(x);
        let i = |k: usize| toml::Value::Integer(k as i64);
        let s = |x: &str| toml::Value::String(x.into());
        let three = self.dim == 3;
        t.insert("dim".into(), i(self.dim));
        if let Some(file) = &self.mesh_file {
            t.insert("mesh".into(), s(&file.display().to_string()));
        } else {
            t.insert("length".into(), f(self.extent[0]));
            t.insert("height".into(), f(self.extent[1]));
            if three {
                t.insert("depth".into(), f(self.extent[2]));
            }
            t.insert("nx".into(), i(self.cells_per_axis[0]));
            t.insert("ny".into(), i(self.cells_per_axis[1]));
            if three {
                t.insert("nz".into(), i(self.cells_per_axis[2]));
            }
            t.insert("cells".into(), s(self.cells.name()));
        }
        t.insert("lame_lambda".into(), f(self.lame.lambda));
        t.insert("lame_mu".into(), f(self.lame.mu));
        t.insert("density".into(), f(self.lame.density));
        t.insert("gap".into(), f(self.gap));
        t.insert("lateral".into(), s(self.lateral.name()));
        t.insert("force".into(), toml::Value::Array(self.force[..self.dim].iter().map(|&x| f(x)).collect()));
        let initial = match &self.initial {
            SolidInitial::Paper => s("paper"),
            SolidInitial::Fields { displacement, velocity } => {
                let texts = |e: &[crate::expr::Expr]| toml::Value::Array(e.iter().map(|x| s(x.text())).collect());
                let mut fields = toml::Table::new();
                fields.insert("displacement".into(), texts(displacement));
                fields.insert("velocity".into(), texts(velocity));
                toml::Value::Table(fields)
            }
        };
        t.insert("initial".into(), initial);
        RawScene { solid: Some(t), ..Default::default() }
    }

    fn header(&self, time: &TimeSpec) -> String {
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

    fn from_any(any: AnyScene) -> Result<Scene<Self>, SceneError> {
        match any {
            AnyScene::Solid(s) => Ok(s),
            other => Err(wrong_geometry(Self::TABLE, &other)),
        }
    }
}
