//! Two discs colliding (issue 30, check 5): two P2 discs of radius R = 20 (λ = μ = 20, ρ = 1,
//! plane strain), one above the other (`fixtures/meshes/hertz_poles_h0.25.msh`: size 0.25 within
//! distance 3 of both poles, growing to 4 at distance 15), the upper one falling at
//! [`SPEED`] onto the lower one at rest from [`GAP`] above it, no force; one `[[pair]]` of their
//! boundaries (node to segment on the curved P2 sides), mod3, Crank–Nicolson, Δt = [`DT`] to
//! T = [`END`].
//!
//! Hertz's 2D contact of two equal cylinders (Johnson, *Contact Mechanics*, §4.3 and §5.6):
//! R* = R/2, E*_pair = E*/2 (E* = E/(1 − ν²) = 160/3 of each disc), so the half-width under a
//! force F per unit thickness is a = 2√(F R*/(π E*_pair)) = 2√(F R/(π E*)), the disc-on-plane
//! formula of [`super::hertz`]. The impact is slow against the waves (V/c_p = 0.1/√60 = 0.013;
//! contact lasts about 21, a P wave crosses a disc in 5.2), so the quasi-static relation should
//! hold at every instant: at each step we measure Σ R_i (the pair's force) and the contact's
//! half-width a_h from the upper disc's pair nodes (deformed abscissa x_i + u_x,i; on each side
//! the midpoint of the outermost node with R_i > 0 and the next one, as [`super::hertz`]), and
//! compare a_h with Hertz's a(Σ R_i), within a_h's resolution (the half-spacing of the
//! bracketing nodes) and Hertz's own error, of order (a/R)² (a/R ≈ 0.1 at the peak).
//! 2D Hertz gives no closed force–approach law (the approach depends on the bodies' size through
//! a logarithm), so the force history itself is not compared with a formula: the table gives its
//! peak, the contact time, the impulse against the momentum exchanged and the final momenta.
//!
//! Every run is repeated from a speed perturbed by at most [`super::bodies::PERTURBATION`]
//! where a printed digit is in reach of the spread ([`Copies::WherePrinted`]).

use super::ReproduceError;
use super::band::stable_digits;
use super::bodies::{PERTURBATION, mesh_dir};
use super::figures::{FigureFile, grid_rows};
use super::hertz::{half_width, hertz};
use super::replicate::{Copies, Printed, replicate};
use crate::plot::{Curve, Figure, Panel, Style};
use massredist::driver::{Observer, Sample};
use massredist::run::{run_scene, setup};
use massredist::scene::{AnyScene, Registered, Scene};
use massredist::solid::SolidSpec;
use std::fmt::Write as _;

/// The mesh (under `fixtures/meshes/`), the discs' radius.
pub const MESH: &str = "hertz_poles_h0.25.msh";
pub const RADIUS: f64 = 20.0;
/// The upper disc's speed, its initial distance to the lower one.
pub const SPEED: f64 = 0.1;
pub const GAP: f64 = 0.05;
/// Time step and final time.
pub const DT: f64 = 0.05;
pub const END: f64 = 30.0;
/// The figure's stem (its CSV holds the unperturbed run's steps).
pub const TWO_DISCS_FIGURE: &str = "two-discs";

/// The scene (mesh paths relative to `fixtures/meshes/`), the speed's tail `tail`.
pub fn two_discs_text(tail: &str) -> String {
    format!(
        "[[solid]]\nname = \"upper\"\nmesh = \"{MESH}\"\noffset = [0.0, {top:?}]\nlame_lambda = 20.0\nlame_mu = 20.0\n\
         initial = {{ velocity = [\"0\", \"-({SPEED:?}{tail})\"] }}\n\
         [[solid]]\nname = \"lower\"\nmesh = \"{MESH}\"\nlame_lambda = 20.0\nlame_mu = 20.0\n\
         [[pair]]\nname = \"impact\"\nbodies = [\"upper\", \"lower\"]\ngroups = [\"boundary\", \"boundary\"]\n\
         [mass]\nkind = \"mod3\"\n[scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = {DT:?}\nend = {END:?}\n\
         [output]\nseries = [\"energy\", \"impact.contact_force\", \"upper.momentum_y\", \"lower.momentum_y\"]\n",
        top = 2.0 * RADIUS + GAP,
    )
}

/// One step: t, Σ R_i, the measured half-width and its resolution (NaN without contact), Hertz's
/// half-width for Σ R_i.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    pub t: f64,
    pub force: f64,
    pub half_width: f64,
    pub resolution: f64,
    pub hertz: f64,
}

/// A run's steps and totals.
#[derive(Debug, Clone)]
pub struct DiscRun {
    pub steps: Vec<Step>,
    /// Σ R at its largest, and Hertz's a for it against a_h there.
    pub peak_force: f64,
    /// max over the steps with Σ R ≥ half its peak of |a_h − a(Σ R)| / a(Σ R), and of the
    /// resolution over a(Σ R) there.
    pub width_error: f64,
    pub width_resolution: f64,
    /// The sum of the steps with Σ R > 0 (Δt each).
    pub contact_time: f64,
    /// ∫ Σ R dt (trapezoidal) over m V, m the disc's mass.
    pub impulse: f64,
    /// The final momenta of the upper and the lower disc over m V (elastic, no vibration left:
    /// 0 and −1).
    pub upper: f64,
    pub lower: f64,
    /// The total momentum's largest drift over m V, and E(T)/E(0).
    pub momentum_drift: f64,
    pub energy_ratio: f64,
}

/// Each step's Σ R and half-width from the upper disc's pair nodes.
struct Widths<'a> {
    nodes: &'a [usize],
    points: &'a [[f64; 3]],
    nodal: Vec<f64>,
    steps: Vec<Step>,
}

impl Observer for Widths<'_> {
    fn observe(&mut self, sample: &Sample) {
        self.nodal.resize(2 * sample.geometry.n_nodes(), 0.0);
        sample.geometry.nodal_values(sample.state.u, &mut self.nodal);
        let mut xr: Vec<(f64, f64)> = self
            .nodes
            .iter()
            .zip(sample.state.lambda)
            .map(|(&i, &l)| (self.points[i][0] + self.nodal[2 * i], -l))
            .collect();
        xr.sort_by(|a, b| a.0.total_cmp(&b.0));
        let force: f64 = xr.iter().map(|n| n.1).sum();
        let (half, resolution) = half_width(&xr).unwrap_or((f64::NAN, f64::NAN));
        let hertz = if force > 0.0 { hertz(force).0 } else { f64::NAN };
        self.steps.push(Step { t: sample.state.t, force, half_width: half, resolution, hertz });
    }
}

/// One run, the speed perturbed in copy `copy` (0: none).
pub fn run_two_discs(copy: usize) -> Result<DiscRun, ReproduceError> {
    let name = format!("two discs copy {copy}");
    let tail = if copy == 0 { String::new() } else { format!(" + {:e}", PERTURBATION * copy as f64) };
    let scene: Scene<SolidSpec> = AnyScene::from_toml_at(&two_discs_text(&tail), &mesh_dir())
        .and_then(SolidSpec::from_any)
        .map_err(|source| ReproduceError::Scene { case: name.clone(), source })?;
    let probe = setup(&scene).map_err(|source| ReproduceError::Scene { case: name.clone(), source })?;
    let system = &probe.problem.system;
    let mut widths =
        Widths { nodes: &system.contact_nodes, points: &system.mesh.points, nodal: Vec::new(), steps: Vec::new() };
    let run = run_scene(&scene, &mut [&mut widths]).map_err(|source| ReproduceError::Run { case: name, source })?;
    let s = &run.series;
    let named = |name: &str| s.columns.iter().find(|c| c.name() == name).and_then(|&c| s.column(c));
    let column = |name: &str| named(name).unwrap_or_default();
    let (energy, upper, lower) = (column("energy"), column("upper.momentum_y"), column("lower.momentum_y"));
    let mv = std::f64::consts::PI * RADIUS * RADIUS * SPEED;
    let steps = widths.steps;
    let peak_force = steps.iter().map(|x| x.force).fold(0.0, f64::max);
    let strong = steps.iter().filter(|x| x.force >= 0.5 * peak_force);
    let width_error = strong.clone().map(|x| ((x.half_width - x.hertz) / x.hertz).abs()).fold(0.0, f64::max);
    let width_resolution = strong.map(|x| x.resolution / x.hertz).fold(0.0, f64::max);
    let impulse = steps.windows(2).map(|w| 0.5 * (w[0].force + w[1].force) * (w[1].t - w[0].t)).sum::<f64>() / mv;
    let p0 = upper.first().copied().unwrap_or(f64::NAN) + lower.first().copied().unwrap_or(f64::NAN);
    let momentum_drift = upper.iter().zip(&lower).map(|(a, b)| (a + b - p0).abs()).fold(0.0, f64::max) / mv;
    Ok(DiscRun {
        contact_time: steps.iter().filter(|x| x.force > 0.0).count() as f64 * DT,
        peak_force,
        width_error,
        width_resolution,
        impulse,
        upper: -upper.last().copied().unwrap_or(f64::NAN) / mv,
        lower: -lower.last().copied().unwrap_or(f64::NAN) / mv,
        momentum_drift,
        energy_ratio: energy.last().copied().unwrap_or(f64::NAN) / energy.first().copied().unwrap_or(f64::NAN),
        steps,
    })
}

fn printed(r: &DiscRun) -> Vec<Printed> {
    [r.peak_force, r.width_error, r.width_resolution, r.contact_time, r.impulse, r.upper, r.lower, r.energy_ratio]
        .into_iter()
        .map(|v| Printed::Value(Some(v), 3))
        .collect()
}

/// The run and, where a printed digit needs them, its perturbed copies.
pub fn compute_two_discs() -> Result<Vec<DiscRun>, ReproduceError> {
    replicate(
        Copies::WherePrinted,
        |c| run_two_discs(c.index().map_or(0, |k| k + 1)),
        |r| r.as_ref().map_or(vec![Printed::Value(None, 0)], printed),
    )
    .into_iter()
    .collect()
}

/// The report's section.
pub fn two_discs_markdown(runs: &[DiscRun]) -> String {
    let d = |f: &dyn Fn(&DiscRun) -> f64| stable_digits(&runs.iter().map(|x| Some(f(x))).collect::<Vec<_>>(), 3);
    let mut out = format!(
        "\n### Two bodies: two discs colliding (Hertz)\n\n\
         Two P2 discs of radius {RADIUS} (λ = μ = 20, ρ = 1, plane strain), the upper one falling at V = {SPEED} onto \
         the lower one at rest from {GAP} above it (`fixtures/meshes/{MESH}`: size 0.25 near both poles); one \
         `[[pair]]` of their boundaries, node to segment on the curved sides; mod3, Crank–Nicolson, Δt = {DT}, \
         T = {END} (`study/src/paper/two_discs.rs`). Hertz for two equal cylinders: a = 2√(F R*/(π E*_pair)) with \
         R* = R/2, E*_pair = E*/2, the same as a disc on a rigid plane. At every step with Σ R ≥ half its peak, the \
         measured half-width a_h (from the nodes with R_i > 0) against Hertz's a(Σ R): the largest relative \
         difference, and a_h's resolution (half a node spacing) over a; Hertz's own error is of order (a/R)² ≈ 1 %. \
         The impulse ∫ Σ R dt and the final momenta are over m V (an elastic exchange of rigid discs: 1, 0 and 1); \
         the momentum drift is the largest change of the total over m V (round-off: the power of ten above it). Cells keep the digits the perturbed runs \
         share (speed perturbed by at most {:e}).\n\n\
         | peak Σ R | max abs(a_h − a)/a | resolution / a | contact time | impulse / mV | upper p(T) / (−mV) | \
         lower p(T) / (−mV) | momentum drift | E(T)/E(0) |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        PERTURBATION * 4.0
    );
    let _ = writeln!(
        out,
        "| {} | {} | {} | {} | {} | {} | {} | < {:.0e} | {} |",
        d(&|x| x.peak_force),
        d(&|x| x.width_error),
        d(&|x| x.width_resolution),
        d(&|x| x.contact_time),
        d(&|x| x.impulse),
        d(&|x| x.upper),
        d(&|x| x.lower),
        // Round-off (its digits change with the perturbation): the next power of ten above it.
        10f64.powf(runs.iter().map(|x| x.momentum_drift).fold(f64::MIN_POSITIVE, f64::max).log10().ceil()),
        d(&|x| x.energy_ratio),
    );
    let _ = write!(out, "\n![{TWO_DISCS_FIGURE}]({TWO_DISCS_FIGURE}.png)\n");
    out
}

/// The figure: Σ R against t, and a_h (with its resolution) against Hertz's a(Σ R), the
/// unperturbed run.
pub(super) fn two_discs_figure(runs: &[DiscRun]) -> FigureFile {
    let steps = runs.first().map(|r| r.steps.clone()).unwrap_or_default();
    let pressed: Vec<&Step> = steps.iter().filter(|x| x.force > 0.0 && x.half_width.is_finite()).collect();
    let curve = |label: &str, i: usize, f: &dyn Fn(&Step) -> f64, all: bool| Curve {
        label: label.into(),
        points: if all {
            steps.iter().map(|x| (x.t, f(x))).collect()
        } else {
            pressed.iter().map(|x| (x.t, f(x))).collect()
        },
        style: Style::Numeric(i),
    };
    let panels = vec![
        Panel {
            title: "contact force".into(),
            x_label: "t".into(),
            y_label: "Σ R".into(),
            curves: vec![curve("Σ R (mod3, CN)", 0, &|x| x.force, true)],
            x_range: None,
            y_range: None,
        },
        Panel {
            title: "half-width against Hertz".into(),
            x_label: "t".into(),
            y_label: "a".into(),
            curves: vec![
                curve("Hertz a(Σ R)", 1, &|x| x.hertz, false),
                curve("a_h − resolution", 2, &|x| x.half_width - x.resolution, false),
                curve("a_h", 0, &|x| x.half_width, false),
                curve("a_h + resolution", 2, &|x| x.half_width + x.resolution, false),
            ],
            x_range: None,
            y_range: None,
        },
    ];
    let times: Vec<f64> = steps.iter().map(|x| x.t).collect();
    let columns: Vec<Vec<f64>> = vec![
        steps.iter().map(|x| x.force).collect(),
        steps.iter().map(|x| x.half_width).collect(),
        steps.iter().map(|x| x.resolution).collect(),
        steps.iter().map(|x| x.hertz).collect(),
    ];
    FigureFile {
        stem: TWO_DISCS_FIGURE.into(),
        figure: Figure {
            title: format!("Two P2 discs colliding at V = {SPEED}: contact force and Hertz's half-width"),
            panels,
            columns: 2,
            panel_size: (620, 480),
        },
        header: ["t", "contact_force", "half_width", "resolution", "hertz_half_width"].map(String::from).to_vec(),
        rows: grid_rows(&times, &columns),
        periods: None,
    }
}
