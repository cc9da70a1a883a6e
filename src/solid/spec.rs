//! The `[solid]` table: its keys validated into a [`SolidSpec`] (a pure function of the raw
//! table, [`parse_solid`], for the one scene type to call), and the problem a spec poses
//! ([`SolidSpec::problem`]: the assembled [`SolidSystem`], the interpolated initial data and the
//! plane-wave exact solution where it applies).
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

use super::assembly::{Lame, Lateral, SolidAssemblyError, SolidSystem};
use crate::characteristics::{CharacteristicsError, InitialData};
use crate::exact::{Exact, ImpactingBar, by_characteristics, paper_data};
use crate::expr::Expr;
use crate::fem::layers::cell_weights;
use crate::fem::mesh::{Cell, Mesh};
use crate::mass::MassKind;
use crate::material::{FarEnd, Material};
use crate::plate::mesh::{CellKind, MeshError};
use crate::problem::Problem;
use crate::scene::SceneError;
use thiserror::Error;

/// The initial data of a solid.
#[derive(Debug, Clone, PartialEq)]
pub enum SolidInitial {
    /// u = ((L − x)/2, 0[, 0]), v = 0 (the paper's data as a plane wave).
    Paper,
    /// One expression per component (variables x, y[, z]; constants L, H[, D], pi).
    Fields { displacement: Vec<Expr>, velocity: Vec<Expr> },
}

impl SolidInitial {
    pub fn name(&self) -> &'static str {
        match self {
            SolidInitial::Paper => "paper",
            SolidInitial::Fields { .. } => "fields",
        }
    }

    /// Whether the data are a plane wave: u_x and v_x depend on x only, the other components 0.
    pub fn x_only(&self) -> bool {
        match self {
            SolidInitial::Paper => true,
            SolidInitial::Fields { displacement, velocity } => [displacement, velocity].iter().all(|f| {
                !f[0].depends_on("y") && !f[0].depends_on("z") && f[1..].iter().all(|e| e.is_constant() == Some(0.0))
            }),
        }
    }
}

/// A validated `[solid]` table (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct SolidSpec {
    pub dim: usize,
    /// `[L, H, D]` (D ignored in 2D).
    pub extent: [f64; 3],
    /// `[nx, ny, nz]` (nz ignored in 2D).
    pub cells_per_axis: [usize; 3],
    pub cells: Cell,
    pub lame: Lame,
    pub gap: f64,
    pub lateral: Lateral,
    /// Constant body force (entries beyond `dim` are 0).
    pub force: [f64; 3],
    pub initial: SolidInitial,
}

impl SolidSpec {
    /// The paper's bar as a solid: (0, 1)^d, λ = 0, μ = ½, ρ = 1, free lateral faces, the
    /// paper's data, Q1 cells (quad | hex).
    pub fn paper(dim: usize, n: [usize; 3]) -> Self {
        SolidSpec {
            dim,
            extent: [1.0, 1.0, 1.0],
            cells_per_axis: n,
            cells: if dim == 2 { Cell::Quad } else { Cell::Hex },
            lame: Lame::PAPER,
            gap: 0.0,
            lateral: Lateral::Free,
            force: [0.0; 3],
            initial: SolidInitial::Paper,
        }
    }

    /// The structured mesh of the spec.
    pub fn mesh(&self) -> Result<Mesh, MeshError> {
        let ([l, h, d], [nx, ny, nz]) = (self.extent, self.cells_per_axis);
        match self.cells {
            Cell::Quad => Mesh::structured_2d(l, h, nx, ny, CellKind::Quad),
            Cell::Triangle => Mesh::structured_2d(l, h, nx, ny, CellKind::Triangle),
            Cell::Hex | Cell::Tet => Mesh::structured_3d([l, h, d], [nx, ny, nz], self.cells),
        }
    }

    /// Whether the solution is a plane wave (module docs of [`crate::solid`]): x-only data, no
    /// force, and λ = 0 or roller lateral faces.
    pub fn is_plane_wave(&self) -> bool {
        self.initial.x_only()
            && self.force.iter().all(|&f| f == 0.0)
            && (self.lame.lambda == 0.0 || self.lateral == Lateral::Roller)
    }

    /// The problem of this spec with a mass redistribution: the assembled solid, the nodal
    /// interpolants of the initial data, and the plane wave up to `t_end` where it applies
    /// (the paper's closed form for λ + 2μ = ρ = 1 without gap, else the solution by
    /// characteristics of the bar with density ρ and modulus λ + 2μ).
    pub fn problem(&self, mass: &MassKind, t_end: f64) -> Result<Problem<SolidSystem>, SolidError> {
        let mesh = self.mesh()?;
        let weights = cell_weights(&mesh, mass).map_err(SolidAssemblyError::from)?;
        let solid = SolidSystem::assemble(mesh, weights, self.lame, self.lateral, self.force, self.gap)?;
        let l = self.extent[0];
        let (u0, v0) = match &self.initial {
            SolidInitial::Paper => {
                (solid.interpolate(|i, p| if i == 0 { (l - p[0]) / 2.0 } else { 0.0 }), vec![0.0; solid.dofs.len()])
            }
            SolidInitial::Fields { displacement, velocity } => {
                let eval = |f: &[Expr]| solid.interpolate(|i, p| f[i].eval(&p[..self.dim]));
                (eval(displacement), eval(velocity))
            }
        };
        let exact = if !self.is_plane_wave() {
            None
        } else if self.initial == SolidInitial::Paper
            && self.lame.p_modulus() == 1.0
            && self.lame.density == 1.0
            && self.gap == 0.0
        {
            Some(Exact::Paper(ImpactingBar { length: l }))
        } else {
            let material = Material { density: self.lame.density, modulus: self.lame.p_modulus() };
            let exact = |data| by_characteristics(l, material, FarEnd::Clamped, self.gap, data, t_end);
            let c = match &self.initial {
                SolidInitial::Paper => {
                    let (x, u, v) = paper_data(l);
                    exact(InitialData::PiecewiseLinear { x: &x, u: &u, v: &v })
                }
                SolidInitial::Fields { displacement, velocity } => {
                    let at = |x: f64| [x, 0.0, 0.0];
                    let u = |x: f64| displacement[0].eval(&at(x)[..self.dim]);
                    let v = |x: f64| velocity[0].eval(&at(x)[..self.dim]);
                    exact(InitialData::Smooth { u: &u, v: &v })
                }
            }
            .map_err(SolidError::Exact)?;
            Some(Exact::General(std::sync::Arc::new(c)))
        };
        Ok(Problem { system: solid, u0, v0, exact })
    }
}

#[derive(Debug, Error)]
pub enum SolidError {
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Assembly(#[from] SolidAssemblyError),
    #[error("the plane-wave exact solution of this solid: {0}")]
    Exact(CharacteristicsError),
}

/// The keys of `[solid]`, for the unknown-key message.
const KEYS: &str =
    "dim, length, height, depth, nx, ny, nz, cells, lame_lambda, lame_mu, density, gap, lateral, force, initial";

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
    crate::scene::finite_in(full, v, v > 0.0, "(0, ∞)")
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
/// and its allowed range; unknown keys are refused. Pure (no file is read: `mesh = "…"` is
/// refused until mesh files are wired for solids).
pub fn parse_solid(t: &toml::Table) -> Result<SolidSpec, SceneError> {
    if let Some(key) = t.keys().find(|k| !KEYS.split(", ").any(|x| x == k.as_str())) {
        return Err(SceneError::Parse(format!("unknown field `{key}` in [solid], expected one of {KEYS}")));
    }
    let dim = match t.get("dim") {
        None => 2,
        Some(toml::Value::Integer(d @ (2 | 3))) => *d as usize,
        Some(v) => return Err(SceneError::Range { key: "solid.dim", value: v.to_string(), range: "2 | 3" }),
    };
    let extent = [
        positive(t, "length", "solid.length", 1.0)?,
        positive(t, "height", "solid.height", 1.0)?,
        positive(t, "depth", "solid.depth", 1.0)?,
    ];
    let n = [
        count(t, "nx", "solid.nx", 2, "integers in [2, 10000]")?,
        count(t, "ny", "solid.ny", 1, "integers in [1, 10000]")?,
        count(t, "nz", "solid.nz", 1, "integers in [1, 10000]")?,
    ];
    if dim == 2 {
        for key in ["depth", "nz"] {
            if t.contains_key(key) {
                let key = if key == "depth" { "solid.depth" } else { "solid.nz" };
                return Err(SceneError::Inapplicable { key, context: "solid.dim = 2".into() });
            }
        }
    }
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
    let lambda = number(t, "lame_lambda", "solid.lame_lambda", 0.0)?;
    let lambda = crate::scene::finite_in("solid.lame_lambda", lambda, lambda >= 0.0, "[0, ∞)")?;
    let lame = Lame {
        lambda,
        mu: positive(t, "lame_mu", "solid.lame_mu", 0.5)?,
        density: positive(t, "density", "solid.density", 1.0)?,
    };
    let gap = number(t, "gap", "solid.gap", 0.0)?;
    let gap = crate::scene::finite_in("solid.gap", gap, gap >= 0.0, "[0, ∞)")?;
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
    Ok(SolidSpec { dim, extent, cells_per_axis: n, cells, lame, gap, lateral, force, initial })
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
