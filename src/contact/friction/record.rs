//! What friction did, for the reports: [`FrictionRecord`], filled after each step from the
//! step's forces and increments ([`Dense::update_record`]).

use super::{Dense, Tangent};

/// What friction did, for the reports (every force in world components, on the body).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrictionRecord {
    /// `Σ` over steps and contact nodes of `−r_t,i · Δu_t,i` (≥ 0 up to round-off).
    pub dissipation: f64,
    /// `Σ Δt Σ_i r_t,i` over the run (world components; entries beyond dim are 0).
    pub impulse: [f64; 3],
    /// `Σ_i r_t,i` at the last step (world components).
    pub force: [f64; 3],
    /// Contact nodes with normal force and a positive bound at the last step that stick /
    /// slide (a bound of 0 carries no friction: such a node counts in neither).
    pub stick: usize,
    pub slip: usize,
    /// The largest `|r_t,i| − bound_i` over the run (bound `μ r_n,i` or `s a_i`): ≤ 0 up to
    /// round-off.
    pub max_cone_excess: f64,
    /// The largest natural residual of a step's solve over the run, relative to its largest
    /// force ([`super::cone`]'s module docs; 3D only, 0 in 2D where the states are solved exactly).
    pub residual: f64,
    /// Per contact node at the last step: 0 free, 1 stick, 2 slip.
    pub state: Vec<u8>,
    /// Per contact node at the last step: the friction traction `r_t,i / a_i` (world
    /// components; entries beyond dim are 0).
    pub traction: Vec<[f64; 3]>,
}

impl Dense {
    /// The record of the step just solved (forces r = f/σ on the body).
    pub(super) fn update_record(&mut self) {
        let mut force = [0.0; 3];
        let (mut stick, mut slip) = (0, 0);
        for (i, (&s, st)) in self.slots.iter().zip(&self.states).enumerate() {
            let closed = st.closed && self.f[s.n] > 0.0;
            self.record.state[i] = 0;
            self.record.traction[i] = [0.0; 3];
            let Some(t) = s.t else {
                self.was_closed[i] = closed;
                continue;
            };
            // The node's tangential reaction r_t (one or two components) and its increment Δu_t.
            let mut r_t = [self.f[t] / self.sigma, 0.0];
            let mut du = [self.span * self.y[t], 0.0];
            if let Some(t2) = s.t2 {
                (r_t[1], du[1]) = (self.f[t2] / self.sigma, self.span * self.y[t2]);
            }
            let bound = self.bound(i, &self.f) / self.sigma;
            let size = if s.t2.is_some() { r_t[0].hypot(r_t[1]) } else { r_t[0].abs() };
            self.record.max_cone_excess = self.record.max_cone_excess.max(size - bound);
            self.record.dissipation -= r_t[0] * du[0];
            if s.t2.is_some() {
                self.record.dissipation -= r_t[1] * du[1];
            }
            let slots = if s.t2.is_some() { 2 } else { 1 };
            for (&r, &a) in r_t.iter().zip(&s.axis).take(slots) {
                let axis = self.axes[a];
                for k in 0..3 {
                    force[k] += r * axis[k];
                    self.record.traction[i][k] += r * axis[k] / self.areas[i];
                }
            }
            // Stick and slip are friction's states: a node whose bound is 0 (μ = 0, s = 0, or
            // Tresca on a node free at the start of the step) carries none and counts as free.
            if closed && bound > 0.0 {
                if matches!(st.tangent, Tangent::Slip(_) | Tangent::Slide(_)) {
                    slip += 1;
                    self.record.state[i] = 2;
                } else {
                    stick += 1;
                    self.record.state[i] = 1;
                }
            }
            self.was_closed[i] = closed;
        }
        for (imp, fw) in self.record.impulse.iter_mut().zip(force) {
            *imp += self.dt * fw;
        }
        self.record.force = force;
        self.record.stick = stick;
        self.record.slip = slip;
    }
}
