//! GetFEM as a live peer (issue 19, item 6): GetFEM's disc of
//! `interface/tests/matlab-octave/demo_dynamic_contact.m` (radius 20 centred at (0, 20) on the
//! plane y = 0, λ = μ = 20, ρ = 1, force (0, −0.1) per unit volume, Newmark β = ¼, γ = ½,
//! Δt = 0.01) stepped by GetFEM itself (`python/crosscheck/getfem_disc.py`, Debian's python3-getfem 5.4:
//! its gmsh import, its assembly, its nodal contact with a rigid obstacle brick solved by Newton
//! with MUMPS) and by this crate from the scenes `scenes/body-getfem-*.toml`, P1 and P2, with
//! the standard mass and GetFEM's "singular mass" (no mass on the cells with a contact face,
//! posed here as `mass.kind = "custom"`).
//!
//! Checked per case: GetFEM's cells and nodes are ours (matched by coordinates, every one, both
//! ways), its contact nodes are ours, its singular-mass weights are the scene's (in our cell
//! order) and its massless nodes ours; then the displacement of every node at every step agrees
//! to [`TOL`] relative to the largest displacement of the run.
//!
//! The disc starts at rest on the plane (touching it at (0, 0)) and slides along it at 0.01:
//! the plane is frictionless and Newmark is exact on rigid translations, so the motion is the
//! disc settling under its weight plus 0.01 t along x. The sliding speed is there for the
//! divergence rule: at rest, E⁰ = 0 and its reference E_F is 0 for a free body (its solve with
//! the contact unknowns held is singular), so the first step would count as diverged.
//! The dropped disc is not a case: Crank–Nicolson with massive contact nodes (the standard mass,
//! and the vertices the singular mass leaves massive) chatters and gains energy on impact (×20
//! to ×35 by step 400 at speed 0.1 from a gap 0.05, in both codes), and differences grow
//! exponentially after impact. Measured on P1, standard mass: this crate against itself with
//! the plane moved by one ulp, 1e-15 at impact (step 50), 5e-9 at step 200, 2e-5 at 300, 8e-3
//! at 400; against GetFEM, 1.5e-13, 7e-7, 3e-3, 0.1.
//!
//! The initial acceleration matters: with the demo's MA⁰ = F − K U⁰ kept on the massless rows
//! (python/crosscheck/getfem_disc.py docs) GetFEM's P2 singular-mass run differs from this crate's by 1e-2
//! relative from step 13 on.

use massredist::fem::Mesh;
use massredist::mass::MassKind;
use massredist::observe::Frame;
use massredist::run::run_scene;
use massredist::scene::SolidScene;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "crosscheck_getfem_static.rs"]
mod static_cases;
pub use static_cases::{
    BLOCKS_SCENE, BLOCKS_TOL, BlockPeer, BlocksAgreement, BlocksPeer, FRICTION_SCENE, FRICTION_TOL, FrictionAgreement,
    FrictionPeer, OBSTACLE_CASES, OBSTACLE_TOL, ObstacleAgreement, ObstacleCase, ObstaclePeer, blocks_case,
    friction_case, obstacle_case,
};

/// The agreement required, relative to the largest displacement: both codes solve the same
/// discrete equations exactly (LCP here, Newton to residual 1e-9 on entries of size 1e3–1e4
/// there) except for the stiffness of curved P2 cells, a rational integrand that GetFEM's
/// IM_TRIANGLE(6) and our degree-5 Grundmann–Möller rule integrate differently (GetFEM's degree
/// 5 and 13 rules differ by 1.8e-7 relative); measured: 1e-11 on P1, 5e-8 on P2.
pub const TOL: f64 = 1e-6;

/// Debian's interpreter, which sees python3-getfem.
pub const PYTHON: &str = "/usr/bin/python3";

/// Relative length for matching coordinates (the disc has radius 20; gmsh writes 16 digits).
const SAME_POINT: f64 = 1e-9;

/// One case: a scene of `scenes/` and the mass GetFEM is asked for.
#[derive(Debug, Clone, Copy)]
pub struct GetfemCase {
    pub name: &'static str,
    pub scene: &'static str,
    /// `"standard"` or `"singular"` (python/crosscheck/getfem_disc.py `--mass`).
    pub mass: &'static str,
}

/// The shipped cases. P2 standard runs 200 steps: after about 250 its contact nodes chatter
/// (energy 6.3 → 18 by step 400, in both codes) and the difference grows to O(1).
pub const CASES: [GetfemCase; 4] = [
    GetfemCase { name: "disc P1 singular mass", scene: "body-getfem-disc-p1-singular.toml", mass: "singular" },
    GetfemCase { name: "disc P2 singular mass", scene: "body-getfem-disc-p2-singular.toml", mass: "singular" },
    GetfemCase { name: "disc P1 standard mass", scene: "body-getfem-disc-p1-standard.toml", mass: "standard" },
    GetfemCase { name: "disc P2 standard mass", scene: "body-getfem-disc-p2-standard.toml", mass: "standard" },
];

/// GetFEM's data, the demo's (python/crosscheck/getfem_disc.py arguments; the scenes hold the same).
const GETFEM_ARGS: [&str; 13] =
    ["--beta", "0.25", "--gamma", "0.5", "--velocity", "0.01", "0", "--point", "0", "0", "--force", "0", "-0.1"];

/// What python/crosscheck/getfem_disc.py writes (GetFEM's numbering).
#[derive(Debug, Clone, Deserialize)]
pub struct Peer {
    pub degree: usize,
    pub dt: f64,
    pub steps: usize,
    /// Per cell, the coordinates of its nodes.
    pub cells: Vec<Vec<[f64; 2]>>,
    pub weights: Vec<f64>,
    pub nodes: Vec<[f64; 2]>,
    pub contact_nodes: Vec<usize>,
    pub massless_nodes: Vec<usize>,
    pub newton_iterations: Vec<usize>,
    /// Per step: min distance, max multiplier, max |d λ|.
    pub complementarity: Vec<[f64; 3]>,
    /// Per step, `[u_x, u_y]` of every node.
    pub u: Vec<Vec<f64>>,
}

/// The agreement of one case.
#[derive(Debug, Clone, Serialize)]
pub struct Agreement {
    pub case: String,
    pub steps: usize,
    /// max over steps and nodes of |u − u_GetFEM| (components).
    pub max_abs_diff: f64,
    /// max over steps and nodes of |u_GetFEM|.
    pub scale: f64,
    pub relative: f64,
    /// The relative difference over the first 100, 200, … steps.
    pub relative_by_steps: Vec<(usize, f64)>,
    /// max |w − w_GetFEM| over cells (our order).
    pub weight_diff: f64,
    /// GetFEM's complementarity: min distance and max |d λ| over steps.
    pub getfem_min_distance: f64,
    pub getfem_max_product: f64,
}

/// The repository (scenes, python, fixtures).
pub fn repo() -> PathBuf {
    crate::repo::root()
}

/// Runs python/crosscheck/getfem_disc.py on `mesh` for `steps` steps of `dt`; its JSON goes to `json`.
pub fn getfem(mesh: &Path, mass: &str, dt: f64, steps: usize, json: &Path) -> Result<Peer, String> {
    let mut args: Vec<String> = ["--mass", mass, "--dt", &dt.to_string(), "--steps", &steps.to_string()]
        .iter()
        .map(|a| a.to_string())
        .collect();
    args.extend(GETFEM_ARGS.iter().map(|a| a.to_string()));
    run_script("getfem_disc.py", mesh, &args, json)
}

/// Runs `python/crosscheck/<script> --mesh <mesh> <args> --out <json>` with [`PYTHON`] and
/// reads the JSON it wrote (GetFEM's warnings left out of an error's stderr).
fn run_script<T: serde::de::DeserializeOwned>(
    script: &str,
    mesh: &Path,
    args: &[String],
    json: &Path,
) -> Result<T, String> {
    let script = repo().join("python/crosscheck").join(script);
    let o = Command::new(PYTHON)
        .arg(&script)
        .arg("--mesh")
        .arg(mesh)
        .args(args)
        .arg("--out")
        .arg(json)
        .output()
        .map_err(|e| format!("{PYTHON} {}: {e} (bash python/install-deps.sh installs GetFEM)", script.display()))?;
    if !o.status.success() {
        let err = String::from_utf8_lossy(&o.stderr);
        let tail: Vec<&str> = err.lines().filter(|l| !l.starts_with("Level 2 Warning")).collect();
        return Err(format!("{} {}: {}\n{}", PYTHON, script.display(), o.status, tail.join("\n")));
    }
    let text = std::fs::read_to_string(json).map_err(|e| format!("{}: {e}", json.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", json.display()))
}

/// For each of GetFEM's points, the index of the point of `ours` at the same place (within
/// [`SAME_POINT`] × `scale`); an error naming the first point with none or two.
fn matching(theirs: &[[f64; 2]], ours: &[[f64; 2]], scale: f64, what: &str) -> Result<Vec<usize>, String> {
    let tol = SAME_POINT * scale;
    let mut order: Vec<usize> = (0..ours.len()).collect();
    order.sort_by(|&a, &b| ours[a][0].total_cmp(&ours[b][0]));
    let mut taken = vec![false; ours.len()];
    let mut map = Vec::with_capacity(theirs.len());
    for (k, p) in theirs.iter().enumerate() {
        let lo = order.partition_point(|&i| ours[i][0] < p[0] - tol);
        let near: Vec<usize> = order[lo..]
            .iter()
            .copied()
            .take_while(|&i| ours[i][0] <= p[0] + tol)
            .filter(|&i| (ours[i][1] - p[1]).abs() <= tol)
            .collect();
        match near[..] {
            [i] if !taken[i] => {
                taken[i] = true;
                map.push(i);
            }
            _ => return Err(format!("GetFEM's {what} {k} at ({}, {}) matches {} of ours", p[0], p[1], near.len())),
        }
    }
    if map.len() != ours.len() {
        return Err(format!("GetFEM has {} {what}s, this crate {}", map.len(), ours.len()));
    }
    Ok(map)
}

fn xy(p: &[f64; 3]) -> [f64; 2] {
    [p[0], p[1]]
}

/// GetFEM's node k → our node, and GetFEM's cell c → our cell (cells matched by the mean of
/// their nodes, then checked node by node through the node map).
pub fn correspondence(mesh: &Mesh, peer: &Peer) -> Result<(Vec<usize>, Vec<usize>), String> {
    let scale = mesh.extent[0].max(mesh.extent[1]);
    let ours: Vec<[f64; 2]> = mesh.points.iter().map(xy).collect();
    let nodes = matching(&peer.nodes, &ours, scale, "node")?;
    let mean = |pts: &mut dyn Iterator<Item = [f64; 2]>| {
        let (mut s, mut n) = ([0.0, 0.0], 0.0);
        for p in pts {
            s = [s[0] + p[0], s[1] + p[1]];
            n += 1.0;
        }
        [s[0] / n, s[1] / n]
    };
    let our_cells: Vec<[f64; 2]> =
        (0..mesh.n_cells()).map(|c| mean(&mut mesh.cell(c).iter().map(|&v| ours[v]))).collect();
    let their_cells: Vec<[f64; 2]> = peer.cells.iter().map(|c| mean(&mut c.iter().copied())).collect();
    let cells = matching(&their_cells, &our_cells, scale, "cell")?;
    for (c, &oc) in cells.iter().enumerate() {
        let mut theirs: Vec<usize> =
            peer.cells[c].iter().map(|p| nearest(&ours, *p, scale)).collect::<Result<_, _>>()?;
        let mut mine = mesh.cell(oc).to_vec();
        theirs.sort_unstable();
        mine.sort_unstable();
        if theirs != mine {
            return Err(format!("GetFEM's cell {c} and our cell {oc} have the same centre but other nodes"));
        }
    }
    Ok((nodes, cells))
}

/// The one node of `ours` at `p`.
fn nearest(ours: &[[f64; 2]], p: [f64; 2], scale: f64) -> Result<usize, String> {
    let tol = SAME_POINT * scale;
    let found: Vec<usize> =
        (0..ours.len()).filter(|&i| (ours[i][0] - p[0]).abs() <= tol && (ours[i][1] - p[1]).abs() <= tol).collect();
    match found[..] {
        [i] => Ok(i),
        _ => Err(format!("a GetFEM cell node at ({}, {}) matches {} of ours", p[0], p[1], found.len())),
    }
}

/// GetFEM's cell weights in our cell order.
pub fn weights_in_our_order(peer: &Peer, cells: &[usize]) -> Vec<f64> {
    let mut w = vec![f64::NAN; cells.len()];
    for (c, &oc) in cells.iter().enumerate() {
        w[oc] = peer.weights[c];
    }
    w
}

/// The scene text of `case` with its mesh path made absolute (so that it parses from anywhere).
pub fn scene_text(case: &GetfemCase) -> Result<String, String> {
    let path = repo().join("scenes").join(case.scene);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let fixtures = repo().join("fixtures");
    Ok(text.replace("\"../fixtures/", &format!("\"{}/", fixtures.display())))
}

/// Runs `case` (its scene text edited by `edit`, for mutations) in this crate and in GetFEM
/// (JSON under `dir`), checks the correspondence and returns the agreement.
pub fn run_case(case: &GetfemCase, dir: &Path, edit: &dyn Fn(String) -> String) -> Result<Agreement, String> {
    let text = edit(scene_text(case)?);
    let mut scene = SolidScene::from_toml(&text).map_err(|e| format!("{}: {e}", case.scene))?;
    let mesh_path =
        scene.geometry.source.path().map(Path::to_path_buf).ok_or_else(|| format!("{}: no solid.mesh", case.scene))?;
    let json = dir.join(case.scene.replace(".toml", ".getfem.json"));
    let peer = getfem(&mesh_path, case.mass, scene.time.dt, scene.time.steps, &json)?;
    let mesh = scene.geometry.source.given().cloned().ok_or_else(|| format!("{}: no mesh", case.scene))?;
    let (nodes, cells) = correspondence(&mesh, &peer)?;
    let theirs = weights_in_our_order(&peer, &cells);
    let ours = match &scene.mass {
        MassKind::Custom(w) => w.clone(),
        MassKind::Standard => vec![1.0; mesh.n_cells()],
        other => return Err(format!("{}: mass.kind {} (standard or custom)", case.scene, other.name())),
    };
    let weight_diff = ours.iter().zip(&theirs).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    scene.output.vtu_every = Some(1);
    let run = run_scene(&scene, &mut []).map_err(|e| format!("{}: {e}", case.scene))?;
    if let Some(d) = &run.summary.divergence {
        return Err(format!("{}: diverged: {d:?}", case.scene));
    }
    check_sets(&run.problem.system, &peer, &nodes, &ours)?;
    let frames = run.frames.map(|f| f.frames).unwrap_or_default();
    compare(case.name, &frames, &peer, &nodes, weight_diff)
}

/// GetFEM's contact nodes are ours, and so are its massless nodes (those whose every cell has
/// weight 0 here).
fn check_sets(
    system: &massredist::solid::SolidSystem,
    peer: &Peer,
    nodes: &[usize],
    weights: &[f64],
) -> Result<(), String> {
    let mut theirs: Vec<usize> = peer.contact_nodes.iter().map(|&k| nodes[k]).collect();
    let mut ours = system.contact_nodes.clone();
    theirs.sort_unstable();
    ours.sort_unstable();
    if theirs != ours {
        return Err(format!("contact nodes: GetFEM {theirs:?}, this crate {ours:?}"));
    }
    let mesh = &system.mesh;
    let mut massive = vec![false; mesh.n_nodes()];
    for c in (0..mesh.n_cells()).filter(|&c| weights[c] > 0.0) {
        mesh.cell(c).iter().for_each(|&v| massive[v] = true);
    }
    let mut theirs: Vec<usize> = peer.massless_nodes.iter().map(|&k| nodes[k]).collect();
    let ours: Vec<usize> = (0..mesh.n_nodes()).filter(|&v| !massive[v]).collect();
    theirs.sort_unstable();
    if theirs != ours {
        return Err(format!("massless nodes: GetFEM {theirs:?}, this crate {ours:?}"));
    }
    Ok(())
}

/// The displacement of every node at every step against GetFEM's (`nodes`: GetFEM's node →
/// ours; frames every step, in world coordinates, [`massredist::observe::FrameRecorder`]).
pub fn compare(
    case: &str,
    frames: &[Frame],
    peer: &Peer,
    nodes: &[usize],
    weight_diff: f64,
) -> Result<Agreement, String> {
    if frames.len() != peer.u.len() {
        return Err(format!("{case}: {} frames here, {} GetFEM states", frames.len(), peer.u.len()));
    }
    let (mut scale, mut per_step) = (0.0_f64, Vec::with_capacity(frames.len()));
    for (f, g) in frames.iter().zip(&peer.u) {
        let mut worst = 0.0_f64;
        for (k, &v) in nodes.iter().enumerate() {
            for a in 0..2 {
                scale = scale.max(g[2 * k + a].abs());
                worst = worst.max((f.u[2 * v + a] - g[2 * k + a]).abs());
            }
        }
        per_step.push(worst);
    }
    let max_abs_diff = per_step.iter().copied().fold(0.0, f64::max);
    let upto = |n: usize| per_step[..=n.min(per_step.len() - 1)].iter().copied().fold(0.0, f64::max) / scale;
    let comp = &peer.complementarity;
    Ok(Agreement {
        case: case.to_string(),
        steps: frames.len() - 1,
        max_abs_diff,
        scale,
        relative: max_abs_diff / scale,
        relative_by_steps: (1..=frames.len() / 100).map(|k| (100 * k, upto(100 * k))).collect(),
        weight_diff,
        getfem_min_distance: comp.iter().map(|c| c[0]).fold(f64::INFINITY, f64::min),
        getfem_max_product: comp.iter().map(|c| c[2]).fold(0.0, f64::max),
    })
}

/// A static case's line of `massredist crosscheck`: the relative displacement difference `rel`
/// (None: the case could not run) in the |ΔU| column against `tolerance`, passing when it is
/// within it and the contact states (`same`) agree; no matrix is compared (NaN).
fn static_report(case: String, rel: Option<f64>, tolerance: f64, same: bool) -> super::CaseReport {
    super::CaseReport {
        backend: "getfem",
        dim: 2,
        physics: "elastic",
        case,
        mass_max_abs_diff: f64::NAN,
        stiffness_max_abs_diff: f64::NAN,
        trajectory_max_abs_diff: rel,
        lambda_max_abs_diff: None,
        mass_tolerance: f64::NAN,
        stiffness_tolerance: f64::NAN,
        trajectory_tolerance: Some(tolerance),
        pass: same && rel.is_some_and(|d| d <= tolerance),
    }
}

/// The cases of [`CASES`] as lines of `massredist crosscheck` (backend `getfem`): the |ΔM|
/// column holds max |w − w_GetFEM| over the cells (tolerance 0: the weights are 0 and 1), the
/// |ΔS| column is not compared (NaN), |ΔU| is the relative displacement difference
/// ([`Agreement::relative`], tolerance [`TOL`]). A case that cannot run fails, its error on
/// stderr.
pub fn case_reports() -> Vec<super::CaseReport> {
    // A folder per call: callers may run in parallel threads (tests); one GetFEM run at a time.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    static ONE: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let _one = ONE.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let dir = std::env::temp_dir().join(format!("massredist-crosscheck-getfem-{}-{call}", std::process::id()));
    let reports = CASES
        .iter()
        .map(|case| {
            let result =
                std::fs::create_dir_all(&dir).map_err(|e| e.to_string()).and_then(|()| run_case(case, &dir, &|t| t));
            let (weights, traj) = match result {
                Ok(a) => (a.weight_diff, Some(a.relative)),
                Err(e) => {
                    eprintln!("crosscheck: GetFEM case {}: {e}", case.name);
                    (f64::NAN, None)
                }
            };
            super::CaseReport {
                backend: "getfem",
                dim: 2,
                physics: "elastic",
                case: format!("{} (trajectory)", case.name),
                mass_max_abs_diff: weights,
                stiffness_max_abs_diff: f64::NAN,
                trajectory_max_abs_diff: traj,
                lambda_max_abs_diff: None,
                mass_tolerance: 0.0,
                stiffness_tolerance: f64::NAN,
                trajectory_tolerance: Some(TOL),
                pass: weights == 0.0 && traj.is_some_and(|d| d <= TOL),
            }
        })
        .collect();
    let mut reports: Vec<super::CaseReport> = reports;
    let friction = std::fs::create_dir_all(&dir).map_err(|e| e.to_string()).and_then(|()| friction_case(&dir, &|t| t));
    let (rel, same_states) = match friction {
        Ok(a) => (Some(a.relative), a.stick.0 == a.stick.1 && a.slip.0 == a.slip.1),
        Err(e) => {
            eprintln!("crosscheck: GetFEM friction case: {e}");
            (None, false)
        }
    };
    reports.push(static_report("disc P1 Coulomb friction (static)".into(), rel, FRICTION_TOL, same_states));
    for case in &OBSTACLE_CASES {
        let result =
            std::fs::create_dir_all(&dir).map_err(|e| e.to_string()).and_then(|()| obstacle_case(case, &dir, &|t| t));
        let (rel, tolerance, same) = match result {
            Ok(a) => (Some(a.relative), a.tolerance, a.active.0 == a.active.1),
            Err(e) => {
                eprintln!("crosscheck: GetFEM obstacle case {}: {e}", case.name);
                (None, OBSTACLE_TOL, false)
            }
        };
        reports.push(static_report(format!("{} (static)", case.name), rel, tolerance, same));
    }
    let blocks = std::fs::create_dir_all(&dir).map_err(|e| e.to_string()).and_then(|()| blocks_case(&dir, &|t| t));
    let (rel, same) = match blocks {
        Ok(a) => (Some(a.relative), a.active.0 == a.active.1),
        Err(e) => {
            eprintln!("crosscheck: GetFEM two-block case: {e}");
            (None, false)
        }
    };
    reports.push(static_report("two P1 blocks, matching interface (static)".into(), rel, BLOCKS_TOL, same));
    let _ = std::fs::remove_dir_all(&dir);
    reports
}
