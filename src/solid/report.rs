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
//!
//! Several bodies (`super::bodies`) report the same over all of them (the totals), then each
//! pair's `<pair>.contact_force`, `<pair>.active_nodes`, `<pair>.min_distance` (its contact
//! nodes only) and each body's `<body>.momentum_k`, `<body>.mean_u_k` (its nodes only; k < dim),
//! in that order ([`dotted_columns`]); the summary adds the nested objects
//! `"pairs": {"<pair>": {max_contact_force, min_distance, final_active_nodes, contact_time}}`
//! and `"bodies": {"<body>": {final_momentum, final_mean_displacement}}`. A pair's
//! `contact_time` is read off its force: the sum of t_n − t_(n−1) over the states n with
//! Σ R_i(t_n) > 0.

use super::assembly::SolidSystem;
pub use super::bodies::BodiesLayout;
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

/// Per pair: contact force, active nodes, min distance.
const PAIR_COLUMNS: [&str; 3] = ["contact_force", "active_nodes", "min_distance"];

/// The dotted columns of several bodies (module docs), their slots after [`COLUMNS`].
pub fn dotted_columns(pairs: &[String], bodies: &[String], dim: usize) -> Vec<Column> {
    let mut names: Vec<String> = Vec::new();
    for p in pairs {
        names.extend(PAIR_COLUMNS.iter().map(|c| format!("{p}.{c}")));
    }
    for b in bodies {
        for c in [Column::Momentum(0), Column::MeanU(0)] {
            for k in 0..dim as u8 {
                let c = if matches!(c, Column::Momentum(_)) { Column::Momentum(k) } else { Column::MeanU(k) };
                names.push(format!("{b}.{}", c.name()));
            }
        }
    }
    names
        .into_iter()
        .enumerate()
        .map(|(k, n)| Column::Dotted { name: crate::column::intern(n), slot: (COLUMNS.len() + k) as u8 })
        .collect()
}

/// Σ R_i, #{R_i > 0}, min d_i over the contact slots `slots`.
fn contact_of(
    s: &crate::system::ContactSystem<crate::linalg::sparse::SpMat>,
    u: &[f64],
    lambda: &[f64],
    slots: std::ops::Range<usize>,
) -> (f64, usize, f64) {
    let (mut contact_force, mut active, mut min_distance) = (0.0, 0, f64::INFINITY);
    for k in slots {
        let l = lambda[k];
        contact_force -= l;
        active += usize::from(l < 0.0);
        min_distance = min_distance.min(u[s.contact[k]] - s.lower[k]);
    }
    (contact_force, active, min_distance)
}

impl SolidSystem {
    /// The values of the own columns at a state (a body only; module docs), into `out`:
    /// [`COLUMNS`], then several bodies' [`dotted_columns`].
    pub fn report(&self, u: &[f64], v: &[f64], lambda: &[f64], out: &mut [f64]) {
        let Some((momentum, mean_u)) = self.moments(u, v) else { return };
        let s = &self.system;
        let (contact_force, active, min_distance) = contact_of(s, u, lambda, 0..s.contact.len());
        out[..COLUMNS.len()].copy_from_slice(&values(contact_force, active, min_distance, momentum, mean_u));
        let Some(layout) = &self.bodies else { return };
        let mut k = COLUMNS.len();
        for slots in &layout.slots {
            let (f, a, d) = contact_of(s, u, lambda, slots.clone());
            out[k..k + 3].copy_from_slice(&[f, a as f64, d]);
            k += 3;
        }
        let (uf, vf) = (self.in_frames(u), self.in_frames(v));
        let dim = self.mesh.dim;
        for (b, &volume) in layout.volumes.iter().enumerate() {
            let (p, m) = self.moments_in(&uf, &vf, layout.node0[b]..layout.node0[b + 1], volume);
            out[k..k + dim].copy_from_slice(&p[..dim]);
            out[k + dim..k + 2 * dim].copy_from_slice(&m[..dim]);
            k += 2 * dim;
        }
    }
}

/// The summary keys of a body (module docs), from the values of [`COLUMNS`] at each state.
#[derive(Debug, Clone)]
pub struct BodyKeys {
    dim: usize,
    /// max Σ R_i, min d_i, and the last state's values (None before the first state).
    seen: Option<(f64, f64, [f64; 9])>,
    /// Several bodies' keys.
    bodies: Option<BodiesKeys>,
}

/// What several bodies accumulate: their layout, per pair max Σ R_i, min d_i and contact time,
/// the last state's time and values.
#[derive(Debug, Clone)]
struct BodiesKeys {
    layout: BodiesLayout,
    pairs: Vec<[f64; 3]>,
    last_t: f64,
    last: Vec<f64>,
}

impl BodyKeys {
    pub fn new(dim: usize) -> Self {
        BodyKeys { dim, seen: None, bodies: None }
    }

    /// The keys of several bodies (module docs).
    pub fn of_bodies(dim: usize, layout: BodiesLayout) -> Self {
        let pairs = vec![[f64::NEG_INFINITY, f64::INFINITY, 0.0]; layout.pairs.len()];
        BodyKeys { dim, seen: None, bodies: Some(BodiesKeys { layout, pairs, last_t: f64::NAN, last: Vec::new() }) }
    }
}

impl OwnSummary for BodyKeys {
    fn observe(&mut self, t: f64, values: &[f64]) {
        if let Some(BodiesKeys { pairs, last_t, last, .. }) = self.bodies.as_mut() {
            for (p, acc) in pairs.iter_mut().enumerate() {
                let v = &values[COLUMNS.len() + 3 * p..];
                acc[0] = crate::observe::max_nan(acc[0], v[0]);
                acc[1] = crate::observe::min_nan(acc[1], v[2]);
                if v[0] > 0.0 && last_t.is_finite() {
                    acc[2] += t - *last_t;
                }
            }
            *last_t = t;
            last.clear();
            last.extend_from_slice(values);
        }
        let (max_force, min_distance) = self.seen.map_or((f64::NEG_INFINITY, f64::INFINITY), |(m, d, _)| (m, d));
        let mut last = [0.0; 9];
        last.copy_from_slice(&values[..9]);
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
        if let Some(BodiesKeys { layout, pairs, last: values, .. }) = &self.bodies {
            let d = self.dim;
            let mut all = serde_json::Map::new();
            for (p, (name, acc)) in layout.pairs.iter().zip(pairs).enumerate() {
                let v = &values[COLUMNS.len() + 3 * p..];
                let mut one = serde_json::Map::new();
                one.insert("max_contact_force".into(), acc[0].into());
                one.insert("min_distance".into(), acc[1].into());
                one.insert("final_active_nodes".into(), (v[1] as u64).into());
                one.insert("contact_time".into(), acc[2].into());
                all.insert(name.clone(), one.into());
            }
            keys.insert("pairs".into(), all.into());
            let mut all = serde_json::Map::new();
            let first = COLUMNS.len() + 3 * layout.pairs.len();
            for (b, name) in layout.bodies.iter().enumerate() {
                let v = &values[first + 2 * d * b..];
                let mut one = serde_json::Map::new();
                one.insert("final_momentum".into(), numbers(&v[..d]));
                one.insert("final_mean_displacement".into(), numbers(&v[d..2 * d]));
                all.insert(name.clone(), one.into());
            }
            keys.insert("bodies".into(), all.into());
        }
        keys
    }
}
