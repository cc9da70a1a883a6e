//! Bar scenes: the problem of a `[bar]` scene and its run (the driver is [`crate::driver`],
//! the observers [`crate::observe`]). Nothing here does I/O but [`run_scene_into`] (through
//! [`crate::output`]).

use super::{Setup, setup_error};
use crate::bar::assembly::{AssemblyError, Bar, BarSystem, Load};
use crate::characteristics::{Characteristics, CharacteristicsError, InitialData};
use crate::exact::{Exact, ImpactingBar, by_characteristics, paper_data};
use crate::output::{OutputDir, commit_run, summary_json};
use crate::scene::{BarScene, Force, Initial, SceneError};
use crate::schemes::SchemeError;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum RunError {
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error(transparent)]
    Scheme(#[from] SchemeError),
    #[error("the exact solution of this scene: {0}")]
    Exact(#[from] CharacteristicsError),
    /// The scene's problem could not be set up (exit code 2: the input is at fault).
    #[error(transparent)]
    Setup(SceneError),
}

pub use crate::problem::Problem;
// The driver and observers every geometry shares, reachable from the bar's entry point too.
use super::RunFolderError;
pub use crate::driver::{
    Divergence, DivergenceCriterion, DivergenceReason, Needs, Observer, Outcome, Sample, integrate, integrate_watched,
};
pub use crate::observe::{SeriesRecorder, Status, Summary, SummaryObserver};

impl Problem {
    /// The bar of a scene: material, far end, gap, initial data and force (module docs of
    /// [`crate::bar::assembly`]); the exact solution where it is known.
    pub fn from_scene(scene: &BarScene) -> Result<Problem, RunError> {
        let spec = &scene.geometry;
        let bar = Bar { length: spec.length, elements: spec.elements };
        let weights = BarSystem::weights(bar, &scene.mass)?;
        let field;
        let load = match &spec.force {
            Force::Constant(f) => Load::Constant(*f),
            Force::Field(e) => {
                field = |x: f64| e.eval(&[x]);
                Load::Field(&field)
            }
            Force::Transient(_) => Load::Constant(0.0), // F(t) below
        };
        let mut system = BarSystem::assemble(bar, weights, spec.material, spec.far_end, &load).with_gap(spec.gap);
        if let Force::Transient(e) = &spec.force {
            let (e, weights) = (e.clone(), system.weights.clone());
            let forcing = move |t: f64, out: &mut [f64]| {
                let f = |x: f64| e.eval(&[x, t]);
                crate::bar::assembly::load_into(&bar, &weights, &Load::Field(&f), out);
            };
            system.system = system.system.with_forcing(crate::system::Forcing(std::sync::Arc::new(forcing)));
        }
        let paper = ImpactingBar { length: bar.length };
        let (u0, v0) = match &spec.initial {
            Initial::Paper => (system.interpolate(|x| paper.initial_displacement(x)), vec![0.0; system.n()]),
            Initial::Fields { displacement, velocity } => {
                (system.interpolate(|x| displacement.eval(&[x])), system.interpolate(|x| velocity.eval(&[x])))
            }
        };
        let exact = if !scene.has_exact_solution() {
            None
        } else if spec.initial == Initial::Paper && spec.is_paper_bar() {
            Some(Exact::Paper(paper))
        } else {
            Some(Exact::General(std::sync::Arc::new(general_exact(scene)?)))
        };
        Ok(Problem { system, u0, v0, exact })
    }

    /// The benchmark problem for a mass on a bar of length L with m elements (f = 0).
    pub fn benchmark(length: f64, elements: usize, mass: &crate::mass::MassKind) -> Result<Problem, RunError> {
        let system = BarSystem::new(Bar { length, elements }, mass, 0.0)?;
        let exact = ImpactingBar { length };
        let u0 = system.interpolate(|x| exact.initial_displacement(x));
        Ok(Problem { system, u0, v0: vec![0.0; elements], exact: Some(Exact::Paper(exact)) })
    }
}

/// The exact solution by characteristics of a bar scene without body force: the continuous
/// initial data (expressions are smooth closures, resolved to about 1e-14 by the solver; the
/// paper's data piecewise linear, exact).
fn general_exact(scene: &BarScene) -> Result<Characteristics, CharacteristicsError> {
    let s = &scene.geometry;
    let exact = |data| by_characteristics(s.length, s.material, s.far_end, s.gap, data, scene.time.end);
    match &s.initial {
        Initial::Paper => {
            let (x, u, v) = paper_data(s.length);
            exact(InitialData::PiecewiseLinear { x: &x, u: &u, v: &v })
        }
        Initial::Fields { displacement, velocity } => {
            let (u, v) = (|x: f64| displacement.eval(&[x]), |x: f64| velocity.eval(&[x]));
            exact(InitialData::Smooth { u: &u, v: &v })
        }
    }
}

/// The problem and scheme of a bar scene; a failure names the keys that shape the matrices.
pub fn setup(scene: &BarScene) -> Result<Setup, SceneError> {
    let keys = "bar.length, bar.elements, bar.density, bar.modulus, mass.*, scheme.*, time.dt";
    let problem = Problem::from_scene(scene).map_err(|e| setup_error(keys, e))?;
    let scheme = problem.scheme(&scene.scheme, scene.time.dt).map_err(|e| setup_error(keys, e))?;
    Ok(Setup { problem, scheme })
}

/// Runs a scene: the summary always, plus the requested series, held in memory (for library
/// users; `massredist run` streams it: [`run_scene_into`]). A run that diverges
/// ([`DivergenceCriterion`] with `output.divergence_factor`) stops there and is still a result:
/// `Summary::divergence` says where and why, the summary and series hold the finite states.
pub fn run_scene(scene: &BarScene, extra: &mut [&mut dyn Observer]) -> Result<(Summary, SeriesRecorder), RunError> {
    let rows = if scene.output.series.is_empty() { 0 } else { scene.time.steps / scene.output.every + 1 };
    let mut series = SeriesRecorder::new(scene.output.series.clone(), scene.output.every, rows);
    let mut observers: Vec<&mut dyn Observer> = vec![&mut series];
    for o in extra.iter_mut() {
        observers.push(&mut **o);
    }
    let summary = run_observed(scene, &mut observers)?;
    Ok((summary, series))
}

/// `massredist run` for a bar scene: runs it into the output folder `out` prepared before
/// computing, `series.csv` streamed into its temporary folder as the run produces it (memory does
/// not depend on the number of steps), then `summary.json` and `scene.resolved.toml`, and commits
/// it ([`OutputDir::commit`]). On an error `out` is dropped, which removes the temporary folder.
pub fn run_scene_into(
    scene: &BarScene,
    out: OutputDir,
    extra: &mut [&mut dyn Observer],
) -> Result<Summary, RunFolderError<RunError>> {
    let summary = super::stream_series(&out, &scene.output, extra, |obs| run_observed(scene, obs))?;
    commit_run(out, &summary_json(scene, &summary), &scene.resolved_toml())?;
    Ok(summary)
}

/// Runs a scene with its summary and `observers` (the series among them).
fn run_observed(scene: &BarScene, observers: &mut [&mut dyn Observer]) -> Result<Summary, RunError> {
    let Setup { problem, mut scheme } = setup(scene).map_err(RunError::Setup)?;
    let steps = scene.time.steps;
    let mut summary = SummaryObserver::new(&problem, steps, scene.time.dt, scene.output.summary_l2);
    let mut all: Vec<&mut dyn Observer> = vec![&mut summary];
    for o in observers.iter_mut() {
        all.push(&mut **o);
    }
    let criterion = DivergenceCriterion { energy_factor: scene.output.divergence_factor };
    // The outcome reaches the summary through `Observer::diverged`.
    let _ = integrate_watched(&problem, scheme.as_mut(), steps, &criterion, &mut all)?;
    Ok(summary.finish())
}
