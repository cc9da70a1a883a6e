//! Bar scenes: the `[bar]` table, validated into a [`BarSpec`] (`super::spec`), the default
//! table of a scene file (the registry, `crate::scene`, reads it through [`SceneGeometry`]).

use super::spec::{BarSpec, Initial};
use crate::column::Column;
use crate::mass::MassKind;
use crate::medium::Force;
use crate::mesh_file::MeshInputs;
use crate::spec::medium::{MediumKeys, RawField, RawInitial, RawMedium, parse_field, parse_force, parse_medium};
use crate::spec::{MAX_ELEMENTS, Number, Offer, Scene, SceneError, SceneGeometry, TimeSpec, length_in};
use serde::{Deserialize, Serialize};

/// The `[bar]` table as written (closed: unknown keys refused by `RawMedium::refuse_unknown`).
#[derive(Debug, Default, Deserialize, Serialize)]
pub struct RawBar {
    #[serde(skip_serializing_if = "Option::is_none")]
    length: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    elements: Option<i64>,
    #[serde(flatten)]
    medium: RawMedium,
    /// Keys no field takes (serde's `deny_unknown_fields` does not combine with `flatten`):
    /// refused by [`RawMedium::refuse_unknown`].
    #[serde(flatten, skip_serializing)]
    unknown: std::collections::BTreeMap<String, toml::Value>,
}

impl SceneGeometry for BarSpec {
    const TABLE: &'static str = "bar";
    type Raw = RawBar;
    type Extras = ();
    const COLUMNS: &'static [Column] = &Column::BAR;
    const COLUMN_LIST: &'static str = "any subset of u0, u1, lambda, energy, l2_error, exact_u0, exact_lambda";
    const SIZE_KEYS: &'static str = "bar.elements";
    const VTU: bool = false;

    /// The `[bar]` table, validated (a bar reads no file).
    fn validate(bar: RawBar, _: (), _: MeshInputs) -> Result<BarSpec, SceneError> {
        let length = length_in("bar.length", bar.length.map_or(1.0, Number::get))?;
        let elements = bar.elements.unwrap_or(6);
        if !(2..=MAX_ELEMENTS as i64).contains(&elements) {
            return Err(SceneError::Range { key: "bar.elements", value: elements.to_string(), range: "[2, 10000000]" });
        }
        let elements = elements as usize;
        RawMedium::refuse_unknown(
            "bar",
            &bar.unknown,
            "length, elements, density, modulus, far_end, gap, initial, force",
        )?;
        let medium = bar.medium;
        let keys =
            MediumKeys { density: "bar.density", modulus: "bar.modulus", far_end: "bar.far_end", gap: "bar.gap" };
        let (material, far_end, gap) =
            parse_medium(&keys, medium.density, medium.modulus, medium.far_end.as_deref(), medium.gap)?;
        let consts = [("L", length), ("pi", std::f64::consts::PI)];
        let field = |key: &'static str, raw: Option<RawField>, vars: &[&str]| parse_field(key, raw, vars, &consts);
        let initial = match medium.initial {
            None => Initial::Paper,
            Some(RawInitial::Name(name)) if name == "paper" => Initial::Paper,
            Some(RawInitial::Name(other)) => {
                return Err(SceneError::Range {
                    key: "bar.initial",
                    value: format!("\"{other}\""),
                    range: "\"paper\" (u0 = (L-x)/2, v0 = 0) or a table { displacement = \"expression in x\", velocity = \"expression in x\" }",
                });
            }
            Some(RawInitial::Fields(f)) => Initial::Fields {
                displacement: field("bar.initial.displacement", f.displacement, &["x"])?,
                velocity: field("bar.initial.velocity", f.velocity, &["x"])?,
            },
        };
        let force = parse_force("bar.force", medium.force, &["x"], &consts)?;
        let nodes = || (0..=elements).map(|i| [length * i as f64 / elements as f64]);
        if let Initial::Fields { displacement, velocity } = &initial {
            displacement.eval_at_nodes(nodes())?;
            velocity.eval_at_nodes(nodes())?;
        }
        // The load is integrated at Gauss points inside the elements (assembly.rs): checked
        // there too (a force infinite there alone used to pass check and diverge at step 0).
        force.check_at_nodes(nodes())?;
        let gauss = || crate::bar::assembly::load_points(crate::bar::assembly::Bar { length, elements });
        match &force {
            Force::Field(f) => f.check_at_load_points(gauss().map(|x| [x]))?,
            Force::Transient(f) => f.check_at_load_points(gauss().map(|x| [x, 0.0]))?,
            Force::Constant(_) => {}
        }
        Ok(BarSpec { length, elements, material, far_end, gap, initial, force })
    }

    fn unknowns(&self) -> usize {
        self.elements
    }

    fn length(&self) -> f64 {
        self.length
    }

    fn contact_weight(&self, mass: &MassKind) -> Result<f64, SceneError> {
        Ok(mass.weights(self.elements)?[0])
    }

    /// One contact node over a tridiagonal system, its row one P1 cell; only node 0 can be
    /// massless (the mass's weights refuse the others), so no contact layer.
    fn offer(&self, mass: &MassKind) -> Result<Offer, SceneError> {
        Ok(Offer {
            one_node_system: true,
            lumped_mass: true,
            w0: self.contact_weight(mass)?,
            contact_layer: false,
            massless_tangents: false,
            one_cell_contact_row: true,
            zero_gap: self.gap == 0.0,
            tangential_dims: 0,
            pairs: false,
            matrix_free: false,
            dense_contact: None,
        })
    }

    fn unavailable(&self, column: Column) -> Option<String> {
        (column.needs_exact() && !self.has_exact_solution())
            .then(|| "the exact solution is known only without body force (bar.force = 0)".into())
    }

    fn default_series(&self) -> Vec<Column> {
        let mut series = vec![Column::U0, Column::Lambda, Column::Energy];
        if self.has_exact_solution() {
            series.push(Column::L2Error);
        }
        series
    }

    fn raw(&self) -> (RawBar, ()) {
        let initial = match &self.initial {
            Initial::Paper => RawInitial::Name("paper".into()),
            Initial::Fields { displacement, velocity } => RawInitial::fields(displacement, velocity),
        };
        let bar = RawBar {
            length: Some(Number::Float(self.length)),
            elements: Some(self.elements as i64),
            medium: RawMedium::resolved(self.material, self.far_end, self.gap, initial, &self.force),
            unknown: Default::default(),
        };
        (bar, ())
    }

    fn header(&self, time: &TimeSpec) -> String {
        format!(
            "# Resolved scene (every default filled in); {} steps, h = {:e}.\n",
            time.steps,
            self.length / self.elements as f64
        )
    }
}

impl Scene<BarSpec> {
    /// The exact solution is known without body force ([`BarSpec::has_exact_solution`]).
    pub fn has_exact_solution(&self) -> bool {
        self.geometry.has_exact_solution()
    }
}
