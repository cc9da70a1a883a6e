//! GetFEM's static cases (issues 29 and 30): the frictional disc, the curved obstacles and the
//! two blocks, each one backward-Euler step from rest here against GetFEM's Newton solve, compared
//! node by node (displacements, reactions, contact states).

use super::{GetfemCase, matching, run_script, scene_text, xy};
use massredist::fem::Mesh;
use massredist::run::run_scene;
use massredist::scene::SolidScene;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// GetFEM's node k → our node, and max over nodes of |u − u_GetFEM| (components) over
/// max |u_GetFEM| (`u` ours at the mesh nodes, interleaved x, y).
fn static_difference(
    mesh: &Mesh,
    nodes: &[[f64; 2]],
    theirs: &[[f64; 2]],
    u: &[f64],
) -> Result<(Vec<usize>, f64), String> {
    let scale = mesh.extent[0].max(mesh.extent[1]);
    let ours: Vec<[f64; 2]> = mesh.points.iter().map(xy).collect();
    let map = matching(nodes, &ours, scale, "node")?;
    let (mut worst, mut u_scale) = (0.0_f64, 0.0_f64);
    for (k, &v) in map.iter().enumerate() {
        for a in 0..2 {
            u_scale = u_scale.max(theirs[k][a].abs());
            worst = worst.max((u[2 * v + a] - theirs[k][a]).abs());
        }
    }
    Ok((map, worst / u_scale))
}

/// Friction (issue 29, check 5): the scene of the static frictional disc, and the agreement
/// required of it, relative to the largest displacement. Both codes solve the same equations
/// (one backward-Euler step from rest, Δt = 1e6: python/crosscheck/getfem_friction.py docs),
/// this crate exactly, GetFEM by Newton to a residual of 1e-12; measured 4.9e-14.
pub const FRICTION_SCENE: &str = "body-getfem-disc-p1-friction.toml";
pub const FRICTION_TOL: f64 = 1e-8;

/// What python/crosscheck/getfem_friction.py writes (GetFEM's numbering).
#[derive(Debug, Clone, Deserialize)]
pub struct FrictionPeer {
    pub cells: Vec<Vec<[f64; 2]>>,
    pub nodes: Vec<[f64; 2]>,
    /// `[u_x, u_y]` per node.
    pub u: Vec<[f64; 2]>,
    pub contact_nodes: Vec<usize>,
    /// GetFEM's multipliers per contact node: λ_n ≤ 0 in contact, λ_t the tangential force.
    pub lambda_n: Vec<f64>,
    pub lambda_t: Vec<f64>,
    pub newton_iterations: Vec<usize>,
}

/// The agreement of the static frictional disc.
#[derive(Debug, Clone, Serialize)]
pub struct FrictionAgreement {
    /// max over nodes of |u − u_GetFEM| (components) over max |u_GetFEM|.
    pub relative: f64,
    /// max over contact nodes of |R_i − (−λ_n,i)| and ||r_t,i| − |λ_t,i|| over max R_i.
    pub force_relative: f64,
    /// The contact nodes (ours) that stick and slide, here and in GetFEM (GetFEM's: λ_n < 0,
    /// sliding where |λ_t| ≥ μ |λ_n| (1 − 1e-9)).
    pub stick: (Vec<usize>, Vec<usize>),
    pub slip: (Vec<usize>, Vec<usize>),
    pub newton_iterations: Vec<usize>,
}

/// Runs the static frictional disc here (the scene edited by `edit`, for mutations) and in
/// GetFEM (JSON under `dir`) and compares them node by node.
pub fn friction_case(dir: &Path, edit: &dyn Fn(String) -> String) -> Result<FrictionAgreement, String> {
    let case = GetfemCase { name: "disc P1 friction (static)", scene: FRICTION_SCENE, mass: "standard" };
    let scene = SolidScene::from_toml(&edit(scene_text(&case)?)).map_err(|e| format!("{FRICTION_SCENE}: {e}"))?;
    let mesh_path = scene
        .geometry
        .source
        .path()
        .map(Path::to_path_buf)
        .ok_or_else(|| format!("{FRICTION_SCENE}: no solid.mesh"))?;
    let mesh = scene.geometry.source.given().cloned().ok_or_else(|| format!("{FRICTION_SCENE}: no mesh"))?;
    let mu = match scene.contact.friction() {
        Some(massredist::contact::law::Friction::Coulomb { mu }) => mu,
        other => return Err(format!("{FRICTION_SCENE}: Coulomb friction expected, {other:?}")),
    };
    // GetFEM is given the data of the unedited scene: a mutation is on this crate's side only.
    let json = dir.join("friction.getfem.json");
    let args: Vec<String> = ["--force", "0.02", "-0.1", "--mu", "0.3", "--dt", "1e6", "--max-res", "1e-12"]
        .iter()
        .map(|a| a.to_string())
        .collect();
    let peer: FrictionPeer = run_script("getfem_friction.py", &mesh_path, &args, &json)?;
    let run = run_scene(&scene, &mut []).map_err(|e| format!("{FRICTION_SCENE}: {e}"))?;
    let (nodes, relative) = static_difference(&mesh, &peer.nodes, &peer.u, &run.last.u)?;
    let system = &run.problem.system;
    let record = run.last.friction.as_ref().ok_or("no friction record")?;
    let slot_of = |v: usize| system.contact_nodes.iter().position(|&c| c == v);
    let (mut stick, mut slip) = ((Vec::new(), Vec::new()), (Vec::new(), Vec::new()));
    let (mut force_diff, mut force_scale) = (0.0_f64, 0.0_f64);
    for (k, &c) in peer.contact_nodes.iter().enumerate() {
        let v = nodes[c];
        let i = slot_of(v).ok_or_else(|| format!("GetFEM's contact node {c} (our {v}) is not ours"))?;
        let (r, rt) = (-run.last.lambda[i], record.traction[i][0] * system.contact_areas[i]);
        let (ln, lt) = (peer.lambda_n[k], peer.lambda_t[k]);
        force_scale = force_scale.max(r.abs()).max(ln.abs());
        force_diff = force_diff.max((r + ln).abs()).max((rt.abs() - lt.abs()).abs());
        match record.state[i] {
            1 => stick.0.push(v),
            2 => slip.0.push(v),
            _ => {}
        }
        if ln < 0.0 {
            if lt.abs() >= mu * ln.abs() * (1.0 - 1e-9) { slip.1.push(v) } else { stick.1.push(v) }
        }
    }
    for list in [&mut stick.0, &mut stick.1, &mut slip.0, &mut slip.1] {
        list.sort_unstable();
    }
    Ok(FrictionAgreement {
        relative,
        force_relative: force_diff / force_scale,
        stick,
        slip,
        newton_iterations: peer.newton_iterations,
    })
}

/// The reactions of a static case, node by node: the pressing nodes on each side (ours R_i > 0,
/// GetFEM's λ_n < 0), and the largest |R_i − (−λ_n,i)| against the largest of both.
#[derive(Default)]
struct Tally {
    active: (Vec<usize>, Vec<usize>),
    diff: f64,
    scale: f64,
}

impl Tally {
    /// Node `v`: our reaction `r` (≥ 0 in contact), GetFEM's multiplier `ln` (≤ 0 in contact).
    fn add(&mut self, v: usize, r: f64, ln: f64) {
        self.scale = self.scale.max(r.abs()).max(ln.abs());
        self.diff = self.diff.max((r + ln).abs());
        if r > 0.0 {
            self.active.0.push(v);
        }
        if ln < 0.0 {
            self.active.1.push(v);
        }
    }

    /// The pressing nodes sorted, and the relative difference of the reactions.
    fn finish(mut self) -> ((Vec<usize>, Vec<usize>), f64) {
        self.active.0.sort_unstable();
        self.active.1.sort_unstable();
        (self.active, self.diff / self.scale)
    }
}

/// Curved obstacles (issue 30, check 3): the half disc clamped on top and pressed by a body force
/// into a rigid obstacle, a scene and GetFEM's form of its signed distance (its weak-form
/// language: `sqr`, no `^`). Both codes solve the static problem (one backward-Euler step from
/// rest, Δt = 1e6, here; GetFEM's Newton to a residual of 1e-12), GetFEM with its nodal contact
/// with a rigid obstacle brick (python/crosscheck/getfem_obstacle.py).
pub struct ObstacleCase {
    pub name: &'static str,
    pub scene: &'static str,
    pub getfem: &'static str,
}

/// The V-shaped trough (a piecewise-affine level set: GetFEM's forward-difference normal is
/// exact at the nodes that press) and the circular cavity (GetFEM's normal off by the forward
/// difference's error, measured by the script).
pub const OBSTACLE_CASES: [ObstacleCase; 2] = [
    ObstacleCase {
        name: "half disc P2 in a V trough (level set)",
        scene: "body-getfem-half-disc-vee.toml",
        getfem: "(y-0.5*abs(x)+2.360679774997897)/sqrt(1.25)",
    },
    ObstacleCase {
        name: "half disc P2 in a circular cavity",
        scene: "body-getfem-half-disc-cavity.toml",
        getfem: "22-sqrt(sqr(x)+sqr(y-22))",
    },
];

/// The agreement required of a curved obstacle, relative to the largest displacement: 1e-8 where
/// GetFEM's normals are exact (the trough; measured 8.7e-9, the size of the curved P2 cells'
/// quadrature, integrated exactly by neither code: GetFEM's answer moves by 3.4e-9 between its
/// degree-6 and degree-5 rules); where they are a forward difference (the cavity), ten times
/// the largest error of its normals at the nodes that press (a normal off by δ moves the
/// constraint, and so the solution, by about δ relative; measured 1.4e-4 against 4.5e-5).
pub const OBSTACLE_TOL: f64 = 1e-8;

/// What python/crosscheck/getfem_obstacle.py writes (GetFEM's numbering).
#[derive(Debug, Clone, Deserialize)]
pub struct ObstaclePeer {
    pub nodes: Vec<[f64; 2]>,
    /// `[u_x, u_y]` per node.
    pub u: Vec<[f64; 2]>,
    pub contact_nodes: Vec<usize>,
    /// GetFEM's multipliers per contact node: λ_n ≤ 0 in contact.
    pub lambda_n: Vec<f64>,
    pub newton_iterations: usize,
    /// The largest error of GetFEM's forward-difference normals at the nodes that press.
    pub normal_deviation: f64,
}

/// The agreement of a curved obstacle.
#[derive(Debug, Clone, Serialize)]
pub struct ObstacleAgreement {
    /// max over nodes of |u − u_GetFEM| (components) over max |u_GetFEM|.
    pub relative: f64,
    /// max over contact nodes of |R_i − (−λ_n,i)| over max R_i.
    pub force_relative: f64,
    /// The tolerance of `relative`: [`OBSTACLE_TOL`], or ten times GetFEM's normal error.
    pub tolerance: f64,
    /// Our pressing contact nodes (R_i > 0) and GetFEM's (λ_n < 0), our numbering, sorted.
    pub active: (Vec<usize>, Vec<usize>),
    pub newton_iterations: usize,
    pub normal_deviation: f64,
}

/// Runs a curved-obstacle case here (the scene edited by `edit`, for mutations) and in GetFEM
/// (JSON under `dir`) and compares them node by node.
pub fn obstacle_case(
    case: &ObstacleCase,
    dir: &Path,
    edit: &dyn Fn(String) -> String,
) -> Result<ObstacleAgreement, String> {
    let getfem_case = GetfemCase { name: case.name, scene: case.scene, mass: "standard" };
    let scene = SolidScene::from_toml(&edit(scene_text(&getfem_case)?)).map_err(|e| format!("{}: {e}", case.scene))?;
    let mesh_path =
        scene.geometry.source.path().map(Path::to_path_buf).ok_or_else(|| format!("{}: no solid.mesh", case.scene))?;
    let mesh = scene.geometry.source.given().cloned().ok_or_else(|| format!("{}: no mesh", case.scene))?;
    let json = dir.join(case.scene.replace(".toml", ".getfem.json"));
    let args: Vec<String> = vec![
        "--obstacle".into(),
        case.getfem.into(),
        "--force".into(),
        "0".into(),
        "-0.05".into(),
        "--max-res".into(),
        "1e-12".into(),
    ];
    let peer: ObstaclePeer = run_script("getfem_obstacle.py", &mesh_path, &args, &json)?;
    let run = run_scene(&scene, &mut []).map_err(|e| format!("{}: {e}", case.scene))?;
    let (nodes, relative) = static_difference(&mesh, &peer.nodes, &peer.u, &run.last.u)?;
    let system = &run.problem.system;
    let slot_of = |v: usize| system.contact_nodes.iter().position(|&c| c == v);
    let mut tally = Tally::default();
    // The arc's two end nodes are clamped too: this crate takes them out of the contact set,
    // GetFEM keeps them there, fixed (they must carry no force in GetFEM).
    let clamped = &scene.geometry.built().map_err(|e| e.to_string())?.contact.clamped;
    let mut ours_seen = 0;
    for (k, &c) in peer.contact_nodes.iter().enumerate() {
        let v = nodes[c];
        if clamped[v] {
            if peer.lambda_n[k] != 0.0 {
                return Err(format!("GetFEM's clamped contact node {c} (our {v}) carries λ_n = {}", peer.lambda_n[k]));
            }
            continue;
        }
        ours_seen += 1;
        let i = slot_of(v).ok_or_else(|| format!("GetFEM's contact node {c} (our {v}) is not ours"))?;
        tally.add(v, -run.last.lambda[i], peer.lambda_n[k]);
    }
    if ours_seen != system.contact_nodes.len() {
        return Err(format!(
            "GetFEM has {ours_seen} unclamped contact nodes, this crate {}",
            system.contact_nodes.len()
        ));
    }
    let (active, force_relative) = tally.finish();
    Ok(ObstacleAgreement {
        relative,
        force_relative,
        tolerance: OBSTACLE_TOL.max(10.0 * peer.normal_deviation),
        active,
        newton_iterations: peer.newton_iterations,
        normal_deviation: peer.normal_deviation,
    })
}

/// Two bodies (issue 30, check 3): two P1 blocks on a matching interface, the upper one clamped
/// on its top and pushed by a body force onto the lower one, clamped on its bottom; both codes
/// solve the static problem (one backward-Euler step from rest, Δt = 1e6, here; GetFEM's Newton
/// to a residual of 1e-12), GetFEM with its nodal contact between non-matching meshes brick
/// (python/crosscheck/getfem_blocks.py), given this crate's triangles (each body its own GetFEM
/// mesh; GetFEM finds the clamped and contact sides itself).
pub const BLOCKS_SCENE: &str = "body-getfem-two-blocks.toml";

/// The upper block's volume force, the scene's `force` (GetFEM is given it as numbers).
const BLOCKS_FORCE: [&str; 2] = ["0.5", "-1"];

/// The agreement required of the two blocks, relative to the largest displacement: both codes
/// solve the same discrete equations (P1 stiffness integrated exactly by both), this crate
/// exactly, GetFEM by Newton to a residual of 1e-12 (measured 3.2e-14, the reactions 1.8e-14).
pub const BLOCKS_TOL: f64 = 1e-8;

/// What python/crosscheck/getfem_blocks.py writes (per body, GetFEM's numbering).
#[derive(Debug, Clone, Deserialize)]
pub struct BlocksPeer {
    pub bodies: Vec<BlockPeer>,
    /// The upper body's slave nodes (its GetFEM numbering) and their multipliers (λ_n ≤ 0 in
    /// contact).
    pub slave_nodes: Vec<usize>,
    pub lambda_n: Vec<f64>,
    pub newton_iterations: usize,
}

#[derive(Debug, Clone, Deserialize)]
pub struct BlockPeer {
    pub name: String,
    pub nodes: Vec<[f64; 2]>,
    pub u: Vec<[f64; 2]>,
}

/// The agreement of the two blocks.
#[derive(Debug, Clone, Serialize)]
pub struct BlocksAgreement {
    /// max over both bodies' nodes of |u − u_GetFEM| (components) over max |u_GetFEM|.
    pub relative: f64,
    /// max over the pair's nodes of |R_i − (−λ_n,i)| over max R_i.
    pub force_relative: f64,
    /// Our pressing pair nodes (R_i > 0) and GetFEM's (λ_n < 0), our numbering, sorted.
    pub active: (Vec<usize>, Vec<usize>),
    pub newton_iterations: usize,
}

/// Runs the two blocks here (the scene edited by `edit`, for mutations) and in GetFEM (JSON
/// under `dir`) and compares them node by node, body by body.
pub fn blocks_case(dir: &Path, edit: &dyn Fn(String) -> String) -> Result<BlocksAgreement, String> {
    let case = GetfemCase { name: "two blocks", scene: BLOCKS_SCENE, mass: "standard" };
    let scene = SolidScene::from_toml(&edit(scene_text(&case)?)).map_err(|e| format!("{BLOCKS_SCENE}: {e}"))?;
    let built = scene.geometry.built().map_err(|e| e.to_string())?;
    let (bodies, joined) = built.joined.as_ref().ok_or_else(|| format!("{BLOCKS_SCENE}: not two bodies"))?;
    if bodies.bodies.len() != 2 || bodies.pairs.len() != 1 || bodies.pairs[0].bodies != [0, 1] {
        return Err(format!("{BLOCKS_SCENE}: two bodies and one pair, the first body's nodes its slaves"));
    }
    let mesh_json = dir.join("two-blocks.mesh.json");
    let written: Vec<serde_json::Value> = bodies
        .bodies
        .iter()
        .map(|b| {
            let points: Vec<[f64; 2]> = b.mesh.points.iter().map(xy).collect();
            let cells: Vec<&[usize]> = (0..b.mesh.n_cells()).map(|c| b.mesh.cell(c)).collect();
            serde_json::json!({ "name": b.name, "points": points, "cells": cells })
        })
        .collect();
    std::fs::write(&mesh_json, serde_json::json!({ "bodies": written }).to_string())
        .map_err(|e| format!("{}: {e}", mesh_json.display()))?;
    let json = dir.join("two-blocks.getfem.json");
    let mut args: Vec<String> = vec!["--force".into()];
    args.extend(BLOCKS_FORCE.iter().map(|s| s.to_string()));
    args.extend(["--max-res".into(), "1e-12".into()]);
    let peer: BlocksPeer = run_script("getfem_blocks.py", &mesh_json, &args, &json)?;
    let run = run_scene(&scene, &mut []).map_err(|e| format!("{BLOCKS_SCENE}: {e}"))?;
    let (mut worst, mut u_scale, mut maps) = (0.0_f64, 0.0_f64, Vec::new());
    for (b, (body, theirs)) in bodies.bodies.iter().zip(&peer.bodies).enumerate() {
        if body.name != theirs.name {
            return Err(format!("GetFEM's body {b} is \"{}\", ours \"{}\"", theirs.name, body.name));
        }
        let ours: Vec<[f64; 2]> = body.mesh.points.iter().map(xy).collect();
        let map = matching(&theirs.nodes, &ours, body.mesh.extent[0].max(body.mesh.extent[1]), "node")?;
        for (k, &v) in map.iter().enumerate() {
            for a in 0..2 {
                u_scale = u_scale.max(theirs.u[k][a].abs());
                worst = worst.max((run.last.u[2 * (joined.node0[b] + v) + a] - theirs.u[k][a]).abs());
            }
        }
        maps.push(map);
    }
    let contact = &run.problem.system.contact_nodes;
    if peer.slave_nodes.len() != contact.len() || peer.lambda_n.len() != contact.len() {
        return Err(format!(
            "GetFEM has {} slave nodes and {} multipliers, this crate {} pair nodes",
            peer.slave_nodes.len(),
            peer.lambda_n.len(),
            contact.len()
        ));
    }
    let mut tally = Tally::default();
    for (&k, &ln) in peer.slave_nodes.iter().zip(&peer.lambda_n) {
        let v = joined.node0[0] + maps[0][k];
        let i = contact
            .iter()
            .position(|&c| c == v)
            .ok_or_else(|| format!("GetFEM's slave node {k} (our {v}) is not ours"))?;
        tally.add(v, -run.last.lambda[i], ln);
    }
    let (active, force_relative) = tally.finish();
    Ok(BlocksAgreement { relative: worst / u_scale, force_relative, active, newton_iterations: peer.newton_iterations })
}
