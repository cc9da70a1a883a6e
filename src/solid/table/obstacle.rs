//! A solid body against a rigid plane (issue 19): the `[obstacle]` table and the body keys of
//! `[solid]` (`force` as expressions in x, y[, z], t). `[obstacle]` is a table of the solid's
//! own beside `[solid]` ([`crate::spec::SceneGeometry::Extras`]).

use crate::expr::Expr;
use crate::spec::medium::{RawField, parse_field};
use crate::spec::{Number, SceneError, finite_in, short};
use serde::{Deserialize, Serialize};

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
