//! The keys a bar's and a plate's table share, their medium ([`crate::medium::Medium`]):
//! material, far end, gap, initial data and force (numbers or expressions). Below the
//! geometries' folders, which read their tables with it (`bar/table.rs`, `plate/table.rs`; a
//! solid's table reads its fields with [`RawField`] and [`parse_field`]).

use super::error::SceneError;
use super::limits::{Number, finite_in};
use crate::expr::Expr;
use crate::material::{FarEnd, Material};
use crate::medium::Force;
use serde::{Deserialize, Serialize};

/// The keys a bar's and a plate's table share: material, far end, gap, initial data, force.
#[derive(Debug, Default, Deserialize, Serialize)]
pub(crate) struct RawMedium {
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

impl RawMedium {
    /// The resolved keys of a medium (every default filled in).
    pub(crate) fn resolved(material: Material, far_end: FarEnd, gap: f64, initial: RawInitial, force: &Force) -> Self {
        let f = Number::Float;
        RawMedium {
            density: Some(f(material.density)),
            modulus: Some(f(material.modulus)),
            far_end: Some(far_end.name().into()),
            gap: Some(f(gap)),
            initial: Some(initial),
            force: Some(match force {
                Force::Constant(c) => RawField::Number(f(*c)),
                Force::Field(e) | Force::Transient(e) => RawField::Expr(e.text().into()),
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
            Some(key) => Err(SceneError::Parse(format!(
                "{table}.{key}: unknown field `{key}` in [{table}], expected one of {expected}"
            ))),
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

/// The scene keys of a medium's table (`bar.*` or `plate.*`).
pub(crate) struct MediumKeys {
    pub density: &'static str,
    pub modulus: &'static str,
    pub far_end: &'static str,
    pub gap: &'static str,
}

/// Density, modulus, far end and gap, validated (defaults: 1, 1, clamped, 0).
pub(crate) fn parse_medium(
    keys: &MediumKeys,
    density: Option<Number>,
    modulus: Option<Number>,
    far_end: Option<&str>,
    gap: Option<Number>,
) -> Result<(Material, FarEnd, f64), SceneError> {
    let positive = |key, v: Option<Number>| super::limits::positive_normal(key, v.map_or(1.0, Number::get));
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
        // The round-trip form: the expression holds the number exactly (`sci` rounds to 5 digits).
        Some(RawField::Number(n)) => format!("{:e}", n.get()),
        Some(RawField::Expr(t)) => t,
    };
    Ok(Expr::parse(key, &text, vars, consts)?)
}

/// A force: a number, or an expression in `vars` and t ([`Force::Transient`] if it depends on t).
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
                return Ok(Force::Transient(e));
            }
            Ok(match e.is_constant() {
                Some(c) => Force::Constant(c),
                None => Force::Field(Expr::parse(key, e.text(), vars, consts)?),
            })
        }
    }
}
