//! The friction tests' block scenes (issue 29; `tests/friction.rs`, `tests/friction_explicit.rs`).
//!
//! The 2D block (0, 1) × (0, ½), ρ = 1 (m = ½), Lamé λ = μ_L = 10⁴ (wave speed 100: stiff against
//! g·size = 1), rests on the plane y = 0 with u⁰ = 0 under a body force and slides at v₀ along x;
//! the 3D block (0, 1) × (0, ½) × (0, 1) slides at v₀ = 1 along (cos 30°, 0, sin 30°).

use massredist::driver::{Observer, Sample};
use massredist::run::{SceneRun, run_scene};
use massredist::scene::SolidScene;
use massredist::solid::SolidSystem;

/// The block scene with a `[contact]` body, a mass (a kind, or `kind/normal` for
/// `contact_directions = "normal"`), a scheme, Δt and the end time; gravity `force` (two
/// expressions) and initial velocity `v0` along x.
pub fn block(contact: &str, mass: &str, scheme: &str, dt: f64, end: f64, force: [&str; 2], v0: f64) -> SolidScene {
    let mass = mass_table(mass);
    let text = format!(
        r#"[solid]
dim = 2
length = 1.0
height = 0.5
nx = 10
ny = 5
cells = "triangle"
lame_lambda = 1e4
lame_mu = 1e4
density = 1.0
force = ["{}", "{}"]
initial = {{ displacement = ["0", "0"], velocity = ["{v0}", "0"] }}
[obstacle]
normal = [0.0, 1.0]
point = [0.0, 0.0]
contact = "auto"
[contact]
{contact}
[mass]
{mass}
[scheme]
kind = "{scheme}"
[time]
dt = {dt}
end = {end}
[output]
series = ["contact_force", "momentum_x", "momentum_y", "mean_u_x", "friction_dissipation", "slip_nodes", "tangential_force_x", "tangential_force_y"]
"#,
        force[0], force[1]
    );
    SolidScene::from_toml(&text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The `[mass]` table's lines of a kind, or of `kind/normal` (`contact_directions = "normal"`).
pub fn mass_table(mass: &str) -> String {
    match mass.split_once('/') {
        Some((kind, directions)) => format!("kind = \"{kind}\"\ncontact_directions = \"{directions}\""),
        None => format!("kind = \"{mass}\""),
    }
}

pub fn run(s: &SolidScene, extra: &mut [&mut dyn Observer]) -> SceneRun<SolidSystem> {
    run_scene(s, extra).unwrap_or_else(|e| panic!("{e}"))
}

pub const COULOMB: &str = "method = \"exact\"\nfriction = \"coulomb\"\nmu = 0.5";
/// s |Γ_C| = 0.25 = μ m g of [`COULOMB`]: the same deceleration.
pub const TRESCA: &str = "method = \"exact\"\nfriction = \"tresca\"\nthreshold = 0.25";

/// The 3D block (0, 1) × (0, ½) × (0, 1) (the data of [`block`], m = ½, bottom face of area 1)
/// on the plane y = 0, sliding at v₀ = 1 along (cos 30°, 0, sin 30°).
pub fn block3(contact: &str, mass: &str, cells: &str, scheme: &str, dt: f64, end: f64, g: &str) -> SolidScene {
    let mass = mass_table(mass);
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let text = format!(
        r#"[solid]
dim = 3
length = 1.0
height = 0.5
depth = 1.0
nx = 4
ny = 2
nz = 4
cells = "{cells}"
lame_lambda = 1e4
lame_mu = 1e4
density = 1.0
force = ["0", "{g}", "0"]
initial = {{ displacement = ["0", "0", "0"], velocity = ["{c}", "0", "{s}"] }}
[obstacle]
normal = [0.0, 1.0, 0.0]
point = [0.0, 0.0, 0.0]
contact = "auto"
[contact]
{contact}
[mass]
{mass}
[scheme]
kind = "{scheme}"
[time]
dt = {dt}
end = {end}
[output]
series = ["mean_u_x", "mean_u_z", "momentum_x", "momentum_z", "contact_force", "tangential_force_x", "tangential_force_z"]
"#
    );
    SolidScene::from_toml(&text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The momentum balance of a scheme that averages the friction force over a step with weight γ
/// on its end: at every step `ΔP_x = Δt ((1 − γ) Σ r_tⁿ + γ Σ r_t^{n+1})` (Newmark's γ; ½ for
/// velocity Verlet), read with the body's momentum (`own_values`: P_x is its fourth column);
/// the worst residual, the smallest step of the dissipation, the largest `max_cone_excess` and
/// the impulse recorded at n = 0.
#[derive(Default)]
pub struct AveragedBalance {
    pub dt: f64,
    pub gamma: f64,
    prev: Option<(f64, f64, f64)>,
    pub worst: f64,
    pub worst_dissipation: f64,
    pub excess: f64,
    pub first_impulse: f64,
}

impl AveragedBalance {
    pub fn new(dt: f64, gamma: f64) -> Self {
        Self { dt, gamma, ..Self::default() }
    }
}

impl Observer for AveragedBalance {
    fn observe(&mut self, s: &Sample) {
        let f = s.friction.expect("a friction law");
        let mut own = [0.0; 9];
        s.geometry.own_values(s.state.u, s.state.v, s.state.lambda, &mut own);
        let p = own[3];
        if let Some((p0, r0, d0)) = self.prev {
            let want = self.dt * ((1.0 - self.gamma) * r0 + self.gamma * f.force[0]);
            self.worst = self.worst.max((p - p0 - want).abs());
            self.worst_dissipation = self.worst_dissipation.min(f.dissipation - d0);
        } else {
            self.first_impulse = f.impulse[0];
        }
        self.excess = self.excess.max(f.max_cone_excess);
        self.prev = Some((p, f.force[0], f.dissipation));
    }
}
