//! Trajectory cross-checks of the FEniCSx engine against the Rust solver (issue 12): the same
//! scene stepped by `massredist run` and by `massredist run --engine fenicsx --ranks N`, compared
//! over every series column and every numeric summary value. Used by `massredist crosscheck`
//! (the trajectory cases below) and by tests/engine_live.rs (the same scenes and comparison).
//!
//! Both runs are processes of the `massredist` binary (the engine is one anyway): this module
//! writes scene files, starts them and reads their output folders, at the edge of the crate.

use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The agreement required between the engine and the Rust run, and between 1 and 2 ranks.
///
/// PETSc's active-set threshold in SNES `vinewtonrsls` (3.18, `SNESVIGetActiveSetIS`): a contact
/// value within 1e-8 of its bound may be set onto it, the solver's worst-case error on a contact
/// value in one step (python/engine/qp.py `VI_BOUND_TOL`; its residual tolerance, 1e-12 ‖r‖∞, is
/// far below). Over the ≤ 60 steps of these runs the schemes are stable (energy bounded, no
/// growth of perturbations beyond their sum), and u0, u_mean, λ (a contact row of K = M + σS
/// with massless contact: entries of S, O(1) here), the energy and the L² error are O(1)-Lipschitz
/// in the contact values: 60 × 1e-8 < 1e-6. (Measured agreement: 1e-15 … 2e-13.)
pub const TOL: f64 = 1e-6;

/// Summary keys whose values are not trajectory quantities: the wall time, the solver's own count
/// (Rust: principal pivots; engine: SNES iterations) and the step of the largest energy increase
/// (for energy-conserving runs the increases are round-off, so their arg-max is too).
pub const NOT_COMPARED: [&str; 3] = ["wall_seconds", "max_pivots", "energy_max_increase_step"];

/// An 8 × 4 plate, Δt = 0.05, T = 3: the paper's data hit the obstacle at t = 1 and leave it at
/// t = 2, so every run has steps before, during and after the impact.
pub fn plate_scene(cells: &str, initial: &str, scheme: &str, mass: &str) -> String {
    let l2 = if initial == "paper" { ", \"l2_error\"" } else { "" };
    format!(
        "[plate]\nlength = 1.0\nheight = 1.0\nnx = 8\nny = 4\ncells = \"{cells}\"\ninitial = \"{initial}\"\n\
         [mass]\nkind = \"{mass}\"\n[scheme]\nkind = \"{scheme}\"\n[time]\ndt = 0.05\nend = 3.0\n\
         [output]\nseries = [\"u0\", \"u_mean\", \"lambda\", \"contact_force\", \"energy\"{l2}]\n"
    )
}

/// A small solid (CONTRACT.md's `[solid]` table): 8 × 4 in 2D, 4 × 2 × 2 in 3D, Δt = 0.05,
/// T = 3; `extra` lines are added to `[solid]` (material, lateral, initial data, gap). With the
/// paper's data the face hits the obstacle at t = 1 and leaves it near t = 2.
pub fn solid_scene(dim: usize, cells: &str, scheme: &str, mass: &str, extra: &str) -> String {
    let size = if dim == 2 { "nx = 8\nny = 4\n" } else { "nx = 4\nny = 2\nnz = 2\n" };
    // The exact L² error: the paper's plane wave (no `extra`) on tensor cells only.
    let l2 = if matches!(cells, "quad" | "hex") && extra.is_empty() { ", \"l2_error\"" } else { "" };
    format!(
        "[solid]\ndim = {dim}\n{size}cells = \"{cells}\"\n{extra}\n\
         [mass]\nkind = \"{mass}\"\n[scheme]\nkind = \"{scheme}\"\n[time]\ndt = 0.05\nend = 3.0\n\
         [output]\nseries = [\"u0\", \"u_mean\", \"lambda\", \"contact_force\", \"energy\"{l2}]\n"
    )
}

/// The series of a body run (issue 19): the reports of src/observe.rs for bodies.
const BODY_SERIES: &str = "[output]\nseries = [\"u0\", \"u_mean\", \"lambda\", \"contact_force\", \"energy\", \
     \"active_nodes\", \"min_distance\", \"momentum_x\", \"momentum_y\", \"mean_u_x\", \"mean_u_y\"]\n";

/// A shipped body mesh (scenes/body-gmsh/), by absolute path: the scene files of these cases
/// are written elsewhere.
pub fn body_mesh(name: &str) -> String {
    crate::repo::root().join("scenes").join("body-gmsh").join(name).display().to_string()
}

/// The P1 disc of scenes/body-gmsh/disc.msh (radius 1, lowest point y = 0.05), free, λ = μ = 20,
/// mod3, Δt = 0.01, T = 0.5, against the plane through `point` with normal `normal` (2D
/// arrays), pulled towards it by `force` (two expressions): it hits the plane at t ≈ 0.32 for a
/// unit force along the normal, so every run has steps before and during the contact.
pub fn disc_scene(scheme: &str, normal: &str, point: &str, force: &str) -> String {
    format!(
        "[solid]\ndim = 2\nmesh = \"{}\"\nlame_lambda = 20.0\nlame_mu = 20.0\nforce = {force}\n\
         initial = {{ displacement = [\"0\", \"0\"], velocity = [\"0\", \"0\"] }}\n\
         [obstacle]\nnormal = {normal}\npoint = {point}\ncontact = \"auto\"\n[mass]\nkind = \"mod3\"\n\
         [scheme]\nkind = \"{scheme}\"\n[time]\ndt = 0.01\nend = 0.5\n{BODY_SERIES}",
        body_mesh("disc.msh")
    )
}

/// The Q1 block of scenes/body-gmsh/block.msh clamped on its group "top", its group "bottom"
/// 0.02 above y = 0 and moving down (scenes/body-gmsh/body-block-clamped-top.toml, T = 0.5).
pub fn clamped_block_scene(scheme: &str) -> String {
    format!(
        "[solid]\ndim = 2\nmesh = \"{}\"\nlame_lambda = 2.0\nlame_mu = 1.0\n\
         initial = {{ displacement = [\"0\", \"0\"], velocity = [\"0\", \"-0.5*(y-0.02)\"] }}\n\
         clamped = \"top\"\n[obstacle]\nnormal = [0.0, 1.0]\npoint = [0.0, 0.0]\ncontact = \"bottom\"\n\
         [mass]\nkind = \"mod3\"\n[scheme]\nkind = \"{scheme}\"\n[time]\ndt = 0.01\nend = 0.5\n{BODY_SERIES}",
        body_mesh("block.msh")
    )
}

/// A free P1 tetrahedral cube (3 × 3 × 3 × 6 cells, side 0.5) 0.05 above z = 0, moving down
/// and sideways under the force (0, 0, −2): it touches the plane at t ≈ 0.05.
pub fn tet_body_scene(scheme: &str) -> String {
    format!(
        "[solid]\ndim = 3\nlength = 0.5\nheight = 0.5\ndepth = 0.5\nnx = 3\nny = 3\nnz = 3\ncells = \"tet\"\n\
         lame_lambda = 1.0\nlame_mu = 1.0\nforce = [\"0\", \"0\", \"-2\"]\n\
         initial = {{ displacement = [\"0\", \"0\", \"0\"], velocity = [\"0.1\", \"0\", \"-1\"] }}\n\
         [obstacle]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.0, 0.0, -0.05]\ncontact = \"auto\"\n\
         [mass]\nkind = \"mod3\"\n[scheme]\nkind = \"{scheme}\"\n[time]\ndt = 0.01\nend = 0.3\n\
         [output]\nseries = [\"u0\", \"u_mean\", \"contact_force\", \"energy\", \"active_nodes\", \
         \"min_distance\", \"momentum_x\", \"momentum_z\", \"mean_u_x\", \"mean_u_z\"]\n"
    )
}

/// A P2 (triangle6) rectangle (0, 1) × (0.05, 0.55) as a gmsh 2.2 file: `nx × ny` squares, each
/// cut along its diagonal from (x_i, y_j) into two counter-clockwise triangles; the nodes are the
/// grid of half the spacing (every one a vertex or a midside node).
pub fn p2_rectangle_msh(nx: usize, ny: usize) -> String {
    let (cols, rows) = (2 * nx + 1, 2 * ny + 1);
    let id = |i: usize, j: usize| j * cols + i + 1;
    let mut s = format!("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{}\n", cols * rows);
    for j in 0..rows {
        for i in 0..cols {
            let (x, y) = (i as f64 / (2 * nx) as f64, 0.05 + 0.5 * j as f64 / (2 * ny) as f64);
            s += &format!("{} {x:?} {y:?} 0\n", id(i, j));
        }
    }
    s += &format!("$EndNodes\n$Elements\n{}\n", 2 * nx * ny);
    let mid = |a: (usize, usize), b: (usize, usize)| id((a.0 + b.0) / 2, (a.1 + b.1) / 2);
    let mut k = 0;
    for j in 0..ny {
        for i in 0..nx {
            let (p00, p10, p11, p01) = ((2 * i, 2 * j), (2 * i + 2, 2 * j), (2 * i + 2, 2 * j + 2), (2 * i, 2 * j + 2));
            for [a, b, c] in [[p00, p10, p11], [p00, p11, p01]] {
                k += 1;
                let (va, vb, vc) = (id(a.0, a.1), id(b.0, b.1), id(c.0, c.1));
                let (m0, m1, m2) = (mid(a, b), mid(b, c), mid(c, a));
                s += &format!("{k} 9 2 1 1 {va} {vb} {vc} {m0} {m1} {m2}\n");
            }
        }
    }
    s + "$EndElements\n"
}

/// A free P2 rectangle ([`p2_rectangle_msh`] as `rect6.msh` next to the scene), 0.05 above y = 0,
/// thrown down and sideways under gravity: it hits the plane at t ≈ 0.1.
pub fn p2_rectangle_scene(scheme: &str) -> String {
    format!(
        "[solid]\ndim = 2\nmesh = \"rect6.msh\"\nlame_lambda = 20.0\nlame_mu = 20.0\nforce = {DOWN}\n\
         initial = {{ displacement = [\"0\", \"0\"], velocity = [\"0.1\", \"-0.5\"] }}\n\
         [obstacle]\nnormal = [0.0, 1.0]\npoint = [0.0, 0.0]\ncontact = \"auto\"\n[mass]\nkind = \"mod3\"\n\
         [scheme]\nkind = \"{scheme}\"\n[time]\ndt = 0.01\nend = 0.5\n{BODY_SERIES}"
    )
}

/// Runs `massredist run SCENE --out OUT` (Rust, or the engine on `ranks`) with `bin`; `env`
/// is added to the process's environment. Returns OUT or the failure with its stderr.
pub fn run(
    bin: &Path,
    scene: &Path,
    out: &Path,
    ranks: Option<usize>,
    env: &[(&str, &str)],
) -> Result<PathBuf, String> {
    let mut cmd = Command::new(bin);
    cmd.arg("run").arg(scene).arg("--out").arg(out);
    if let Some(n) = ranks {
        cmd.args(["--engine", "fenicsx", "--ranks", &n.to_string()]);
    }
    // `massredist crosscheck` has MPI initialised in-process (mpi4py through the bridge), which
    // puts Open MPI's and PMIx's own variables into its environment; an mpirun started with them
    // fails or runs isolated singletons (measured: exit 1, or 141 s instead of 5 s). The child
    // gets a clean launcher environment (only the run-as-root permissions are kept).
    for (k, _) in std::env::vars_os() {
        let k = k.to_string_lossy();
        if (k.starts_with("OMPI_") && !k.starts_with("OMPI_ALLOW_RUN_AS_ROOT")) || k.starts_with("PMIX_") {
            cmd.env_remove(k.as_ref());
        }
    }
    cmd.envs(env.iter().copied());
    let o = cmd.output().map_err(|e| format!("{}: {e}", bin.display()))?;
    if !o.status.success() {
        return Err(format!("{cmd:?}: {}\n{}", o.status, String::from_utf8_lossy(&o.stderr)));
    }
    Ok(out.to_path_buf())
}

type Rows = Vec<BTreeMap<String, f64>>;

fn series(dir: &Path) -> Result<Rows, String> {
    let path = dir.join("series.csv");
    let mut r = csv::Reader::from_path(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let header: Vec<String> = r.headers().map_err(|e| e.to_string())?.iter().map(String::from).collect();
    r.records()
        .map(|rec| {
            let rec = rec.map_err(|e| e.to_string())?;
            let nums = rec.iter().map(|x| x.parse::<f64>().map_err(|e| format!("{}: {x}: {e}", path.display())));
            header.iter().cloned().zip(nums).map(|(k, v)| Ok((k, v?))).collect()
        })
        .collect()
}

/// A JSON file of a run folder as an object.
pub fn json(path: &Path) -> Result<serde_json::Map<String, serde_json::Value>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    match serde_json::from_str(&text) {
        Ok(serde_json::Value::Object(m)) => Ok(m),
        _ => Err(format!("{}: not a JSON object", path.display())),
    }
}

/// The largest difference between two run folders over every series column (but pivots) and
/// every numeric summary value (but [`NOT_COMPARED`]); an error if the columns, the rows, the
/// summary keys or a non-numeric summary value differ.
pub fn difference(a: &Path, b: &Path) -> Result<f64, String> {
    let (sa, sb) = (series(a)?, series(b)?);
    let (da, db) = (a.display(), b.display());
    if sa.len() != sb.len() {
        return Err(format!("{da} has {} rows, {db} {}", sa.len(), sb.len()));
    }
    let mut worst: f64 = 0.0;
    for (ra, rb) in sa.iter().zip(&sb) {
        if ra.keys().ne(rb.keys()) {
            return Err(format!("series columns differ: {:?} vs {:?}", ra.keys(), rb.keys()));
        }
        for (k, x) in ra.iter().filter(|(k, _)| k.as_str() != "pivots") {
            // NaN in both (no exact L² error on simplices) agrees.
            if !(x.is_nan() && rb[k].is_nan()) {
                worst = worst.max((x - rb[k]).abs());
            }
        }
    }
    let (ja, jb) = (json(&a.join("summary.json"))?, json(&b.join("summary.json"))?);
    if ja.keys().ne(jb.keys()) {
        let only: Vec<&String> =
            ja.keys().filter(|k| !jb.contains_key(*k)).chain(jb.keys().filter(|k| !ja.contains_key(*k))).collect();
        return Err(format!("summary.json keys differ: {only:?}"));
    }
    for (k, va) in ja.iter().filter(|(k, _)| !NOT_COMPARED.contains(&k.as_str())) {
        worst = worst.max(value_difference(k, va, &jb[k])?);
    }
    Ok(worst)
}

/// The largest difference of the numbers in two summary values (a number, an array or an object
/// of them such as `divergence`); an error naming `key` if anything else differs.
fn value_difference(key: &str, a: &serde_json::Value, b: &serde_json::Value) -> Result<f64, String> {
    use serde_json::Value;
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            Ok((x.as_f64().unwrap_or(f64::NAN) - y.as_f64().unwrap_or(f64::NAN)).abs())
        }
        // A body's vectors (final_momentum, final_mean_displacement), entry by entry.
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .try_fold(0.0_f64, |w, (i, (u, v))| Ok(w.max(value_difference(&format!("{key}[{i}]"), u, v)?))),
        (Value::Object(x), Value::Object(y)) if x.keys().eq(y.keys()) => {
            x.iter().try_fold(0.0_f64, |w, (k, v)| Ok(w.max(value_difference(&format!("{key}.{k}"), v, &y[k])?)))
        }
        _ if a == b => Ok(0.0),
        _ => Err(format!("summary.json {key}: {a} vs {b}")),
    }
}

/// One trajectory case of `massredist crosscheck`.
#[derive(Debug, Clone)]
pub struct TrajectoryCase {
    pub name: &'static str,
    pub scene: String,
    pub ranks: usize,
}

/// Plate and solid scenes stepped by both engines (one per geometry and cell kind, the engine
/// on 2 ranks).
pub fn cases() -> Vec<TrajectoryCase> {
    let case = |name, scene| TrajectoryCase { name, scene, ranks: 2 };
    vec![
        case("plate quad crank-nicolson mod3", plate_scene("quad", "paper", "crank-nicolson", "mod3")),
        case("plate triangle hybrid mod3 bump", plate_scene("triangle", "bump", "hybrid", "mod3")),
        case("solid 2D quad crank-nicolson mod3", solid_scene(2, "quad", "crank-nicolson", "mod3", "")),
        case("solid 2D triangle hybrid mod3 roller", solid_scene(2, "triangle", "hybrid", "mod3", ROLLER)),
        case("solid 3D hex backward-euler mod1", solid_scene(3, "hex", "backward-euler", "mod1", "")),
        case("solid 3D tet crank-nicolson mod2", solid_scene(3, "tet", "crank-nicolson", "mod2", "lame_lambda = 0.25")),
        case("body P1 disc drop crank-nicolson mod3", disc_scene("crank-nicolson", "[0.0, 1.0]", "[0.0, 0.0]", DOWN)),
        case("body P1 disc -e_x hybrid mod3", disc_scene("hybrid", "[-1.0, 0.0]", "[2.05, 0.0]", "[\"1\", \"0\"]")),
        case("body Q1 block clamped backward-euler", clamped_block_scene("backward-euler")),
        case("body 3D P1 tet crank-nicolson mod3", tet_body_scene("crank-nicolson")),
        case("body P2 rectangle crank-nicolson mod3", p2_rectangle_scene("crank-nicolson")),
    ]
}

/// Gravity along −y, per unit volume.
pub const DOWN: &str = "[\"0\", \"-1\"]";

/// A solid that is not a plane wave: λ > 0, roller lateral faces, data varying in y.
pub const ROLLER: &str = "lame_lambda = 0.3\nlateral = \"roller\"\n\
     initial = { displacement = [\"(1-x)/2*(1+0.3*y)\", \"0.05*x\"], velocity = [\"0\", \"0\"] }";

/// The result of one case.
#[derive(Debug, Clone, Serialize)]
pub struct TrajectoryReport {
    pub case: String,
    pub ranks: usize,
    /// Largest difference ([`difference`]); None when a run failed (`error`).
    pub max_abs_diff: Option<f64>,
    pub tolerance: f64,
    pub error: Option<String>,
    pub pass: bool,
}

/// Runs every case of [`cases`] with `bin` in fresh folders under `dir`.
pub fn run_all(bin: &Path, dir: &Path) -> Vec<TrajectoryReport> {
    cases()
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let scene = dir.join(format!("case{k}.toml"));
            // The P2 body's mesh file, next to the scene (p2_rectangle_scene).
            let mesh = std::fs::write(dir.join("rect6.msh"), p2_rectangle_msh(4, 2)).map_err(|e| e.to_string());
            let result =
                mesh.and_then(|()| std::fs::write(&scene, &c.scene).map_err(|e| e.to_string())).and_then(|()| {
                    let rust = run(bin, &scene, &dir.join(format!("case{k}-rust")), None, &[])?;
                    let eng = run(bin, &scene, &dir.join(format!("case{k}-fenicsx")), Some(c.ranks), &[])?;
                    difference(&rust, &eng)
                });
            let (max_abs_diff, error) = match result {
                Ok(d) => (Some(d), None),
                Err(e) => (None, Some(e)),
            };
            let pass = max_abs_diff.is_some_and(|d| d <= TOL);
            TrajectoryReport { case: c.name.to_string(), ranks: c.ranks, max_abs_diff, tolerance: TOL, error, pass }
        })
        .collect()
}

/// The one line reporting that the cases could not be set up (no folder for them).
pub fn failed_setup(dir: &Path, e: &std::io::Error) -> TrajectoryReport {
    let error = Some(format!("{}: {e}", dir.display()));
    TrajectoryReport {
        case: "trajectory cases".into(),
        ranks: 0,
        max_abs_diff: None,
        tolerance: TOL,
        error,
        pass: false,
    }
}

/// The report as a text table.
pub fn table(reports: &[TrajectoryReport]) -> String {
    let mut s = format!(
        "{:<40} {:>5} {:>12} {:>10}  pass\n",
        "trajectory (rust vs fenicsx engine)", "ranks", "max diff", "tol"
    );
    for r in reports {
        let d = r.max_abs_diff.map_or("failed".to_string(), |d| format!("{d:.3e}"));
        s += &format!(
            "{:<40} {:>5} {:>12} {:>10.1e}  {}\n",
            r.case,
            r.ranks,
            d,
            r.tolerance,
            if r.pass { "yes" } else { "NO" }
        );
        if let Some(e) = &r.error {
            let lines: Vec<&str> = e.lines().filter(|l| !l.starts_with("INFO:")).collect();
            lines[lines.len().saturating_sub(6)..].iter().for_each(|l| s += &format!("    {l}\n"));
        }
    }
    s
}
