//! Beyond the paper: the Hertz limit of GetFEM's disc (issue 19, item 5).
//!
//! The disc of [`super::bodies`] (radius R = 20 centred at (0, 20), λ = μ = 20, ρ = 1, P2
//! triangles, free, contact nodes by GetFEM's rule on y = 0), in plane strain, pressed onto the
//! plane by the volume force f = (0, −g·min((t + Δt)/T_r, 1)): ramped over T_r = [`RAMP`], then
//! held to T = [`END`], stepped by backward Euler with Δt = [`DT`] and the standard mass (the
//! state at rest is the static solution, whatever the mass). Backward Euler damps every mode
//! (its amplification 1/√(1 + ω²Δt²) < 1), the slow bounce of the disc on its contact zone
//! the least: with Δt = 1 and T = 150 it still moved (measured: P_y ≈ 2, ΣR 0.1 % off F at T),
//! with Δt = 10 (ωΔt ten times larger) the 80 steps of the hold leave no motion
//! ([`HertzResult::kinetic`] says how little: ½VᵀMV at T, and |ΣR − F|/F, zero at rest since
//! 1ᵀK = 0 on a free body's vertical motion).
//! The ramp starts at g·Δt/T_r (not 0) because a run whose load and state are 0 at t_0 gives the
//! divergence rule no energy scale.
//!
//! Hertz's 2D contact of a cylinder with a rigid plane under a load F per unit thickness:
//! half-width a = 2√(F R/(π E*)), peak pressure p₀ = 2F/(π a), pressure p(x) = p₀√(1 − x²/a²),
//! with E* = E/(1 − ν²) in plane strain, E = μ(3λ + 2μ)/(λ + μ) = 50, ν = λ/(2(λ + μ)) = ¼,
//! E* = 160/3. Hertz assumes a ≪ R (the disc seen as a half-space, its arc as a parabola):
//! its corrections are of relative order (a/R)², so we pick the load for a/R = 0.1
//! ([`TARGET_A`] = 2): F = π a² E*/(4R) = 8.3776, g = F/(πR²) = 1/150, small enough that the
//! model is within about 1 % and large enough that the finest mesh has 32 contact nodes across
//! the zone. The meshes ([`MESHES`], `python/meshes/shapes.py::hertz_disc`) have size h within
//! distance 3 of (0, 0) (1.5 a), growing to 4 at distance 15.
//!
//! Measured from the state at T: the nodal pressure p_i = R_i/a_i (reaction over the node's
//! share of the contact area, as `contact_pressure` in the VTU frames) at the deformed abscissa
//! x_i + u_x,i; the half-width from the contact nodes: on each side the contact edge lies
//! between the outermost node with R_i > 0 and the next contact node, estimated at their
//! midpoint (within half their spacing); a_h = (right edge − left edge)/2; p_h = max_i p_i.
//! F is the load applied to the mesh, g|Ω_h|.

use super::ReproduceError;
use super::bodies::mesh_dir;
use super::experiments::Experiment;
use massredist::driver::{Observer, Sample};
use massredist::linalg::SymMatrix;
use massredist::run::{run_scene, setup};
use massredist::scene::{AnyScene, Registered, Scene};
use massredist::solid::SolidSpec;
use rayon::prelude::*;

/// Radius of the disc and its Lamé parameters.
pub const RADIUS: f64 = 20.0;
pub const LAME: f64 = 20.0;
/// The Hertz half-width the load is chosen for (a/R = 0.1).
pub const TARGET_A: f64 = 2.0;
/// Time step, ramp duration and final time of every run.
pub const DT: f64 = 10.0;
pub const RAMP: f64 = 200.0;
pub const END: f64 = 1000.0;
/// The meshes: (size h near the contact point, file under `fixtures/meshes/`), coarsest first.
pub const MESHES: [(f64, &str); 3] =
    [(0.5, "hertz_disc_h0.5.msh"), (0.25, "hertz_disc_h0.25.msh"), (0.125, "hertz_disc_h0.125.msh")];

/// E* = E/(1 − ν²) of λ = μ = [`LAME`] (plane strain): E = 50, ν = ¼, E* = 160/3.
pub fn plane_strain_modulus() -> f64 {
    let (l, m) = (LAME, LAME);
    let e = m * (3.0 * l + 2.0 * m) / (l + m);
    let nu = l / (2.0 * (l + m));
    e / (1.0 - nu * nu)
}

/// Hertz's half-width and peak pressure for a load `f` per unit thickness:
/// a = 2√(F R/(π E*)), p₀ = 2F/(π a).
pub fn hertz(f: f64) -> (f64, f64) {
    let a = 2.0 * (f * RADIUS / (std::f64::consts::PI * plane_strain_modulus())).sqrt();
    (a, 2.0 * f / (std::f64::consts::PI * a))
}

/// The volume force g giving Hertz's half-width [`TARGET_A`] on the exact disc:
/// F = π a² E*/(4R), g = F/(πR²) (= 1/150).
pub fn load_density() -> f64 {
    TARGET_A * TARGET_A * plane_strain_modulus() / (4.0 * RADIUS * RADIUS * RADIUS)
}

/// The scene of mesh `k` as TOML text (mesh path relative to `fixtures/meshes/`).
pub fn hertz_scene_text(k: usize) -> String {
    let g = load_density();
    format!(
        "[solid]\ndim = 2\nmesh = \"{}\"\nlame_lambda = {LAME:?}\nlame_mu = {LAME:?}\ndensity = 1.0\n\
         force = [\"0\", \"-{g:e} * min((t + {DT:?}) / {RAMP:?}, 1)\"]\n\
         initial = {{ displacement = [\"0\", \"0\"], velocity = [\"0\", \"0\"] }}\n\
         [obstacle]\nnormal = [0.0, 1.0]\npoint = [0.0, 0.0]\ncontact = \"auto\"\n\
         [mass]\nkind = \"standard\"\n[scheme]\n{}\n[time]\ndt = {DT:?}\nend = {END:?}\n\
         [output]\nseries = [\"contact_force\", \"momentum_y\"]\ndivergence_factor = 1e300\n",
        MESHES[k].1,
        toml::to_string(&Experiment::BackwardEuler.spec()).expect("a scheme always serialises").trim_end(),
    )
}

/// What one mesh gives.
#[derive(Debug, Clone)]
pub struct HertzResult {
    /// Mesh size near the contact point.
    pub h: f64,
    pub unknowns: usize,
    /// F = g|Ω_h|, the load per unit thickness applied to the mesh.
    pub load: f64,
    /// Hertz's a and p₀ for that load.
    pub hertz_a: f64,
    pub hertz_p0: f64,
    /// ΣR_i at T (= F at rest).
    pub contact_force: f64,
    /// ½VᵀMV at T, and its largest value over the run (the scale it fell from).
    pub kinetic: f64,
    pub kinetic_max: f64,
    /// Contact nodes with R_i > 0 at T.
    pub active: usize,
    /// (x_i + u_x,i, p_i) of the contact nodes within 2a of x = 0, by x.
    pub profile: Vec<(f64, f64)>,
    /// a_h, and the largest half-spacing of the pairs that bracket the edges (a_h's resolution).
    pub half_width: f64,
    pub edge_resolution: f64,
    /// p_h = max_i p_i.
    pub peak: f64,
}

impl HertzResult {
    pub fn half_width_error(&self) -> f64 {
        (self.half_width - self.hertz_a) / self.hertz_a
    }
    pub fn peak_error(&self) -> f64 {
        (self.peak - self.hertz_p0) / self.hertz_p0
    }
}

/// Keeps ½VᵀMV of every state (the mass matrix of the run's system).
struct Kinetic<'a> {
    mass: &'a massredist::linalg::sparse::SpMat,
    values: Vec<f64>,
}

impl Observer for Kinetic<'_> {
    fn observe(&mut self, sample: &Sample) {
        self.values.push(0.5 * self.mass.quad_form(sample.state.v));
    }
}

/// The half-width and its resolution from the contact nodes `(x, R)` sorted by x (type docs):
/// on each side the midpoint of the outermost node with R > 0 and the next node out.
pub fn half_width(nodes: &[(f64, f64)]) -> Option<(f64, f64)> {
    let first = nodes.iter().position(|n| n.1 > 0.0)?;
    let last = nodes.iter().rposition(|n| n.1 > 0.0)?;
    let (left_out, right_out) = (nodes.get(first.checked_sub(1)?)?, nodes.get(last + 1)?);
    let left = 0.5 * (left_out.0 + nodes[first].0);
    let right = 0.5 * (right_out.0 + nodes[last].0);
    let resolution = 0.5 * (nodes[first].0 - left_out.0).max(right_out.0 - nodes[last].0);
    Some((0.5 * (right - left), resolution))
}

/// Runs mesh `k` to rest and measures it.
pub fn run_hertz(k: usize) -> Result<HertzResult, ReproduceError> {
    let name = format!("hertz / h = {}", MESHES[k].0);
    let scene: Scene<SolidSpec> = AnyScene::from_toml_at(&hertz_scene_text(k), &mesh_dir())
        .and_then(SolidSpec::from_any)
        .map_err(|source| ReproduceError::Scene { case: name.clone(), source })?;
    // The system is built twice (once here for its mass matrix, once by the run): a few ms.
    let probe = setup(&scene).map_err(|source| ReproduceError::Scene { case: name.clone(), source })?;
    let mut kinetic = Kinetic { mass: &probe.problem.system.system.mass, values: Vec::new() };
    let run = run_scene(&scene, &mut [&mut kinetic]).map_err(|source| ReproduceError::Run { case: name, source })?;
    let solid = &run.problem.system;
    let frame = solid.frame.as_ref().expect("a scene with [obstacle] is a body");
    let load = load_density() * frame.volume;
    let (hertz_a, hertz_p0) = hertz(load);
    let d = solid.mesh.dim;
    let mut nodes: Vec<(f64, f64, f64)> = solid
        .contact_nodes
        .iter()
        .zip(&run.last.lambda)
        .zip(&solid.contact_areas)
        .map(|((&i, &l), &a)| (solid.mesh.points[i][0] + run.last.u[i * d], -l, -l / a))
        .collect();
    nodes.sort_by(|a, b| a.0.total_cmp(&b.0));
    let xr: Vec<(f64, f64)> = nodes.iter().map(|n| (n.0, n.1)).collect();
    let (half, resolution) = half_width(&xr).unwrap_or((f64::NAN, f64::NAN));
    Ok(HertzResult {
        h: MESHES[k].0,
        unknowns: solid.system.n(),
        load,
        hertz_a,
        hertz_p0,
        contact_force: nodes.iter().map(|n| n.1).sum(),
        kinetic: kinetic.values.last().copied().unwrap_or(f64::NAN),
        kinetic_max: kinetic.values.iter().copied().fold(0.0, f64::max),
        active: nodes.iter().filter(|n| n.1 > 0.0).count(),
        profile: nodes.iter().filter(|n| n.0.abs() <= 2.0 * hertz_a).map(|n| (n.0, n.2)).collect(),
        half_width: half,
        edge_resolution: resolution,
        peak: nodes.iter().map(|n| n.2).fold(0.0, f64::max),
    })
}

/// Every mesh, in parallel, `done` after each.
pub fn compute_hertz(done: &(dyn Fn() + Sync)) -> Result<Vec<HertzResult>, ReproduceError> {
    (0..MESHES.len())
        .into_par_iter()
        .map(|k| {
            let r = run_hertz(k);
            done();
            r
        })
        .collect()
}
