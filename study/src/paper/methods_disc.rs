//! Problem (e) of the method comparison (issue 20, item 2): a solid that impacts, GetFEM's disc
//! of the bodies section ([`super::bodies`]) dropped onto the plane y = 0: radius 20, λ = μ = 20,
//! ρ = 1, P2 meshes h = 8 and 4, [`DROP_GAP`] above the plane at [`DROP_SPEED`] downwards, no
//! force, T = [`DROP_END`] (impact, about 16 of contact, free flight after). The implicit classes
//! step at Δt = [`DT`]; central differences at the comparison's one safety factor,
//! [`SAFETY`] · Δt_c (rounded down to divide T; [`disc_dt`]), with Δt_c and its estimator from
//! a one-step probe (issue 32, item 2).
//!
//! There is no exact solution; the rigid approach brings the disc onto the plane at exactly
//! t = 0.5 (free flight is exact in every scheme) and the elastic disc should leave with |v̄| close
//! to V₀ with an energy-conserving method. Every contact event is read off the force (λ < 0,
//! Σ R > 0; issue 32, item 1): the first impact is the first step that pushes, the release the
//! first later step without force, the episodes the runs of steps with force. Per run ([`super::bodies::metrics`]): first impact, contact duration
//! (first release − first impact), the rebound ratio v̄/V₀ (P_y(T)/(1ᵀM1 V₀)), the energy drift
//! (E(T) − E(0))/E(0) of the scheme's own energy, the total variation of the total contact force,
//! the number of contact episodes, the largest penetration max(0, −min_distance)/R and the CPU
//! time of the whole run. Every run is repeated [`COPIES`] times from a velocity perturbed by at
//! most [`PERTURBATION`] (the bodies section's patterns, [`velocity_perturbation`]): the impact is
//! round-off sensitive, and the table keeps only the digits all five runs share, else their band.
//!
//! The methods are one table, [`DISC_METHODS`]: the classes that apply to a body
//! (Nitsche is built for bars only; central differences with penalty need mass at the contact
//! nodes on solids).

use super::ReproduceError;
use super::band::{count_band, sig, stable_digits};
use super::bodies::{
    COPIES, DROP_END, DROP_GAP, DROP_SPEED, DT, MESHES, Metrics, PERTURBATION, mesh_dir, metrics, velocity_perturbation,
};
use super::methods::{SAFETY, step_dividing};
use super::replicate::{Copies, Printed, replicate};
use massredist::observe::Column;
use massredist::run::run_scene;
use massredist::scene::{AnyScene, Registered, Scene};
use massredist::solid::SolidSpec;
use rayon::prelude::*;
use serde::Serialize;
use std::time::Instant;

/// Young's modulus of the disc, E = μ(3λ + 2μ)/(λ + μ) with λ = μ = 20; the penalty is a
/// multiple of E/h as in the 1D comparison.
const YOUNG: f64 = 50.0;
/// The disc's radius (penetration is reported relative to it).
const RADIUS: f64 = 20.0;

/// One method of problem (e): label, the `[scheme]` body, the `[contact]` body (empty: exact),
/// the penalty factor (κ = factor · E/h), the masses it applies to.
#[derive(Debug, Clone, Copy)]
pub struct DiscMethod {
    pub label: &'static str,
    pub scheme: &'static str,
    pub penalty: Option<f64>,
    pub masses: &'static [&'static str],
    /// Explicit: stepped at [`SAFETY`] · Δt_c ([`disc_dt`]), else at [`DT`].
    pub explicit: bool,
}

const ALL: &[&str] = &["standard", "mod1", "mod2", "mod3"];
const MASSLESS: &[&str] = &["mod1", "mod2", "mod3"];
const STANDARD: &[&str] = &["standard"];
const CN: &str = "kind = \"crank-nicolson\"";
const BE: &str = "kind = \"backward-euler\"";
const CD: &str = "kind = \"central-difference\"";

/// The methods of problem (e), one line each.
#[rustfmt::skip]
pub const DISC_METHODS: &[DiscMethod] = &[
    DiscMethod { label: "CN", scheme: CN, penalty: None, masses: ALL, explicit: false },
    DiscMethod { label: "BE", scheme: BE, penalty: None, masses: ALL, explicit: false },
    DiscMethod { label: "hybrid", scheme: "kind = \"hybrid\"", penalty: None, masses: MASSLESS, explicit: false },
    DiscMethod { label: "CN pen 100", scheme: CN, penalty: Some(100.0), masses: ALL, explicit: false },
    DiscMethod { label: "BE pen 100", scheme: BE, penalty: Some(100.0), masses: ALL, explicit: false },
    DiscMethod { label: "CD", scheme: CD, penalty: None, masses: ALL, explicit: true },
    DiscMethod { label: "CD pen 100", scheme: CD, penalty: Some(100.0), masses: STANDARD, explicit: true },
    DiscMethod { label: "MJ θ=½ e=0", scheme: "kind = \"moreau-jean\"\ntheta = 0.5\nrestitution = 0.0", penalty: None, masses: STANDARD, explicit: false },
    DiscMethod { label: "MJ θ=1 e=0", scheme: "kind = \"moreau-jean\"\ntheta = 1.0\nrestitution = 0.0", penalty: None, masses: STANDARD, explicit: false },
];

/// The meshes of problem (e): the bodies section's two coarsest.
pub const DISC_MESHES: usize = 2;

/// One run of problem (e) and its [`COPIES`] perturbed copies.
#[derive(Debug, Clone, Serialize)]
pub struct DiscResult {
    pub method: &'static str,
    pub mass: &'static str,
    pub h: f64,
    /// The time step ([`disc_dt`]).
    pub dt: f64,
    /// Central differences' Δt_c and its estimator (the summary's `stable_step`,
    /// `stable_step_method`); None for the implicit classes.
    pub stable_step: Option<f64>,
    pub stable_step_method: Option<&'static str>,
    /// The unperturbed run first, then the copies.
    #[serde(skip)]
    pub metrics: Vec<Metrics>,
    /// Total mass 1ᵀM1 (the rebound ratio's denominator).
    pub mass_total: f64,
    /// The unperturbed run's.
    pub cpu_seconds: f64,
}

/// The scene of `method` with `mass` on mesh `mesh` at time step `dt` to `end`; copy `copy` (0:
/// unperturbed) as in the bodies section ([`velocity_perturbation`]).
pub fn disc_scene(method: &DiscMethod, mass: &str, mesh: usize, copy: usize, dt: f64, end: f64) -> String {
    let (h, file) = MESHES[mesh];
    let dv = velocity_perturbation(copy);
    let contact = method
        .penalty
        .map_or(String::new(), |f| format!("[contact]\nmethod = \"penalty\"\npenalty = {:?}\n", f * YOUNG / h));
    format!(
        "[solid]\ndim = 2\nmesh = \"{file}\"\nlame_lambda = 20.0\nlame_mu = 20.0\ndensity = 1.0\nforce = [\"0\", \"0\"]\n\
         initial = {{ displacement = [\"0\", \"0\"], velocity = [\"0\", \"{:?}{dv}\"] }}\n\
         [obstacle]\nnormal = [0.0, 1.0]\npoint = [0.0, {:?}]\ncontact = \"auto\"\n[mass]\nkind = \"{mass}\"\n\
         [scheme]\n{}\n{contact}[time]\ndt = {dt:?}\nend = {end:?}\n\
         [output]\nseries = [\"energy\", \"contact_force\", \"active_nodes\", \"min_distance\", \"momentum_y\"]\n\
         divergence_factor = 1e300\n",
        -DROP_SPEED, -DROP_GAP, method.scheme,
    )
}

/// The parsed scene of a case (`case` names it in errors).
fn parsed(text: &str, case: &str) -> Result<Scene<SolidSpec>, ReproduceError> {
    AnyScene::from_toml_at(text, &mesh_dir())
        .and_then(SolidSpec::from_any)
        .map_err(|source| ReproduceError::Scene { case: case.to_string(), source })
}

/// The time step of `method` with `mass` on mesh `mesh`, and for an explicit method its Δt_c and
/// estimator: [`DT`] for the implicit classes; for central differences the largest Δt dividing
/// T = [`DROP_END`] that is at most [`SAFETY`] · Δt_c, Δt_c read off a one-step probe's summary.
pub fn disc_dt(
    method: &DiscMethod,
    mass: &str,
    mesh: usize,
) -> Result<(f64, Option<(f64, &'static str)>), ReproduceError> {
    if !method.explicit {
        return Ok((DT, None));
    }
    let case = format!("disc-drop {} {mass} h={} (Δt_c probe)", method.label, MESHES[mesh].0);
    let probe = parsed(&disc_scene(method, mass, mesh, 0, 1e-9, 1e-9), &case)?;
    let (dt, limit) = explicit_step(&probe, DROP_END, case)?;
    Ok((dt, Some(limit)))
}

/// The one safety factor's step of an explicit body scene ending at `end`: the largest Δt
/// dividing `end` that is at most [`SAFETY`] · Δt_c, with Δt_c and its estimator read off the
/// summary of `probe` (the scene run for one tiny step; `case` names it in errors).
pub fn explicit_step(
    probe: &Scene<SolidSpec>,
    end: f64,
    case: String,
) -> Result<(f64, (f64, &'static str)), ReproduceError> {
    let run = run_scene(probe, &mut []).map_err(|source| ReproduceError::Run { case: case.clone(), source })?;
    let Some((limit, by)) = run.summary.stable_step.zip(run.summary.stable_step_method) else {
        return Err(ReproduceError::NoStableLimit { case });
    };
    Ok((step_dividing(end, SAFETY * limit), (limit, by)))
}

/// One run at time step `dt`: its metrics, 1ᵀM1 and its CPU (wall, one thread) seconds.
pub fn run_one(
    method: &DiscMethod,
    mass: &str,
    mesh: usize,
    copy: usize,
    dt: f64,
) -> Result<(Metrics, f64, f64), ReproduceError> {
    let case = format!("disc-drop {} {mass} h={} copy {copy}", method.label, MESHES[mesh].0);
    let scene = parsed(&disc_scene(method, mass, mesh, copy, dt, DROP_END), &case)?;
    let started = Instant::now();
    let run = run_scene(&scene, &mut []).map_err(|source| ReproduceError::Run { case, source })?;
    let seconds = started.elapsed().as_secs_f64();
    let col = |c: Column| run.series.column(c).unwrap_or_default();
    let total = run.problem.system.frame.as_ref().map_or(f64::NAN, |b| b.lumped.iter().sum());
    let m = metrics(
        &col(Column::Energy),
        &col(Column::ContactForce),
        &col(Column::ActiveNodes),
        &col(Column::Momentum(1)),
        total,
        &run.summary,
    );
    Ok((m, total, seconds))
}

/// Every (method, mass, mesh) of problem (e) with its [`COPIES`] perturbed copies (`copies`:
/// all, or where a printed digit can change: [`super::replicate`]), in parallel.
pub fn compute_disc(copies: Copies) -> Result<Vec<DiscResult>, ReproduceError> {
    let cases: Vec<(&DiscMethod, &'static str, usize)> = DISC_METHODS
        .iter()
        .flat_map(|m| m.masses.iter().flat_map(move |&k| (0..DISC_MESHES).map(move |i| (m, k, i))))
        .collect();
    cases
        .par_iter()
        .map(|&(method, mass, mesh)| {
            let (dt, limit) = disc_dt(method, mass, mesh)?;
            // Copy k of `replicate` is the bodies' velocity pattern k + 1 (0 is the base run).
            let runs = replicate(
                copies,
                |c| run_one(method, mass, mesh, c.index().map_or(0, |k| k + 1), dt),
                |r| r.as_ref().map_or(vec![Printed::Value(None, 0)], |(m, total, _)| printed(m, *total)),
            );
            let runs = runs.into_iter().collect::<Result<Vec<_>, _>>()?;
            Ok(DiscResult {
                method: method.label,
                mass,
                h: MESHES[mesh].0,
                dt,
                stable_step: limit.map(|l| l.0),
                stable_step_method: limit.map(|l| l.1),
                metrics: runs.iter().map(|r| r.0).collect(),
                mass_total: runs[0].1,
                cpu_seconds: runs[0].2,
            })
        })
        .collect()
}

/// What [`disc_markdown`] prints of a run (4 significant digits; the episodes as a count).
fn printed(m: &Metrics, total: f64) -> Vec<Printed> {
    let e0 = 0.5 * total * DROP_SPEED * DROP_SPEED;
    [
        m.first_impact,
        m.first_impact.zip(m.first_release).map(|(a, b)| b - a),
        Some(m.rebound_velocity / DROP_SPEED),
        Some(m.drift / e0),
        Some(m.force_variation),
        Some((-m.min_distance).max(0.0) / RADIUS),
    ]
    .into_iter()
    .map(|v| Printed::Value(v, 4))
    .chain([Printed::Count(m.episodes)])
    .collect()
}

/// The markdown table of problem (e) (shared digits of the five runs, at most 4 significant).
pub fn disc_markdown(results: &[DiscResult]) -> String {
    let mut out = format!(
        "### (e) GetFEM's disc dropped onto the plane (P2, h = 8 and 4; Δt = {DT} implicit, 0.9 Δt_c explicit; T = {DROP_END})\n\n\
         No exact solution: the disc reaches the plane at exactly t = {:.1} (free flight is exact); every contact event is read off the force \
         (first impact: the first step with Σ R > 0; release: the first later step with Σ R = 0; episodes: runs of steps with Σ R > 0); an energy-conserving method \
         leaves with v̄/V₀ near 1. Each run is repeated {COPIES} times from a velocity perturbed by at most \
         {PERTURBATION:e} (four patterns): cells keep only the digits all five runs share, else their band min–max; \
         episodes are one count, or the band min–max. Penetration is max(0, −min_distance)/R. CPU s is one run \
         (wall time of one thread, runs in parallel). The implicit classes step at Δt = {DT}; central differences at \
         {SAFETY} Δt_c (the largest Δt dividing T below it), Δt_c by the estimator named beside it.\n\n\
         | h | method | mass | Δt | Δt_c (estimator) | first impact | contact duration | rebound v̄/V₀ | energy drift | force TV | episodes | penetration/R | CPU s |\n\
         |---:|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        DROP_GAP / DROP_SPEED
    );
    for r in results {
        let d = |f: &dyn Fn(&Metrics, f64) -> Option<f64>| {
            let values: Vec<Option<f64>> = r.metrics.iter().map(|m| f(m, r.mass_total)).collect();
            stable_digits(&values, 4)
        };
        let e0 = 0.5 * r.mass_total * DROP_SPEED * DROP_SPEED;
        out += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.3} |\n",
            r.h,
            r.method,
            r.mass,
            sig(r.dt, 4),
            r.stable_step.zip(r.stable_step_method).map_or("—".into(), |(l, by)| format!("{} ({by})", sig(l, 4))),
            d(&|m, _| m.first_impact),
            d(&|m, _| m.first_impact.zip(m.first_release).map(|(a, b)| b - a)),
            d(&|m, _| Some(m.rebound_velocity / DROP_SPEED)),
            d(&|m, _| Some(m.drift / e0)),
            d(&|m, _| Some(m.force_variation)),
            episodes(&r.metrics),
            d(&|m, _| Some((-m.min_distance).max(0.0) / RADIUS)),
            r.cpu_seconds,
        );
    }
    out
}

/// The episode counts of the runs: one number if all agree, else their band min–max.
fn episodes(runs: &[Metrics]) -> String {
    count_band(&runs.iter().map(|m| m.episodes).collect::<Vec<_>>())
}

/// The CSV rows of problem (e), one per run (copy 0, unperturbed, to [`COPIES`]).
pub fn disc_csv(results: &[DiscResult]) -> String {
    let mut out = String::from(
        "method,mass,h,dt,stable_step,stable_step_method,copy,first_impact,first_release,rebound_ratio,energy_drift,force_tv,episodes,min_distance,mass_total,cpu_seconds\n",
    );
    let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:e}"));
    for r in results {
        let e0 = 0.5 * r.mass_total * DROP_SPEED * DROP_SPEED;
        for (k, m) in r.metrics.iter().enumerate() {
            out += &format!(
                "{},{},{},{:e},{},{},{k},{},{},{:e},{:e},{:e},{},{:e},{:e},{:e}\n",
                r.method,
                r.mass,
                r.h,
                r.dt,
                opt(r.stable_step),
                r.stable_step_method.unwrap_or(""),
                opt(m.first_impact),
                opt(m.first_release),
                m.rebound_velocity / DROP_SPEED,
                m.drift / e0,
                m.force_variation,
                m.episodes,
                m.min_distance,
                r.mass_total,
                r.cpu_seconds,
            );
        }
    }
    out
}
