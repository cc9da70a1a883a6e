//! A sphere landing on the plane with a tangential velocity under Coulomb friction (issue 29,
//! check 7): the bodies section's sphere ([`super::bodies`]: radius 20, λ = μ = 20, ρ = 1, the
//! tetra10 mesh h = 20, the plane z = 0) starting [`DROP_GAP`] above the plane with the velocity
//! (V_t, 0, −V₀) = ([`TANGENTIAL_SPEED`], 0, −[`DROP_SPEED`]), no force, μ = [`MU`], mod3, Δt =
//! [`SPHERE_DT`], T = [`SPHERE_END`], under Crank–Nicolson and central differences (Δt = 0.02 is
//! far below central differences' Δt_c, which the table gives with its estimator). Friction
//! slows the contact point and turns the sphere: the centre of mass leaves with less tangential
//! velocity, the difference in rotation and dissipation. Per run: first impact, contact duration
//! (read off the force), episodes, v̄_x(T)/V_t and v̄_z(T)/V₀ (P/(1ᵀM1)), D(T)/E(0), the balance
//! (E(T) + D(T) − E(0))/E(0), the most sticking and sliding nodes; five runs from normal
//! velocities perturbed by at most [`super::bodies::PERTURBATION`] (the bodies section's patterns). The figure
//! `friction-sphere` draws v̄_x, v̄_z and D/E(0) over time (the unperturbed runs).

use super::ReproduceError;
use super::band::{count_band, stable_digits};
use super::bodies::{DROP_GAP, DROP_SPEED, SPHERE_DT, SPHERE_END, SPHERE_MESHES, mesh_dir, velocity_perturbation};
use super::figures::{FigureFile, grid_rows};
use super::friction_disc::{MU, TANGENTIAL_SPEED};
use super::replicate::{Copies, Printed, replicate};
use crate::plot::{Curve, Figure, Panel, Style};
use massredist::numfmt::fmt_f64;
use massredist::observe::Column;
use massredist::run::run_scene;
use massredist::scene::{AnyScene, Registered, Scene};
use massredist::solid::SolidSpec;
use rayon::prelude::*;
use std::fmt::Write as _;

/// The schemes: label, `scheme.kind`.
pub const SCHEMES: [(&str, &str); 2] = [("CN", "crank-nicolson"), ("CD", "central-difference")];
/// The figure's stem.
pub const FRICTION_SPHERE: &str = "friction-sphere";

/// One run's numbers, and (the unperturbed run's) series.
#[derive(Debug, Clone)]
pub struct SphereRun {
    pub first_impact: Option<f64>,
    pub first_release: Option<f64>,
    pub episodes: usize,
    pub vx: f64,
    pub vz: f64,
    pub dissipation_ratio: f64,
    pub balance: f64,
    pub max_stick: usize,
    pub max_slip: usize,
    /// Δt_c and its estimator (central differences).
    pub limit: Option<(f64, &'static str)>,
    /// t, v̄_x/V_t, v̄_z/V₀, D/E(0).
    pub series: [Vec<f64>; 4],
}

/// A scheme's five runs, the unperturbed first.
#[derive(Debug, Clone)]
pub struct SchemeRuns {
    pub scheme: &'static str,
    pub runs: Vec<SphereRun>,
}

/// The scene of a scheme; copy `copy` (0: unperturbed) as in the bodies section.
pub fn friction_sphere_scene(kind: &str, copy: usize) -> String {
    let dv = velocity_perturbation(copy);
    format!(
        "[solid]\ndim = 3\nmesh = \"{}\"\nlame_lambda = 20.0\nlame_mu = 20.0\ndensity = 1.0\nforce = [\"0\", \"0\", \"0\"]\n\
         initial = {{ displacement = [\"0\", \"0\", \"0\"], velocity = [\"{TANGENTIAL_SPEED:?}\", \"0\", \"{:?}{dv}\"] }}\n\
         [obstacle]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.0, 0.0, {:?}]\ncontact = \"auto\"\n\
         [contact]\nmethod = \"exact\"\nfriction = \"coulomb\"\nmu = {MU:?}\n[mass]\nkind = \"mod3\"\n\
         [scheme]\nkind = \"{kind}\"\n[time]\ndt = {SPHERE_DT:?}\nend = {SPHERE_END:?}\n\
         [output]\nseries = [\"energy\", \"contact_force\", \"active_nodes\", \"momentum_x\", \"momentum_z\", \
         \"friction_dissipation\", \"stick_nodes\", \"slip_nodes\"]\ndivergence_factor = 1e300\n",
        SPHERE_MESHES[0].1, -DROP_SPEED, -DROP_GAP,
    )
}

fn run_one(label: &str, kind: &str, copy: usize) -> Result<SphereRun, ReproduceError> {
    let case = format!("friction sphere {label} copy {copy}");
    let scene: Scene<SolidSpec> = AnyScene::from_toml_at(&friction_sphere_scene(kind, copy), &mesh_dir())
        .and_then(SolidSpec::from_any)
        .map_err(|source| ReproduceError::Scene { case: case.clone(), source })?;
    let run = run_scene(&scene, &mut []).map_err(|source| ReproduceError::Run { case, source })?;
    let col = |c: Column| run.series.column(c).unwrap_or_default();
    let (energy, dissipation, active) =
        (col(Column::Energy), col(Column::FrictionDissipation), col(Column::ActiveNodes));
    let e0 = energy.first().copied().unwrap_or(f64::NAN);
    let last = |v: &[f64]| v.last().copied().unwrap_or(f64::NAN);
    let total: f64 = run.problem.system.frame.as_ref().map_or(f64::NAN, |b| b.lumped.iter().sum());
    let count = |v: &[f64]| v.iter().fold(0.0f64, |m, &x| m.max(x)) as usize;
    let vx: Vec<f64> = col(Column::Momentum(0)).iter().map(|p| p / total / TANGENTIAL_SPEED).collect();
    let vz: Vec<f64> = col(Column::Momentum(2)).iter().map(|p| p / total / DROP_SPEED).collect();
    let d: Vec<f64> = dissipation.iter().map(|x| x / e0).collect();
    Ok(SphereRun {
        first_impact: run.summary.first_impact_time,
        first_release: run.summary.first_release_time,
        episodes: super::bodies::episodes(&active),
        vx: last(&vx),
        vz: last(&vz),
        dissipation_ratio: last(&d),
        balance: (last(&energy) + last(&dissipation) - e0) / e0,
        max_stick: count(&col(Column::StickNodes)),
        max_slip: count(&col(Column::SlipNodes)),
        limit: run.summary.stable_step.zip(run.summary.stable_step_method),
        series: [run.series.times().to_vec(), vx, vz, d],
    })
}

fn printed(r: &SphereRun) -> Vec<Printed> {
    let values = [
        r.first_impact,
        r.first_impact.zip(r.first_release).map(|(a, b)| b - a),
        Some(r.vx),
        Some(r.vz),
        Some(r.dissipation_ratio),
        Some(r.balance),
    ];
    values
        .into_iter()
        .map(|v| Printed::Value(v, 4))
        .chain([r.episodes, r.max_stick, r.max_slip].map(Printed::Count))
        .collect()
}

/// Both schemes' runs with their [`super::bodies::COPIES`] perturbed copies, in parallel.
pub fn compute_friction_sphere() -> Result<Vec<SchemeRuns>, ReproduceError> {
    SCHEMES
        .par_iter()
        .map(|&(label, kind)| {
            let runs = replicate(
                Copies::All,
                |c| run_one(label, kind, c.index().map_or(0, |k| k + 1)),
                |r| r.as_ref().map_or(vec![Printed::Value(None, 0)], printed),
            );
            Ok(SchemeRuns { scheme: label, runs: runs.into_iter().collect::<Result<Vec<_>, _>>()? })
        })
        .collect()
}

/// The report's section (its table; the figure below it).
pub fn friction_sphere_markdown(results: &[SchemeRuns]) -> String {
    let mut out = format!(
        "\n### A sphere landing with a tangential velocity under Coulomb friction\n\n\
         The bodies section's sphere (tetra10, h = {}) {DROP_GAP} above the plane z = 0 with the velocity \
         ({TANGENTIAL_SPEED}, 0, −{DROP_SPEED}), no force, Coulomb friction μ = {MU}, mod3, Δt = {}, T = {}; scenes from \
         `study/src/paper/friction_sphere.rs`. Contact events are read off the force; v̄ = P/(1ᵀM1) at T over the \
         initial speed along the same axis; D the friction dissipation. Five runs per scheme as above.\n\n\
         | scheme | Δt/Δt_c | first impact | contact duration | episodes | v̄_x(T)/V_t | v̄_z(T)/V₀ | D(T)/E(0) | (E + D − E(0))/E(0) | most sticking | most sliding |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        fmt_f64(SPHERE_MESHES[0].0),
        fmt_f64(SPHERE_DT),
        fmt_f64(SPHERE_END)
    );
    for s in results {
        let d = |f: &dyn Fn(&SphereRun) -> Option<f64>| stable_digits(&s.runs.iter().map(f).collect::<Vec<_>>(), 4);
        let c = |f: &dyn Fn(&SphereRun) -> usize| count_band(&s.runs.iter().map(f).collect::<Vec<_>>());
        let limit = s.runs[0]
            .limit
            .map_or("implicit".to_string(), |(l, est)| format!("{:.3} (Δt_c = {:.4}, {est})", SPHERE_DT / l, l));
        let _ = writeln!(
            out,
            "| {} | {limit} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            s.scheme,
            d(&|r| r.first_impact),
            d(&|r| r.first_impact.zip(r.first_release).map(|(a, b)| b - a)),
            c(&|r| r.episodes),
            d(&|r| Some(r.vx)),
            d(&|r| Some(r.vz)),
            d(&|r| Some(r.dissipation_ratio)),
            d(&|r| Some(r.balance)),
            c(&|r| r.max_stick),
            c(&|r| r.max_slip),
        );
    }
    let _ = write!(out, "\n![{FRICTION_SPHERE}]({FRICTION_SPHERE}.png)\n");
    out
}

/// The figure: v̄_x/V_t, v̄_z/V₀ and D/E(0) over time, a curve per scheme (unperturbed runs),
/// with its CSV.
pub(super) fn friction_sphere_figure(results: &[SchemeRuns]) -> FigureFile {
    let titles = ["v̄_x/V_t", "v̄_z/V₀", "D/E(0)"];
    let panels = titles
        .iter()
        .enumerate()
        .map(|(k, &title)| Panel {
            title: title.into(),
            x_label: "t".into(),
            y_label: title.into(),
            curves: results
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    let [t, ..] = &s.runs[0].series;
                    let y = &s.runs[0].series[k + 1];
                    Curve {
                        label: s.scheme.into(),
                        points: t.iter().copied().zip(y.iter().copied()).collect(),
                        style: Style::Numeric(i),
                    }
                })
                .collect(),
            x_range: None,
            y_range: None,
        })
        .collect();
    let title = format!(
        "Sphere (tetra10) landing at ({TANGENTIAL_SPEED}, 0, −{DROP_SPEED}), Coulomb μ = {MU}, mod3, Δt = {}",
        fmt_f64(SPHERE_DT)
    );
    let times = results.first().map(|s| s.runs[0].series[0].clone()).unwrap_or_default();
    let mut header = vec!["t".to_string()];
    let mut columns = Vec::new();
    for s in results {
        for (k, name) in ["vx", "vz", "dissipation"].iter().enumerate() {
            header.push(format!("{}_{name}", s.scheme));
            columns.push(s.runs[0].series[k + 1].clone());
        }
    }
    FigureFile {
        stem: FRICTION_SPHERE.into(),
        figure: Figure { title, panels, columns: 3, panel_size: (620, 480) },
        header,
        rows: grid_rows(&times, &columns),
        periods: None,
    }
}
