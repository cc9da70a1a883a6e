//! The solid as a scene geometry: [`SceneGeometry`] for [`SolidSpec`] (its table, columns,
//! validation, sizes, the resolved scene written back, its header and memory estimate).

use super::bodies;
use super::mesh;
use super::obstacle::{RawObstacle, raw_obstacle};
use super::{RawSolid, RawSolidFields, RawSolidInitial, RawSolids, setup_error, validate_solid};
use crate::column::Column;
use crate::expr::Expr;
use crate::fem::layers::layers_of;
use crate::fem::mesh::Cell;
use crate::mass::MassKind;
use crate::mesh_file::MeshInputs;
use crate::solid::assembly::Lateral;
use crate::solid::spec::{MeshSource, SolidInitial, SolidSpec, Support};
use crate::spec::medium::RawField;
use crate::spec::{Number, SceneError, SceneGeometry, TimeSpec, forbid};

/// The series columns of a solid (the body ones need an [obstacle]).
const SOLID_SERIES_NAMES: &str = "any subset of u0, u_mean, lambda, contact_force, energy, l2_error, exact_u0, exact_lambda, pivots, and for bodies active_nodes, min_distance, momentum_x|y|z, mean_u_x|y|z, and friction_dissipation, stick_nodes, slip_nodes, tangential_force_x|y|z";

impl SceneGeometry for SolidSpec {
    const TABLE: &'static str = "solid";
    type Raw = RawSolids;
    /// A body's `[obstacle]`, several bodies' `[[pair]]`s.
    type Extras = (Option<RawObstacle>, Option<Vec<bodies::RawPair>>);
    const EXTRAS_WHY: &'static str = "a [solid] body meets a plane";
    const FILE_KEYS: &'static [&'static str] = &["mesh"];
    const COLUMNS: &'static [Column] = &Column::SOLID;
    const COLUMN_LIST: &'static str = SOLID_SERIES_NAMES;
    const SIZE_KEYS: &'static str = "solid.nx, solid.ny[, solid.nz]";
    const VTU: bool = true;
    const MASSLESS_TANGENTS: bool = true;

    fn tangential_dims(&self) -> usize {
        self.dim - 1
    }

    /// Every box and every body against one obstacle: the box generator's Q1 box has its
    /// stencil ([`crate::solid::stencil`]), any other mesh the cell-by-cell kernel
    /// ([`crate::solid::kernel`]); several bodies in contact have none (their pairs' change of
    /// variables is applied to an assembled matrix).
    fn matrix_free(&self) -> bool {
        self.support.bodies().is_none()
    }

    /// A generated box against its face x = 0: the nodes of that face (`solid.ny[, solid.nz]`);
    /// a body against one obstacle: its contact set. Both
    /// checked by the compatibility rule where the scheme forms their dense Schur complement
    /// (central differences with the exact law do not: a 10⁷-unknown cube runs).
    fn dense_contact(&self) -> Option<(usize, &'static str)> {
        match (&self.source, &self.support) {
            (MeshSource::Box, Support::Face { .. }) => {
                let axes = if self.dim == 2 { 2 } else { 3 };
                let contact = self.cells_per_axis[1..axes].iter().map(|&k| k + 1).product();
                Some((contact, if self.dim == 2 { "solid.ny" } else { "solid.ny, solid.nz" }))
            }
            // A body against one obstacle: its contact set (built and checked at validation).
            (source, Support::Plane(_)) => {
                let keys = if matches!(source, MeshSource::Box) {
                    "obstacle.contact, or solid.nx, solid.ny[, solid.nz]"
                } else {
                    "obstacle.contact, or solid.mesh"
                };
                Some((self.built().ok()?.contact.nodes.len(), keys))
            }
            _ => None,
        }
    }

    fn pairs(&self) -> bool {
        self.support.bodies().is_some()
    }

    fn pair_laws(&self) -> Vec<(String, Option<toml::Table>)> {
        self.support
            .bodies()
            .map_or_else(Vec::new, |b| b.pairs.iter().map(|p| (p.name.clone(), p.law.clone())).collect())
    }

    fn named_column(&self, name: &str) -> Option<Column> {
        bodies::dotted(self)?.into_iter().find(|c| c.name() == name)
    }

    fn massless_inner_nodes(&self, mass: &MassKind) -> Result<bool, SceneError> {
        let built = self.built().map_err(setup_error)?;
        let weights = built.weights(mass)?;
        let mut weighed = vec![false; built.mesh.n_nodes()];
        for (c, &w) in weights.iter().enumerate() {
            if w > 0.0 {
                built.mesh.cell(c).iter().for_each(|&v| weighed[v] = true);
            }
        }
        let (contact, clamped) = (&built.contact.contact, &built.contact.clamped);
        Ok((0..weighed.len()).any(|v| !weighed[v] && !contact[v] && !clamped[v]))
    }

    fn validate(raw: RawSolids, (obstacle, pairs): Self::Extras, inputs: MeshInputs) -> Result<SolidSpec, SceneError> {
        match raw {
            RawSolids::One(t) => {
                forbid("[[pair]]", &pairs, "a single [solid] (pairs join several [[solid]] bodies)")?;
                validate_solid(t, obstacle, inputs)
            }
            RawSolids::Many(v) => bodies::validate_bodies(v, obstacle, pairs, inputs),
        }
    }

    fn size_keys(&self) -> &'static str {
        if matches!(self.source, MeshSource::Box) { mesh::keys_of(self.dim) } else { "solid.mesh (a coarser mesh)" }
    }

    /// The free unknowns: the components of the nodes not clamped (x = L for the box), less the
    /// normal components a roller face removes, on the mesh built for the contact weight.
    fn unknowns(&self) -> usize {
        // Validated: the mesh and the contact set build (contact_weight, check_body).
        let built = self.built().expect("a validated solid has its mesh and contact set");
        let (mesh, d) = (&built.mesh, self.dim);
        let roller = self.support.lateral() == Lateral::Roller;
        let free = |v: usize| (0..d).filter(|&c| !(c >= 1 && roller && mesh.on_lateral(v, c))).count();
        (0..mesh.n_nodes()).filter(|&v| !built.contact.clamped[v]).map(free).sum()
    }

    fn length(&self) -> f64 {
        self.extent[0]
    }

    /// The largest weight of the cells holding a contact node (0 iff every component of a
    /// contact node is massless), on the mesh and contact set built once ([`SolidSpec::built`]).
    fn contact_weight(&self, mass: &MassKind) -> Result<f64, SceneError> {
        let built = self.built().map_err(setup_error)?;
        let weights = built.weights(mass)?;
        let layer = layers_of(&built.mesh, &built.contact.contact);
        Ok(layer.iter().zip(&weights).filter(|(l, _)| **l == 0).map(|(_, w)| *w).fold(0.0, f64::max))
    }

    fn unavailable(&self, column: Column) -> Option<String> {
        if column.is_body() && !self.support.is_body() {
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
        if !matches!(self.source, MeshSource::Box) {
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
        if let Some(dotted) = bodies::dotted(self) {
            // Every pair's contact force and every body's momentum (issue 30).
            let mut series = vec![Column::Energy, Column::ContactForce];
            series.extend((0..self.dim as u8).map(Column::Momentum));
            let wanted = |n: &str| n.ends_with(".contact_force") || n.contains(".momentum_");
            series.extend(dotted.into_iter().filter(|c| wanted(c.name())));
            return series;
        }
        if self.support.is_body() {
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

    fn raw(&self) -> (RawSolids, Self::Extras) {
        if let Support::Bodies(b) = &self.support {
            return bodies::raw_bodies(b);
        }
        let (f, i) = (|x: f64| Some(Number::Float(x)), |k: usize| Some(k as i64));
        let (three, structured) = (self.dim == 3, matches!(self.source, MeshSource::Box));
        let initial = match &self.initial {
            SolidInitial::Paper => RawSolidInitial::Name("paper".into()),
            SolidInitial::Fields { displacement, velocity } => {
                let texts = |e: &[Expr]| Some(e.iter().map(|x| RawField::Expr(x.text().into())).collect());
                RawSolidInitial::Fields(RawSolidFields { displacement: texts(displacement), velocity: texts(velocity) })
            }
        };
        let solid = RawSolid {
            dim: i(self.dim),
            mesh: match &self.source {
                MeshSource::Box => None,
                MeshSource::File { path, .. } => Some(path.display().to_string()),
                MeshSource::Arrays(_) => Some(crate::mesh_file::ARRAY_MESH.into()),
            },
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
            gap: None,
            lateral: None,
            force: None,
            initial: Some(initial),
            clamped: None,
            name: None,
            offset: None,
        };
        let solid = match &self.support {
            Support::Face { gap, lateral, force } => RawSolid {
                gap: f(*gap),
                lateral: Some(lateral.name().into()),
                force: Some(force[..self.dim].iter().map(|&x| RawField::Number(Number::Float(x))).collect()),
                ..solid
            },
            Support::Plane(b) => RawSolid {
                force: Some(b.force.iter().map(|e| RawField::Expr(e.text().into())).collect()),
                clamped: b.clamped.clone(),
                ..solid
            },
            Support::Bodies(_) => unreachable!("written by bodies::raw_bodies"),
        };
        let obstacle = self.support.body().map(|b| raw_obstacle(&b.obstacle, self.dim));
        (RawSolids::One(solid), (obstacle, None))
    }

    fn header(&self, time: &TimeSpec) -> String {
        if self.support.bodies().is_some() {
            return format!("# Resolved scene of several bodies; {} steps.\n", time.steps);
        }
        if self.support.body().is_some() {
            return format!("# Resolved body scene (every default filled in); {} steps.\n", time.steps);
        }
        if !matches!(self.source, MeshSource::Box) {
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

    /// The element triplets of `crate::solid::assembly` (per cell k²·d mass and k²·d²
    /// stiffness triplets (two indices and a value, 24 bytes), each with its value copied out
    /// and the pattern's row index and slot: 48 bytes per triplet, k the cell's vertices)
    /// times 1.6, the measured ratio of the set-up's peak to them (issue 32, E4): the address
    /// space at the first factor (`VmPeak`) was 3.39 GB for a 40³ hex box (1.44× its 2.36 GB
    /// of triplets), 2.02 GB for 30³ × 6 tets (1.35×), 1.20 GB for 400² × 2 triangles (1.44×)
    /// and 0.38 GB for 200² × 2 (1.82×, the process's own share counting more). Body meshes
    /// are counted the same, from their cells.
    ///
    /// A box stepped by central differences is set up lean (`crate::solid::lean`): no
    /// triplets, no consistent mass, of the stiffness either the stencil or one matrix in
    /// compressed columns (16 bytes an entry, `n_b` entries a row: 9 quad, 27 hex, 7
    /// triangle, 15 Kuhn tetrahedron neighbours times d) that becomes the row-run form (none
    /// matrix-free), and
    /// about 300 bytes per unknown of vectors, mesh and layer; times 1.2. Measured at 69³ hex:
    /// peak 1.43 kB per unknown assembled and 0.28 kB matrix-free, where this gives 1.92 and
    /// 0.36.
    fn assembly_bytes(&self, scheme: Option<&crate::schemes::SchemeSpec>) -> f64 {
        if let (
            Some(crate::schemes::SchemeSpec::CentralDifference { operator }),
            MeshSource::Box,
            Support::Face { .. },
        ) = (scheme, &self.source, &self.support)
        {
            let neighbours = match self.cells {
                Cell::Quad => Some(9.0),
                Cell::Hex => Some(27.0),
                Cell::Triangle => Some(7.0),
                Cell::Tet => Some(15.0),
                Cell::Triangle6 | Cell::Tet10 => None,
            };
            if let Some(nb) = neighbours {
                let d = self.dim as f64;
                let nodes: f64 = self.cells_per_axis[..self.dim].iter().map(|&n| n as f64 + 1.0).product();
                use crate::schemes::StiffnessOperator;
                // No matrix: the stencil (`auto` on a Q1 box) or the cell-by-cell kernel.
                let matrix_free = *operator == StiffnessOperator::MatrixFree
                    || (*operator == StiffnessOperator::Auto && crate::solid::stencil::BoxStencil::applies(self));
                let matrix = if matrix_free { 0.0 } else { nb * d * 16.0 };
                return nodes * d * (matrix + 300.0) * 1.2;
            }
        }
        // A body against a plane or a curved obstacle stepped by central differences is set
        // up lean too (`SolidSystem::assemble_body`, `curved_lean`): its whole masses (≤ 2 k²·d
        // entries a cell; a curved obstacle's weighted one only, and its load's k² unit
        // triplets a cell, 24 bytes each) go before the stiffness (≤ k²·d² a cell, fewer where
        // cells share nodes) is assembled in compressed columns; 16 bytes an entry, the same 300
        // bytes per unknown, times 1.2. Measured on a 245 000-unknown tetra10 box: 1.81 kB per
        // unknown where this gives 4.3 (1.86 kB onto a cylinder). Matrix-free (the kernel: no
        // stiffness matrix) the masses are the peak, 2 k²·d entries a cell: measured on a
        // 1 073 733-unknown tetra10 cube 1.19 kB per unknown where this gives 3.1.
        if let (Some(crate::schemes::SchemeSpec::CentralDifference { operator }), Support::Plane(_), Some(m)) =
            (scheme, &self.support, self.source.given())
        {
            let (k, d) = (self.cells.verts() as f64, self.dim as f64);
            let unknowns = m.n_nodes() as f64 * d;
            let per_cell = if *operator == crate::schemes::StiffnessOperator::Assembled { d * d } else { 2.0 * d };
            return (m.n_cells() as f64 * k * k * per_cell * 16.0 + unknowns * 300.0) * 1.2;
        }
        let cells = match self.source.given() {
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
        cells * k * k * d * (1.0 + d) * 48.0 * 1.6
    }
}
