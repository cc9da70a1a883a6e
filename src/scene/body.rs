//! The keys a bar's and a plate's table share: material, far end, gap, initial data and force
//! (numbers or expressions).

use super::*;
use crate::expr::Expr;
use crate::material::{FarEnd, Material};

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

// A solid body against a rigid plane (issue 19): the `[obstacle]` table and the body keys of
// `[solid]` (`force` as expressions in x, y[, z], t).

/// The `[obstacle]` table as written (closed).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawObstacle {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) normal: Option<Vec<Number>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) point: Option<Vec<Number>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) contact: Option<String>,
}

/// The `[obstacle]` table validated (dim entries each; the normal is normalised, a zero or
/// non-finite one refused; the point defaults to the origin; the contact to `"auto"`).
pub(crate) fn parse_obstacle(raw: RawObstacle, dim: usize) -> Result<crate::solid::Obstacle, SceneError> {
    use crate::solid::{ContactSet, Obstacle};
    let Some(normal) = raw.normal else {
        return Err(SceneError::Missing {
            key: "obstacle.normal",
            hint: " (the unit normal of the plane, pointing into the body, one entry per component)",
        });
    };
    let normal: Vec<f64> = normal.iter().map(|x| x.get()).collect();
    let normal = crate::solid::body::unit_normal(&normal, dim)?;
    let mut point = [0.0; 3];
    if let Some(p) = raw.point {
        let value = || format!("[{}]", p.iter().map(|x| short(x.get())).collect::<Vec<_>>().join(", "));
        if p.len() != dim || p.iter().any(|x| !x.get().is_finite()) {
            return Err(SceneError::Range {
                key: "obstacle.point",
                value: value(),
                range: "one finite number per component (solid.dim of them)",
            });
        }
        for (a, x) in point.iter_mut().zip(&p) {
            *a = x.get();
        }
    }
    let contact = match raw.contact.as_deref().unwrap_or("auto") {
        "auto" => ContactSet::Auto,
        "" => {
            let range = "\"auto\" or the name of a physical group of the mesh";
            return Err(SceneError::Range { key: "obstacle.contact", value: "\"\"".into(), range });
        }
        group => ContactSet::Group(group.into()),
    };
    Ok(Obstacle { normal, point, contact })
}

/// The resolved `[obstacle]` table.
pub(crate) fn raw_obstacle(o: &crate::solid::Obstacle, dim: usize) -> RawObstacle {
    let numbers = |v: &[f64]| Some(v[..dim].iter().map(|&x| Number::Float(x)).collect());
    RawObstacle {
        normal: numbers(&o.normal),
        point: numbers(&o.point),
        contact: Some(match &o.contact {
            crate::solid::ContactSet::Auto => "auto".into(),
            crate::solid::ContactSet::Group(g) => g.clone(),
        }),
    }
}

/// A body's `solid.force`: one number or expression in `vars` and t per component (absent: 0),
/// a force per unit volume.
pub(crate) fn parse_body_force(
    raw: Option<Vec<RawField>>,
    dim: usize,
    vars: &[&str],
    consts: &[(&str, f64)],
) -> Result<Vec<Expr>, SceneError> {
    let key = "solid.force";
    let with_t: Vec<&str> = vars.iter().copied().chain(["t"]).collect();
    let Some(fields) = raw else {
        return (0..dim).map(|_| parse_field(key, None, &with_t, consts)).collect();
    };
    if fields.len() != dim {
        let value = format!("{} entries", fields.len());
        return Err(SceneError::Range { key, value, range: "one number or expression per component (solid.dim)" });
    }
    fields
        .into_iter()
        .map(|f| {
            if let RawField::Number(n) = &f {
                finite_in(key, n.get(), true, "finite numbers or expressions in x, y[, z], t")?;
            }
            parse_field(key, Some(f), &with_t, consts)
        })
        .collect()
}
