//! What a body against a rigid plane reports of its states (issue 19), the solid's own series
//! columns and summary keys ([`crate::problem::GeometryView::own_columns`],
//! [`crate::problem::GeometryView::own_summary`]): with `R_i = −λ_i ≥ 0` the reaction of
//! contact node i and `d_i = u_n,i + g_i ≥ 0` its distance to the obstacle,
//!
//! ```text
//! contact_force = Σ_i R_i,   active_nodes = #{i : R_i > 0},   min_distance = min_i d_i,
//! momentum_k = P_k = 1ᵀ M V_k,   mean_u_k = ū_k = 1ᵀ M_std U_k / |Ω|   (world components),
//! ```
//!
//! and over a run the summary keys `max_contact_force` (max over t_n of Σ_i R_i),
//! `min_distance` (min over t_n of min_i d_i), and at the last state `final_active_nodes`,
//! `final_momentum` and `final_mean_displacement` (dim entries each). The box reports none of
//! these (its reports are the driver's).

use super::assembly::SolidSystem;
use crate::column::Column;
use crate::problem::OwnSummary;

/// A body's own columns, in the order of [`values`]: the total contact force, then
/// [`Column::BODY`] (derived from it: one list of the body-only columns).
pub const COLUMNS: [Column; 9] = {
    let mut all = [Column::ContactForce; 9];
    let mut k = 1;
    while k < 9 {
        all[k] = Column::BODY[k - 1];
        k += 1;
    }
    all
};

/// The values of [`COLUMNS`] from a state's reports.
pub fn values(contact_force: f64, active: usize, min_distance: f64, momentum: [f64; 3], mean_u: [f64; 3]) -> [f64; 9] {
    let [p0, p1, p2] = momentum;
    let [m0, m1, m2] = mean_u;
    [contact_force, active as f64, min_distance, p0, p1, p2, m0, m1, m2]
}

impl SolidSystem {
    /// The values of [`COLUMNS`] at a state (a body only; module docs), into `out`.
    pub fn report(&self, u: &[f64], v: &[f64], lambda: &[f64], out: &mut [f64]) {
        let Some((momentum, mean_u)) = self.moments(u, v) else { return };
        let s = &self.system;
        let (mut contact_force, mut active, mut min_distance) = (0.0, 0, f64::INFINITY);
        for ((&c, &lb), &l) in s.contact.iter().zip(&s.lower).zip(lambda) {
            contact_force -= l;
            active += usize::from(l < 0.0);
            min_distance = min_distance.min(u[c] - lb);
        }
        out.copy_from_slice(&values(contact_force, active, min_distance, momentum, mean_u));
    }
}

/// The summary keys of a body (module docs), from the values of [`COLUMNS`] at each state.
#[derive(Debug, Clone)]
pub struct BodyKeys {
    dim: usize,
    /// max Σ R_i, min d_i, and the last state's values (None before the first state).
    seen: Option<(f64, f64, [f64; 9])>,
}

impl BodyKeys {
    pub fn new(dim: usize) -> Self {
        BodyKeys { dim, seen: None }
    }
}

impl OwnSummary for BodyKeys {
    fn observe(&mut self, values: &[f64]) {
        let (max_force, min_distance) = self.seen.map_or((f64::NEG_INFINITY, f64::INFINITY), |(m, d, _)| (m, d));
        let mut last = [0.0; 9];
        last.copy_from_slice(values);
        self.seen = Some((
            crate::observe::max_nan(max_force, values[0]),
            crate::observe::min_nan(min_distance, values[2]),
            last,
        ));
    }

    fn keys(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut keys = serde_json::Map::new();
        let Some((max_force, min_distance, last)) = self.seen else { return keys };
        let numbers = |v: &[f64]| serde_json::Value::from(v.to_vec());
        keys.insert("max_contact_force".into(), max_force.into());
        keys.insert("min_distance".into(), min_distance.into());
        keys.insert("final_active_nodes".into(), (last[1] as u64).into());
        keys.insert("final_momentum".into(), numbers(&last[3..3 + self.dim]));
        keys.insert("final_mean_displacement".into(), numbers(&last[6..6 + self.dim]));
        keys
    }
}
