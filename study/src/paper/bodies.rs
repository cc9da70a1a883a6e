//! Beyond the paper: an elastic body against a rigid plane (issue 19, item 5), GetFEM's disc of
//! `interface/tests/matlab-octave/demo_dynamic_contact.m`.
//!
//! The disc: radius R = 20 centred at (0, 20), λ = μ = 20, ρ = 1, P2 triangles (gmsh meshes
//! `fixtures/meshes/disc_p2_22a.msh` (h = 8), `disc_p2_h4.msh`, `disc_p2_h2.msh`, made by
//! `python/meshes/shapes.py`), a free body, contact nodes by GetFEM's rule (`contact = "auto"`)
//! on the plane y = 0, Δt = 0.01. Two benchmarks:
//!
//! - **At rest**: the disc at rest touching the plane at (0, 0) under the volume force
//!   f = (0, −0.1) up to T = [`REST_END`] (the full run; [`REST_END_QUICK`] in `--quick`), for
//!   Crank–Nicolson, backward Euler and the hybrid scheme with every mass each allows. Per run:
//!   the energy drift Eᴺ − E⁰ and max_n |Eⁿ − E⁰| (E⁰ = 0: U⁰ = V⁰ = 0; the energy
//!   Eⁿ = ½VMV + ½UKU − F·U is conserved by the continuous problem), the contact-force
//!   oscillation TV = Σ_n |Σ_i R_iⁿ⁺¹ − Σ_i R_iⁿ| (total variation of the total contact force),
//!   the number of contact episodes (maximal runs of steps with some node in contact, read off
//!   the force: R_i > 0, issue 32 item 1) and
//!   `min_distance`.
//! - **Drop**: the disc [`DROP_GAP`] above the plane, moving down at [`DROP_SPEED`], no force,
//!   Crank–Nicolson with every mass: first impact, contact duration (first release − first
//!   impact) and the rebound velocity P_y(T)/(1ᵀM1) (momentum over the redistributed mass's
//!   total: the velocity of its centre of mass after release, constant in free flight) against
//!   the mesh size. 1ᵀM1 = ρ|Ω| but for mod1, which drops layer 0's mass.
//!
//! - **Sphere drop**: the sphere of radius 20 centred at (0, 0, 20) (tetra10 meshes
//!   [`SPHERE_MESHES`], `python/meshes/generate.py --fixtures`), the same material, free,
//!   [`DROP_GAP`] above the plane z = 0 moving down at [`DROP_SPEED`], no force, Crank–Nicolson
//!   with every mass, Δt = [`SPHERE_DT`] to T = [`SPHERE_END`]: the drop's table in 3D
//!   (rebound velocity P_z(T)/(1ᵀM1)). Δt is twice the disc's to keep the set's cost down; the
//!   contact lasts about 19 (≈ 950 steps), so it is still well resolved.
//!
//! Round-off (issue 22): every run is repeated [`COPIES`] times from an initial velocity
//! perturbed by at most [`PERTURBATION`] ([`velocity_perturbation`]: four distinct patterns in x;
//! absolute on the rest disc, whose V⁰ = 0, relative on the drops, whose |V⁰| = 1), and the
//! report keeps only the digits all five runs share, else their band
//! ([`super::band::stable_digits`]). The base run is unperturbed: where the five agree, its digits
//! are the ones printed before the copies existed.

use super::ReproduceError;
/// Re-exported: the bodies' tables print episode counts with it.
pub use super::band::count_band;
use super::experiments::Experiment;
use super::replicate::{Copies, Printed, replicate};
use massredist::driver::{Observer, Sample};
use massredist::mass::MassKind;
use massredist::observe::{Column, Summary};
use massredist::run::{RunError, run_scene};
use massredist::scene::{AnyScene, Registered, Scene};
use massredist::schemes::SchemeSpec;
use massredist::solid::SolidSpec;
use rayon::prelude::*;

/// Final time of the rest benchmark (GetFEM's T = 40) and of its quick form.
pub const REST_END: f64 = 40.0;
pub const REST_END_QUICK: f64 = 4.0;
/// Final time of the drop: impact at 0.5, release near t = 16 (measured: 16.27 for mod3, h = 8),
/// free flight after it.
pub const DROP_END: f64 = 24.0;
/// The drop's initial height above the plane and downward speed.
pub const DROP_GAP: f64 = 0.5;
pub const DROP_SPEED: f64 = 1.0;
/// Time step of every run (GetFEM's).
pub const DT: f64 = 0.01;
/// Largest perturbation of the initial velocity of a run's copies.
pub const PERTURBATION: f64 = 1e-13;
/// Perturbed copies of every run (with the unperturbed run: five runs behind each printed number).
pub const COPIES: usize = super::band::PERTURBATIONS;

/// The perturbation of V⁰'s normal component in copy `copy` (0: none, the base run; 1 to
/// [`COPIES`]: `− PERTURBATION · p_k(x)` with p_k ∈ [−1, 1] on the bodies, x ∈ [−20, 20]), as a
/// tail for a scene's velocity expression. Four patterns that differ in sign and shape, so that
/// the copies are not one perturbation scaled.
pub fn velocity_perturbation(copy: usize) -> String {
    let pattern = match copy {
        0 => return String::new(),
        1 => "(1 + x/20)/2",
        2 => "(x/20 - 1)/2",
        3 => "x/20",
        _ => "x*x/400",
    };
    format!(" - {PERTURBATION:e} * ({pattern})")
}

/// The meshes: (nominal gmsh size h, file under `fixtures/meshes/`), coarsest first.
pub const MESHES: [(f64, &str); 3] = [(8.0, "disc_p2_22a.msh"), (4.0, "disc_p2_h4.msh"), (2.0, "disc_p2_h2.msh")];
/// The sphere's tetra10 meshes (gmsh size h; 1485, 2121, 2871, 8181 and 13 218 unknowns),
/// coarsest first. The first [`SPHERE_ALL_MASSES`] run every mass; the finer ones (issue 32,
/// item 6: the coarse meshes put over half the sphere's mass in the redistributed layer) run
/// mod1, mod3 and the reference ([`FINE_MASSES`]: the standard mass chatters with CN and costs
/// all five runs, mod2 follows mod3).
pub const SPHERE_MESHES: [(f64, &str); 5] = [
    (20.0, "sphere_tet10_22a.msh"),
    (16.0, "sphere_tet10_h16.msh"),
    (14.0, "sphere_tet10_h14.msh"),
    (5.0, "sphere_tet10_h5.msh"),
    (4.0, "sphere_tet10_h4.msh"),
];
/// The sphere meshes that run every mass with Crank–Nicolson.
pub const SPHERE_ALL_MASSES: usize = 3;
/// The masses of the finer sphere meshes.
pub const FINE_MASSES: [MassKind; 2] = [MassKind::Mod1, MassKind::Mod3];
/// The sphere's time step and final time (release near t = 19.8 at h = 20, measured; free
/// flight after it).
pub const SPHERE_DT: f64 = 0.02;
pub const SPHERE_END: f64 = 22.0;

/// Which benchmark a run belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bench {
    Rest,
    Drop,
    /// The sphere dropped (3D).
    Sphere,
}

impl Bench {
    /// The benchmark's meshes (size h, file).
    pub fn meshes(self) -> &'static [(f64, &'static str)] {
        if self == Bench::Sphere { &SPHERE_MESHES } else { &MESHES }
    }

    /// Its time step.
    pub fn dt(self) -> f64 {
        if self == Bench::Sphere { SPHERE_DT } else { DT }
    }
}

/// A run's scheme: one of the paper's at the bench's Δt, or the redistribution-free reference
/// of the drops (issue 32, item 6): central differences with the standard lumped mass at the
/// largest Δt dividing T that is at most [`super::methods::SAFETY`] · Δt_c, whose contact node keeps its mass
/// and whose contact is exact (the forward-increment multiplier).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyScheme {
    Paper(Experiment),
    Reference,
}

impl BodyScheme {
    /// The scheme table of the scene.
    pub fn spec(self) -> SchemeSpec {
        match self {
            BodyScheme::Paper(e) => e.spec(),
            BodyScheme::Reference => SchemeSpec::CENTRAL_DIFFERENCE,
        }
    }

    /// File-name part (the scene's `scheme.kind`).
    pub fn slug(self) -> &'static str {
        self.spec().name()
    }

    /// Name in tables and titles.
    pub fn title(self) -> &'static str {
        match self {
            BodyScheme::Paper(e) => e.title(),
            BodyScheme::Reference => "central differences",
        }
    }
}

/// One run: benchmark, scheme, mass, mesh (index into [`MESHES`]).
#[derive(Debug, Clone, PartialEq)]
pub struct BodyCase {
    pub bench: Bench,
    pub scheme: BodyScheme,
    pub mass: MassKind,
    pub mesh: usize,
}

impl BodyCase {
    pub fn name(&self) -> String {
        let b = match self.bench {
            Bench::Rest => "disc-rest",
            Bench::Drop => "disc-drop",
            Bench::Sphere => "sphere-drop",
        };
        format!("{b} / h = {} / {} / {}", self.h(), self.scheme.slug(), self.mass.name())
    }

    /// The nominal mesh size.
    pub fn h(&self) -> f64 {
        self.bench.meshes()[self.mesh].0
    }
}

/// The runs: at rest, CN, BE and hybrid × their masses on every mesh (`quick`: the coarsest
/// only); the drops, CN × every mass (the sphere's finer meshes: [`FINE_MASSES`]) and the
/// reference (central differences, the standard mass) on every mesh (`quick`: the coarsest).
pub fn body_cases(quick: bool) -> Vec<BodyCase> {
    let schemes = [Experiment::CrankNicolson, Experiment::BackwardEuler, Experiment::Hybrid];
    let meshes = |b: Bench| if quick { 1 } else { b.meshes().len() };
    let mut out = Vec::new();
    for mesh in 0..meshes(Bench::Rest) {
        for e in schemes {
            out.extend(e.masses().into_iter().map(|mass| BodyCase {
                bench: Bench::Rest,
                scheme: BodyScheme::Paper(e),
                mass,
                mesh,
            }));
        }
    }
    for bench in [Bench::Drop, Bench::Sphere] {
        for mesh in 0..meshes(bench) {
            let all = bench != Bench::Sphere || mesh < SPHERE_ALL_MASSES;
            let masses = if all { Experiment::CrankNicolson.masses() } else { FINE_MASSES.to_vec() };
            let cn = BodyScheme::Paper(Experiment::CrankNicolson);
            out.extend(masses.into_iter().map(|mass| BodyCase { bench, scheme: cn, mass, mesh }));
            out.push(BodyCase { bench, scheme: BodyScheme::Reference, mass: MassKind::Standard, mesh });
        }
    }
    out
}

/// The scene of a case as TOML text (mesh path relative to `fixtures/meshes/`); copy `copy`
/// (0: none) perturbs the initial normal velocity by [`velocity_perturbation`]. The
/// divergence criterion is off in effect (factor 1e300): E⁰ is 0 or, perturbed, ~1e-24, which
/// gives it no scale (the first step's energy, ~0.1, would stop the run).
pub fn body_scene_text(case: &BodyCase, dt: f64, end: f64, copy: usize) -> String {
    if case.bench == Bench::Sphere {
        return sphere_scene_text(case, dt, end, copy);
    }
    let (fy, v0, point) = match case.bench {
        Bench::Rest => ("-0.1", 0.0, 0.0),
        _ => ("0", -DROP_SPEED, -DROP_GAP),
    };
    let dv = velocity_perturbation(copy);
    format!(
        "[solid]\ndim = 2\nmesh = \"{}\"\nlame_lambda = 20.0\nlame_mu = 20.0\ndensity = 1.0\n\
         force = [\"0\", \"{fy}\"]\ninitial = {{ displacement = [\"0\", \"0\"], velocity = [\"0\", \"{v0:?}{dv}\"] }}\n\
         [obstacle]\nnormal = [0.0, 1.0]\npoint = [0.0, {point:?}]\ncontact = \"auto\"\n\
         [mass]\nkind = \"{}\"\n[scheme]\n{}\n[time]\ndt = {dt:?}\nend = {end:?}\n\
         [output]\nseries = [\"energy\", \"contact_force\", \"active_nodes\", \"min_distance\", \"momentum_y\"]\n\
         divergence_factor = 1e300\n",
        MESHES[case.mesh].1,
        case.mass.name(),
        toml::to_string(&case.scheme.spec()).expect("a scheme always serialises").trim_end(),
    )
}

/// The sphere's scene ([`body_scene_text`]; the same perturbation, along z).
fn sphere_scene_text(case: &BodyCase, dt: f64, end: f64, copy: usize) -> String {
    let dv = velocity_perturbation(copy);
    format!(
        "[solid]\ndim = 3\nmesh = \"{}\"\nlame_lambda = 20.0\nlame_mu = 20.0\ndensity = 1.0\n\
         force = [\"0\", \"0\", \"0\"]\ninitial = {{ displacement = [\"0\", \"0\", \"0\"], velocity = [\"0\", \"0\", \"{:?}{dv}\"] }}\n\
         [obstacle]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.0, 0.0, {:?}]\ncontact = \"auto\"\n\
         [mass]\nkind = \"{}\"\n[scheme]\n{}\n[time]\ndt = {dt:?}\nend = {end:?}\n\
         [output]\nseries = [\"energy\", \"contact_force\", \"active_nodes\", \"min_distance\", \"momentum_z\"]\n\
         divergence_factor = 1e300\n",
        SPHERE_MESHES[case.mesh].1,
        -DROP_SPEED,
        -DROP_GAP,
        case.mass.name(),
        toml::to_string(&case.scheme.spec()).expect("a scheme always serialises").trim_end(),
    )
}

/// The folder of the benchmark meshes (the crate's `fixtures/meshes/`).
pub fn mesh_dir() -> std::path::PathBuf {
    crate::repo::root().join("fixtures").join("meshes")
}

/// What one run gives (and its perturbed copies' metrics).
#[derive(Debug, Clone)]
pub struct BodyResult {
    pub case: BodyCase,
    pub end: f64,
    /// The time step, and (the reference) Δt_c and its estimator.
    pub dt: f64,
    pub stable: Option<(f64, &'static str)>,
    /// Unknowns of the run (3 per node for the sphere, 2 for the disc; the body is free).
    pub unknowns: usize,
    /// The redistributed layer's share of the body's mass: Σ ρ|c| over the cells whose weight
    /// is not 1, over ρ|Ω| (0 for the standard mass).
    pub layer_fraction: f64,
    pub summary: Summary,
    /// Recorded every step: t, energy, total contact force, active nodes, P_y (P_z for the sphere).
    pub t: Vec<f64>,
    pub energy: Vec<f64>,
    pub contact_force: Vec<f64>,
    pub active: Vec<f64>,
    pub momentum_y: Vec<f64>,
    /// 1ᵀM1, the total of the redistributed mass (ρ|Ω| but for mod1).
    pub mass_total: f64,
    pub metrics: Metrics,
    /// The same metrics from the [`COPIES`] perturbed initial velocities.
    pub perturbed: Vec<Metrics>,
    /// The 2D body at its largest total contact force (drawn by `bodies-impact`); None in 3D.
    pub snapshot: Option<Snapshot>,
}

impl BodyResult {
    /// The five runs' metrics, the unperturbed run first.
    pub fn runs(&self) -> impl Iterator<Item = &Metrics> {
        std::iter::once(&self.metrics).chain(&self.perturbed)
    }

    /// What the report prints of a quantity: the digits (at most 4) all five runs share, else
    /// their band min–max ([`super::band::stable_digits`]).
    pub fn stable(&self, f: impl Fn(&Metrics) -> Option<f64>) -> String {
        super::band::stable_digits(&self.runs().map(f).collect::<Vec<_>>(), 4)
    }

    /// What the report prints of a count: the one value if all five runs agree, else their band.
    pub fn count(&self, f: impl Fn(&Metrics) -> usize) -> String {
        count_band(&self.runs().map(f).collect::<Vec<_>>())
    }
}

/// A 2D body's deformed mesh and contact pressure at one time.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    pub t: f64,
    /// Σ_i R_i then.
    pub contact_force: f64,
    /// Deformed node positions X + u.
    pub points: Vec<[f64; 2]>,
    /// Cell sides as node polylines (2 nodes, or 3 for P2: vertex, mid-side, vertex).
    pub sides: Vec<Vec<usize>>,
    /// (x_i + u_x,i, R_i/a_i) of the contact nodes, by x.
    pub pressure: Vec<(f64, f64)>,
}

/// Keeps the state of largest total contact force (nodal u, λ).
#[derive(Default)]
struct PeakForce {
    force: f64,
    t: f64,
    u: Vec<f64>,
    lambda: Vec<f64>,
}

impl Observer for PeakForce {
    fn observe(&mut self, sample: &Sample) {
        // Σ_c λ_c ≤ 0 for a body: the total force is its opposite.
        if -sample.contact_force > self.force {
            self.force = -sample.contact_force;
            self.t = sample.state.t;
            self.u.resize(sample.geometry.n_nodes() * sample.geometry.components(), 0.0);
            sample.geometry.nodal_values(sample.state.u, &mut self.u);
            self.lambda.clear();
            self.lambda.extend_from_slice(sample.state.lambda);
        }
    }
}

/// The snapshot of a 2D solid from its state of largest force ([`PeakForce`]).
fn snapshot(solid: &massredist::solid::assembly::SolidSystem, peak: &PeakForce) -> Option<Snapshot> {
    let mesh = &solid.mesh;
    if mesh.dim != 2 || peak.u.is_empty() {
        return None;
    }
    let points: Vec<[f64; 2]> =
        mesh.points.iter().enumerate().map(|(i, p)| [p[0] + peak.u[2 * i], p[1] + peak.u[2 * i + 1]]).collect();
    let k = mesh.kind.verts();
    let corners = mesh.kind.corners();
    let sides = mesh
        .cells
        .chunks(k)
        .flat_map(|c| {
            (0..corners).map(move |j| {
                let (a, b) = (c[j], c[(j + 1) % corners]);
                // P2 (triangle6): the mid-side node of side j is node corners + j.
                if k == 2 * corners { vec![a, c[corners + j], b] } else { vec![a, b] }
            })
        })
        .collect();
    let mut pressure: Vec<(f64, f64)> = solid
        .contact_nodes
        .iter()
        .zip(&peak.lambda)
        .zip(&solid.contact_areas)
        .map(|((&i, &l), &a)| (points[i][0], -l / a))
        .collect();
    pressure.sort_by(|a, b| a.0.total_cmp(&b.0));
    Some(Snapshot { t: peak.t, contact_force: peak.force, points, sides, pressure })
}

/// The per-run numbers of the section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    pub drift: f64,
    pub max_energy_deviation: f64,
    /// max_n (Eⁿ⁺¹ − Eⁿ) (≤ round-off for backward Euler, whose energy cannot increase).
    pub max_energy_increase: f64,
    pub force_variation: f64,
    pub episodes: usize,
    pub min_distance: f64,
    pub first_impact: Option<f64>,
    pub first_release: Option<f64>,
    pub rebound_velocity: f64,
}

impl Metrics {
    /// What the report prints of a run (4 significant digits; the episodes as a count).
    pub fn printed(&self) -> Vec<Printed> {
        let duration = self.first_release.zip(self.first_impact).map(|(r, i)| r - i);
        let values = [
            Some(self.drift),
            Some(self.max_energy_deviation),
            Some(self.max_energy_increase),
            Some(self.force_variation),
            Some(self.min_distance),
            self.first_impact,
            self.first_release,
            duration,
            Some(self.rebound_velocity),
        ];
        values.into_iter().map(|v| Printed::Value(v, 4)).chain([Printed::Count(self.episodes)]).collect()
    }
}

/// The metrics of a run from its series (`t`, E, Σ R, active nodes, P_y) and summary.
/// Contact episodes: maximal runs of steps with some node in contact (`active` > 0, read off
/// the force).
pub fn episodes(active: &[f64]) -> usize {
    let on: Vec<bool> = active.iter().map(|&a| a > 0.0).collect();
    on.iter().enumerate().filter(|&(n, &c)| c && (n == 0 || !on[n - 1])).count()
}

pub fn metrics(energy: &[f64], force: &[f64], active: &[f64], momentum_y: &[f64], mass: f64, s: &Summary) -> Metrics {
    let e0 = energy.first().copied().unwrap_or(0.0);
    Metrics {
        drift: energy.last().copied().unwrap_or(e0) - e0,
        max_energy_deviation: energy.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max),
        max_energy_increase: energy.windows(2).map(|w| w[1] - w[0]).fold(f64::NEG_INFINITY, f64::max),
        force_variation: force.windows(2).map(|w| (w[1] - w[0]).abs()).sum(),
        episodes: episodes(active),
        min_distance: s.own_number("min_distance").unwrap_or(f64::NAN),
        first_impact: s.first_impact_time,
        first_release: s.first_release_time,
        rebound_velocity: momentum_y.last().copied().unwrap_or(f64::NAN) / mass,
    }
}

/// One run: its summary, 1ᵀM1, the series (t, E, Σ R, active nodes, P_y), metrics, snapshot,
/// unknowns and layer fraction.
type OneRun = (Summary, f64, [Vec<f64>; 5], Metrics, Option<Snapshot>, usize, f64);

/// The parsed scene of `case` at `dt` to `end`, copy `copy`.
fn scene_of(case: &BodyCase, dt: f64, end: f64, copy: usize) -> Result<Scene<SolidSpec>, ReproduceError> {
    AnyScene::from_toml_at(&body_scene_text(case, dt, end, copy), &mesh_dir())
        .and_then(SolidSpec::from_any)
        .map_err(|source| ReproduceError::Scene { case: case.name(), source })
}

/// The time step of `case` ending at `end`, and for the reference its Δt_c and estimator: the
/// bench's Δt for the paper's schemes; for central differences the largest Δt dividing `end`
/// that is at most [`super::methods::SAFETY`] · Δt_c, Δt_c read off a one-step probe's summary.
pub fn body_dt(case: &BodyCase, end: f64) -> Result<(f64, Option<(f64, &'static str)>), ReproduceError> {
    if case.scheme != BodyScheme::Reference {
        return Ok((case.bench.dt(), None));
    }
    let probe = scene_of(case, 1e-9, 1e-9, 0)?;
    let (dt, limit) = super::methods_disc::explicit_step(&probe, end, format!("{} (Δt_c probe)", case.name()))?;
    Ok((dt, Some(limit)))
}

/// One run of `case` at `dt` to `end` (copy `copy`, 0: unperturbed): the summary, the series and the metrics.
fn run_one(case: &BodyCase, dt: f64, end: f64, copy: usize) -> Result<OneRun, ReproduceError> {
    let name = case.name();
    let scene = scene_of(case, dt, end, copy)?;
    let mut peak = PeakForce::default();
    let run =
        run_scene(&scene, &mut [&mut peak]).map_err(|source: RunError| ReproduceError::Run { case: name, source })?;
    let col = |c: Column| run.series.column(c).unwrap_or_default();
    // 1ᵀM1 of the redistributed mass, Σ_b ρ Σ_c w_c ∫_c φ_b: ρ|Ω| for the standard mass, mod2
    // and mod3; less for mod1, which drops layer 0's mass.
    let volume = run.problem.system.frame.as_ref().map_or(f64::NAN, |b| b.lumped.iter().sum());
    let series = [
        run.series.times(),
        col(Column::Energy),
        col(Column::ContactForce),
        col(Column::ActiveNodes),
        col(Column::Momentum(if case.bench == Bench::Sphere { 2 } else { 1 })),
    ];
    let m = metrics(&series[1], &series[2], &series[3], &series[4], volume, &run.summary);
    let solid = &run.problem.system;
    let layer = layer_fraction(&solid.mesh, &solid.weights);
    Ok((run.summary, volume, series, m, snapshot(solid, &peak), solid.system.n(), layer))
}

/// Σ |c| over the cells whose weight is not 1, over Σ |c| (ρ uniform: the layer's mass share).
pub fn layer_fraction(mesh: &massredist::fem::mesh::Mesh, weights: &[f64]) -> f64 {
    let (mut layer, mut all) = (0.0, 0.0);
    for (c, &w) in weights.iter().enumerate() {
        let v = mesh.measure(c);
        all += v;
        if w != 1.0 {
            layer += v;
        }
    }
    layer / all
}

/// Runs `case` and its [`COPIES`] perturbed copies.
pub fn run_body(case: &BodyCase, quick: bool) -> Result<BodyResult, ReproduceError> {
    let end = match case.bench {
        Bench::Rest if quick => REST_END_QUICK,
        Bench::Rest => REST_END,
        Bench::Drop => DROP_END,
        Bench::Sphere => SPHERE_END,
    };
    // Copy k of `replicate` is this section's pattern k + 1 (0 is the base run).
    let printed = |r: &Result<OneRun, ReproduceError>| match r {
        Ok((_, _, _, m, ..)) => Metrics::printed(m),
        Err(_) => vec![Printed::Value(None, 0)],
    };
    let (dt, stable) = body_dt(case, end)?;
    let mut runs = replicate(Copies::WherePrinted, |c| run_one(case, dt, end, c.index().map_or(0, |k| k + 1)), printed)
        .into_iter();
    let first = runs.next().expect("the base run");
    let (summary, volume, [t, energy, contact_force, active, momentum_y], metrics, snapshot, unknowns, layer_fraction) =
        first?;
    let perturbed = runs.map(|r| r.map(|r| r.3)).collect::<Result<Vec<_>, _>>()?;
    Ok(BodyResult {
        case: case.clone(),
        end,
        dt,
        stable,
        unknowns,
        layer_fraction,
        summary,
        t,
        energy,
        contact_force,
        active,
        momentum_y,
        mass_total: volume,
        metrics,
        perturbed,
        snapshot,
    })
}

/// Every run of [`body_cases`] in parallel, `done` after each.
pub fn compute_bodies(quick: bool, done: &(dyn Fn() + Sync)) -> Result<Vec<BodyResult>, ReproduceError> {
    body_cases(quick)
        .par_iter()
        .map(|c| {
            let r = run_body(c, quick);
            done();
            r
        })
        .collect()
}
