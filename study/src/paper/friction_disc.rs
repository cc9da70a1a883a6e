//! The frictional disc of GetFEM's removed `tests/dynamic_friction` (issue 29, check 6): the
//! bodies section's P2 disc ([`super::bodies`]: radius 20, λ = μ = 20, ρ = 1, mesh h = 8, the
//! plane y = 0) starting [`DROP_GAP`] above the plane with the velocity (V_t, −V₀) =
//! ([`TANGENTIAL_SPEED`], −[`DROP_SPEED`]), no force, Coulomb friction μ = [`MU`] (GetFEM's),
//! Crank–Nicolson, Δt = [`DT`], T = [`DROP_END`]; with the standard mass, mod3 (`contact_directions
//! = "all"`) and mod3 with `"normal"`; and the hybrid scheme with mod3 `"normal"` (the hybrid
//! scheme takes friction on massive tangential unknowns only). Units are GetFEM's demo's, as in
//! the bodies section.
//!
//! Per run: first impact and contact duration (read off the force), the contact episodes, the
//! total variations of the total contact force and of the total friction force Σ r_t,x (their
//! chatter), E(T)/E(0), the friction dissipation D(T)/E(0) and the balance
//! (E(T) + D(T) − E(0))/E(0) (Crank–Nicolson conserves the elastic energy; contact by the exact
//! law adds its own losses), the tangential velocity of the centre of mass at T over V_t, and
//! the largest stick and slip counts; over time, D/E(0) and the stick and slip counts at
//! [`TIMES`]. Every run is repeated [`COPIES`] times from a normal velocity perturbed by at most
//! [`PERTURBATION`] (the bodies section's patterns): cells keep the digits all five runs share,
//! else their band.

use super::ReproduceError;
use super::band::{count_band, stable_digits};
use super::bodies::{
    COPIES, DROP_END, DROP_GAP, DROP_SPEED, DT, MESHES, PERTURBATION, mesh_dir, velocity_perturbation,
};
use super::replicate::{Copies, Printed, replicate};
use massredist::observe::Column;
use massredist::run::run_scene;
use massredist::scene::{AnyScene, Registered, Scene};
use massredist::solid::SolidSpec;
use rayon::prelude::*;
use std::fmt::Write as _;

/// Coulomb's coefficient (GetFEM's `dynamic_friction` test).
pub const MU: f64 = 0.1;
/// The initial tangential velocity.
pub const TANGENTIAL_SPEED: f64 = 0.5;
/// The rows of the table: label, `[mass]` body, scheme.
pub const MASSES: [(&str, &str, &str); 4] = [
    ("standard", "kind = \"standard\"", "crank-nicolson"),
    ("mod3 all", "kind = \"mod3\"", "crank-nicolson"),
    ("mod3 normal", "kind = \"mod3\"\ncontact_directions = \"normal\"", "crank-nicolson"),
    ("mod3 normal, hybrid", "kind = \"mod3\"\ncontact_directions = \"normal\"", "hybrid"),
];
/// The times of the table over time (in contact from 0.5 to about 16).
pub const TIMES: [f64; 5] = [1.0, 4.0, 8.0, 12.0, 16.0];
/// The CSV file of every run.
pub const FRICTION_TABLE: &str = "friction-disc.csv";

/// One run's numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    pub first_impact: Option<f64>,
    pub first_release: Option<f64>,
    pub episodes: usize,
    pub force_tv: f64,
    pub traction_tv: f64,
    pub energy_ratio: f64,
    pub dissipation_ratio: f64,
    pub balance: f64,
    pub tangential_velocity: f64,
    pub max_stick: usize,
    pub max_slip: usize,
    /// D/E(0), stick and slip counts at [`TIMES`].
    pub over_time: Vec<(f64, usize, usize)>,
}

/// A mass's five runs, the unperturbed first.
#[derive(Debug, Clone)]
pub struct MassRuns {
    pub mass: &'static str,
    pub runs: Vec<Run>,
}

/// The scene of a mass and scheme; copy `copy` (0: unperturbed) as in the bodies section.
pub fn friction_disc_scene(mass: &str, scheme: &str, copy: usize) -> String {
    let dv = velocity_perturbation(copy);
    format!(
        "[solid]\ndim = 2\nmesh = \"{}\"\nlame_lambda = 20.0\nlame_mu = 20.0\ndensity = 1.0\nforce = [\"0\", \"0\"]\n\
         initial = {{ displacement = [\"0\", \"0\"], velocity = [\"{TANGENTIAL_SPEED:?}\", \"{:?}{dv}\"] }}\n\
         [obstacle]\nnormal = [0.0, 1.0]\npoint = [0.0, {:?}]\ncontact = \"auto\"\n\
         [contact]\nmethod = \"exact\"\nfriction = \"coulomb\"\nmu = {MU:?}\n[mass]\n{mass}\n\
         [scheme]\nkind = \"{scheme}\"\n[time]\ndt = {DT:?}\nend = {DROP_END:?}\n\
         [output]\nseries = [\"energy\", \"contact_force\", \"active_nodes\", \"momentum_x\", \"friction_dissipation\", \
         \"stick_nodes\", \"slip_nodes\", \"tangential_force_x\"]\ndivergence_factor = 1e300\n",
        MESHES[0].1, -DROP_SPEED, -DROP_GAP,
    )
}

fn run_one(label: &str, mass: &str, scheme: &str, copy: usize) -> Result<Run, ReproduceError> {
    let case = format!("friction disc {label} copy {copy}");
    let scene: Scene<SolidSpec> = AnyScene::from_toml_at(&friction_disc_scene(mass, scheme, copy), &mesh_dir())
        .and_then(SolidSpec::from_any)
        .map_err(|source| ReproduceError::Scene { case: case.clone(), source })?;
    let run = run_scene(&scene, &mut []).map_err(|source| ReproduceError::Run { case, source })?;
    let col = |c: Column| run.series.column(c).unwrap_or_default();
    let (energy, force, traction) = (col(Column::Energy), col(Column::ContactForce), col(Column::TangentialForce(0)));
    let (dissipation, stick, slip) =
        (col(Column::FrictionDissipation), col(Column::StickNodes), col(Column::SlipNodes));
    let active = col(Column::ActiveNodes);
    let tv = |v: &[f64]| v.windows(2).map(|w| (w[1] - w[0]).abs()).sum::<f64>();
    let e0 = energy.first().copied().unwrap_or(f64::NAN);
    let last = |v: &[f64]| v.last().copied().unwrap_or(f64::NAN);
    let total: f64 = run.problem.system.frame.as_ref().map_or(f64::NAN, |b| b.lumped.iter().sum());
    let times = run.series.times();
    let at = |t: f64| times.iter().position(|&s| (s - t).abs() <= 1e-9 * t).unwrap_or(times.len() - 1);
    let count = |v: &[f64]| v.iter().fold(0.0f64, |m, &x| m.max(x)) as usize;
    Ok(Run {
        first_impact: run.summary.first_impact_time,
        first_release: run.summary.first_release_time,
        episodes: super::bodies::episodes(&active),
        force_tv: tv(&force),
        traction_tv: tv(&traction),
        energy_ratio: last(&energy) / e0,
        dissipation_ratio: last(&dissipation) / e0,
        balance: (last(&energy) + last(&dissipation) - e0) / e0,
        tangential_velocity: last(&col(Column::Momentum(0))) / total / TANGENTIAL_SPEED,
        max_stick: count(&stick),
        max_slip: count(&slip),
        over_time: TIMES
            .iter()
            .map(|&t| {
                let n = at(t);
                (dissipation[n] / e0, stick[n] as usize, slip[n] as usize)
            })
            .collect(),
    })
}

/// What the report prints of a run (4 significant digits; the counts as counts).
fn printed(r: &Run) -> Vec<Printed> {
    let values = [
        r.first_impact,
        r.first_impact.zip(r.first_release).map(|(a, b)| b - a),
        Some(r.force_tv),
        Some(r.traction_tv),
        Some(r.energy_ratio),
        Some(r.dissipation_ratio),
        Some(r.balance),
        Some(r.tangential_velocity),
    ];
    let counts = [r.episodes, r.max_stick, r.max_slip];
    let times = r
        .over_time
        .iter()
        .flat_map(|&(d, st, sl)| [Printed::Value(Some(d), 4), Printed::Count(st), Printed::Count(sl)]);
    values.into_iter().map(|v| Printed::Value(v, 4)).chain(counts.map(Printed::Count)).chain(times).collect()
}

/// Every mass's runs with their [`COPIES`] perturbed copies, in parallel.
pub fn compute_friction_disc() -> Result<Vec<MassRuns>, ReproduceError> {
    MASSES
        .par_iter()
        .map(|&(label, mass, scheme)| {
            let runs = replicate(
                Copies::All,
                |c| run_one(label, mass, scheme, c.index().map_or(0, |k| k + 1)),
                |r| r.as_ref().map_or(vec![Printed::Value(None, 0)], printed),
            );
            Ok(MassRuns { mass: label, runs: runs.into_iter().collect::<Result<Vec<_>, _>>()? })
        })
        .collect()
}

/// The report's section: the table per mass and the table over time.
pub fn friction_disc_markdown(results: &[MassRuns]) -> String {
    let mut out = format!(
        "### GetFEM's frictional disc (`tests/dynamic_friction`, removed in 2015)\n\n\
         The P2 disc (h = 8) {DROP_GAP} above the plane with the velocity ({TANGENTIAL_SPEED}, −{DROP_SPEED}), no force, \
         Coulomb friction μ = {MU}, Crank–Nicolson (the last row: the hybrid scheme), Δt = {DT}, T = {DROP_END}; scenes from \
         `study/src/paper/friction_disc.rs`. Contact events are read off the force: the lowest node reaches the plane at t = 0.5 \
         exactly in free flight, so that step 50 carries a force of round-off size or none (mod3 all: 2.0e-12 against 0.36 \
         at t = 0.51: the frictional solve orders the factor differently from the frictionless one, whose drop \
         table above lands at 0.51). Force TV and traction TV are the \
         total variations of Σ R_i and of Σ r_t,x over the run (their chatter); E is the scheme's energy, D the \
         friction dissipation Σ −r_t·Δu_t; v̄_x(T)/V_t the centre of mass's tangential velocity at T. Each run is \
         repeated {COPIES} times from a normal velocity perturbed by at most {PERTURBATION:e}: cells keep the digits \
         all five runs share, else their band min–max. The hybrid scheme takes friction on massive tangential unknowns \
         only (`contact_directions = \"normal\"`); its energy never grows, so its E + D − E(0) is its own contact losses.\n\n\
         | mass | first impact | contact duration | episodes | force TV | traction TV | E(T)/E(0) | D(T)/E(0) | (E + D − E(0))/E(0) | v̄_x(T)/V_t | most sticking | most sliding |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    );
    for m in results {
        let d = |f: &dyn Fn(&Run) -> Option<f64>| stable_digits(&m.runs.iter().map(f).collect::<Vec<_>>(), 4);
        let c = |f: &dyn Fn(&Run) -> usize| count_band(&m.runs.iter().map(f).collect::<Vec<_>>());
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            m.mass,
            d(&|r| r.first_impact),
            d(&|r| r.first_impact.zip(r.first_release).map(|(a, b)| b - a)),
            c(&|r| r.episodes),
            d(&|r| Some(r.force_tv)),
            d(&|r| Some(r.traction_tv)),
            d(&|r| Some(r.energy_ratio)),
            d(&|r| Some(r.dissipation_ratio)),
            d(&|r| Some(r.balance)),
            d(&|r| Some(r.tangential_velocity)),
            c(&|r| r.max_stick),
            c(&|r| r.max_slip),
        );
    }
    out += "\nOver time: D/E(0), and the contact nodes that stick / slide.\n\n| mass |";
    for t in TIMES {
        let _ = write!(out, " t = {t} |");
    }
    out += "\n|---|";
    out += &"---:|".repeat(TIMES.len());
    out += "\n";
    for m in results {
        let _ = write!(out, "| {} |", m.mass);
        for k in 0..TIMES.len() {
            let d = stable_digits(&m.runs.iter().map(|r| Some(r.over_time[k].0)).collect::<Vec<_>>(), 4);
            let st = count_band(&m.runs.iter().map(|r| r.over_time[k].1).collect::<Vec<_>>());
            let sl = count_band(&m.runs.iter().map(|r| r.over_time[k].2).collect::<Vec<_>>());
            let _ = write!(out, " {d}; {st} / {sl} |");
        }
        out += "\n";
    }
    out
}

/// The CSV rows, one per run (copy 0, unperturbed, to [`COPIES`]).
pub fn friction_disc_csv(results: &[MassRuns]) -> String {
    let mut out = String::from(
        "mass,copy,first_impact,first_release,episodes,force_tv,traction_tv,energy_ratio,dissipation_ratio,balance,tangential_velocity,max_stick,max_slip\n",
    );
    let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:e}"));
    for m in results {
        for (k, r) in m.runs.iter().enumerate() {
            let _ = writeln!(
                out,
                "{},{k},{},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{},{}",
                m.mass,
                opt(r.first_impact),
                opt(r.first_release),
                r.episodes,
                r.force_tv,
                r.traction_tv,
                r.energy_ratio,
                r.dissipation_ratio,
                r.balance,
                r.tangential_velocity,
                r.max_stick,
                r.max_slip,
            );
        }
    }
    out
}
