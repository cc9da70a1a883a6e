//! Running the comparison: one case ([`run_case`]: its time step, the observed run, the
//! perturbed copies of a sensitive case, the CPU time) and every case in parallel ([`compute`]),
//! measured by the observer [`Watch`] (`methods`' module docs for the measurements).

use super::super::band;
use super::{
    CD, Case, Law, MethodResult, MethodsConfig, Metrics, Problem1d, SAFETY, Step, cases, scene_text, sensitive,
};
use massredist::bar::BarProblem;
use massredist::driver::{DivergenceCriterion, Needs, Observer, Outcome, Sample, integrate, integrate_watched};
use massredist::scene::BarScene;
use massredist::schemes::SchemeError;
use rayon::prelude::*;
use std::time::Instant;

/// Time step of a case ([`Step`]) and, for an explicit scheme, its stable limit and estimator.
/// A [`Step::Stable`] method whose scheme reports no stable limit is an error, never a silent
/// step at h/c (no bound or default may decide a ranking; issue 32, item 3).
fn time_step(
    case: &Case,
    problem: &BarProblem,
    scene: &BarScene,
) -> Result<(f64, Option<(f64, &'static str)>), String> {
    let courant = case.courant * case.problem.length / case.elements as f64 / case.problem.c();
    let build = |dt: f64| problem.scheme_with(&scene.scheme, &scene.contact, dt);
    let no_limit = || format!("{}: an explicit method whose scheme reports no stable limit", case.method.label);
    if let Some(dt) = case.dt {
        return build(dt).map(|s| (dt, s.stable_limit())).map_err(|e| e.to_string());
    }
    match (build(courant), case.method.step) {
        (Ok(s), Step::Stable) => match s.stable_limit() {
            Some((limit, by)) => Ok((SAFETY * limit, Some((limit, by)))),
            None => Err(no_limit()),
        },
        (Ok(s), Step::Courant) => Ok((courant, s.stable_limit())),
        (Err(SchemeError::AboveStableLimit { limit, .. }), Step::Stable) => {
            let dt = SAFETY * limit;
            let limit = build(dt).map_err(|e| e.to_string())?.stable_limit().ok_or_else(no_limit)?;
            Ok((dt, Some(limit)))
        }
        (Err(e), _) => Err(e.to_string()),
    }
}

/// Parses the scene of a case and builds its problem.
fn build(case: &Case, dt: f64, steps: usize) -> Result<(BarScene, BarProblem), String> {
    let text = scene_text(case, dt, steps);
    let scene = BarScene::from_toml(&text).map_err(|e| e.to_string())?;
    let problem = BarProblem::from_scene(&scene).map_err(|e| e.to_string())?;
    Ok((scene, problem))
}

/// Runs one case (and its perturbed copies when [`sensitive`]).
pub fn run_case(case: &Case) -> MethodResult {
    let p = case.problem;
    let mut r = MethodResult {
        method: case.method.label,
        class: case.method.class,
        mass: case.mass,
        problem: p.key,
        elements: case.elements,
        dt: f64::NAN,
        courant: f64::NAN,
        in_sweep: case.courant != 1.0,
        own: case.dt.is_some(),
        steps: 0,
        exact_impacts: 0,
        status: "failed",
        failure: None,
        runs: Vec::new(),
        cpu_seconds: f64::NAN,
        step_seconds: f64::NAN,
        stable_step: None,
        stable_step_method: None,
    };
    // Δt from a first build at h/c (any horizon: only Δt matters there).
    let dt = match build(case, p.length / case.elements as f64 / p.c(), 1).and_then(|(s, pr)| time_step(case, &pr, &s))
    {
        Ok((dt, limit)) => {
            (r.stable_step, r.stable_step_method) = (limit.map(|l| l.0), limit.map(|l| l.1));
            dt
        }
        Err(e) => {
            r.failure = Some(e);
            return r;
        }
    };
    let steps = (p.horizon() / dt * (1.0 - 1e-12)).ceil() as usize;
    let (scene, mut problem) = match build(case, dt, steps) {
        Ok(x) => x,
        Err(e) => {
            r.failure = Some(e);
            return r;
        }
    };
    (r.dt, r.steps, r.courant) = (dt, steps, dt * p.c() / (p.length / case.elements as f64));
    r.exact_impacts = problem.exact.as_ref().map_or(0, |e| count_impacts(e, steps as f64 * dt, p.length / p.c()));
    let (u0, v0) = (problem.u0.clone(), problem.v0.clone());
    let copies = if sensitive(case) { band::PERTURBATIONS } else { 0 };
    let scale = velocity_scale(p);
    for k in 0..=copies {
        problem.u0 = if k == 0 { u0.clone() } else { band::perturbed(&u0, k - 1) };
        problem.v0 = if k == 0 { v0.clone() } else { perturbed_velocity(&v0, k - 1, scale) };
        match measure(case, &scene, &problem, dt, steps) {
            Ok(Ok(m)) => r.runs.push(m),
            Ok(Err(d)) if k == 0 => {
                (r.status, r.failure) = ("diverged", Some(d));
                return r;
            }
            Err(e) if k == 0 => {
                r.failure = Some(e);
                return r;
            }
            // A copy that diverges or fails: the band is then not a result; say so.
            Ok(Err(d)) | Err(d) => {
                (r.status, r.failure) = ("failed", Some(format!("perturbed copy {k}: {d}")));
                r.runs.clear();
                return r;
            }
        }
    }
    (problem.u0, problem.v0) = (u0, v0);
    r.status = "ok";
    (r.cpu_seconds, r.step_seconds) = cpu_seconds(&scene, &problem, dt, steps);
    r
}

/// A velocity scale of a problem: the arrival speed V₀ of a free rod, else c·L/2/L = c/2 (the
/// paper's bar: u⁰ = (L − x)/2 releases at speed about c/2).
fn velocity_scale(p: &Problem1d) -> f64 {
    p.v0.unwrap_or(0.5 * p.c())
}

/// `V⁰` of copy k: `v_i (1 + δ_{k,i}) + δ_{k,i} · scale`, δ_{k,i} ∈ {−1, −½, 0, ½, 1}·
/// [`band::PERTURBATION`] from a fixed pattern, distinct for k = 0..4 at every i and shifted
/// from [`band::perturbed`]'s (so U⁰ and V⁰ are not perturbed alike). The absolute part
/// perturbs the free rods, whose U⁰ = 0 (a relative perturbation of U⁰ alone left their five
/// runs identical, issue 22), and any zero entry of V⁰.
fn perturbed_velocity(v0: &[f64], k: usize, scale: f64) -> Vec<f64> {
    v0.iter()
        .enumerate()
        .map(|(i, &v)| {
            let d = (((7 * i + 3 * k + 3) % 5) as f64 / 2.0 - 1.0) * band::PERTURBATION;
            v * (1.0 + d) + d * scale
        })
        .collect()
}

/// Number of contact phases of the exact solution starting in (0, t_end], counted as its sign
/// changes of λ sampled 64 times per crossing time (contacts last 2 crossings here).
fn count_impacts(exact: &massredist::exact::Exact, t_end: f64, crossing: f64) -> usize {
    let n = (t_end / crossing * 64.0).ceil() as usize;
    let on = |k: usize| exact.lambda(t_end * k as f64 / n as f64) < 0.0;
    (1..=n).filter(|&k| on(k) && !on(k - 1)).count()
}

/// The fastest of up to 3 bare runs (set-up and stepping, no observer): (total, stepping) seconds.
fn cpu_seconds(scene: &BarScene, problem: &BarProblem, dt: f64, steps: usize) -> (f64, f64) {
    let started = Instant::now();
    let mut best = (f64::INFINITY, f64::INFINITY);
    for _ in 0..3 {
        let t = Instant::now();
        let Ok(mut s) = problem.scheme_with(&scene.scheme, &scene.contact, dt) else { return (f64::NAN, f64::NAN) };
        let stepping = Instant::now();
        if integrate(problem, s.as_mut(), steps, &mut []).is_err() {
            return (f64::NAN, f64::NAN);
        }
        let total = t.elapsed().as_secs_f64();
        if total < best.0 {
            best = (total, stepping.elapsed().as_secs_f64());
        }
        if started.elapsed().as_secs_f64() > 0.05 {
            break;
        }
    }
    best
}

/// One observed run: Ok(Ok(metrics)), Ok(Err(divergence)), or Err(the scheme's error).
fn measure(
    case: &Case,
    scene: &BarScene,
    problem: &BarProblem,
    dt: f64,
    steps: usize,
) -> Result<Result<Metrics, String>, String> {
    let p = case.problem;
    let mut scheme = problem.scheme_with(&scene.scheme, &scene.contact, dt).map_err(|e| e.to_string())?;
    let window = p.error_window.map_or(f64::INFINITY, |w| w * p.length / p.c());
    let verlet = case.method.scheme == CD && case.method.law == Law::Exact;
    let mut watch = Watch::new(problem, window, verlet.then_some(dt));
    let criterion = DivergenceCriterion::default();
    let outcome =
        integrate_watched(problem, scheme.as_mut(), steps, &criterion, &mut [&mut watch]).map_err(|e| e.to_string())?;
    if let Outcome::Diverged(d) = outcome {
        return Ok(Err(d.to_string()));
    }
    Ok(Ok(watch.metrics(problem, p)))
}

/// The observer of a run (O(1) memory): the module docs' measurements.
struct Watch {
    lower: f64,
    window: f64,
    /// `M 1` (the consistent weighted mass; row sums = the lumped mass) and its sum.
    weights: Vec<f64>,
    total: f64,
    l2: f64,
    norm: f64,
    first_impact: Option<f64>,
    first_release: Option<f64>,
    min_u0: f64,
    tv: f64,
    tv_exact: f64,
    impulse: f64,
    impulse_exact: f64,
    last: Option<(f64, f64)>,
    e0: f64,
    e: f64,
    mean_velocity: f64,
    /// Central differences with the exact law: the half-step energy's state.
    half: Option<HalfStep>,
}

/// What the half-step energy needs: K, M_L, Δt, Uⁿ, and H^{½} and the latest H.
struct HalfStep {
    stiffness: massredist::linalg::tridiag::SymTridiag,
    lumped: Vec<f64>,
    dt: f64,
    prev: Vec<f64>,
    work: Vec<f64>,
    first: Option<f64>,
    last: f64,
}

impl Watch {
    fn new(problem: &BarProblem, window: f64, verlet_dt: Option<f64>) -> Self {
        let system = &problem.system.system;
        let mut weights = vec![0.0; system.n()];
        system.mass.mul_into(&vec![1.0; system.n()], &mut weights);
        Self {
            lower: system.lower[0],
            window,
            total: weights.iter().sum(),
            weights,
            l2: 0.0,
            norm: 0.0,
            first_impact: None,
            first_release: None,
            min_u0: f64::INFINITY,
            tv: 0.0,
            tv_exact: 0.0,
            impulse: 0.0,
            impulse_exact: 0.0,
            last: None,
            e0: f64::NAN,
            e: f64::NAN,
            mean_velocity: f64::NAN,
            half: verlet_dt.map(|dt| HalfStep {
                stiffness: system.stiffness.clone(),
                lumped: problem.system.lumped.clone(),
                dt,
                prev: Vec::new(),
                work: vec![0.0; system.n()],
                first: None,
                last: f64::NAN,
            }),
        }
    }

    fn metrics(&self, problem: &BarProblem, p: &Problem1d) -> Metrics {
        let first = problem.exact.as_ref().and_then(|e| e.first_contact());
        let duration = first.map(|(a, b)| b - a);
        let impact_error = match (self.first_impact, first, duration) {
            (Some(t), Some((a, _)), Some(d)) => Some((t - a) / d),
            _ => None,
        };
        let duration_error = match (self.first_impact, self.first_release, duration) {
            (Some(a), Some(b), Some(d)) => Some((b - a - d) / d),
            _ => None,
        };
        let ratio = |a: f64, b: f64| (b != 0.0).then(|| a / b);
        Metrics {
            l2_error: self.l2 / self.norm,
            impact_error,
            duration_error,
            rebound: p.v0.map(|v| self.mean_velocity / v),
            force_tv: ratio(self.tv, self.tv_exact),
            impulse: ratio(self.impulse, self.impulse_exact),
            penetration: (self.lower - self.min_u0).max(0.0) / p.length,
            energy_drift: (self.e - self.e0) / self.e0.abs(),
            half_step_drift: self.half.as_ref().and_then(|h| h.first.map(|h0| (h.last - h0) / h0.abs())),
            first_impact: self.first_impact,
            first_release: self.first_release,
        }
    }
}

impl Observer for Watch {
    fn needs(&self) -> Needs {
        Needs { energy: true, l2: true, y_variation: false }
    }

    fn observe(&mut self, s: &Sample) {
        let t = s.state.t;
        if t <= self.window * (1.0 + 1e-12) {
            self.l2 = self.l2.max(s.l2_error);
            self.norm = self.norm.max(s.exact_interp_norm);
        }
        let u0 = s.state.u[0];
        self.min_u0 = self.min_u0.min(u0);
        let touching = s.state.lambda[0] < 0.0; // off the force (module docs)
        match (self.first_impact, self.first_release) {
            (None, _) if touching => self.first_impact = Some(t),
            (Some(_), None) if !touching => self.first_release = Some(t),
            _ => {}
        }
        let (lambda, exact) = (s.state.lambda[0], s.exact.map_or(0.0, |e| e.lambda(t)));
        if let Some((l, le)) = self.last {
            self.tv += (lambda - l).abs();
            self.tv_exact += (exact - le).abs();
        }
        self.last = Some((lambda, exact));
        self.impulse += lambda;
        self.impulse_exact += exact;
        if self.e0.is_nan() {
            self.e0 = s.energy;
        }
        self.e = s.energy;
        let momentum: f64 = self.weights.iter().zip(s.state.v).map(|(w, v)| w * v).sum();
        self.mean_velocity = momentum / self.total;
        if let Some(h) = self.half.as_mut() {
            if !h.prev.is_empty() {
                let e = super::super::cd_growth::shadow_energy(
                    &h.stiffness,
                    &h.lumped,
                    &h.prev,
                    s.state.u,
                    h.dt,
                    &mut h.work,
                );
                h.first.get_or_insert(e);
                h.last = e;
            }
            h.prev.clear();
            h.prev.extend_from_slice(s.state.u);
        }
    }
}

/// Runs every case of `config` in parallel (largest first), calling `tick` after each; results
/// in the order of [`cases`].
pub fn compute(config: &MethodsConfig, tick: &(dyn Fn() + Sync)) -> Vec<MethodResult> {
    let all = cases(config);
    let mut order: Vec<usize> = (0..all.len()).collect();
    let work = |c: &Case| {
        (c.elements * c.elements) as f64 * c.problem.crossings * if sensitive(c) { 5.0 } else { 1.0 } / c.courant
    };
    order.sort_by(|&a, &b| work(&all[b]).total_cmp(&work(&all[a])));
    let mut out: Vec<(usize, MethodResult)> = order
        .par_iter()
        .map(|&i| {
            let r = run_case(&all[i]);
            tick();
            (i, r)
        })
        .collect();
    out.sort_by_key(|p| p.0);
    out.into_iter().map(|p| p.1).collect()
}
