//! Bar scenes: the `[bar]` table and the validated [`Scene`].

use super::*;
use crate::expr::Expr;
use crate::mass::MassKind;
use crate::material::{FarEnd, Material};

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    bar: Option<RawBar>,
    mass: Option<RawMass>,
    scheme: Option<RawScheme>,
    time: Option<RawTime>,
    output: Option<RawOutput>,
}

#[derive(Debug, Default, Deserialize, Serialize)]
struct RawBar {
    #[serde(skip_serializing_if = "Option::is_none")]
    length: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    elements: Option<i64>,
    #[serde(flatten)]
    body: RawBody,
    /// Keys no field takes (serde's `deny_unknown_fields` does not combine with `flatten`):
    /// refused by [`RawBody::refuse_unknown`].
    #[serde(flatten, skip_serializing)]
    unknown: std::collections::BTreeMap<String, toml::Value>,
}

/// Initial data of the bar.
#[derive(Debug, Clone, PartialEq)]
pub enum Initial {
    /// u⁰ = (L − x)/2, v⁰ = 0: the paper's benchmark (exact solution known when f = 0).
    Paper,
    /// u⁰(x), v⁰(x) as expressions in x (and L, pi), interpolated at every node.
    Fields { displacement: Expr, velocity: Expr },
}

#[derive(Debug, Clone, PartialEq)]
pub struct BarSpec {
    pub length: f64,
    pub elements: usize,
    pub material: Material,
    pub far_end: FarEnd,
    /// The obstacle at x = 0: u(0, t) ≥ −gap.
    pub gap: f64,
    pub initial: Initial,
    pub force: Force,
}

impl BarSpec {
    /// The paper's bar: ρ = E = 1, clamped at L, no gap.
    pub fn is_paper_bar(&self) -> bool {
        self.material == Material::UNIT && self.far_end == FarEnd::Clamped && self.gap == 0.0
    }
}

/// A validated scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub bar: BarSpec,
    pub mass: MassKind,
    pub scheme: SchemeSpec,
    pub time: TimeSpec,
    pub output: OutputSpec,
}

impl Scene {
    /// Reads and validates a scene file.
    pub fn from_file(path: &std::path::Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| SceneError::Io { path: path.display().to_string(), source })?;
        Scene::from_toml(&text)
    }

    /// Parses and validates scene text.
    pub fn from_toml(text: &str) -> Result<Scene, SceneError> {
        let raw: RawScene = toml::from_str(text).map_err(|e| SceneError::Parse(e.to_string()))?;
        Scene::validate(raw)
    }

    fn validate(raw: RawScene) -> Result<Scene, SceneError> {
        let bar = raw.bar.unwrap_or_default();
        let length = finite_in("bar.length", bar.length.map_or(1.0, Number::get), true, "(0, ∞)")?;
        finite_in("bar.length", length, length > 0.0, "(0, ∞)")?;
        let elements = bar.elements.unwrap_or(6);
        if !(2..=MAX_ELEMENTS as i64).contains(&elements) {
            return Err(SceneError::Range { key: "bar.elements", value: elements.to_string(), range: "[2, 10000000]" });
        }
        let elements = elements as usize;
        RawBody::refuse_unknown(
            "bar",
            &bar.unknown,
            "length, elements, density, modulus, far_end, gap, initial, force",
        )?;
        let body = bar.body;
        let keys = BodyKeys { density: "bar.density", modulus: "bar.modulus", far_end: "bar.far_end", gap: "bar.gap" };
        let (Material { density, modulus }, far_end, gap) =
            parse_body(&keys, body.density, body.modulus, body.far_end.as_deref(), body.gap)?;
        let consts = [("L", length), ("pi", std::f64::consts::PI)];
        let field = |key: &'static str, raw: Option<RawField>, vars: &[&str]| parse_field(key, raw, vars, &consts);
        let initial = match body.initial {
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
        let force = parse_force("bar.force", body.force, &["x"], &consts)?;
        if let Initial::Fields { displacement, velocity } = &initial {
            let nodes = || (0..=elements).map(|i| [length * i as f64 / elements as f64]);
            displacement.eval_at_nodes(nodes())?;
            velocity.eval_at_nodes(nodes())?;
        }
        if let Force::Field(f) = &force {
            // The load is integrated at Gauss points inside the elements (assembly.rs).
            f.eval_at_nodes((0..=elements).map(|i| [length * i as f64 / elements as f64]))?;
        }

        let mass = parse_mass(raw.mass)?;
        let weights = mass.weights(elements)?;

        let scheme = parse_scheme(raw.scheme, weights[0], &mass)?;

        let time = parse_time(raw.time, 3.0 * length, elements)?;

        let o = raw.output.unwrap_or_default();
        let names = o.series.unwrap_or_else(|| vec!["u0".into(), "lambda".into(), "energy".into(), "l2_error".into()]);
        let range = "any subset of u0, u1, lambda, energy, l2_error, exact_u0, exact_lambda";
        let series = parse_series(names, &Column::BAR, range)?;
        let every = parse_every(o.every, time.steps, series.len())?;
        let divergence_factor = parse_divergence_factor(o.divergence_factor)?;
        forbid("output.vtu", &o.vtu, "[bar] scenes (VTU frames are written for plates)")?;
        forbid("output.vtu_every", &o.vtu_every, "[bar] scenes (VTU frames are written for plates)")?;
        let output =
            OutputSpec { series, every, summary_l2: o.summary_l2.unwrap_or(true), divergence_factor, vtu_every: None };
        let bar = BarSpec { length, elements, material: Material { density, modulus }, far_end, gap, initial, force };
        let scene = Scene { bar, mass, scheme, time, output };
        if !scene.has_exact_solution() {
            if let Some(c) = scene.output.series.iter().find(|c| c.needs_exact()) {
                return Err(SceneError::Inapplicable {
                    key: "output.series",
                    context: format!(
                        "column \"{}\" of this scene: the exact solution is known only without body force (bar.force = 0)",
                        c.name(),
                    ),
                });
            }
        }
        Ok(scene)
    }

    /// The exact solution is known without body force: the paper's closed form on its bar, the
    /// solution by characteristics otherwise ([`crate::characteristics`]).
    pub fn has_exact_solution(&self) -> bool {
        self.bar.force.constant() == Some(0.0)
    }

    /// The scene with every default filled in, as TOML.
    pub fn resolved_toml(&self) -> String {
        let f = Number::Float;
        let (mass, scheme, time, output) = raw_sections(&self.mass, &self.scheme, &self.time, &self.output, false);
        let raw = RawScene {
            bar: Some(RawBar {
                length: Some(f(self.bar.length)),
                elements: Some(self.bar.elements as i64),
                body: RawBody::resolved(
                    self.bar.material,
                    self.bar.far_end,
                    self.bar.gap,
                    match &self.bar.initial {
                        Initial::Paper => RawInitial::Name("paper".into()),
                        Initial::Fields { displacement, velocity } => RawInitial::fields(displacement, velocity),
                    },
                    &self.bar.force,
                ),
                unknown: Default::default(),
            }),
            mass,
            scheme,
            time,
            output,
        };
        let mut text = format!(
            "# Resolved scene (every default filled in); {} steps, h = {:e}.\n",
            self.time.steps,
            self.bar.length / self.bar.elements as f64
        );
        text.push_str(&toml::to_string(&raw).expect("a resolved scene always serialises"));
        text
    }
}
