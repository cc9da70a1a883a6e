//! Curved rigid obstacles (issue 30): GetFEM's P1 disc (radius 20 centred at (0, 20),
//! `fixtures/meshes/disc_p1.msh`) dropped onto a circle of radius 50 and into a circular cavity of
//! radius 25.5, and the bodies section's tetra10 sphere (radius 20, h = 20) dropped onto a
//! cylinder of radius 30 along x; each body's lowest point [`DROP_GAP`] from the obstacle, moving
//! towards it at [`DROP_SPEED`], no force, λ = μ = 20, ρ = 1, Crank–Nicolson, Δt = [`DT`], T =
//! [`END`], with the standard mass and mod3. A body in uniform motion is exact under any scheme
//! and mass, so the first state with force is the first t_n after [`DROP_GAP`]/[`DROP_SPEED`] =
//! 0.5 whose step closes the gap.
//!
//! Per run: the first impact and the contact duration (read off the force, Σ R_i > 0), the
//! contact episodes, the total variation of Σ R_i over the run (its chatter), its largest value
//! and E(T)/E(0). Every run is repeated five times from a velocity perturbed by at most
//! [`super::bodies::PERTURBATION`] (the bodies section's patterns): cells keep the digits all
//! five runs share, else their band. The figure `obstacles` draws Σ R_i over time for each case,
//! standard against mod3 (the unperturbed runs).

use super::ReproduceError;
use super::band::{count_band, stable_digits};
use super::bodies::{PERTURBATION, mesh_dir, velocity_perturbation};
use super::figures::{FigureFile, grid_rows};
use super::replicate::{Copies, Printed, replicate};
use crate::plot::{Curve, Figure, Panel, Style};
use massredist::observe::Column;
use massredist::run::run_scene;
use massredist::scene::{AnyScene, Registered, Scene};
use massredist::solid::SolidSpec;
use rayon::prelude::*;
use std::fmt::Write as _;

/// The bodies' initial distance to the obstacle and their speed towards it.
pub const DROP_GAP: f64 = 0.5;
pub const DROP_SPEED: f64 = 1.0;
/// Time step and final time of every run (the bodies' contact lasts about 16 on the plane: the
/// bodies section's drop, [`super::bodies::DROP_END`]).
pub const DT: f64 = 0.02;
pub const END: f64 = 24.0;
/// The masses: label, `mass.kind`.
pub const MASSES: [&str; 2] = ["standard", "mod3"];
/// The figure's stem, and the CSV of every run.
pub const OBSTACLES_FIGURE: &str = "obstacles";
pub const OBSTACLES_TABLE: &str = "obstacles-table.csv";

/// A case: its label, dimension, mesh and `[obstacle]` table.
pub struct Case {
    pub label: &'static str,
    pub dim: usize,
    pub mesh: &'static str,
    pub obstacle: &'static str,
}

/// The three cases (module docs).
pub const CASES: [Case; 3] = [
    Case {
        label: "disc onto a circle",
        dim: 2,
        mesh: "disc_p1.msh",
        obstacle: "shape = \"sphere\"\ncenter = [0.0, -50.5]\nradius = 50.0",
    },
    Case {
        label: "disc into a cavity",
        dim: 2,
        mesh: "disc_p1.msh",
        obstacle: "shape = \"sphere\"\ncenter = [0.0, 25.0]\nradius = 25.5\nside = \"inside\"",
    },
    Case {
        label: "sphere onto a cylinder",
        dim: 3,
        mesh: "sphere_tet10_22a.msh",
        obstacle: "shape = \"cylinder\"\ncenter = [0.0, 0.0, -30.5]\naxis = [1.0, 0.0, 0.0]\nradius = 30.0",
    },
];

/// One run's numbers and (kept for the figure) its t and Σ R_i.
#[derive(Debug, Clone)]
pub struct Run {
    pub first_impact: Option<f64>,
    pub first_release: Option<f64>,
    pub episodes: usize,
    pub force_tv: f64,
    pub max_force: f64,
    pub energy_ratio: f64,
    pub series: [Vec<f64>; 2],
}

/// A case × mass's five runs, the unperturbed first.
#[derive(Debug, Clone)]
pub struct CaseRuns {
    pub case: &'static str,
    pub mass: &'static str,
    pub runs: Vec<Run>,
}

/// The scene of a case and mass; copy `copy` (0: unperturbed) perturbs the velocity towards the
/// obstacle as in the bodies section.
pub fn obstacle_scene(case: &Case, mass: &str, copy: usize) -> String {
    let dv = velocity_perturbation(copy);
    let (zeros, velocity) = if case.dim == 2 {
        ("\"0\", \"0\"", format!("\"0\", \"{:?}{dv}\"", -DROP_SPEED))
    } else {
        ("\"0\", \"0\", \"0\"", format!("\"0\", \"0\", \"{:?}{dv}\"", -DROP_SPEED))
    };
    format!(
        "[solid]\ndim = {}\nmesh = \"{}\"\nlame_lambda = 20.0\nlame_mu = 20.0\ndensity = 1.0\nforce = [{zeros}]\n\
         initial = {{ displacement = [{zeros}], velocity = [{velocity}] }}\n[obstacle]\n{}\n[mass]\nkind = \"{mass}\"\n\
         [scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = {DT:?}\nend = {END:?}\n\
         [output]\nseries = [\"energy\", \"contact_force\", \"active_nodes\"]\ndivergence_factor = 1e300\n",
        case.dim, case.mesh, case.obstacle
    )
}

fn run_one(case: &Case, mass: &str, copy: usize) -> Result<Run, ReproduceError> {
    let name = format!("obstacles {} {mass} copy {copy}", case.label);
    let scene: Scene<SolidSpec> = AnyScene::from_toml_at(&obstacle_scene(case, mass, copy), &mesh_dir())
        .and_then(SolidSpec::from_any)
        .map_err(|source| ReproduceError::Scene { case: name.clone(), source })?;
    let run = run_scene(&scene, &mut []).map_err(|source| ReproduceError::Run { case: name, source })?;
    let col = |c: Column| run.series.column(c).unwrap_or_default();
    let (energy, force, active) = (col(Column::Energy), col(Column::ContactForce), col(Column::ActiveNodes));
    let e0 = energy.first().copied().unwrap_or(f64::NAN);
    Ok(Run {
        first_impact: run.summary.first_impact_time,
        first_release: run.summary.first_release_time,
        episodes: super::bodies::episodes(&active),
        force_tv: force.windows(2).map(|w| (w[1] - w[0]).abs()).sum(),
        max_force: force.iter().fold(0.0, |m: f64, &x| m.max(x)),
        energy_ratio: energy.last().copied().unwrap_or(f64::NAN) / e0,
        series: [run.series.times(), force],
    })
}

fn printed(r: &Run) -> Vec<Printed> {
    let values = [
        r.first_impact,
        r.first_impact.zip(r.first_release).map(|(a, b)| b - a),
        Some(r.force_tv),
        Some(r.max_force),
        Some(r.energy_ratio),
    ];
    values.into_iter().map(|v| Printed::Value(v, 4)).chain([Printed::Count(r.episodes)]).collect()
}

/// Every case × mass with its perturbed copies, in parallel.
pub fn compute_obstacles() -> Result<Vec<CaseRuns>, ReproduceError> {
    let pairs: Vec<(&Case, &'static str)> = CASES.iter().flat_map(|c| MASSES.iter().map(move |&m| (c, m))).collect();
    pairs
        .par_iter()
        .map(|&(case, mass)| {
            let runs = replicate(
                Copies::All,
                |c| run_one(case, mass, c.index().map_or(0, |k| k + 1)),
                |r| r.as_ref().map_or(vec![Printed::Value(None, 0)], printed),
            );
            Ok(CaseRuns { case: case.label, mass, runs: runs.into_iter().collect::<Result<Vec<_>, _>>()? })
        })
        .collect()
}

/// The report's section (its table; the figure below it).
pub fn obstacles_markdown(results: &[CaseRuns]) -> String {
    let mut out = format!(
        "\n### Curved rigid obstacles\n\n\
         GetFEM's P1 disc (radius 20) dropped onto a circle of radius 50 and into a circular cavity of radius 25.5, the \
         bodies section's tetra10 sphere (radius 20, h = 20) dropped onto a cylinder of radius 30 (`obstacle.shape`, \
         [scenes.md](../scenes.md#curved-rigid-obstacles-obstacleshape)); each {DROP_GAP} from the obstacle moving towards \
         it at {DROP_SPEED}, no force, Crank–Nicolson, Δt = {DT}, T = {END}; scenes from `study/src/paper/obstacles.rs`. \
         Each contact node is in its own frame along the obstacle's normal there. Contact events are read off the force: \
         the first state with force is the first t_n after 0.5 whose step closes the gap. Force TV is the total \
         variation of Σ R_i over the run (its chatter), E(T)/E(0) the scheme's energy at T. Each run is repeated five \
         times from a velocity perturbed by at most {PERTURBATION:e}: cells keep the digits all five runs share, else \
         their band.\n\n\
         | case | mass | first impact | contact duration | episodes | force TV | max Σ R_i | E(T)/E(0) |\n\
         |---|---|---:|---:|---:|---:|---:|---:|\n"
    );
    for r in results {
        let d = |f: &dyn Fn(&Run) -> Option<f64>| stable_digits(&r.runs.iter().map(f).collect::<Vec<_>>(), 4);
        let c = |f: &dyn Fn(&Run) -> usize| count_band(&r.runs.iter().map(f).collect::<Vec<_>>());
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            r.case,
            r.mass,
            d(&|x| x.first_impact),
            d(&|x| x.first_impact.zip(x.first_release).map(|(a, b)| b - a)),
            c(&|x| x.episodes),
            d(&|x| Some(x.force_tv)),
            d(&|x| Some(x.max_force)),
            d(&|x| Some(x.energy_ratio)),
        );
    }
    let _ = write!(out, "\n![{OBSTACLES_FIGURE}]({OBSTACLES_FIGURE}.png)\n");
    out
}

/// The CSV rows, one per run.
pub fn obstacles_csv(results: &[CaseRuns]) -> String {
    let mut out = String::from("case,mass,copy,first_impact,first_release,episodes,force_tv,max_force,energy_ratio\n");
    let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:e}"));
    for r in results {
        for (k, x) in r.runs.iter().enumerate() {
            let _ = writeln!(
                out,
                "{},{},{k},{},{},{},{:e},{:e},{:e}",
                r.case,
                r.mass,
                opt(x.first_impact),
                opt(x.first_release),
                x.episodes,
                x.force_tv,
                x.max_force,
                x.energy_ratio
            );
        }
    }
    out
}

/// The figure: Σ R_i over time, a panel per case, standard against mod3 (unperturbed runs), with
/// its CSV.
pub(super) fn obstacles_figure(results: &[CaseRuns]) -> FigureFile {
    let panels = CASES
        .iter()
        .map(|case| Panel {
            title: case.label.into(),
            x_label: "t".into(),
            y_label: "Σ R_i".into(),
            curves: results
                .iter()
                .filter(|r| r.case == case.label)
                .enumerate()
                .map(|(i, r)| {
                    let [t, f] = &r.runs[0].series;
                    Curve {
                        label: r.mass.into(),
                        points: t.iter().copied().zip(f.iter().copied()).collect(),
                        style: Style::Numeric(i),
                    }
                })
                .collect(),
            x_range: None,
            y_range: None,
        })
        .collect();
    let title = format!("Contact force on curved obstacles: dropped at {DROP_SPEED} from {DROP_GAP}, CN, Δt = {DT}");
    let times = results.first().map(|r| r.runs[0].series[0].clone()).unwrap_or_default();
    let mut header = vec!["t".to_string()];
    let mut columns = Vec::new();
    for r in results {
        header.push(format!("{} {}", r.case, r.mass).replace(' ', "_"));
        columns.push(r.runs[0].series[1].clone());
    }
    FigureFile {
        stem: OBSTACLES_FIGURE.into(),
        figure: Figure { title, panels, columns: 3, panel_size: (620, 480) },
        header,
        rows: grid_rows(&times, &columns),
        periods: None,
    }
}
