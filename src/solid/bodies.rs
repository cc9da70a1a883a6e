//! Several elastic bodies in one scene (issue 30): `[[solid]]` tables with names, `[[pair]]`
//! tables naming the facing facet groups ([`super::pair`] for the contact condition).
//!
//! The bodies are joined into one [`Mesh`]: their nodes and cells concatenated in the order of
//! the tables (body b's node v is node `node0[b] + v`), their groups kept with the body's name
//! and a dot before them (`striker.xmax`). Nothing couples the bodies but the pairs: the mass
//! and the stiffness are block diagonal before the pairs' change of variables. The mass
//! redistribution is each body's own: its contact layer is its cells holding a node of any of
//! its pairs' groups (first or second: both sides are redistributed), and its weights are
//! computed on its own mesh ([`crate::fem::layers::cell_weights_of`]: mod2/mod3 keep each
//! body's mass).
//!
//! An `[obstacle]` beside the pairs ([`Bodies::obstacle`]) meets every body with the nodes its
//! contact set selects on that body, as for one body (`super::body::contact`), but the pairs'
//! nodes (a pair node or a node of a facet a pair node faces: that node meets the other body).
//! Its nodes follow the pairs' in the contact set, each in its own frame (the obstacle's normal
//! there), and join their body's layer 0.

use super::body::BodyContact;
use super::pair::{PairContact, PairError, pair_contact};
use crate::expr::Expr;
use crate::fem::Mesh;
use crate::fem::layers::{LayerMassError, cell_weights_of};
use crate::mass::MassKind;
use crate::material::Lame;
use std::sync::Arc;
use thiserror::Error;

/// One body of a multi-body scene: its name, its mesh placed in the world (the box's
/// `offset` applied), what holds it and what loads it, its initial data.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedBody {
    pub name: String,
    pub mesh: Arc<Mesh>,
    /// The group whose nodes are fixed (None: free).
    pub clamped: Option<String>,
    /// Force per unit volume, one expression per component in x, y[, z], t.
    pub force: Vec<Expr>,
    /// Displacement and velocity, one expression per component in x, y[, z].
    pub displacement: Vec<Expr>,
    pub velocity: Vec<Expr>,
    pub lame: Lame,
}

/// A pair of facing facet groups: `bodies[0]`'s group `groups[0]` (its nodes carry the
/// condition) against `bodies[1]`'s `groups[1]`.
#[derive(Debug, Clone, PartialEq)]
pub struct PairSpec {
    pub name: String,
    pub bodies: [usize; 2],
    pub groups: [String; 2],
    /// The pair's own law, its `contact` table as written (None: the scene's `[contact]`), read
    /// with `[contact]` by the scene (one law for all pairs).
    pub law: Option<toml::Table>,
}

/// The bodies and pairs of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Bodies {
    pub bodies: Vec<NamedBody>,
    pub pairs: Vec<PairSpec>,
    /// A rigid obstacle beside the pairs (`[obstacle]`): every body meets it, with the nodes
    /// its contact set selects on that body ("auto": the facets facing it; a group: the
    /// bodies that have it), but the pairs' nodes (module docs).
    pub obstacle: Option<super::body::Obstacle>,
    /// Each body's name and its table as written (a scene's resolved file writes them back;
    /// empty for bodies built in code).
    pub written: Vec<(String, toml::Table)>,
}

#[derive(Debug, Clone, PartialEq, Error)]
pub enum BodiesError {
    #[error(
        "solid.mesh of body \"{body}\": {kind} cells, but body \"{first}\" has {first_kind}: the bodies of a scene share one cell kind"
    )]
    Kind { body: String, kind: &'static str, first: String, first_kind: &'static str },
    #[error("{key} = \"{group}\": body \"{body}\" has no group of this name (its groups: {known})")]
    NoGroup { key: &'static str, group: String, body: String, known: String },
    #[error(transparent)]
    Pair(#[from] PairError),
    #[error("[obstacle] against body \"{body}\": {source}")]
    Obstacle { body: String, source: super::body::BodyError },
    #[error(
        "obstacle.contact = \"{contact}\": no node of any body meets the obstacle (\"auto\": no boundary facet faces it; a group: no body has it; and nodes clamped or in a pair are not the obstacle's)"
    )]
    NoObstacleContact { contact: String },
}

/// The joined bodies: the one mesh, each body's first node and cell, the pairs' contact and
/// the contact set of the system (the pairs' first-group nodes, pair after pair).
#[derive(Debug, Clone, PartialEq)]
pub struct Joined {
    pub mesh: Arc<Mesh>,
    /// First node of each body, then the node count.
    pub node0: Vec<usize>,
    /// First cell of each body, then the cell count.
    pub cell0: Vec<usize>,
    pub pairs: Vec<PairContact>,
    /// Each pair's slots in the contact set.
    pub slots: Vec<std::ops::Range<usize>>,
    pub contact: BodyContact,
    /// Mask over the nodes: a node of a pair's group, either side (the layers' contact set).
    pub layer_contact: Vec<bool>,
}

impl Joined {
    /// The body of node `v`.
    pub fn body_of(&self, v: usize) -> usize {
        owner_body(&self.node0, v)
    }
}

/// The nodes of group `name` of a body's mesh, refused naming the key if missing.
fn group<'m>(body: &'m NamedBody, key: &'static str, name: &str) -> Result<&'m [usize], BodiesError> {
    body.mesh.groups.get(name).map(Vec::as_slice).ok_or_else(|| BodiesError::NoGroup {
        key,
        group: name.into(),
        body: body.name.clone(),
        known: body.mesh.groups.keys().map(|k| format!("\"{k}\"")).collect::<Vec<_>>().join(", "),
    })
}

impl Bodies {
    /// The dimension (every body's: checked when the tables are validated).
    pub fn dim(&self) -> usize {
        self.bodies[0].mesh.dim
    }

    /// Joins the bodies and builds the pairs' contact (module docs).
    pub fn join(&self) -> Result<Joined, BodiesError> {
        let first = &self.bodies[0];
        let (dim, kind) = (first.mesh.dim, first.mesh.kind);
        let (mut points, mut cells) = (Vec::new(), Vec::new());
        let (mut node0, mut cell0) = (vec![0], vec![0]);
        let mut groups = std::collections::BTreeMap::new();
        let mut clamped = Vec::new();
        for b in &self.bodies {
            if b.mesh.kind != kind {
                let (body, first) = (b.name.clone(), first.name.clone());
                return Err(BodiesError::Kind { body, kind: b.mesh.kind.name(), first, first_kind: kind.name() });
            }
            let base = points.len();
            points.extend_from_slice(&b.mesh.points);
            cells.extend(b.mesh.cells.iter().map(|&v| v + base));
            for (g, nodes) in &b.mesh.groups {
                groups.insert(format!("{}.{g}", b.name), nodes.iter().map(|&v| v + base).collect());
            }
            let mut mask = vec![false; b.mesh.n_nodes()];
            if let Some(name) = &b.clamped {
                group(b, "solid.clamped", name)?.iter().for_each(|&v| mask[v] = true);
            }
            clamped.extend(mask);
            node0.push(points.len());
            cell0.push(cells.len() / kind.verts());
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in &points {
            for a in 0..3 {
                (lo[a], hi[a]) = (lo[a].min(p[a]), hi[a].max(p[a]));
            }
        }
        let extent = [hi[0], hi[1] - lo[1], if dim == 3 { hi[2] - lo[2] } else { 0.0 }];
        let mesh = Mesh { dim, points, cells, kind, extent, grid: None, groups };
        let n = mesh.n_nodes();
        let mut pairs = Vec::with_capacity(self.pairs.len());
        let mut layer_contact = vec![false; n];
        let mut owner: Vec<Option<usize>> = vec![None; n];
        let mut master_of: Vec<Option<usize>> = vec![None; n];
        for (p_index, p) in self.pairs.iter().enumerate() {
            let nodes = |side: usize| -> Result<Vec<usize>, BodiesError> {
                let b = &self.bodies[p.bodies[side]];
                let base = node0[p.bodies[side]];
                Ok(group(b, "pair.groups", &p.groups[side])?.iter().map(|&v| v + base).collect())
            };
            let (a, b) = (nodes(0)?, nodes(1)?);
            let groups = [p.groups[0].as_str(), p.groups[1].as_str()];
            let contact = pair_contact(&mesh, &p.name, (&a, &b), groups, &clamped)?;
            for &v in a.iter().chain(&b) {
                layer_contact[v] = true;
            }
            let shared = |v: usize, other: usize| {
                let body = self.bodies[owner_body(&node0, v)].name.clone();
                let (first, second) = (self.pairs[other].name.clone(), p.name.clone());
                BodiesError::Pair(PairError::Shared { node: v, body, first, second })
            };
            for &v in &contact.nodes {
                if let Some(o) = owner[v].or(master_of[v]) {
                    return Err(shared(v, o));
                }
                owner[v] = Some(p_index);
            }
            for &(k, _) in contact.masters.iter().flatten() {
                if let Some(o) = owner[k] {
                    return Err(shared(k, o));
                }
                master_of[k] = Some(p_index);
            }
            pairs.push(contact);
        }
        let obstacle = self.obstacle_contact(&node0, |v| owner[v].is_some() || master_of[v].is_some())?;
        for &(v, ..) in &obstacle {
            layer_contact[v] = true;
        }
        let mut slots = Vec::new();
        let mut contact = BodyContact {
            nodes: Vec::new(),
            gaps: Vec::new(),
            areas: Vec::new(),
            normals: Vec::new(),
            clamped,
            contact: vec![false; n],
        };
        for p in &pairs {
            let start = contact.nodes.len();
            contact.nodes.extend_from_slice(&p.nodes);
            contact.gaps.extend_from_slice(&p.gaps);
            contact.areas.extend_from_slice(&p.areas);
            contact.normals.extend_from_slice(&p.normals);
            slots.push(start..contact.nodes.len());
        }
        for (v, g, a, n) in obstacle {
            contact.nodes.push(v);
            contact.gaps.push(g);
            contact.areas.push(a);
            contact.normals.push(n);
        }
        for &v in &contact.nodes {
            contact.contact[v] = true;
        }
        Ok(Joined { mesh: Arc::new(mesh), node0, cell0, pairs, slots, contact, layer_contact })
    }

    /// The obstacle's contact nodes on every body ([`Bodies::obstacle`]; none without one): per
    /// node (joined index, g_i, a_i, n_i), each body's nodes as one body's against the obstacle
    /// (`super::body::contact`), but those `in_pair`. A body with no node meeting the obstacle
    /// ("auto": no facet facing it; a group it does not have, or all clamped) takes no part;
    /// a body starting behind the obstacle is refused, named.
    #[allow(clippy::type_complexity)]
    fn obstacle_contact(
        &self,
        node0: &[usize],
        in_pair: impl Fn(usize) -> bool,
    ) -> Result<Vec<(usize, f64, f64, [f64; 3])>, BodiesError> {
        use super::body::{BodyError, BodySpec, ContactSet, contact};
        let Some(obstacle) = &self.obstacle else { return Ok(Vec::new()) };
        let mut out = Vec::new();
        for (b, body) in self.bodies.iter().enumerate() {
            let spec = BodySpec { obstacle: obstacle.clone(), clamped: body.clamped.clone(), force: Vec::new() };
            let c = match contact(&body.mesh, &spec) {
                Ok(c) => c,
                Err(BodyError::NoAutoContact | BodyError::NoGroup { .. } | BodyError::AllClamped { .. }) => continue,
                Err(source) => return Err(BodiesError::Obstacle { body: body.name.clone(), source }),
            };
            for k in 0..c.nodes.len() {
                let v = c.nodes[k] + node0[b];
                if !in_pair(v) {
                    out.push((v, c.gaps[k], c.areas[k], c.normals[k]));
                }
            }
        }
        if out.is_empty() {
            let contact = match &obstacle.contact {
                ContactSet::Auto => "auto".into(),
                ContactSet::Group(g) => g.clone(),
            };
            return Err(BodiesError::NoObstacleContact { contact });
        }
        Ok(out)
    }

    /// The cell weights of `mass`, each body's on its own mesh and contact layer (module docs),
    /// in the joined mesh's cell order.
    pub fn weights(&self, joined: &Joined, mass: &MassKind) -> Result<Vec<f64>, LayerMassError> {
        let mut w = Vec::with_capacity(joined.mesh.n_cells());
        for (b, body) in self.bodies.iter().enumerate() {
            let range = joined.node0[b]..joined.node0[b + 1];
            let contact = &joined.layer_contact[range.clone()];
            let clamped = &joined.contact.clamped[range];
            w.extend(cell_weights_of(&body.mesh, mass, contact, clamped)?);
        }
        Ok(w)
    }
}

fn owner_body(node0: &[usize], v: usize) -> usize {
    node0.partition_point(|&s| s <= v) - 1
}

/// The layout of several bodies' own columns (`super::report`'s module docs): the pairs' and the bodies' names,
/// each pair's contact slots, each body's first node (then the node count) and volume.
#[derive(Debug, Clone, PartialEq)]
pub struct BodiesLayout {
    pub pairs: Vec<String>,
    pub bodies: Vec<String>,
    pub slots: Vec<std::ops::Range<usize>>,
    pub node0: Vec<usize>,
    pub volumes: Vec<f64>,
    /// `super::report::COLUMNS`, then `super::report::dotted_columns`.
    pub columns: Vec<crate::column::Column>,
}
