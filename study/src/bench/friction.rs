//! `massredist bench --friction CSV`: the cost of a frictional step against the frictionless
//! one (issue 29), implicit and explicit, on the shipped disc and sphere scenes, written as the
//! table CSV and CSV's `.md` beside it.
//!
//! Cases (the shipped meshes and material; each scene's data changed only as listed):
//! - the P2 disc of `scenes/body-getfem-disc-p2-standard.toml` (2D, falling with the tangential
//!   velocity 0.01 onto the plane under the body force (0, −0.1)), t ∈ (0, 2);
//! - the P2 sphere of `scenes/body-sphere-drop.toml` (3D), given the tangential velocity 0.5
//!   beside its normal −1, t ∈ (0, 6): it lands at t = 0.52 and slides.
//!
//! - the explicit cube of `bench --explicit-scaling` (issue 29's bound): N³ Q1 hexahedra, N = 69
//!   (1 030 000 unknowns), the standard mass (the forward increment on every contact node,
//!   `src/contact/friction/massive.rs` with friction), pushed onto the plane x = 0 at velocity
//!   (−1, 0.5, 0) so that every contact node carries force and slides; central differences only,
//!   at 0.9 Δt_c for [`CUBE_STEPS`] steps.
//!
//! The disc and sphere with mod3 (`contact_directions = "all"`: the massless layer's frictional
//! problem) under Crank–Nicolson at the scene's Δt and under central differences at the largest
//! Δt dividing the end that is at most both 0.9 Δt_c and the scene's Δt (Δt_c from a one-step
//! probe of the same scene; the estimator is in the table), each once
//! frictionless and once with Coulomb friction μ = 0.1, one after the other in this process.
//! Per run: the wall time of each step (between consecutive observer calls); the table gives
//! the mean over the steps with contact (some node carrying force: the steps where the friction
//! law has work) and over all steps, the largest sweep count of a step, and the frictional
//! run's ratio to the frictionless one's. An edge: it times and writes.

use crate::paper::methods::{SAFETY, step_dividing};
use massredist::driver::{Observer, Sample};
use massredist::run::run_scene;
use massredist::scene::SolidScene;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Coulomb's coefficient of every frictional run (GetFEM's `dynamic_friction` disc used 0.1).
const MU: f64 = 0.1;

/// One case: a shipped scene and the changes to its data, or the explicit cube.
struct Case {
    name: &'static str,
    scene: Source,
    /// The initial velocity, if changed.
    velocity: Option<&'static [&'static str]>,
    /// The end (the cube: ignored, [`CUBE_STEPS`] steps at 0.9 Δt_c).
    end: f64,
}

/// Where a case's scene comes from.
enum Source {
    /// A shipped scene file (mod3).
    File(&'static str),
    /// The N³ box of `bench --explicit-scaling` (the standard mass, central differences only).
    Cube(usize),
}

/// The cube's side in cells (N³ Q1 hexahedra: 3 · 70² · 70 ≈ 1.03 · 10⁶ unknowns).
pub const CUBE_CELLS: usize = 69;
/// The cube's steps per run.
pub const CUBE_STEPS: usize = 60;

const CASES: [Case; 3] = [
    Case {
        name: "disc P2 (2D)",
        scene: Source::File("scenes/body-getfem-disc-p2-standard.toml"),
        velocity: None,
        end: 2.0,
    },
    Case {
        name: "sphere P2 (3D)",
        scene: Source::File("scenes/body-sphere-drop.toml"),
        velocity: Some(&["0.5", "0", "-1"]),
        end: 6.0,
    },
    Case { name: "explicit cube (3D)", scene: Source::Cube(CUBE_CELLS), velocity: Some(&["-1", "0.5", "0"]), end: 0.0 },
];

/// One measured run.
#[derive(Debug, Clone)]
pub struct Row {
    pub case: &'static str,
    pub scheme: &'static str,
    pub law: &'static str,
    pub unknowns: usize,
    pub steps: usize,
    pub dt: f64,
    /// Δt_c and its estimator (central differences).
    pub limit: Option<(f64, &'static str)>,
    pub contact_steps: usize,
    /// Mean step over the steps with contact, and over all steps (ms).
    pub contact_ms: f64,
    pub mean_ms: f64,
    pub max_sweeps: usize,
    pub dissipation: f64,
}

/// The wall time of every step, and whether a node carried force after it.
#[derive(Default)]
struct Clock {
    last: Option<Instant>,
    steps: Vec<(f64, bool)>,
}

impl Observer for Clock {
    fn observe(&mut self, s: &Sample) {
        let now = Instant::now();
        if let Some(last) = self.last {
            self.steps.push(((now - last).as_secs_f64() * 1e3, s.contact.touching));
        }
        self.last = Some(now);
    }
}

/// The case's scene with mod3, `scheme`, Δt, and the law (None: frictionless).
fn scene(case: &Case, scheme: &str, dt: f64, end: f64, mu: Option<f64>) -> Result<SolidScene, String> {
    let (mut t, mass) = match case.scene {
        Source::File(file) => {
            let path = crate::repo::root().join(file);
            let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            let mut t: toml::Table = text.parse().map_err(|e| format!("{}: {e}", path.display()))?;
            let solid = t.get_mut("solid").and_then(toml::Value::as_table_mut).ok_or("no [solid]")?;
            let dir = path.parent().unwrap_or(Path::new("."));
            if let Some(toml::Value::String(mesh)) = solid.get_mut("mesh") {
                *mesh = dir.join(&*mesh).to_string_lossy().into_owned();
            }
            (t, "mod3")
        }
        Source::Cube(n) => {
            let text = format!(
                "[solid]\ndim = 3\nnx = {n}\nny = {n}\nnz = {n}\ninitial = {{ displacement = [\"0\", \"0\", \"0\"] }}\n"
            );
            (text.parse().map_err(|e| format!("the cube: {e}"))?, "standard")
        }
    };
    let solid = t.get_mut("solid").and_then(toml::Value::as_table_mut).ok_or("no [solid]")?;
    if let (Some(v), Some(init)) = (case.velocity, solid.get_mut("initial").and_then(toml::Value::as_table_mut)) {
        init.insert("velocity".into(), toml::Value::Array(v.iter().map(|x| toml::Value::from(*x)).collect()));
    }
    let table = |pairs: &[(&str, toml::Value)]| {
        toml::Value::Table(pairs.iter().map(|(k, v)| (k.to_string(), v.clone())).collect())
    };
    t.insert("mass".into(), table(&[("kind", mass.into())]));
    t.insert("scheme".into(), table(&[("kind", scheme.into())]));
    t.insert("time".into(), table(&[("dt", dt.into()), ("end", end.into())]));
    let contact = match mu {
        None => table(&[("method", "exact".into())]),
        Some(mu) => table(&[("method", "exact".into()), ("friction", "coulomb".into()), ("mu", mu.into())]),
    };
    t.insert("contact".into(), contact);
    t.insert("output".into(), table(&[("series", toml::Value::Array(vec!["contact_force".into()]))]));
    let text = toml::to_string(&t).map_err(|e| e.to_string())?;
    SolidScene::from_toml(&text).map_err(|e| format!("{}: {e}", case.name))
}

/// Central differences' Δt_c on the case (a one-step probe) and its estimator.
fn stable_limit(case: &Case) -> Result<(f64, &'static str), String> {
    let probe = scene(case, "central-difference", 1e-9, 1e-9, None)?;
    let r = run_scene(&probe, &mut []).map_err(|e| format!("{}: {e}", case.name))?;
    r.summary.stable_step.zip(r.summary.stable_step_method).ok_or_else(|| format!("{}: no Δt_c", case.name))
}

fn measure(
    case: &Case,
    scheme: &'static str,
    dt: f64,
    end: f64,
    limit: Option<(f64, &'static str)>,
    mu: Option<f64>,
) -> Result<Row, String> {
    let s = scene(case, scheme, dt, end, mu)?;
    let mut clock = Clock::default();
    let r = run_scene(&s, &mut [&mut clock]).map_err(|e| format!("{} {scheme}: {e}", case.name))?;
    let contact: Vec<f64> = clock.steps.iter().filter(|s| s.1).map(|s| s.0).collect();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let all: Vec<f64> = clock.steps.iter().map(|s| s.0).collect();
    Ok(Row {
        case: case.name,
        scheme,
        law: if mu.is_some() { "coulomb" } else { "none" },
        unknowns: r.problem.u0.len(),
        steps: all.len(),
        dt,
        limit,
        contact_steps: contact.len(),
        contact_ms: mean(&contact),
        mean_ms: mean(&all),
        max_sweeps: r.summary.max_pivots,
        dissipation: r.summary.friction.as_ref().map_or(0.0, |f| f.friction_dissipation),
    })
}

/// Measures every case and writes `csv` and its `.md`; returns the paths written.
pub fn run(csv: &Path) -> Result<Vec<PathBuf>, String> {
    // The tree's state before this command writes into it (its own CSV is tracked).
    let env = super::env::Environment::detect();
    let mut rows = Vec::new();
    for case in &CASES {
        let limit = stable_limit(case)?;
        let runs = match case.scene {
            Source::File(file) => {
                let implicit_dt = {
                    let path = crate::repo::root().join(file);
                    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
                    let t: toml::Table = text.parse().map_err(|e| format!("{}: {e}", path.display()))?;
                    t.get("time").and_then(|t| t.get("dt")).and_then(toml::Value::as_float).ok_or("no time.dt")?
                };
                // The largest Δt dividing the end at most min(0.9 Δt_c, the implicit Δt): the
                // explicit run takes no fewer steps than the implicit one.
                let explicit_dt = step_dividing(case.end, (SAFETY * limit.0).min(implicit_dt));
                vec![
                    ("crank-nicolson", implicit_dt, case.end, None),
                    ("central-difference", explicit_dt, case.end, Some(limit)),
                ]
            }
            Source::Cube(_) => {
                let dt = SAFETY * limit.0;
                vec![("central-difference", dt, CUBE_STEPS as f64 * dt, Some(limit))]
            }
        };
        for (scheme, dt, end, limit) in runs {
            for mu in [None, Some(MU)] {
                eprintln!("{} {scheme} {}", case.name, if mu.is_some() { "coulomb" } else { "frictionless" });
                rows.push(measure(case, scheme, dt, end, limit, mu)?);
            }
        }
    }
    std::fs::write(csv, to_csv(&rows)).map_err(|e| format!("{}: {e}", csv.display()))?;
    let md = csv.with_extension("md");
    std::fs::write(&md, to_markdown(&rows, &env)).map_err(|e| format!("{}: {e}", md.display()))?;
    Ok(vec![csv.to_path_buf(), md])
}

const HEADER: &str = "case,scheme,law,unknowns,steps,dt,dt_c,estimator,contact_steps,contact_step_ms,mean_step_ms,max_sweeps,friction_dissipation";

pub fn to_csv(rows: &[Row]) -> String {
    let mut s = format!("{HEADER}\n");
    for r in rows {
        let (limit, estimator) = r.limit.map_or((String::new(), ""), |(l, e)| (format!("{l:.6e}"), e));
        let _ = writeln!(
            s,
            "{},{},{},{},{},{:.6e},{limit},{estimator},{},{:.5},{:.5},{},{:.6e}",
            r.case,
            r.scheme,
            r.law,
            r.unknowns,
            r.steps,
            r.dt,
            r.contact_steps,
            r.contact_ms,
            r.mean_ms,
            r.max_sweeps,
            r.dissipation
        );
    }
    s
}

/// The table of `rows`, measured in the environment `e` (detected before the files were written).
pub fn to_markdown(rows: &[Row], e: &super::env::Environment) -> String {
    let mut s = format!(
        "# The cost of friction\n\nWritten by `massredist bench --friction docs/bench/friction.csv` (study/src/bench/friction.rs) on \
         {} ({} logical CPUs), {} build, massredist {} at {}{}. Each case run frictionless and with Coulomb friction \
         μ = {MU}, one after the other in this process; the disc and the sphere with mod3 (`contact_directions = \"all\"`), \
         central differences at the largest Δt dividing the end that is at most {SAFETY} Δt_c and the implicit Δt; \
         the explicit cube ({CUBE_CELLS}³ Q1 hexahedra, the standard mass, pushed onto the plane at velocity (−1, 0.5, 0)) \
         under central differences at {SAFETY} Δt_c for {CUBE_STEPS} steps. A step's time is the wall time between two observer calls; \"in contact\" are the steps after \
         which some node carries force.\n\n\
         | case | scheme | unknowns | Δt | steps (in contact) | frictionless ms/step in contact | Coulomb ms/step in contact | ratio | ratio over all steps | largest sweeps (Coulomb) |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
        e.cpu,
        e.logical_cpus,
        e.profile,
        e.crate_version,
        &e.git_commit[..e.git_commit.len().min(12)],
        if e.git_dirty { " (uncommitted changes)" } else { "" },
    );
    for pair in rows.chunks(2) {
        let [a, b] = pair else { continue };
        let dt = match a.limit {
            Some((l, est)) => format!("{:.3e} ({:.3} Δt_c; Δt_c = {l:.3e}, {est})", a.dt, a.dt / l),
            None => format!("{:.3e}", a.dt),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {dt} | {} ({} / {}) | {:.3} | {:.3} | {:.2} | {:.2} | {} |",
            a.case,
            a.scheme,
            a.unknowns,
            a.steps,
            a.contact_steps,
            b.contact_steps,
            a.contact_ms,
            b.contact_ms,
            b.contact_ms / a.contact_ms,
            b.mean_ms / a.mean_ms,
            b.max_sweeps
        );
    }
    s.push_str(
        "\nThe frictional step solves the contact nodes' frictional problem on the dense `D = Eᵀ K⁻¹ E` of all \
         candidate contact-node unknowns (normal and tangential): its sweeps, its checks and the two triangular \
         solves with the factor's trailing block cost O(m²) per step for m such unknowns, where the frictionless \
         exact law works on the normal unknowns alone (`src/contact/friction.rs`, `cone.rs`). On massive contact \
         nodes (the explicit cube's standard mass) friction is the forward-increment multiplier returned onto the \
         friction disc node by node, O(1) per contact node (`src/contact/friction/massive.rs`).\n",
    );
    s
}
