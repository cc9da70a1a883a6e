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

use crate::assembly::{FarEnd, Material};
use crate::expr::Expr;
use crate::mass::MassKind;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Upper bound on `elements`: 10⁷ nodes take ~1 GB of work vectors across a scheme and observers.
pub const MAX_ELEMENTS: usize = 10_000_000;
/// Upper bound on elements × steps: at ~10 ns per node-step (release build) about 2 minutes.
pub const MAX_NODE_STEPS: f64 = 1e10;
/// Upper bound on the values `series.csv` may hold in memory (8 bytes each: 400 MB).
pub const MAX_SERIES_VALUES: f64 = 5e7;

#[derive(Debug, Error)]
pub enum SceneError {
    #[error("cannot read {path}: {source}")]
    Io { path: String, source: std::io::Error },
    #[error("{0}")]
    Parse(String),
    #[error("{key} = {value}: allowed range is {range}")]
    Range { key: &'static str, value: String, range: &'static str },
    #[error("{key} is required{hint}")]
    Missing { key: &'static str, hint: &'static str },
    #[error("{key} does not apply to {context}")]
    Inapplicable { key: &'static str, context: String },
    #[error(
        "time.end / time.dt = {ratio} is not an integer (within 1e-9 relative): choose dt dividing end (end = {end}, dt = {dt})"
    )]
    NotAnInteger { end: f64, dt: f64, ratio: f64 },
    #[error(
        "bar.elements × steps = {work:.3e} node-steps exceeds the limit {limit:.0e} (about 2 minutes of computing in a release build): reduce bar.elements or time.end / time.dt"
    )]
    TooMuchWork { work: f64, limit: f64 },
    #[error("output.series would record {values:.3e} values (limit {limit:.0e}): set output.every to at least {every}")]
    TooManyValues { values: f64, limit: f64, every: usize },
    #[error("output.series lists \"{0}\" twice")]
    DuplicateColumn(String),
    #[error(transparent)]
    Mass(#[from] crate::mass::MassError),
    #[error(transparent)]
    Expr(#[from] crate::expr::ExprError),
}

impl SceneError {
    /// Exit code for the CLI: 2 for anything wrong with the input.
    pub fn exit_code(&self) -> i32 {
        2
    }
}

/// A number written as a TOML integer or float (`end = 3` and `end = 3.0` both work).
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(untagged)]
pub(crate) enum Number {
    Int(i64),
    Float(f64),
}

impl Number {
    pub(crate) fn get(self) -> f64 {
        match self {
            Number::Int(i) => i as f64,
            Number::Float(f) => f,
        }
    }
}

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

/// The keys a bar's and a plate's table share: material, far end, gap, initial data, force.
#[derive(Debug, Default, Deserialize, Serialize)]
pub(crate) struct RawBody {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) density: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) modulus: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) far_end: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) gap: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) initial: Option<RawInitial>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) force: Option<RawField>,
}

impl RawBody {
    /// The resolved table of a body (every default filled in).
    pub(crate) fn resolved(material: Material, far_end: FarEnd, gap: f64, initial: RawInitial, force: &Force) -> Self {
        let f = Number::Float;
        RawBody {
            density: Some(f(material.density)),
            modulus: Some(f(material.modulus)),
            far_end: Some(far_end.name().into()),
            gap: Some(f(gap)),
            initial: Some(initial),
            force: Some(match force {
                Force::Constant(c) => RawField::Number(f(*c)),
                Force::Field(e) => RawField::Expr(e.text().into()),
            }),
        }
    }

    /// Refuses the keys of a flattened table that no field took, naming the table and its keys.
    pub(crate) fn refuse_unknown(
        table: &str,
        unknown: &std::collections::BTreeMap<String, toml::Value>,
        expected: &str,
    ) -> Result<(), SceneError> {
        match unknown.keys().next() {
            Some(key) => {
                Err(SceneError::Parse(format!("unknown field `{key}` in [{table}], expected one of {expected}")))
            }
            None => Ok(()),
        }
    }
}

impl RawInitial {
    /// The table of expressions as written.
    pub(crate) fn fields(displacement: &Expr, velocity: &Expr) -> Self {
        RawInitial::Fields(RawInitialFields {
            displacement: Some(RawField::Expr(displacement.text().into())),
            velocity: Some(RawField::Expr(velocity.text().into())),
        })
    }
}

/// `initial = "paper"` or `initial = { displacement = "…", velocity = "…" }`.
#[derive(Debug, Deserialize, Serialize)]
#[serde(untagged)]
pub(crate) enum RawInitial {
    Name(String),
    Fields(RawInitialFields),
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawInitialFields {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) displacement: Option<RawField>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) velocity: Option<RawField>,
}

/// A number or an expression (a string).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(untagged)]
pub(crate) enum RawField {
    Number(Number),
    Expr(String),
}

/// The `[mass]` table (shared with the plate scenes of `crate::plate::scene`).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMass {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) kind: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) weights: Option<Vec<Number>>,
}

/// The `[scheme]` table (shared with the plate scenes).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawScheme {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) kind: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) beta: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) gamma: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) restitution: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) formulation: Option<String>,
}

/// The `[time]` table (shared with the plate scenes).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTime {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) dt: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) end: Option<Number>,
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RawOutput {
    #[serde(skip_serializing_if = "Option::is_none")]
    series: Option<Vec<String>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    every: Option<i64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    summary_l2: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    divergence_factor: Option<Number>,
}

/// Initial data of the bar.
#[derive(Debug, Clone, PartialEq)]
pub enum Initial {
    /// u⁰ = (L − x)/2, v⁰ = 0: the paper's benchmark (exact solution known when f = 0).
    Paper,
    /// u⁰(x), v⁰(x) as expressions in x (and L, pi), interpolated at every node.
    Fields { displacement: Expr, velocity: Expr },
}

/// The body force: a constant, or an expression in x (and L, pi).
#[derive(Debug, Clone, PartialEq)]
pub enum Force {
    Constant(f64),
    Field(Expr),
}

impl Force {
    /// The constant value, if the force does not depend on x.
    pub fn constant(&self) -> Option<f64> {
        match self {
            Force::Constant(f) => Some(*f),
            Force::Field(e) => e.is_constant(),
        }
    }
}

/// The material, far end, gap and force of a body (bar or plate).
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    pub material: Material,
    pub far_end: FarEnd,
    /// The obstacle at x = 0: u ≥ −gap on the contact boundary.
    pub gap: f64,
    pub force: Force,
}

impl Default for Body {
    /// The paper's body: ρ = E = 1, clamped at x = L, no gap, no force.
    fn default() -> Self {
        Body { material: Material::UNIT, far_end: FarEnd::Clamped, gap: 0.0, force: Force::Constant(0.0) }
    }
}

/// The scene keys of a body's table (`bar.*` or `plate.*`).
pub(crate) struct BodyKeys {
    pub density: &'static str,
    pub modulus: &'static str,
    pub far_end: &'static str,
    pub gap: &'static str,
}

/// Density, modulus, far end and gap, validated (defaults: 1, 1, clamped, 0).
pub(crate) fn parse_body(
    keys: &BodyKeys,
    density: Option<Number>,
    modulus: Option<Number>,
    far_end: Option<&str>,
    gap: Option<Number>,
) -> Result<(Material, FarEnd, f64), SceneError> {
    let positive = |key, v: Option<Number>| {
        let v = finite_in(key, v.map_or(1.0, Number::get), true, "(0, ∞)")?;
        finite_in(key, v, v > 0.0, "(0, ∞)")
    };
    let (density, modulus) = (positive(keys.density, density)?, positive(keys.modulus, modulus)?);
    let far_end = match far_end.unwrap_or("clamped") {
        "clamped" => FarEnd::Clamped,
        "free" => FarEnd::Free,
        other => {
            return Err(SceneError::Range {
                key: keys.far_end,
                value: format!("\"{other}\""),
                range: "\"clamped\" (u(L,t) = 0) or \"free\" (E u_x(L,t) = 0)",
            });
        }
    };
    let gap = finite_in(keys.gap, gap.map_or(0.0, Number::get), true, "[0, ∞)")?;
    finite_in(keys.gap, gap, gap >= 0.0, "[0, ∞)")?;
    Ok((Material { density, modulus }, far_end, gap))
}

/// A number or an expression as an [`Expr`] (absent: 0).
pub(crate) fn parse_field(
    key: &str,
    raw: Option<RawField>,
    vars: &[&str],
    consts: &[(&str, f64)],
) -> Result<Expr, SceneError> {
    let text = match raw {
        None => "0".to_string(),
        Some(RawField::Number(n)) => crate::expr::sci(n.get()),
        Some(RawField::Expr(t)) => t,
    };
    Ok(Expr::parse(key, &text, vars, consts)?)
}

/// A force: a number, or an expression in `vars` (time-dependent forces are refused).
pub(crate) fn parse_force(
    key: &'static str,
    raw: Option<RawField>,
    vars: &[&str],
    consts: &[(&str, f64)],
) -> Result<Force, SceneError> {
    match raw {
        None => Ok(Force::Constant(0.0)),
        Some(RawField::Number(n)) => {
            Ok(Force::Constant(finite_in(key, n.get(), true, "finite real numbers, or an expression")?))
        }
        Some(raw) => {
            let with_t: Vec<&str> = vars.iter().copied().chain(["t"]).collect();
            let e = parse_field(key, Some(raw), &with_t, consts)?;
            if e.depends_on("t") {
                return Err(SceneError::Inapplicable {
                    key,
                    context: format!(
                        "time: \"{}\" depends on t, and time-dependent forces are not supported yet (the schemes assume a constant load); write an expression without t",
                        e.text()
                    ),
                });
            }
            Ok(match e.is_constant() {
                Some(c) => Force::Constant(c),
                None => Force::Field(Expr::parse(key, e.text(), vars, consts)?),
            })
        }
    }
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

/// Which form of Newmark to solve: the full m-unknown system with the contact multiplier, or the
/// reduced (P^mod_U) system of a massless contact node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Formulation {
    Full,
    Reduced,
}

#[derive(Debug, Clone, PartialEq)]
pub enum SchemeSpec {
    CrankNicolson { formulation: Formulation },
    Newmark { beta: f64, gamma: f64, formulation: Formulation },
    BackwardEuler,
    PaoliSchatzman { beta: f64, restitution: f64 },
    Hybrid,
}

impl SchemeSpec {
    /// Why other geometries reject this scheme, if it is bar-only (Paoli–Schatzman and the
    /// reduced Newmark formulation use the bar's one contact node): the scene key and the reason.
    /// The one place that decides it, for scenes ([`crate::plate::scene`]) and problems
    /// ([`crate::problem::Problem::scheme`]) alike.
    pub fn bar_only(&self) -> Option<(&'static str, &'static str)> {
        const WHY: &str = "a bar-only scheme (it uses the bar's one contact node); use crank-nicolson, newmark, backward-euler or hybrid";
        match self {
            SchemeSpec::PaoliSchatzman { .. } => Some(("scheme.kind = \"paoli-schatzman\"", WHY)),
            SchemeSpec::CrankNicolson { formulation: Formulation::Reduced }
            | SchemeSpec::Newmark { formulation: Formulation::Reduced, .. } => {
                Some(("scheme.formulation = \"reduced\"", WHY))
            }
            _ => None,
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            SchemeSpec::CrankNicolson { .. } => "crank-nicolson",
            SchemeSpec::Newmark { .. } => "newmark",
            SchemeSpec::BackwardEuler => "backward-euler",
            SchemeSpec::PaoliSchatzman { .. } => "paoli-schatzman",
            SchemeSpec::Hybrid => "hybrid",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeSpec {
    pub dt: f64,
    pub end: f64,
    pub steps: usize,
}

/// A per-step diagnostic that can be recorded in `series.csv`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Column {
    /// Contact-node displacement u_0ⁿ (plates: the contact node at the lowest y).
    U0,
    /// Displacement of node 1 (bars only).
    U1,
    /// Mean of u on Γ_C (plates).
    UMean,
    /// Contact force λⁿ (plates: the mean pressure Σ_c λ_c / |Γ_C|, the 1D λ for y-independent
    /// fields).
    Lambda,
    /// Total contact force Σ_c λ_c (plates).
    ContactForce,
    /// Discrete energy ½VᵀMV + ½UᵀSU − UᵀF.
    Energy,
    /// Exact ‖u_h(t_n) − u(t_n)‖_{L²(0,L)}.
    L2Error,
    /// Exact u(0, t_n).
    ExactU0,
    /// Exact λ(t_n).
    ExactLambda,
    /// Principal pivots of the step's contact solves (plates).
    Pivots,
}

impl Column {
    /// The columns of a bar scene.
    pub const BAR: [Column; 7] =
        [Column::U0, Column::U1, Column::Lambda, Column::Energy, Column::L2Error, Column::ExactU0, Column::ExactLambda];
    /// The columns of a plate scene.
    pub const PLATE: [Column; 9] = [
        Column::U0,
        Column::UMean,
        Column::Lambda,
        Column::ContactForce,
        Column::Energy,
        Column::L2Error,
        Column::ExactU0,
        Column::ExactLambda,
        Column::Pivots,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Column::U0 => "u0",
            Column::U1 => "u1",
            Column::UMean => "u_mean",
            Column::Lambda => "lambda",
            Column::ContactForce => "contact_force",
            Column::Energy => "energy",
            Column::L2Error => "l2_error",
            Column::ExactU0 => "exact_u0",
            Column::ExactLambda => "exact_lambda",
            Column::Pivots => "pivots",
        }
    }

    pub fn needs_exact(self) -> bool {
        matches!(self, Column::L2Error | Column::ExactU0 | Column::ExactLambda)
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct OutputSpec {
    pub series: Vec<Column>,
    pub every: usize,
    /// Compute the exact L² error at every step for the summary's `linf_l2_error` (one O(m) pass
    /// per step, about the cost of a step); false leaves those summary keys null.
    pub summary_l2: bool,
    /// The run stops as diverged when its energy exceeds this factor times its reference
    /// ([`crate::driver::DivergenceCriterion`]); in (1, ∞), default 1e6.
    pub divergence_factor: f64,
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

pub(crate) fn finite_in(key: &'static str, v: f64, ok: bool, range: &'static str) -> Result<f64, SceneError> {
    if v.is_finite() && ok { Ok(v) } else { Err(SceneError::Range { key, value: v.to_string(), range }) }
}

pub(crate) fn forbid<T>(key: &'static str, value: &Option<T>, context: &str) -> Result<(), SceneError> {
    match value {
        Some(_) => Err(SceneError::Inapplicable { key, context: context.to_string() }),
        None => Ok(()),
    }
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
        let mut series = Vec::new();
        for name in names {
            let col = Column::BAR.into_iter().find(|c| c.name() == name).ok_or_else(|| SceneError::Range {
                key: "output.series",
                value: format!("\"{name}\""),
                range: "any subset of u0, u1, lambda, energy, l2_error, exact_u0, exact_lambda",
            })?;
            if series.contains(&col) {
                return Err(SceneError::DuplicateColumn(name));
            }
            series.push(col);
        }
        let every = o.every.unwrap_or(1);
        if every < 1 {
            return Err(SceneError::Range { key: "output.every", value: every.to_string(), range: "integers >= 1" });
        }
        let every = every as usize;
        let values = ((time.steps / every + 1) * (series.len() + 1)) as f64;
        if !series.is_empty() && values > MAX_SERIES_VALUES {
            let min_every = (time.steps as f64 * (series.len() + 1) as f64 / MAX_SERIES_VALUES).ceil() as usize;
            return Err(SceneError::TooManyValues { values, limit: MAX_SERIES_VALUES, every: min_every });
        }
        let divergence_factor = parse_divergence_factor(o.divergence_factor)?;
        let output = OutputSpec { series, every, summary_l2: o.summary_l2.unwrap_or(true), divergence_factor };
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
            mass: Some(raw_mass(&self.mass)),
            scheme: Some(raw_scheme(&self.scheme)),
            time: Some(raw_time(&self.time)),
            output: Some(RawOutput {
                series: Some(self.output.series.iter().map(|c| c.name().to_string()).collect()),
                every: Some(self.output.every as i64),
                summary_l2: Some(self.output.summary_l2),
                divergence_factor: Some(f(self.output.divergence_factor)),
            }),
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

/// The `[mass]` table as a [`MassKind`] (its weights are validated by the caller, who knows the
/// mesh).
pub(crate) fn parse_mass(raw: Option<RawMass>) -> Result<MassKind, SceneError> {
    let mass = raw.unwrap_or_default();
    let kind = mass.kind.as_deref().unwrap_or("mod3");
    let mass = match kind {
        "custom" => {
            let w = mass.weights.ok_or(SceneError::Missing {
                key: "mass.weights",
                hint: " for mass.kind = \"custom\" (one weight >= 0 per element, element 0 at the contact node)",
            })?;
            MassKind::Custom(w.into_iter().map(Number::get).collect())
        }
        "standard" | "mod1" | "mod2" | "mod3" => {
            forbid("mass.weights", &mass.weights, &format!("mass.kind = \"{kind}\" (only to \"custom\")"))?;
            match kind {
                "standard" => MassKind::Standard,
                "mod1" => MassKind::Mod1,
                "mod2" => MassKind::Mod2,
                _ => MassKind::Mod3,
            }
        }
        other => {
            return Err(SceneError::Range {
                key: "mass.kind",
                value: format!("\"{other}\""),
                range: "standard | mod1 | mod2 | mod3 | custom",
            });
        }
    };
    Ok(mass)
}

/// The `[scheme]` table; `w0` is the weight of the cells at the contact node (0 iff it is
/// massless), which the reduced formulation and the hybrid scheme need.
pub(crate) fn parse_scheme(raw: Option<RawScheme>, w0: f64, mass: &MassKind) -> Result<SchemeSpec, SceneError> {
    let s = raw.unwrap_or_default();
    let kind = s.kind.clone().unwrap_or_else(|| "crank-nicolson".into());
    let ctx = format!("scheme.kind = \"{kind}\"");
    let formulation = |s: &RawScheme| -> Result<Formulation, SceneError> {
        match s.formulation.as_deref().unwrap_or("full") {
            "full" => Ok(Formulation::Full),
            "reduced" if w0 == 0.0 => Ok(Formulation::Reduced),
            "reduced" => Err(SceneError::Inapplicable {
                key: "scheme.formulation = \"reduced\"",
                context: format!("a mass with w_0 = {} (it needs a massless contact node: mod1, mod2, mod3)", w0),
            }),
            other => Err(SceneError::Range {
                key: "scheme.formulation",
                value: format!("\"{other}\""),
                range: "full | reduced",
            }),
        }
    };
    let beta_range = "(0, 1]";
    let scheme = match kind.as_str() {
        "crank-nicolson" => {
            forbid("scheme.beta", &s.beta, &ctx)?;
            forbid("scheme.gamma", &s.gamma, &ctx)?;
            forbid("scheme.restitution", &s.restitution, &ctx)?;
            SchemeSpec::CrankNicolson { formulation: formulation(&s)? }
        }
        "newmark" => {
            forbid("scheme.restitution", &s.restitution, &ctx)?;
            let beta = s.beta.map_or(0.25, Number::get);
            let gamma = s.gamma.map_or(0.5, Number::get);
            finite_in("scheme.beta", beta, beta > 0.0 && beta <= 1.0, beta_range)?;
            finite_in("scheme.gamma", gamma, (0.0..=1.0).contains(&gamma), "[0, 1]")?;
            SchemeSpec::Newmark { beta, gamma, formulation: formulation(&s)? }
        }
        "backward-euler" | "hybrid" => {
            forbid("scheme.beta", &s.beta, &ctx)?;
            forbid("scheme.gamma", &s.gamma, &ctx)?;
            forbid("scheme.restitution", &s.restitution, &ctx)?;
            forbid("scheme.formulation", &s.formulation, &ctx)?;
            if kind == "hybrid" {
                if w0 != 0.0 {
                    return Err(SceneError::Inapplicable {
                        key: "scheme.kind = \"hybrid\"",
                        context: format!(
                            "mass.kind = \"{}\" (w_0 = {}): the hybrid scheme works on the reduced system and needs w_0 = 0 (mod1, mod2, mod3 or custom with weights[0] = 0)",
                            mass.name(),
                            w0
                        ),
                    });
                }
                SchemeSpec::Hybrid
            } else {
                SchemeSpec::BackwardEuler
            }
        }
        "paoli-schatzman" => {
            forbid("scheme.gamma", &s.gamma, &ctx)?;
            forbid("scheme.formulation", &s.formulation, &ctx)?;
            let beta = s.beta.map_or(0.25, Number::get);
            let restitution = s.restitution.map_or(1.0, Number::get);
            finite_in("scheme.beta", beta, beta > 0.0 && beta <= 1.0, beta_range)?;
            finite_in("scheme.restitution", restitution, (0.0..=1.0).contains(&restitution), "[0, 1]")?;
            SchemeSpec::PaoliSchatzman { beta, restitution }
        }
        other => {
            return Err(SceneError::Range {
                key: "scheme.kind",
                value: format!("\"{other}\""),
                range: "crank-nicolson | newmark | backward-euler | paoli-schatzman | hybrid",
            });
        }
    };
    Ok(scheme)
}

/// The `[time]` table; `default_end` is used without `time.end`, `elements` (the unknowns per
/// step) bounds the work.
pub(crate) fn parse_time(raw: Option<RawTime>, default_end: f64, elements: usize) -> Result<TimeSpec, SceneError> {
    let t = raw.unwrap_or_default();
    let dt = t.dt.map_or(0.01, Number::get);
    let end = t.end.map_or(default_end, Number::get);
    finite_in("time.dt", dt, dt > 0.0, "(0, ∞)")?;
    finite_in("time.end", end, end > 0.0, "(0, ∞)")?;
    let ratio = end / dt;
    if !(ratio <= 1e15) {
        return Err(SceneError::TooMuchWork { work: ratio * elements as f64, limit: MAX_NODE_STEPS });
    }
    let steps = ratio.round();
    if steps < 1.0 || (steps - ratio).abs() > 1e-9 * ratio {
        return Err(SceneError::NotAnInteger { end, dt, ratio });
    }
    let work = steps * elements as f64;
    if work > MAX_NODE_STEPS {
        return Err(SceneError::TooMuchWork { work, limit: MAX_NODE_STEPS });
    }
    let time = TimeSpec { dt, end, steps: steps as usize };
    Ok(time)
}

/// `output.divergence_factor` (shared with the plate scenes): in (1, ∞), default
/// [`DivergenceCriterion::DEFAULT_ENERGY_FACTOR`](crate::driver::DivergenceCriterion).
pub(crate) fn parse_divergence_factor(raw: Option<Number>) -> Result<f64, SceneError> {
    let factor = raw.map_or(crate::driver::DivergenceCriterion::DEFAULT_ENERGY_FACTOR, Number::get);
    finite_in("output.divergence_factor", factor, factor > 1.0, "(1, ∞)")
}

/// The resolved `[mass]` table of a mass redistribution.
pub(crate) fn raw_mass(mass: &MassKind) -> RawMass {
    RawMass {
        kind: Some(mass.name().into()),
        weights: match mass {
            MassKind::Custom(w) => Some(w.iter().copied().map(Number::Float).collect()),
            _ => None,
        },
    }
}

/// The resolved `[scheme]` table of a scheme.
pub(crate) fn raw_scheme(scheme: &SchemeSpec) -> RawScheme {
    let f = Number::Float;
    let (kind, beta, gamma, restitution, formulation) = match scheme {
        SchemeSpec::CrankNicolson { formulation } => ("crank-nicolson", None, None, None, Some(*formulation)),
        SchemeSpec::Newmark { beta, gamma, formulation } => {
            ("newmark", Some(*beta), Some(*gamma), None, Some(*formulation))
        }
        SchemeSpec::BackwardEuler => ("backward-euler", None, None, None, None),
        SchemeSpec::PaoliSchatzman { beta, restitution } => {
            ("paoli-schatzman", Some(*beta), None, Some(*restitution), None)
        }
        SchemeSpec::Hybrid => ("hybrid", None, None, None, None),
    };
    RawScheme {
        kind: Some(kind.into()),
        beta: beta.map(f),
        gamma: gamma.map(f),
        restitution: restitution.map(f),
        formulation: formulation.map(|x| match x {
            Formulation::Full => "full".into(),
            Formulation::Reduced => "reduced".into(),
        }),
    }
}

/// The resolved `[time]` table.
pub(crate) fn raw_time(time: &TimeSpec) -> RawTime {
    RawTime { dt: Some(Number::Float(time.dt)), end: Some(Number::Float(time.end)) }
}
