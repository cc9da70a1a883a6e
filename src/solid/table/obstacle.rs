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
    pub(crate) shape: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) normal: Option<Vec<Number>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) point: Option<Vec<Number>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) center: Option<Vec<Number>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) radius: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) side: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) axis: Option<Vec<Number>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) distance: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) contact: Option<String>,
}

/// The keys each shape takes (besides `shape` and `contact`).
const SHAPE_KEYS: [(&str, &[&str]); 4] = [
    ("plane", &["normal", "point"]),
    ("sphere", &["center", "radius", "side"]),
    ("cylinder", &["center", "radius", "side", "axis"]),
    ("level-set", &["distance"]),
];

/// A vector key: `dim` finite numbers.
fn vector(key: &'static str, v: Vec<Number>, dim: usize) -> Result<[f64; 3], SceneError> {
    if v.len() != dim || v.iter().any(|x| !x.get().is_finite()) {
        let value = format!("[{}]", v.iter().map(|x| short(x.get())).collect::<Vec<_>>().join(", "));
        return Err(SceneError::Range { key, value, range: "one finite number per component (solid.dim of them)" });
    }
    let mut out = [0.0; 3];
    for (a, x) in out.iter_mut().zip(&v) {
        *a = x.get();
    }
    Ok(out)
}

/// The `[obstacle]` table validated (issue 30; [`crate::solid::surface`]): `shape` (default
/// `"plane"`) and its own keys, each other shape's key refused by name. A plane: the normal
/// normalised (a zero or non-finite one refused), the point by default the origin. A sphere or
/// cylinder: the center, a radius > 0, the side (default `"outside"`); a cylinder (3D only)
/// its axis normalised. A level set: `distance`, an expression in x, y[, z] and pi. The
/// contact set defaults to `"auto"`.
pub(crate) fn parse_obstacle(raw: RawObstacle, dim: usize) -> Result<crate::solid::Obstacle, SceneError> {
    use crate::solid::{ContactSet, Obstacle, Side, Surface};
    let shape = raw.shape.clone().unwrap_or_else(|| "plane".into());
    let Some((_, keys)) = SHAPE_KEYS.iter().find(|(s, _)| *s == shape) else {
        let range = "\"plane\" | \"sphere\" | \"cylinder\" (3D) | \"level-set\"";
        return Err(SceneError::Range { key: "obstacle.shape", value: format!("\"{shape}\""), range });
    };
    if shape == "cylinder" && dim != 3 {
        let range = "\"plane\" | \"sphere\" (a circle in 2D) | \"level-set\" in 2D; \"cylinder\" needs solid.dim = 3";
        return Err(SceneError::Range { key: "obstacle.shape", value: "\"cylinder\"".into(), range });
    }
    let given = [
        ("obstacle.normal", raw.normal.is_some()),
        ("obstacle.point", raw.point.is_some()),
        ("obstacle.center", raw.center.is_some()),
        ("obstacle.radius", raw.radius.is_some()),
        ("obstacle.side", raw.side.is_some()),
        ("obstacle.axis", raw.axis.is_some()),
        ("obstacle.distance", raw.distance.is_some()),
    ];
    if let Some((key, _)) = given.iter().find(|(k, on)| *on && !keys.contains(&&k["obstacle.".len()..])) {
        return Err(SceneError::Inapplicable { key, context: format!("obstacle.shape = \"{shape}\"") });
    }
    let side = match raw.side.as_deref().unwrap_or("outside") {
        "outside" => Side::Outside,
        "inside" => Side::Inside,
        other => {
            let range = "\"outside\" (the body outside the surface) | \"inside\" (in its cavity)";
            return Err(SceneError::Range { key: "obstacle.side", value: format!("\"{other}\""), range });
        }
    };
    let center = |raw: Option<Vec<Number>>| match raw {
        Some(c) => vector("obstacle.center", c, dim),
        None => {
            Err(SceneError::Missing { key: "obstacle.center", hint: " (a point of the axis, one entry per component)" })
        }
    };
    let radius = |raw: Option<Number>| match raw {
        Some(r) => finite_in("obstacle.radius", r.get(), r.get() > 0.0, "finite numbers > 0"),
        None => Err(SceneError::Missing { key: "obstacle.radius", hint: " (a number > 0)" }),
    };
    let surface = match shape.as_str() {
        "plane" => {
            let Some(normal) = raw.normal else {
                return Err(SceneError::Missing {
                    key: "obstacle.normal",
                    hint: " (the unit normal of the plane, pointing into the body, one entry per component)",
                });
            };
            let normal: Vec<f64> = normal.iter().map(|x| x.get()).collect();
            let normal = crate::solid::body::unit_normal(&normal, dim)?;
            let point = match raw.point {
                Some(p) => vector("obstacle.point", p, dim)?,
                None => [0.0; 3],
            };
            Surface::Plane { normal, point }
        }
        "sphere" => Surface::Sphere { center: center(raw.center)?, radius: radius(raw.radius)?, side },
        "cylinder" => {
            let Some(axis) = raw.axis else {
                return Err(SceneError::Missing {
                    key: "obstacle.axis",
                    hint: " (the cylinder's direction, three entries)",
                });
            };
            let axis: Vec<f64> = axis.iter().map(|x| x.get()).collect();
            let axis = crate::solid::body::unit_normal(&axis, dim).map_err(|_| SceneError::Range {
                key: "obstacle.axis",
                value: format!("[{}]", axis.iter().map(|x| short(*x)).collect::<Vec<_>>().join(", ")),
                range: "three finite numbers, not all zero (normalised)",
            })?;
            Surface::Cylinder { center: center(raw.center)?, axis, radius: radius(raw.radius)?, side }
        }
        _ => {
            let Some(text) = raw.distance else {
                return Err(SceneError::Missing {
                    key: "obstacle.distance",
                    hint: " (φ(x, y[, z]) > 0 on the body's side, 0 on the obstacle)",
                });
            };
            let vars: &[&str] = if dim == 2 { &["x", "y"] } else { &["x", "y", "z"] };
            Surface::LevelSet(crate::expr::Expr::parse(
                "obstacle.distance",
                &text,
                vars,
                &[("pi", std::f64::consts::PI)],
            )?)
        }
    };
    let contact = match raw.contact.as_deref().unwrap_or("auto") {
        "auto" => ContactSet::Auto,
        "" => {
            let range = "\"auto\" or the name of a physical group of the mesh";
            return Err(SceneError::Range { key: "obstacle.contact", value: "\"\"".into(), range });
        }
        group => ContactSet::Group(group.into()),
    };
    Ok(Obstacle { surface, contact })
}

/// The resolved `[obstacle]` table (a plane's written as today: no `shape`).
pub(crate) fn raw_obstacle(o: &crate::solid::Obstacle, dim: usize) -> RawObstacle {
    use crate::solid::Surface;
    let numbers = |v: &[f64]| Some(v[..dim].iter().map(|&x| Number::Float(x)).collect());
    let mut raw = RawObstacle {
        contact: Some(match &o.contact {
            crate::solid::ContactSet::Auto => "auto".into(),
            crate::solid::ContactSet::Group(g) => g.clone(),
        }),
        ..Default::default()
    };
    match &o.surface {
        Surface::Plane { normal, point } => (raw.normal, raw.point) = (numbers(normal), numbers(point)),
        Surface::Sphere { center, radius, side } => {
            raw.shape = Some("sphere".into());
            (raw.center, raw.radius, raw.side) =
                (numbers(center), Some(Number::Float(*radius)), Some(side.name().into()));
        }
        Surface::Cylinder { center, axis, radius, side } => {
            raw.shape = Some("cylinder".into());
            (raw.center, raw.axis) = (numbers(center), numbers(axis));
            (raw.radius, raw.side) = (Some(Number::Float(*radius)), Some(side.name().into()));
        }
        Surface::LevelSet(e) => {
            raw.shape = Some("level-set".into());
            raw.distance = Some(e.text().into());
        }
    }
    raw
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
