//! Plate scenes (TOML): a `[plate]` table replaces `[bar]`; the other sections are the ones every
//! scene shares (`crate::scene`'s sections); `[output]` has plate columns and VTU options.
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

use super::spec::{PlateInitial, PlateSpec};
use crate::column::Column;
use crate::fem::layers::{cell_weights, layers};
use crate::fem::{Cell, Mesh};
use crate::mass::MassKind;
use crate::medium::Medium;
use crate::mesh_file::{MeshInput, MeshInputs};
use crate::spec::medium::{MediumKeys, RawInitial, RawMedium, parse_field, parse_force, parse_medium};
use crate::spec::{Number, Scene, SceneError, SceneGeometry, TimeSpec, check_contact_memory, forbid, length_in, short};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The `[plate]` table as written (closed: unknown keys refused by `RawMedium::refuse_unknown`).
#[derive(Debug, Default, Deserialize, Serialize)]
pub struct RawPlate {
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
    medium: RawMedium,
    /// Keys no field takes, refused by `RawMedium::refuse_unknown`.
    #[serde(flatten, skip_serializing)]
    unknown: std::collections::BTreeMap<String, toml::Value>,
}

/// The structured mesh of a `[plate]` table without `mesh`.
fn structured_mesh(p: &RawPlate) -> Result<Mesh, SceneError> {
    let length = length_in("plate.length", p.length.map_or(1.0, Number::get))?;
    let height = length_in("plate.height", p.height.map_or(1.0, Number::get))?;
    let nx = p.nx.unwrap_or(20);
    if !(2..=4000).contains(&nx) {
        return Err(SceneError::Range { key: "plate.nx", value: nx.to_string(), range: "[2, 4000]" });
    }
    let ny = p.ny.unwrap_or(20);
    if !(1..=4000).contains(&ny) {
        return Err(SceneError::Range { key: "plate.ny", value: ny.to_string(), range: "[1, 4000]" });
    }
    let (nx, ny) = (nx as usize, ny as usize);
    // Cells far from square make the stiffness ill-conditioned beyond what double precision
    // factors (height = 1e-9 with a unit length fails as "not positive definite").
    let aspect = (length / nx as f64) / (height / ny as f64);
    if !(1e-6..=1e6).contains(&aspect) {
        return Err(SceneError::Range {
            key: "plate.height",
            value: short(height),
            range: "a cell aspect ratio (length/nx)/(height/ny) within [1e-6, 1e6]",
        });
    }
    let cells = match p.cells.as_deref().unwrap_or("quad") {
        "quad" => Cell::Quad,
        "triangle" => Cell::Triangle,
        other => {
            return Err(SceneError::Range {
                key: "plate.cells",
                value: format!("\"{other}\""),
                range: "\"quad\" (Q1) | \"triangle\" (P1)",
            });
        }
    };
    // Checked before the mesh is built: a hostile nx, ny must fail fast.
    check_contact_memory(ny + 1, "plate.ny")?;
    Ok(Mesh::structured_2d(length, height, nx, ny, cells)?)
}

pub(crate) const SERIES_NAMES: &str =
    "any subset of u0, u_mean, lambda, contact_force, energy, l2_error, exact_u0, exact_lambda, pivots";

impl SceneGeometry for PlateSpec {
    const TABLE: &'static str = "plate";
    type Raw = RawPlate;
    type Extras = ();
    const FILE_KEYS: &'static [&'static str] = &["mesh"];
    const COLUMNS: &'static [Column] = &Column::PLATE;
    const COLUMN_LIST: &'static str = SERIES_NAMES;
    const SIZE_KEYS: &'static str = "plate.nx, plate.ny";
    const VTU: bool = true;

    /// The `[plate]` table, validated; a mesh file is relative to `inputs.base` (or the arrays
    /// given for `"<arrays>"`) and read here, once.
    fn validate(p: RawPlate, _: (), inputs: MeshInputs) -> Result<PlateSpec, SceneError> {
        let (mesh, mesh_file) = match &p.mesh {
            Some(file) => {
                let context = "plate.mesh (the mesh file gives the geometry)";
                forbid("plate.length", &p.length, context)?;
                forbid("plate.height", &p.height, context)?;
                forbid("plate.nx", &p.nx, context)?;
                forbid("plate.ny", &p.ny, context)?;
                forbid("plate.cells", &p.cells, context)?;
                let path = inputs.base.join(file);
                (plate_file_mesh(&path, &inputs.resolve(file))?, Some(path))
            }
            None => (structured_mesh(&p)?, None),
        };
        let [nx, ny, _] = mesh.grid.unwrap_or([0; 3]);
        let contact = (0..mesh.n_nodes()).filter(|&v| mesh.on_contact(v)).count();
        check_contact_memory(contact, if mesh_file.is_some() { "its edge x = 0 in plate.mesh" } else { "plate.ny" })?;
        let (initial, medium) = parse_plate_medium(p.medium, &p.unknown, &mesh)?;
        let ([length, height, _], cells) = (mesh.extent, mesh.kind);
        Ok(PlateSpec { length, height, nx, ny, cells, initial, medium, mesh_file, mesh: Some(Arc::new(mesh)) })
    }

    fn size_keys(&self) -> &'static str {
        if self.mesh_file.is_some() { "plate.mesh (a coarser mesh)" } else { Self::SIZE_KEYS }
    }

    fn unknowns(&self) -> usize {
        let mesh = self.mesh.as_ref().expect("a validated plate has its mesh");
        (0..mesh.n_nodes()).filter(|&v| !mesh.on_dirichlet(v)).count()
    }

    fn length(&self) -> f64 {
        self.length
    }

    /// The contact nodes are massless iff every cell touching x = 0 has weight 0; the shared
    /// scheme parser calls the largest of those weights w_0.
    fn contact_weight(&self, mass: &MassKind) -> Result<f64, SceneError> {
        let mesh = self.mesh.as_ref().expect("a validated plate has its mesh");
        let weights = cell_weights(mesh.as_ref(), mass)?;
        Ok(layers(mesh.as_ref()).iter().zip(&weights).filter(|(l, _)| **l == 0).map(|(_, w)| *w).fold(0.0, f64::max))
    }

    fn unavailable(&self, column: Column) -> Option<String> {
        (column.needs_exact() && !self.has_plane_wave()).then(|| {
            format!(
                "plate.initial = \"{}\": the exact solution (l2_error, exact_u0, exact_lambda) is known for y-independent data without force (a plane wave)",
                self.initial.name()
            )
        })
    }

    fn default_series(&self) -> Vec<Column> {
        let mut series = vec![Column::U0, Column::UMean, Column::Lambda, Column::ContactForce, Column::Energy];
        if self.has_plane_wave() {
            series.push(Column::L2Error);
        }
        series
    }

    fn raw(&self) -> (RawPlate, ()) {
        let f = Number::Float;
        let structured = self.mesh_file.is_none();
        let initial = match &self.initial {
            PlateInitial::Fields { displacement, velocity } => RawInitial::fields(displacement, velocity),
            named => RawInitial::Name(named.name().into()),
        };
        let plate = RawPlate {
            length: structured.then_some(f(self.length)),
            height: structured.then_some(f(self.height)),
            nx: structured.then_some(self.nx as i64),
            ny: structured.then_some(self.ny as i64),
            cells: structured.then(|| self.cells.name().into()),
            medium: RawMedium::resolved(
                self.medium.material,
                self.medium.far_end,
                self.medium.gap,
                initial,
                &self.medium.force,
            ),
            unknown: Default::default(),
            mesh: self.mesh_file.as_ref().map(|m| m.display().to_string()),
        };
        (plate, ())
    }

    fn header(&self, time: &TimeSpec) -> String {
        if self.mesh_file.is_none() {
            format!(
                "# Resolved plate scene (every default filled in); {} steps, dx1 = {:e}, dx2 = {:e}.\n",
                time.steps,
                self.length / self.nx as f64,
                self.height / self.ny as f64
            )
        } else {
            format!("# Resolved plate scene (every default filled in); {} steps, mesh from a file.\n", time.steps)
        }
    }

    /// The element buffers of `crate::plate::assembly` (per cell k² positions (two indices),
    /// k² mass and k² stiffness values, and the pattern's row index and slot of each: 48
    /// bytes per entry) times 3, the measured ratio of the set-up's peak to them (issue 32,
    /// E4): the address space at the first factor (`VmPeak`) was 688 MB for a 600² quad plate
    /// (2.5× its 276 MB of buffers) and 256 MB for 300² (3.7×, the process's own share
    /// counting more); a 1200² plate counted 1.1 GB here and aborted in its assembly at 1.8 GB.
    fn assembly_bytes(&self, _scheme: Option<&crate::schemes::SchemeSpec>) -> f64 {
        let mesh = self.mesh.as_ref().expect("a validated plate has its mesh");
        let k = self.cells.verts() as f64;
        mesh.n_cells() as f64 * k * k * 48.0 * 3.0
    }
}

impl Scene<PlateSpec> {
    /// The paper's closed form is the exact solution ([`PlateSpec::has_paper_solution`]).
    pub fn has_exact_solution(&self) -> bool {
        self.geometry.has_paper_solution()
    }
}

/// The plate's medium keys (shared with bars) and its initial data, checked at the mesh nodes.
fn parse_plate_medium(
    b: RawMedium,
    unknown: &std::collections::BTreeMap<String, toml::Value>,
    mesh: &Mesh,
) -> Result<(PlateInitial, Medium), SceneError> {
    let [length, height, _] = mesh.extent;
    let keys =
        MediumKeys { density: "plate.density", modulus: "plate.modulus", far_end: "plate.far_end", gap: "plate.gap" };
    let expected = "length, height, nx, ny, cells, mesh, density, modulus, far_end, gap, initial, force";
    RawMedium::refuse_unknown("plate", unknown, expected)?;
    let (material, far_end, gap) = parse_medium(&keys, b.density, b.modulus, b.far_end.as_deref(), b.gap)?;
    let consts = [("L", length), ("H", height), ("pi", std::f64::consts::PI)];
    let initial = parse_initial(b.initial, &consts)?;
    let force = parse_force("plate.force", b.force, &["x", "y"], &consts)?;
    let points = || mesh.points.iter().map(|p| [p[0], p[1]]);
    if let PlateInitial::Fields { displacement, velocity } = &initial {
        displacement.eval_at_nodes(points()).map_err(SceneError::from)?;
        velocity.eval_at_nodes(points()).map_err(SceneError::from)?;
    }
    force.check_at_nodes(points())?;
    let medium = Medium { material, far_end, gap, force };
    Ok((initial, medium))
}

/// `plate.initial`: "paper", "bump" or a table of expressions in x, y.
fn parse_initial(raw: Option<RawInitial>, consts: &[(&str, f64)]) -> Result<PlateInitial, SceneError> {
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

/// The mesh of `plate.mesh` ([`crate::mesh_file`]): a triangle or quad mesh.
fn plate_file_mesh(path: &std::path::Path, input: &MeshInput) -> Result<Mesh, SceneError> {
    let mesh = crate::mesh_file::read_input("plate.mesh", input)?;
    if mesh.dim != 2 {
        return Err(SceneError::Range {
            key: "plate.mesh",
            value: format!("\"{}\" (a {} mesh)", path.display(), mesh.kind.data().meshio),
            range: "a triangle or quad mesh file",
        });
    }
    Ok(mesh)
}
