//! Plate scenes (TOML): a `[plate]` table replaces `[bar]`; `[mass]`, `[scheme]` and `[time]`
//! are parsed by the 1D scene's own parsers; `[output]` has plate columns and VTU options.
//!
//! ```toml
//! [plate]
//! length = 1.0
//! height = 1.0
//! nx = 20                    # cells along x (Δx₁ = length/nx)
//! ny = 20                    # cells along y (Δx₂ = height/ny)
//! cells = "quad"             # quad (Q1) | triangle (P1, one diagonal per square)
//! initial = "paper"          # paper: u0 = (L-x)/2 (exact solution known) | bump: y-dependent
//! # mesh = "square.msh"      # instead of length/height/nx/ny/cells: a triangle (or axis-aligned
//! #                          # quad) mesh file read by meshio (feature `python`), path relative
//! #                          # to the scene file; Γ_C = {x = min x}, Γ_D = {x = max x}
//! force = 0.0
//! [mass]
//! kind = "mod3"              # standard | mod1 | mod2 | mod3 | custom (one weight per cell)
//! [scheme]
//! kind = "crank-nicolson"    # crank-nicolson | newmark | backward-euler | hybrid
//! [time]
//! dt = 0.01
//! end = 3.0
//! [output]
//! series = ["u0", "u_mean", "lambda", "contact_force", "energy", "l2_error"]
//! every = 1
//! vtu = false                # write vtu/frame_*.vtu and plate.pvd
//! vtu_every = 10             # steps between VTU frames (only with vtu = true)
//! divergence_factor = 1e6    # stop as diverged when |E| > factor · max(|E⁰|, E_F), in (1, ∞)
//! ```

use super::layers::{PlateMassError, cell_weights, layers};
use super::mesh::{CellKind, Mesh2d, MeshError};
use crate::expr::Expr;
use crate::mass::MassKind;
use crate::scene::{
    Body, BodyKeys, Column, Force, Number, RawBody, RawInitial, RawMass, RawOutput, RawScheme, RawTime, SceneError,
    SchemeSpec, TimeSpec, finite_in, forbid, parse_body, parse_divergence_factor, parse_every, parse_field,
    parse_force, parse_mass, parse_scheme, parse_series, parse_time, raw_sections,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Upper bound on `free nodes × contact nodes`: the dense contact responses Z = K⁻¹E take
/// 8 bytes each (2.5·10⁷ is 200 MB; a 400 × 400 mesh has 6.4·10⁷).
pub const MAX_CONTACT_WORK: f64 = 2.5e7;

#[derive(Debug, Error)]
pub enum PlateSceneError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Mass(#[from] PlateMassError),
    #[error(
        "free nodes × steps = {work:.3e} exceeds the limit {limit:.0e} (about 20 minutes of computing): reduce plate.nx, plate.ny or time.end / time.dt"
    )]
    TooMuchWork { work: f64, limit: f64 },
    #[error(
        "free nodes × contact nodes = {work:.3e} exceeds {limit:.1e} (the dense contact responses would take {megabytes:.0} MB): reduce plate.nx or plate.ny"
    )]
    TooManyContactNodes { work: f64, limit: f64, megabytes: f64 },
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RawPlateScene {
    plate: Option<RawPlate>,
    mass: Option<RawMass>,
    scheme: Option<RawScheme>,
    time: Option<RawTime>,
    output: Option<RawOutput>,
}

#[derive(Debug, Default, Deserialize, Serialize)]
struct RawPlate {
    #[serde(skip_serializing_if = "Option::is_none")]
    length: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    height: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    nx: Option<i64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    ny: Option<i64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    cells: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    mesh: Option<String>,
    #[serde(flatten)]
    body: RawBody,
    /// Keys no field takes, refused by `RawBody::refuse_unknown`.
    #[serde(flatten, skip_serializing)]
    unknown: std::collections::BTreeMap<String, toml::Value>,
}

/// Initial data of the plate.
#[derive(Debug, Clone, PartialEq)]
pub enum PlateInitial {
    /// u⁰ = (L − x)/2, v⁰ = 0: the 1D benchmark extended constantly in y (exact solution known
    /// for f = 0: the 1D one).
    Paper,
    /// u⁰ = (L − x)/2 · (1 + ½ cos(π y/H)), v⁰ = 0: y-dependent (no exact solution). The
    /// edge x = 0 starts at heights 3/4 (y = 0) to 1/4 (y = H) above the obstacle, so its parts
    /// hit it at different times and the contact state varies along Γ_C. `∂_y u⁰ = 0` on
    /// y = 0, H (compatible with the Neumann condition) and u⁰ = 0 on x = L.
    Bump,
    /// u⁰(x, y), v⁰(x, y) as expressions (in x, y, L, H, pi), interpolated at every node.
    Fields { displacement: Expr, velocity: Expr },
}

impl PlateInitial {
    pub fn name(&self) -> &'static str {
        match self {
            PlateInitial::Paper => "paper",
            PlateInitial::Bump => "bump",
            PlateInitial::Fields { .. } => "expressions",
        }
    }

    /// `u⁰(x, y)` on the plate (0, L) × (0, H).
    pub fn displacement(&self, length: f64, height: f64, x: f64, y: f64) -> f64 {
        let base = (length - x) / 2.0;
        match self {
            PlateInitial::Paper => base,
            PlateInitial::Bump => base * (1.0 + 0.5 * (std::f64::consts::PI * y / height).cos()),
            PlateInitial::Fields { displacement, .. } => displacement.eval(&[x, y]),
        }
    }

    /// Whether the data are constant in y (so that, without force, the solution is a plane
    /// wave: the bar's solution by characteristics extended in y).
    pub fn y_independent(&self) -> bool {
        match self {
            PlateInitial::Paper => true,
            PlateInitial::Bump => false,
            PlateInitial::Fields { displacement, velocity } => {
                !displacement.depends_on("y") && !velocity.depends_on("y")
            }
        }
    }

    /// `v⁰(x, y)` (0 for the named data).
    pub fn velocity(&self, x: f64, y: f64) -> f64 {
        match self {
            PlateInitial::Fields { velocity, .. } => velocity.eval(&[x, y]),
            _ => 0.0,
        }
    }
}

/// The geometry and discretisation of a plate run.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateSpec {
    pub length: f64,
    pub height: f64,
    pub nx: usize,
    pub ny: usize,
    pub cells: CellKind,
    pub initial: PlateInitial,
    /// Material, far end (x = L), gap and force.
    pub body: Body,
}

/// The output of a plate scene: the one output spec of every scene (with its VTU frames).
pub type PlateOutputSpec = crate::scene::OutputSpec;

/// A validated plate scene.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateScene {
    pub plate: PlateSpec,
    /// A mesh file (read by meshio) replacing the structured mesh of `plate`; `plate.length`,
    /// `plate.height` and `plate.cells` then describe the file's mesh, `nx`, `ny` are 0.
    pub mesh_file: Option<std::path::PathBuf>,
    pub mass: MassKind,
    pub scheme: SchemeSpec,
    pub time: TimeSpec,
    pub output: PlateOutputSpec,
}

/// Whether TOML text has a `[plate]` table (a plate scene rather than a bar scene).
pub fn is_plate_scene(text: &str) -> bool {
    text.parse::<toml::Table>().is_ok_and(|t| t.contains_key("plate"))
}

/// Whether the file at `path` is a plate scene (false if it cannot be read or parsed: the bar
/// scene reader then reports the problem).
pub fn is_plate_file(path: &std::path::Path) -> bool {
    std::fs::read_to_string(path).is_ok_and(|t| is_plate_scene(&t))
}

const SERIES_NAMES: &str =
    "any subset of u0, u_mean, lambda, contact_force, energy, l2_error, exact_u0, exact_lambda, pivots";

impl PlateScene {
    pub fn from_file(path: &std::path::Path) -> Result<PlateScene, PlateSceneError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| SceneError::Io { path: path.display().to_string(), source })?;
        let raw: RawPlateScene = toml::from_str(&text).map_err(|e| SceneError::Parse(e.to_string()))?;
        PlateScene::validate(raw, path.parent().unwrap_or(std::path::Path::new(".")))
    }

    /// Parses and validates scene text; a `plate.mesh` path is relative to the current directory.
    pub fn from_toml(text: &str) -> Result<PlateScene, PlateSceneError> {
        let raw: RawPlateScene = toml::from_str(text).map_err(|e| SceneError::Parse(e.to_string()))?;
        PlateScene::validate(raw, std::path::Path::new("."))
    }

    fn validate(mut raw: RawPlateScene, base: &std::path::Path) -> Result<PlateScene, PlateSceneError> {
        let p = raw.plate.take().unwrap_or_default();
        if let Some(file) = &p.mesh {
            let context = "plate.mesh (the mesh file gives the geometry)";
            forbid("plate.length", &p.length, context)?;
            forbid("plate.height", &p.height, context)?;
            forbid("plate.nx", &p.nx, context)?;
            forbid("plate.ny", &p.ny, context)?;
            forbid("plate.cells", &p.cells, context)?;
            let path = base.join(file);
            let mesh = read_mesh_file(&path)?;
            return PlateScene::validate_on(raw, p, mesh, Some(path));
        }
        let length = p.length.map_or(1.0, Number::get);
        finite_in("plate.length", length, length > 0.0, "(0, ∞)")?;
        let height = p.height.map_or(1.0, Number::get);
        finite_in("plate.height", height, height > 0.0, "(0, ∞)")?;
        let nx = p.nx.unwrap_or(20);
        if !(2..=4000).contains(&nx) {
            return Err(SceneError::Range { key: "plate.nx", value: nx.to_string(), range: "[2, 4000]" }.into());
        }
        let ny = p.ny.unwrap_or(20);
        if !(1..=4000).contains(&ny) {
            return Err(SceneError::Range { key: "plate.ny", value: ny.to_string(), range: "[1, 4000]" }.into());
        }
        let (nx, ny) = (nx as usize, ny as usize);
        let cells = match p.cells.as_deref().unwrap_or("quad") {
            "quad" => CellKind::Quad,
            "triangle" => CellKind::Triangle,
            other => {
                return Err(SceneError::Range {
                    key: "plate.cells",
                    value: format!("\"{other}\""),
                    range: "\"quad\" (Q1) | \"triangle\" (P1)",
                }
                .into());
            }
        };
        // Checked before the mesh is built: a hostile nx, ny must fail fast.
        check_contact_work(nx * (ny + 1), ny + 1)?;
        let mesh = Mesh2d::structured(length, height, nx, ny, cells)?;
        PlateScene::validate_on(raw, p, mesh, None)
    }

    /// The sections after `[plate]` (`raw`, its plate table already taken out as `p`), on a built
    /// mesh (structured or from a file).
    fn validate_on(
        raw: RawPlateScene,
        p: RawPlate,
        mesh: Mesh2d,
        mesh_file: Option<std::path::PathBuf>,
    ) -> Result<PlateScene, PlateSceneError> {
        let (length, height, cells) = (mesh.length, mesh.height, mesh.kind);
        let (initial, body) = parse_plate_body(p.body, &p.unknown, &mesh)?;
        let (nx, ny) = match (&mesh_file, p.nx, p.ny) {
            (None, nx, ny) => (nx.unwrap_or(20) as usize, ny.unwrap_or(20) as usize),
            (Some(_), _, _) => (0, 0),
        };
        let contact = (0..mesh.n_nodes()).filter(|&v| mesh.on_contact(v)).count();
        let free = (0..mesh.n_nodes()).filter(|&v| !mesh.on_dirichlet(v)).count();
        check_contact_work(free, contact)?;
        let mass = parse_mass(raw.mass)?;
        let weights = cell_weights(&mesh, &mass)?;
        // The contact nodes are massless iff every cell touching x = 0 has weight 0; the shared
        // scheme parser calls the largest of those weights w_0.
        let w0 = layers(&mesh).iter().zip(&weights).filter(|(l, _)| **l == 0).map(|(_, w)| *w).fold(0.0, f64::max);
        let scheme = parse_scheme(raw.scheme, w0, &mass)?;
        if let Some((key, why)) = scheme.bar_only() {
            return Err(SceneError::Inapplicable { key, context: format!("[plate] scenes ({why})") }.into());
        }
        let time = parse_time(raw.time, 3.0 * length, free).map_err(|e| match e {
            SceneError::TooMuchWork { work, limit } => PlateSceneError::TooMuchWork { work, limit },
            e => e.into(),
        })?;

        // The closed form (and its exact L² norm) on the paper's body; a plane wave by
        // characteristics (u0, λ and their errors) for any y-independent data without force.
        let has_exact = initial == PlateInitial::Paper && body == Body::default();
        let plane_wave = initial.y_independent() && body.force.constant() == Some(0.0);
        let o = raw.output.unwrap_or_default();
        let names = o.series.unwrap_or_else(|| {
            let mut d = vec!["u0", "u_mean", "lambda", "contact_force", "energy"];
            if has_exact {
                d.push("l2_error");
            }
            d.into_iter().map(String::from).collect()
        });
        let series = parse_series(names, &Column::PLATE, SERIES_NAMES)?;
        if let Some(col) =
            series.iter().find(|c| c.needs_exact() && !if **c == Column::L2Error { has_exact } else { plane_wave })
        {
            return Err(SceneError::Inapplicable {
                key: "output.series",
                context: format!(
                    "column \"{}\" with plate.initial = \"{}\": the plate's exact L² error needs initial = \"paper\" on the paper's body (density = modulus = 1, clamped, gap = 0, force = 0); exact_u0 and exact_lambda need y-independent data without force",
                    col.name(),
                    initial.name()
                ),
            }
            .into());
        }
        let every = parse_every(o.every, time.steps, series.len())?;
        let vtu_every = if o.vtu.unwrap_or(false) {
            let k = o.vtu_every.unwrap_or(10);
            if k < 1 {
                return Err(SceneError::Range {
                    key: "output.vtu_every",
                    value: k.to_string(),
                    range: "integers >= 1",
                }
                .into());
            }
            Some(k as usize)
        } else {
            forbid("output.vtu_every", &o.vtu_every, "output.vtu = false (set vtu = true)")?;
            None
        };
        let divergence_factor = parse_divergence_factor(o.divergence_factor)?;
        Ok(PlateScene {
            plate: PlateSpec { length, height, nx, ny, cells, initial, body },
            mesh_file,
            mass,
            scheme,
            time,
            output: crate::scene::OutputSpec {
                series,
                every,
                vtu_every,
                summary_l2: o.summary_l2.unwrap_or(true),
                divergence_factor,
            },
        })
    }

    /// The exact solution is known for the paper's initial data without body force.
    pub fn has_exact_solution(&self) -> bool {
        self.plate.initial == PlateInitial::Paper && self.plate.body == Body::default()
    }

    /// The scene with every default filled in, as TOML.
    pub fn resolved_toml(&self) -> String {
        let f = Number::Float;
        let p = &self.plate;
        let structured = self.mesh_file.is_none();
        let (mass, scheme, time, output) = raw_sections(&self.mass, &self.scheme, &self.time, &self.output, true);
        let raw = RawPlateScene {
            plate: Some(RawPlate {
                length: structured.then_some(f(p.length)),
                height: structured.then_some(f(p.height)),
                nx: structured.then_some(p.nx as i64),
                ny: structured.then_some(p.ny as i64),
                cells: structured.then(|| p.cells.name().into()),
                body: RawBody::resolved(
                    p.body.material,
                    p.body.far_end,
                    p.body.gap,
                    match &p.initial {
                        PlateInitial::Fields { displacement, velocity } => RawInitial::fields(displacement, velocity),
                        named => RawInitial::Name(named.name().into()),
                    },
                    &p.body.force,
                ),
                unknown: Default::default(),
                mesh: self.mesh_file.as_ref().map(|m| m.display().to_string()),
            }),
            mass,
            scheme,
            time,
            output,
        };
        let mut text = if structured {
            format!(
                "# Resolved plate scene (every default filled in); {} steps, dx1 = {:e}, dx2 = {:e}.\n",
                self.time.steps,
                p.length / p.nx as f64,
                p.height / p.ny as f64
            )
        } else {
            format!("# Resolved plate scene (every default filled in); {} steps, mesh from a file.\n", self.time.steps)
        };
        text.push_str(&toml::to_string(&raw).expect("a resolved scene always serialises"));
        text
    }
}

/// The plate's body keys (shared with bars) and its initial data, checked at the mesh nodes.
fn parse_plate_body(
    b: RawBody,
    unknown: &std::collections::BTreeMap<String, toml::Value>,
    mesh: &Mesh2d,
) -> Result<(PlateInitial, Body), PlateSceneError> {
    let (length, height) = (mesh.length, mesh.height);
    let keys =
        BodyKeys { density: "plate.density", modulus: "plate.modulus", far_end: "plate.far_end", gap: "plate.gap" };
    let expected = "length, height, nx, ny, cells, mesh, density, modulus, far_end, gap, initial, force";
    RawBody::refuse_unknown("plate", unknown, expected)?;
    let (material, far_end, gap) = parse_body(&keys, b.density, b.modulus, b.far_end.as_deref(), b.gap)?;
    let consts = [("L", length), ("H", height), ("pi", std::f64::consts::PI)];
    let initial = parse_initial(b.initial, &consts)?;
    let force = parse_force("plate.force", b.force, &["x", "y"], &consts)?;
    let points = || mesh.points.iter().copied();
    if let PlateInitial::Fields { displacement, velocity } = &initial {
        displacement.eval_at_nodes(points()).map_err(SceneError::from)?;
        velocity.eval_at_nodes(points()).map_err(SceneError::from)?;
    }
    if let Force::Field(f) = &force {
        f.eval_at_nodes(points()).map_err(SceneError::from)?;
    }
    let body = Body { material, far_end, gap, force };
    Ok((initial, body))
}

/// `plate.initial`: "paper", "bump" or a table of expressions in x, y.
fn parse_initial(raw: Option<RawInitial>, consts: &[(&str, f64)]) -> Result<PlateInitial, PlateSceneError> {
    match raw {
        None => Ok(PlateInitial::Paper),
        Some(RawInitial::Name(name)) if name == "paper" => Ok(PlateInitial::Paper),
        Some(RawInitial::Name(name)) if name == "bump" => Ok(PlateInitial::Bump),
        Some(RawInitial::Name(other)) => Err(SceneError::Range {
            key: "plate.initial",
            value: format!("\"{other}\""),
            range: "\"paper\" (u0 = (L-x)/2) | \"bump\" (u0 = (L-x)/2 (1 + cos(pi y/H)/2)) | { displacement = \"expression in x, y\", velocity = \"…\" }",
        }
        .into()),
        Some(RawInitial::Fields(f)) => Ok(PlateInitial::Fields {
            displacement: parse_field("plate.initial.displacement", f.displacement, &["x", "y"], consts)?,
            velocity: parse_field("plate.initial.velocity", f.velocity, &["x", "y"], consts)?,
        }),
    }
}

/// The dense contact responses take free × contact values.
fn check_contact_work(free: usize, contact: usize) -> Result<(), PlateSceneError> {
    let work = free as f64 * contact as f64;
    if work > MAX_CONTACT_WORK {
        return Err(PlateSceneError::TooManyContactNodes {
            work,
            limit: MAX_CONTACT_WORK,
            megabytes: work * 8.0 / 1e6,
        });
    }
    Ok(())
}

/// A mesh file through meshio (feature `python`).
#[cfg(feature = "python")]
fn read_mesh_file(path: &std::path::Path) -> Result<Mesh2d, PlateSceneError> {
    Ok(Mesh2d::read_file(path)?)
}

#[cfg(not(feature = "python"))]
fn read_mesh_file(path: &std::path::Path) -> Result<Mesh2d, PlateSceneError> {
    Err(SceneError::Inapplicable {
        key: "plate.mesh",
        context: format!(
            "this build ({}): mesh files are read by meshio through the `python` feature; run `cargo run --features python -- run SCENE --out DIR` after `bash python/install-deps.sh`",
            path.display()
        ),
    }
    .into())
}
