//! The observers of a run, for every geometry: the series recorder (`series.csv`), the summary
//! (`summary.json`), VTU frames and an energy recorder. Their cadence is kept by the driver
//! ([`crate::driver::Observer::every`]).

pub use crate::column::Column;
use crate::driver::{Divergence, Needs, Observer, Sample};
use crate::exact::Exact;
use crate::problem::{Geometry, GeometryView, OwnSummary, Problem};
use serde::Serialize;

/// Records the requested columns every `every` steps (t_0 included), in memory: for library
/// users who want the values (the command line streams them instead, with
/// [`crate::output::SeriesWriter`]).
#[derive(Debug, Clone)]
pub struct SeriesRecorder {
    pub columns: Vec<Column>,
    pub every: usize,
    /// Row-major: t, then one value per column.
    pub rows: Vec<f64>,
}

impl SeriesRecorder {
    pub fn new(columns: Vec<Column>, every: usize, expected_rows: usize) -> Self {
        let rows = Vec::with_capacity(expected_rows * (columns.len() + 1));
        Self { columns, every: every.max(1), rows }
    }

    pub fn width(&self) -> usize {
        self.columns.len() + 1
    }

    /// Iterates over recorded rows (t first).
    pub fn iter_rows(&self) -> impl Iterator<Item = &[f64]> {
        self.rows.chunks(self.width())
    }

    /// The recorded values of one column (None if not recorded).
    pub fn column(&self, c: Column) -> Option<Vec<f64>> {
        let k = self.columns.iter().position(|&x| x == c)? + 1;
        Some(self.iter_rows().map(|r| r[k]).collect())
    }

    pub fn times(&self) -> Vec<f64> {
        self.iter_rows().map(|r| r[0]).collect()
    }
}

/// What the series columns need computed ([`Observer::needs`] of [`SeriesRecorder`] and of
/// [`crate::output::SeriesWriter`]).
pub fn series_needs(columns: &[Column]) -> Needs {
    Needs { energy: columns.contains(&Column::Energy), l2: columns.contains(&Column::L2Error), y_variation: false }
}

/// The most columns a geometry computes itself ([`GeometryView::own_columns`]).
pub const MAX_OWN_COLUMNS: usize = 128;

/// The values of the geometry's own columns at a sample, into `out` (None if the geometry has
/// none, or none of them is `wanted`); computed once per row or state.
fn own_values<'o>(
    s: &Sample,
    wanted: impl Fn(&[Column]) -> bool,
    out: &'o mut [f64; MAX_OWN_COLUMNS],
) -> Option<&'o [f64]> {
    let own = s.geometry.own_columns();
    if own.is_empty() || !wanted(own) {
        return None;
    }
    let out = &mut out[..own.len()];
    s.geometry.own_values(s.state.u, s.state.v, s.state.lambda, out);
    Some(out)
}

/// Appends the series row of a sample to `row`: t, then the value of each column (one line of
/// `series.csv`). A column the geometry computes itself takes its value (a body's
/// `contact_force` is its total reaction `Σ R_i ≥ 0`); one nobody computes is NaN.
pub fn push_series_row(columns: &[Column], s: &Sample, row: &mut Vec<f64>) {
    row.push(s.state.t);
    let mut buffer = [0.0; MAX_OWN_COLUMNS];
    let values = own_values(s, |own| columns.iter().any(|c| own.contains(c)), &mut buffer);
    let own = s.geometry.own_columns();
    row.extend(columns.iter().map(|&c| {
        let mine = values.and_then(|v| own.iter().position(|&o| o == c).map(|k| v[k]));
        mine.unwrap_or_else(|| series_value(c, s))
    }));
}

/// The value of series column `c` at a sample as the driver computes it for every geometry
/// (one CSV cell of `series.csv`; NaN for a geometry's own columns).
fn series_value(c: Column, s: &Sample) -> f64 {
    let t = s.state.t;
    match c {
        Column::U0 => s.u0,
        Column::U1 => s.state.u[1],
        Column::UMean => s.u_mean,
        Column::Lambda => s.pressure,
        Column::ContactForce => s.contact_force,
        Column::ActiveNodes | Column::MinDistance | Column::Momentum(_) | Column::MeanU(_) | Column::Dotted { .. } => {
            f64::NAN
        }
        Column::Energy => s.energy,
        Column::L2Error => s.l2_error,
        Column::ExactU0 => s.exact.map_or(f64::NAN, |e| e.u0(t)),
        Column::ExactLambda => s.exact.map_or(f64::NAN, |e| e.lambda(t)),
        Column::Pivots => s.pivots as f64,
        // A solid's friction (0 for a frictionless law: nothing slides, nothing is dissipated).
        Column::FrictionDissipation => s.friction.map_or(0.0, |f| f.dissipation),
        Column::StickNodes => s.friction.map_or(0.0, |f| f.stick as f64),
        Column::SlipNodes => s.friction.map_or(0.0, |f| f.slip as f64),
        Column::TangentialForce(k) => s.friction.map_or(0.0, |f| f.force[k.min(2) as usize]),
    }
}

impl Observer for SeriesRecorder {
    fn needs(&self) -> Needs {
        series_needs(&self.columns)
    }

    fn every(&self) -> usize {
        self.every
    }

    fn observe(&mut self, s: &Sample) {
        if self.columns.is_empty() {
            return;
        }
        push_series_row(&self.columns, s, &mut self.rows);
    }
}

/// Whether a run went to its end (`status` in `summary.json`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Every step was taken.
    Ok,
    /// The run stopped at a divergence ([`crate::driver::DivergenceCriterion`]).
    Diverged,
}

/// The summary of a run (`summary.json`), accumulated in the step loop. A `null` (`None`) means
/// "not applicable" (no exact solution, no impact, …), never "not finite". A diverged run's
/// summary describes the states up to the last finite one shown (the energies, errors and
/// extremes are over t_0 … that state); `divergence` says where it stopped and why.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub status: Status,
    /// Where and why the run stopped (null for a run with status "ok").
    pub divergence: Option<Divergence>,
    /// The steps whose states this summary describes: `steps_requested` for a completed run,
    /// the last state shown for a diverged one (0 when even t_0 was not finite).
    pub steps: usize,
    /// The steps the scene asked for (`time.end / time.dt`).
    pub steps_requested: usize,
    pub h: f64,
    pub dt: f64,
    /// max over t_n of ‖u_h(t_n) − u(t_n)‖_{L²(Ω)} (null without exact solution).
    pub linf_l2_error: Option<f64>,
    /// `linf_l2_error` / max over t_n of ‖I_h u(t_n)‖_{L²(Ω)}.
    pub linf_l2_error_relative: Option<f64>,
    /// max over n of |u_0ⁿ − u(0, t_n)| (u_0 at the reference contact node).
    pub max_contact_error: Option<f64>,
    /// sqrt(Σ_n w_n Δt (λⁿ − λ(t_n))²) with trapezoidal weights w_n: the L²(0,T) error of the
    /// contact pressure λ = Σ_c λ_c / |Γ_C|.
    pub l2_lambda_error: Option<f64>,
    pub energy_initial: f64,
    pub energy_final: f64,
    pub energy_min: f64,
    pub energy_max: f64,
    /// Exact energy (null without exact solution; L|Ω|/(8L) for the paper's benchmark).
    pub energy_exact: Option<f64>,
    /// First t_n at which some contact node carries force, λ_cⁿ < 0 (Σ R > 0; read off the
    /// force, not the displacement: [`crate::driver::ContactStats::touching`]).
    pub first_impact_time: Option<f64>,
    /// First t_n after the first impact at which no contact node carries force (every λ_cⁿ = 0).
    pub first_release_time: Option<f64>,
    /// `first_impact_time` − the exact first impact (L for the paper's benchmark), null if no
    /// impact or no exact solution.
    pub impact_time_shift: Option<f64>,
    /// `first_release_time` − the exact end of the first contact (2L for the paper's benchmark).
    pub release_time_shift: Option<f64>,
    pub final_u0: f64,
    /// min over n and contact nodes of u_c (≥ −gap by complementarity).
    pub min_u0: f64,
    /// max over n and contact nodes of λ_c (≤ 0 by complementarity).
    pub max_lambda: f64,
    /// max over n and contact nodes of |(u_c + gap) λ_c| (0 by complementarity).
    pub max_complementarity_product: f64,
    /// Largest per-step energy increase `max_n (E^{n+1} − Eⁿ)` (≤ 0 for a dissipative scheme);
    /// null if no step was seen (a run that diverged at step 1).
    pub energy_max_increase: f64,
    /// The step n+1 at which it happened.
    pub energy_max_increase_step: usize,
    /// The same, over the steps n ≥ 1 only (null if there are none).
    pub energy_max_increase_after_first: f64,
    /// max over t_n of `max_{nodes} |u(x, y) − u(x, y_min)|` (plates only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_y_variation: Option<f64>,
    /// Largest pivot count of one step's contact solves.
    pub max_pivots: usize,
    /// An explicit scheme's stable step Δt_c (null for implicit schemes), and which estimator
    /// gave it (issue 31, item 3): `"lanczos"` (converged Ritz value, ~1e-12 relative), or,
    /// where Lanczos stopped unconverged, the smaller of two upper bounds of λ_max, so that
    /// Δt_c errs on the small side: `"element"` (the element eigenvalue inequality, where the
    /// stiffness knows its cells) or `"gershgorin"` (the row sums). A comparison reads the
    /// step's safety factor as `dt / stable_step` (issue 32, item 3).
    pub stable_step: Option<f64>,
    pub stable_step_method: Option<&'static str>,
    pub final_u_mean: f64,
    /// Σ_c λ_c at the last state (a geometry that computes `contact_force` itself: its value,
    /// a body's total reaction Σ_i R_i ≥ 0).
    pub final_contact_force: f64,
    /// A solid's friction keys (every law; 0 and empty without friction; issue 29).
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub friction: Option<FrictionKeys>,
    pub wall_seconds: f64,
    /// The keys the geometry adds ([`GeometryView::own_summary`]; a body's:
    /// `crate::solid::report`), after the core's; empty for most geometries.
    #[serde(flatten)]
    pub own: serde_json::Map<String, serde_json::Value>,
}

/// A solid's friction keys in `summary.json` ([`crate::contact::friction::FrictionRecord`] at
/// the last state; forces on the body, world components).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrictionKeys {
    /// `Σ` over steps and contact nodes of `−r_t,i · Δu_t,i` (≥ 0 up to round-off).
    pub friction_dissipation: f64,
    /// `Σ_n Δt Σ_i r_t,i` (dim entries).
    pub tangential_impulse: Vec<f64>,
    /// Contact nodes carrying normal force at the last step that stick / slide.
    pub final_stick_nodes: usize,
    pub final_slip_nodes: usize,
    /// max over steps and nodes of `|r_t,i| − bound_i` (≤ 0 up to round-off).
    pub max_cone_excess: f64,
}

impl FrictionKeys {
    /// The keys of a solid of dimension `dim` from the last record (zeros without friction).
    pub fn of(dim: usize, record: Option<&crate::contact::friction::FrictionRecord>) -> Self {
        let Some(r) = record else {
            return Self {
                friction_dissipation: 0.0,
                tangential_impulse: vec![0.0; dim],
                final_stick_nodes: 0,
                final_slip_nodes: 0,
                max_cone_excess: 0.0,
            };
        };
        Self {
            friction_dissipation: r.dissipation,
            tangential_impulse: r.impulse[..dim].to_vec(),
            final_stick_nodes: r.stick,
            final_slip_nodes: r.slip,
            max_cone_excess: r.max_cone_excess,
        }
    }
}

impl Summary {
    /// The number under a key the geometry added (None if absent or not a number).
    pub fn own_number(&self, key: &str) -> Option<f64> {
        self.own.get(key).and_then(serde_json::Value::as_f64)
    }
}

/// `max(a, b)`, NaN if either is: a summary's maximum never skips a NaN state or comparison
/// (`f64::max` returns the other operand; issue 32, E5).
pub(crate) fn max_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() { f64::NAN } else { a.max(b) }
}

/// `min(a, b)`, NaN if either is ([`max_nan`]).
pub(crate) fn min_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() { f64::NAN } else { a.min(b) }
}

/// Accumulates a [`Summary`] in the step loop (O(1) memory).
#[derive(Debug)]
pub struct SummaryObserver {
    steps: usize,
    h: f64,
    dt: f64,
    exact_energy: f64,
    /// The exact solution's first contact phase (for the impact and release shifts).
    first_contact: Option<(f64, f64)>,
    has_exact: bool,
    with_l2: bool,
    with_y: bool,
    linf_l2: f64,
    linf_interp: f64,
    max_contact: f64,
    lambda_sq: f64,
    energy: [f64; 4],
    prev_energy: f64,
    max_increase: (f64, usize),
    max_increase_after_first: f64,
    first_impact: Option<f64>,
    first_release: Option<f64>,
    final_u0: f64,
    min_u0: f64,
    max_lambda: f64,
    max_product: f64,
    max_y_variation: f64,
    max_pivots: usize,
    final_u_mean: f64,
    final_force: f64,
    /// The last state seen, and its λ term `Δt (λⁿ − λ(t_n))²` (weighted 1 unless n = steps).
    last_n: usize,
    last_lambda_term: f64,
    /// Whether any state was shown (a run diverged at t_0 shows none: its maxima are null).
    seen: bool,
    divergence: Option<Divergence>,
    started: std::time::Instant,
    /// The geometry's own summary keys ([`GeometryView::own_summary`]).
    own: Option<Box<dyn OwnSummary>>,
    /// A solid's dimension (it reports the friction keys), and the last state's friction record.
    friction_dim: Option<usize>,
    friction: Option<crate::contact::friction::FrictionRecord>,
}

impl SummaryObserver {
    /// `with_l2 = false` skips the per-step L² error (the L² fields are then null).
    pub fn new<G: Geometry>(problem: &Problem<G>, steps: usize, dt: f64, with_l2: bool) -> Self {
        Self::of_view(&problem.system, problem.exact.as_ref(), steps, dt, with_l2)
    }

    /// [`SummaryObserver::new`] from what it reads of a problem: the geometry's measures and
    /// the exact solution (a run whose state lives elsewhere: `crate::engine`).
    pub fn of_view(g: &dyn GeometryView, exact: Option<&Exact>, steps: usize, dt: f64, with_l2: bool) -> Self {
        Self {
            steps,
            h: g.h(),
            dt,
            exact_energy: match exact {
                Some(Exact::Paper(_)) => g.length() * g.section() / 8.0,
                Some(e) => e.energy() * g.section(),
                None => f64::NAN,
            },
            first_contact: exact.and_then(|e| e.first_contact()),
            has_exact: exact.is_some(),
            with_l2: with_l2 && exact.is_some_and(|e| g.integrates(e)),
            with_y: g.dim() > 1,
            linf_l2: 0.0,
            linf_interp: 0.0,
            max_contact: 0.0,
            lambda_sq: 0.0,
            energy: [f64::NAN, f64::NAN, f64::INFINITY, f64::NEG_INFINITY],
            prev_energy: f64::NAN,
            max_increase: (f64::NEG_INFINITY, 0),
            max_increase_after_first: f64::NEG_INFINITY,
            first_impact: None,
            first_release: None,
            final_u0: f64::NAN,
            min_u0: f64::INFINITY,
            max_lambda: f64::NEG_INFINITY,
            max_product: 0.0,
            max_y_variation: 0.0,
            max_pivots: 0,
            final_u_mean: f64::NAN,
            final_force: f64::NAN,
            last_n: 0,
            last_lambda_term: 0.0,
            seen: false,
            divergence: None,
            started: std::time::Instant::now(),
            own: g.own_summary(),
            friction_dim: g.has_tangential().then(|| g.dim()),
            friction: None,
        }
    }

    pub fn finish(&self) -> Summary {
        let exact = |v: f64| (self.has_exact && self.seen).then_some(v);
        let l2 = |v: f64| (self.has_exact && self.with_l2 && self.seen).then_some(v);
        Summary {
            status: if self.divergence.is_some() { Status::Diverged } else { Status::Ok },
            divergence: self.divergence,
            steps: if self.divergence.is_some() { self.last_n } else { self.steps },
            steps_requested: self.steps,
            h: self.h,
            dt: self.dt,
            linf_l2_error: l2(self.linf_l2),
            linf_l2_error_relative: l2(self.linf_l2 / self.linf_interp),
            max_contact_error: exact(self.max_contact),
            l2_lambda_error: exact(self.lambda_sq.sqrt()),
            energy_initial: self.energy[0],
            energy_final: self.energy[1],
            energy_min: self.energy[2],
            energy_max: self.energy[3],
            energy_exact: self.has_exact.then_some(self.exact_energy),
            first_impact_time: self.first_impact,
            first_release_time: self.first_release,
            impact_time_shift: self.first_impact.zip(self.first_contact).map(|(t, c)| t - c.0),
            release_time_shift: self.first_release.zip(self.first_contact).map(|(t, c)| t - c.1),
            final_u0: self.final_u0,
            min_u0: self.min_u0,
            max_lambda: self.max_lambda,
            max_complementarity_product: if self.seen { self.max_product } else { f64::NAN },
            energy_max_increase: self.max_increase.0,
            energy_max_increase_step: self.max_increase.1,
            energy_max_increase_after_first: self.max_increase_after_first,
            max_y_variation: self.with_y.then_some(self.max_y_variation),
            max_pivots: self.max_pivots,
            stable_step: None,
            stable_step_method: None,
            final_u_mean: self.final_u_mean,
            final_contact_force: self.final_force,
            friction: self.friction_dim.map(|d| FrictionKeys::of(d, self.friction.as_ref())),
            wall_seconds: self.started.elapsed().as_secs_f64(),
            own: self.own.as_ref().map(|o| o.keys()).unwrap_or_default(),
        }
    }

    fn energy(&mut self, n: usize, e: f64) {
        if n == 0 {
            self.energy[0] = e;
        } else {
            let de = e - self.prev_energy;
            // The first NaN increase is kept (with its step): no later one compares above it.
            if !self.max_increase.0.is_nan() && (de > self.max_increase.0 || de.is_nan()) {
                self.max_increase = (de, n);
            }
            if n >= 2 {
                self.max_increase_after_first = max_nan(self.max_increase_after_first, de);
            }
        }
        self.prev_energy = e;
        self.energy[1] = e;
        self.energy[2] = min_nan(self.energy[2], e);
        self.energy[3] = max_nan(self.energy[3], e);
    }
}

impl Observer for SummaryObserver {
    fn needs(&self) -> Needs {
        Needs { energy: true, l2: self.with_l2 && self.has_exact, y_variation: self.with_y }
    }

    fn observe(&mut self, s: &Sample) {
        let st = s.state;
        self.last_n = st.n;
        self.seen = true;
        self.energy(st.n, s.energy);
        let u0 = s.u0;
        self.final_u0 = u0;
        // Impact and release are read off the force, node by node ([`ContactStats::touching`]).
        let touching = s.contact.touching;
        self.min_u0 = min_nan(self.min_u0, s.contact.min_u);
        self.max_lambda = max_nan(self.max_lambda, s.contact.max_lambda);
        self.max_product = max_nan(self.max_product, s.contact.max_product);
        if self.with_y {
            self.max_y_variation = max_nan(self.max_y_variation, s.y_variation);
        }
        self.max_pivots = self.max_pivots.max(s.pivots);
        self.final_u_mean = s.u_mean;
        self.final_force = s.contact_force;
        if let (Some(r), Some(_)) = (s.friction, self.friction_dim) {
            match &mut self.friction {
                Some(mine) => mine.clone_from(r),
                None => self.friction = Some(r.clone()),
            }
        }
        // The geometry's own values: its `contact_force` is the final one, its keys accumulate.
        let mut buffer = [0.0; MAX_OWN_COLUMNS];
        if let Some(values) = own_values(s, |_| true, &mut buffer) {
            let own = s.geometry.own_columns();
            if let Some(k) = own.iter().position(|&c| c == Column::ContactForce) {
                self.final_force = values[k];
            }
            if let Some(keys) = self.own.as_mut() {
                keys.observe(st.t, values);
            }
        }
        if self.first_impact.is_none() {
            if touching {
                self.first_impact = Some(st.t);
            }
        } else if self.first_release.is_none() && !touching {
            self.first_release = Some(st.t);
        }
        if let Some(ex) = s.exact {
            self.max_contact = max_nan(self.max_contact, (u0 - ex.u0(st.t)).abs());
            let w = if st.n == 0 || st.n == self.steps { 0.5 } else { 1.0 };
            self.last_lambda_term = self.dt * (s.pressure - ex.lambda(st.t)).powi(2);
            self.lambda_sq += w * self.last_lambda_term;
            if self.with_l2 {
                self.linf_l2 = max_nan(self.linf_l2, s.l2_error);
                self.linf_interp = max_nan(self.linf_interp, s.exact_interp_norm);
            }
        }
    }

    /// The trapezoidal rule of `l2_lambda_error` ends at the last state seen: its weight is ½
    /// (0 at t_0: a rule over [0, 0]).
    fn diverged(&mut self, divergence: &Divergence) {
        if self.last_n != self.steps {
            self.lambda_sq = max_nan(self.lambda_sq - 0.5 * self.last_lambda_term, 0.0);
        }
        self.divergence = Some(*divergence);
    }
}

/// One recorded frame of the displacement and velocity at all mesh nodes.
#[derive(Debug, Clone)]
pub struct Frame {
    pub t: f64,
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    /// The contact multipliers (contact order).
    pub lambda: Vec<f64>,
    /// The step's friction (None without a friction law).
    pub friction: Option<crate::contact::friction::FrictionRecord>,
}

/// Records [`Frame`]s every `every` steps, in memory (for library users; the command line
/// streams them to VTU files with `plate::vtu::FrameWriter`).
#[derive(Debug, Clone)]
pub struct FrameRecorder {
    pub every: usize,
    pub frames: Vec<Frame>,
}

impl FrameRecorder {
    pub fn new(every: usize) -> Self {
        Self { every: every.max(1), frames: Vec::new() }
    }
}

impl Observer for FrameRecorder {
    fn every(&self) -> usize {
        self.every
    }

    fn observe(&mut self, s: &Sample) {
        let n = s.geometry.n_nodes() * s.geometry.components();
        let mut u = vec![0.0; n];
        let mut v = vec![0.0; n];
        s.geometry.nodal_values(s.state.u, &mut u);
        s.geometry.nodal_values(s.state.v, &mut v);
        let friction = s.friction.cloned();
        self.frames.push(Frame { t: s.state.t, u, v, lambda: s.state.lambda.to_vec(), friction });
    }
}

/// Energies `Eⁿ` of every step (for energy analyses).
#[derive(Debug, Clone, Default)]
pub struct EnergyRecorder {
    pub energy: Vec<f64>,
}

impl Observer for EnergyRecorder {
    fn needs(&self) -> Needs {
        Needs { energy: true, ..Needs::default() }
    }

    fn observe(&mut self, s: &Sample) {
        self.energy.push(s.energy);
    }
}
