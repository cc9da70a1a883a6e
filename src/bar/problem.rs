//! The problem a bar scene poses ([`BarSpec`] → [`BarProblem`]: the assembled bar, the
//! interpolated initial data and the exact solution where it is known), and the bar's place in
//! the one run path ([`GeometrySpec`]).

use super::assembly::{AssemblyError, Bar, BarSystem, Load, load_into};
use super::spec::{BarSpec, Initial};
use crate::characteristics::{Characteristics, CharacteristicsError, InitialData};
use crate::exact::{Exact, ImpactingBar, by_characteristics, paper_data};
use crate::medium::Force;
use crate::problem::Problem;
use crate::spec::Scene;
use crate::spec::{GeometrySpec, Totals};
use serde::Serialize;
use thiserror::Error;

/// A bar problem.
pub type BarProblem = Problem<BarSystem>;

/// Why a bar problem cannot be built.
#[derive(Debug, Error)]
pub enum BarError {
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error("the exact solution of this scene: {0}")]
    Exact(#[from] CharacteristicsError),
}

impl BarProblem {
    /// The bar of a scene: material, far end, gap, initial data and force (module docs of
    /// [`super::assembly`]); the exact solution where it is known.
    pub fn from_scene(scene: &Scene<BarSpec>) -> Result<BarProblem, BarError> {
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
                load_into(&bar, &weights, &Load::Field(&f), out);
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
        let exact = if !spec.has_exact_solution() {
            None
        } else if spec.initial == Initial::Paper && spec.is_paper_bar() {
            Some(Exact::Paper(paper))
        } else {
            Some(Exact::General(std::sync::Arc::new(general_exact(spec, scene.time.exact_end())?)))
        };
        Ok(Problem { system, u0, v0, exact })
    }

    /// The benchmark problem for a mass on a bar of length L with m elements (f = 0).
    pub fn benchmark(length: f64, elements: usize, mass: &crate::mass::MassKind) -> Result<BarProblem, BarError> {
        let system = BarSystem::new(Bar { length, elements }, mass, 0.0)?;
        let exact = ImpactingBar { length };
        let u0 = system.interpolate(|x| exact.initial_displacement(x));
        Ok(Problem { system, u0, v0: vec![0.0; elements], exact: Some(Exact::Paper(exact)) })
    }
}

/// The exact solution by characteristics up to `t_end` of a bar without body force: the
/// continuous initial data (expressions are smooth closures, resolved to about 1e-14 by the
/// solver; the paper's data piecewise linear, exact).
fn general_exact(s: &BarSpec, t_end: f64) -> Result<Characteristics, CharacteristicsError> {
    let exact = |data| by_characteristics(s.length, s.material, s.far_end, s.gap, data, t_end);
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

/// A bar's `summary.json` has no keys beyond those every geometry writes.
#[derive(Serialize)]
pub struct BarHead {}

impl GeometrySpec for BarSpec {
    type System = BarSystem;
    type Error = BarError;
    type Head = BarHead;
    const SETUP_KEYS: &'static str = "bar.length, bar.elements, bar.density, bar.modulus, mass.*, scheme.*, time.dt";

    fn elements(&self) -> usize {
        self.elements
    }

    fn problem(scene: &Scene<Self>) -> Result<BarProblem, BarError> {
        BarProblem::from_scene(scene)
    }

    fn summary_head(_: &Scene<Self>, _: &Totals) -> BarHead {
        BarHead {}
    }

    fn totals(system: &BarSystem) -> Totals {
        Totals { total_mass: system.total_mass(), unknowns: system.n() }
    }
}
