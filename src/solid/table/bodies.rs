//! Several bodies: `[[solid]]` tables (every `[solid]` key of a body, plus `name`, and for a box
//! `offset`) and `[[pair]]` tables (issue 30's contract; [`crate::solid::bodies`]).
//!
//! ```toml
//! [[solid]]
//! name = "striker"
//! length = 1.0             # the box keys, or mesh = "striker.msh"
//! offset = [-1.0, 0.0]     # added to every node (a box's lowest corner is then the offset)
//! initial = { velocity = ["1", "0"] }
//! [[solid]]
//! name = "target"
//! clamped = "xmax"
//! [[pair]]
//! name = "impact"
//! bodies = ["striker", "target"]
//! groups = ["xmax", "xmin"]   # the facing facet groups, the first body's then the second's
//! ```
//!
//! One `[mass]` for all bodies (each body's layers its own); the bodies share one material
//! (`lame_lambda`, `lame_mu`, `density`) and one cell kind; every body is in a pair, or meets
//! an `[obstacle]` beside the pairs (its keys as for one body). A pair's own `contact` table is
//! kept as written and read by the scene with `[contact]` (one law for all pairs:
//! `crate::scene`'s `pair_law`).

use super::*;
use crate::solid::bodies::{Bodies, NamedBody, PairSpec};

/// A `[[pair]]` table as written (closed).
#[derive(Debug, Default, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawPair {
    #[serde(skip_serializing_if = "Option::is_none")]
    name: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    bodies: Option<Vec<String>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    groups: Option<Vec<String>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    contact: Option<toml::Table>,
}

/// An error of body `name`'s table, with the body named first.
fn of_body(name: &str, e: SceneError) -> SceneError {
    SceneError::Parse(format!("[[solid]] \"{name}\": {e}"))
}

/// A required string key.
fn required<T>(key: &'static str, v: Option<T>, range: &'static str) -> Result<T, SceneError> {
    v.ok_or(SceneError::Range { key, value: "absent".into(), range })
}

/// One `[[solid]]` table validated into a body (its name checked by the caller).
fn body(t: RawSolid, name: String, inputs: &MeshInputs) -> Result<(NamedBody, Lame, usize), SceneError> {
    let dim = dim_of(&t)?;
    let why = "[[solid]] bodies (free but where clamped; pairs place their contact)";
    forbid("solid.gap", &t.gap, why)?;
    forbid("solid.lateral", &t.lateral, why)?;
    let (mut mesh, extent) = match &t.mesh {
        Some(file) => {
            let m = body_file_mesh(&t, dim, &inputs.resolve(file))?;
            let e = m.extent;
            (m, e)
        }
        None => {
            let (extent, [nx, ny, nz], cells) = structured(&t, dim)?;
            let [l, h, d] = extent;
            let mut m = match dim {
                2 => Mesh::structured_2d(l, h, nx, ny, cells),
                _ => Mesh::structured_3d([l, h, d], [nx, ny, nz], cells),
            }
            .map_err(SceneError::Mesh)?;
            crate::solid::spec::face_groups(&mut m);
            (m, extent)
        }
    };
    if let Some(offset) = &t.offset {
        let range = "one finite number per component (solid.dim of them)";
        if offset.len() != dim || offset.iter().any(|x| !x.get().is_finite()) {
            let value = format!("[{}]", offset.iter().map(|x| short(x.get())).collect::<Vec<_>>().join(", "));
            return Err(SceneError::Range { key: "solid.offset", value, range });
        }
        for p in mesh.points.iter_mut() {
            for (a, x) in offset.iter().enumerate() {
                p[a] += x.get();
            }
        }
        mesh.grid = None;
    }
    let lame = Lame {
        lambda: non_negative("solid.lame_lambda", t.lame_lambda)?,
        mu: positive("solid.lame_mu", t.lame_mu, 0.5)?,
        density: positive("solid.density", t.density, 1.0)?,
    };
    let (vars, consts) = variables(dim, extent);
    let force = parse_body_force(t.force, dim, vars, &consts)?;
    let initial = match t.initial {
        None => zero_initial(dim, extent)?,
        Some(RawSolidInitial::Name(s)) => {
            let range = "{ displacement = [...], velocity = [...] } (the paper's data are the box's)";
            return Err(SceneError::Range { key: "solid.initial", value: format!("\"{s}\""), range });
        }
        raw => parse_initial(raw, dim, extent)?,
    };
    let SolidInitial::Fields { displacement, velocity } = initial else {
        unreachable!("a body's initial data are fields")
    };
    for e in displacement.iter().chain(&velocity) {
        e.eval_at_nodes(mesh.points.iter().map(|p| &p[..dim])).map_err(SceneError::from)?;
    }
    for e in &force {
        e.eval_at_nodes(mesh.points.iter().map(|p| [&p[..dim], &[0.0][..]].concat())).map_err(SceneError::from)?;
    }
    let mesh = Arc::new(mesh);
    let named = NamedBody { name, mesh, clamped: t.clamped, force, displacement, velocity, lame };
    Ok((named, lame, dim))
}

/// `[[solid]]` and `[[pair]]` validated into a spec whose support is [`Support::Bodies`]
/// (module docs): each body's errors name the body and the key.
pub(crate) fn validate_bodies(
    raws: Vec<RawSolid>,
    obstacle: Option<RawObstacle>,
    pairs: Option<Vec<RawPair>>,
    inputs: MeshInputs,
) -> Result<SolidSpec, SceneError> {
    let mut bodies: Vec<NamedBody> = Vec::with_capacity(raws.len());
    let mut material: Option<(Lame, usize, String)> = None;
    let mut raw_bodies = Vec::with_capacity(raws.len());
    for mut t in raws {
        let name = required("solid.name", t.name.take(), "a name for each [[solid]] body")?;
        if name.is_empty() || name.contains('.') || bodies.iter().any(|b| b.name == name) {
            let range = "a non-empty name without dots, one per body";
            return Err(SceneError::Range { key: "solid.name", value: format!("\"{name}\""), range });
        }
        let mut written = toml::Table::try_from(&t).map_err(|e| SceneError::Parse(e.to_string()))?;
        // A mesh file as its path from here (the resolved scene is written elsewhere).
        if let Some(file) = t.mesh.as_deref().filter(|f| *f != crate::mesh_file::ARRAY_MESH) {
            written.insert("mesh".into(), inputs.base.join(file).display().to_string().into());
        }
        let (b, lame, dim) = body(t, name.clone(), &inputs).map_err(|e| of_body(&name, e))?;
        match &material {
            None => material = Some((lame, dim, name.clone())),
            Some((first, first_dim, first_name)) => {
                if dim != *first_dim {
                    let e = SceneError::Range { key: "solid.dim", value: dim.to_string(), range: "the first body's" };
                    return Err(of_body(&name, e));
                }
                if lame != *first {
                    return Err(of_body(
                        &name,
                        SceneError::Parse(format!(
                            "solid.lame_lambda, solid.lame_mu, solid.density: the bodies share one material (body \"{first_name}\" has λ = {}, μ = {}, ρ = {})",
                            short(first.lambda),
                            short(first.mu),
                            short(first.density)
                        )),
                    ));
                }
            }
        }
        raw_bodies.push((name, written));
        bodies.push(b);
    }
    let Some((lame, dim, _)) = material else {
        return Err(SceneError::Range { key: "[[solid]]", value: "no table".into(), range: "one or more bodies" });
    };
    let obstacle = obstacle.map(|o| parse_obstacle(o, dim)).transpose()?;
    let pairs = pairs.unwrap_or_default();
    if pairs.is_empty() && obstacle.is_none() {
        let range = "at least one [[pair]] or an [obstacle] (several bodies meet through pairs)";
        return Err(SceneError::Range { key: "[[pair]]", value: "none".into(), range });
    }
    let mut specs: Vec<PairSpec> = Vec::with_capacity(pairs.len());
    for p in pairs {
        let name = required("pair.name", p.name, "a name for each [[pair]]")?;
        if name.is_empty() || name.contains('.') || specs.iter().any(|s| s.name == name) {
            let range = "a non-empty name without dots, one per pair";
            return Err(SceneError::Range { key: "pair.name", value: format!("\"{name}\""), range });
        }
        let two = |key: &'static str, v: Option<Vec<String>>, what: &'static str| -> Result<[String; 2], SceneError> {
            match v {
                Some(v) if v.len() == 2 => Ok([v[0].clone(), v[1].clone()]),
                Some(v) => Err(SceneError::Range { key, value: format!("{} entries", v.len()), range: what }),
                None => Err(SceneError::Range { key, value: "absent".into(), range: what }),
            }
        };
        let names = two("pair.bodies", p.bodies, "two [[solid]] names, the first body's then the second's")?;
        let groups = two("pair.groups", p.groups, "two facet groups, the first body's then the second's")?;
        let index = |n: &str| bodies.iter().position(|b| b.name == n);
        let (Some(a), Some(b)) = (index(&names[0]), index(&names[1])) else {
            let known = bodies.iter().map(|b| format!("\"{}\"", b.name)).collect::<Vec<_>>().join(", ");
            let value = format!("[\"{}\", \"{}\"]", names[0], names[1]);
            return Err(SceneError::Parse(format!("pair.bodies = {value}: the bodies are {known}")));
        };
        if a == b {
            let value = format!("[\"{}\", \"{}\"]", names[0], names[1]);
            return Err(SceneError::Range { key: "pair.bodies", value, range: "two different bodies" });
        }
        specs.push(PairSpec { name, bodies: [a, b], groups, law: p.contact });
    }
    // Without an obstacle, a body in no pair would meet nothing.
    let lonely = bodies.iter().enumerate().find(|(i, _)| !specs.iter().any(|p| p.bodies.contains(i)));
    if let (Some(lonely), None) = (lonely, &obstacle) {
        let range = "every body in a pair (or an [obstacle])";
        let e = SceneError::Range { key: "pair.bodies", value: "no pair".into(), range };
        return Err(of_body(&lonely.1.name, e));
    }
    let all = Bodies { bodies, pairs: specs, obstacle, written: Vec::new() };
    let joined = all.join().map_err(|e| SceneError::Geometry(Box::new(e)))?;
    check_contact_memory(joined.contact.nodes.len(), "pair.groups, obstacle.contact, or the bodies' meshes")?;
    let (mesh, kind, extent) = (Arc::clone(&joined.mesh), joined.mesh.kind, joined.mesh.extent);
    let first = &all.bodies[0];
    let initial = SolidInitial::Fields { displacement: first.displacement.clone(), velocity: first.velocity.clone() };
    let cache = Default::default();
    let source = MeshSource::Arrays(mesh);
    let spec = SolidSpec {
        dim,
        extent,
        cells_per_axis: [0; 3],
        cells: kind,
        lame,
        initial,
        source,
        support: Support::Bodies(Bodies { written: raw_bodies, ..all }),
        cache,
    };
    Ok(spec)
}

/// The tables of several bodies as written (each body's table as given, its name first), and
/// their pairs.
pub(super) fn raw_bodies(b: &Bodies) -> (RawSolids, (Option<RawObstacle>, Option<Vec<RawPair>>)) {
    let solids = b
        .written
        .iter()
        .map(|(name, t)| {
            let mut raw = RawSolid::deserialize(toml::Value::Table(t.clone())).expect("written from a RawSolid");
            raw.name = Some(name.clone());
            raw
        })
        .collect();
    let pairs = b
        .pairs
        .iter()
        .map(|p| RawPair {
            name: Some(p.name.clone()),
            bodies: Some(p.bodies.iter().map(|&i| b.bodies[i].name.clone()).collect()),
            groups: Some(p.groups.to_vec()),
            contact: None,
        })
        .collect();
    let obstacle = b.obstacle.as_ref().map(|o| raw_obstacle(o, b.dim()));
    (RawSolids::Many(solids), (obstacle, Some(pairs)))
}

/// The dotted columns of a scene of several bodies (None: one body), as its run reports them
/// (`crate::solid::report::dotted_columns`).
pub(super) fn dotted(spec: &SolidSpec) -> Option<Vec<Column>> {
    let b = spec.support.bodies()?;
    let pairs: Vec<String> = b.pairs.iter().map(|p| p.name.clone()).collect();
    let names: Vec<String> = b.bodies.iter().map(|b| b.name.clone()).collect();
    Some(crate::solid::report::dotted_columns(&pairs, &names, spec.dim))
}
