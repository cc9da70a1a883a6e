//! The driver: a problem, a scheme, a loop, and observers that see the states.
//!
//! Observers state what they need ([`Needs`]) and how often ([`Observer::every`]); the driver
//! keeps the cadence (argmin's `ObserverMode::Every`) and computes what the observers due at a
//! step need (energy, exact L² error, y-variation) once, for all of them. Recording, summaries,
//! progress bars and files are observers or live at the edge; nothing here does I/O.

use crate::exact::Exact;
use crate::problem::{Geometry, GeometryView, Problem};
use crate::schemes::{Scheme, SchemeError, StateView};

/// What an observer needs computed at a step, beyond the state itself.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Needs {
    /// The discrete energy ½VᵀMV + ½UᵀSU − UᵀF.
    pub energy: bool,
    /// The exact L²(Ω) error and the L² norm of the exact solution's nodal interpolant.
    pub l2: bool,
    /// The largest variation of u across y (plates).
    pub y_variation: bool,
}

impl Needs {
    /// What either needs.
    pub fn or(self, o: Needs) -> Needs {
        Needs { energy: self.energy || o.energy, l2: self.l2 || o.l2, y_variation: self.y_variation || o.y_variation }
    }
}

/// What the driver hands to observers at a step. Quantities nobody due at this step needs are
/// NaN.
#[derive(Debug, Clone, Copy)]
pub struct Sample<'a> {
    pub state: StateView<'a>,
    pub geometry: &'a dyn GeometryView,
    pub exact: Option<&'a Exact>,
    pub energy: f64,
    /// Exact ‖u_h − u(·, t_n)‖_{L²(Ω)}.
    pub l2_error: f64,
    /// ‖I_h u(·, t_n)‖_{L²(Ω)}: the norm of the nodal interpolant of the exact solution.
    pub exact_interp_norm: f64,
    /// u at the reference contact node (x = 0, lowest y; u_0 for a bar).
    pub u0: f64,
    /// Mean of u over Γ_C (u_0 for a bar).
    pub u_mean: f64,
    /// Total contact force Σ_c λ_c (≤ 0).
    pub contact_force: f64,
    /// Mean contact pressure Σ_c λ_c / |Γ_C| (λ for a bar).
    pub pressure: f64,
    /// max |u(x, y) − u(x, y_min)| (0 for a bar).
    pub y_variation: f64,
    /// Principal pivots of the step's contact solves.
    pub pivots: usize,
}

pub trait Observer {
    fn needs(&self) -> Needs {
        Needs::default()
    }
    /// The observer sees the states n with n % every == 0 (t_0 included).
    fn every(&self) -> usize {
        1
    }
    fn observe(&mut self, sample: &Sample);
}

/// Runs `steps` steps, showing the states (t_0 included) to the observers due at each.
pub fn integrate<G: Geometry>(
    problem: &Problem<G>,
    scheme: &mut dyn Scheme,
    steps: usize,
    observers: &mut [&mut dyn Observer],
) -> Result<(), SchemeError> {
    let cadence: Vec<usize> = observers.iter().map(|o| o.every().max(1)).collect();
    let needs: Vec<Needs> = observers.iter().map(|o| o.needs()).collect();
    let geometry: &dyn GeometryView = &problem.system;
    let mut interp = Vec::new();
    let mut show = |scheme: &dyn Scheme, observers: &mut [&mut dyn Observer]| {
        let state = scheme.state();
        let due = |k: usize| state.n.is_multiple_of(cadence[k]);
        let need = (0..observers.len()).filter(|&k| due(k)).fold(Needs::default(), |n, k| n.or(needs[k]));
        let energy = if need.energy { problem.energy(state.u, state.v) } else { f64::NAN };
        let (l2_error, exact_interp_norm) = match (need.l2, &problem.exact) {
            (true, Some(ex)) => {
                (geometry.l2_error(state.u, ex, state.t), geometry.interp_norm(ex, state.t, &mut interp))
            }
            _ => (f64::NAN, f64::NAN),
        };
        let contact_force: f64 = state.lambda.iter().sum();
        let sample = Sample {
            state,
            geometry,
            exact: problem.exact.as_ref(),
            energy,
            l2_error,
            exact_interp_norm,
            u0: state.u[geometry.contact()[0]],
            u_mean: geometry.contact_mean(state.u),
            contact_force,
            pressure: contact_force / geometry.contact_measure(),
            y_variation: if need.y_variation { geometry.y_variation(state.u) } else { f64::NAN },
            pivots: scheme.pivots(),
        };
        for (k, o) in observers.iter_mut().enumerate() {
            if due(k) {
                o.observe(&sample);
            }
        }
    };
    show(scheme, observers);
    for _ in 0..steps {
        scheme.step()?;
        show(scheme, observers);
    }
    Ok(())
}
