//! Shared test helpers: record whole trajectories through the public driver.
#![allow(dead_code)]

pub mod alloc;
pub mod block;

use massredist::bar::BarProblem;
use massredist::driver::{Observer, Sample, integrate};
use massredist::mass::MassKind;
use massredist::scene::{Formulation, SchemeSpec};
use massredist::schemes::{Beta, Gamma, Restitution};

/// One recorded state.
#[derive(Debug, Clone)]
pub struct Frame {
    pub t: f64,
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    pub lambda: f64,
    pub energy: f64,
}

#[derive(Default)]
pub struct Recorder(pub Vec<Frame>);

impl Observer for Recorder {
    fn needs(&self) -> massredist::driver::Needs {
        massredist::driver::Needs { energy: true, ..Default::default() }
    }
    fn observe(&mut self, s: &Sample) {
        let st = s.state;
        self.0.push(Frame { t: st.t, u: st.u.to_vec(), v: st.v.to_vec(), lambda: st.lambda[0], energy: s.energy });
    }
}

pub fn trajectory(problem: &BarProblem, spec: &SchemeSpec, dt: f64, steps: usize) -> Vec<Frame> {
    let mut scheme = problem.scheme(spec, dt).expect("scheme builds");
    let mut rec = Recorder::default();
    integrate(problem, scheme.as_mut(), steps, &mut [&mut rec]).expect("run succeeds");
    rec.0
}

pub const CN: SchemeSpec = SchemeSpec::CrankNicolson { formulation: Formulation::Full };
pub const CN_REDUCED: SchemeSpec = SchemeSpec::CrankNicolson { formulation: Formulation::Reduced };
pub const PS: SchemeSpec = SchemeSpec::PaoliSchatzman { beta: Beta::new(0.25), restitution: Restitution::new(1.0) };

pub fn all_masses(m: usize) -> Vec<MassKind> {
    let custom: Vec<f64> = (0..m).map(|j| if j == 0 { 0.0 } else { 0.5 + ((j * 7919) % 13) as f64 / 8.0 }).collect();
    vec![MassKind::Standard, MassKind::Mod1, MassKind::Mod2, MassKind::Mod3, MassKind::Custom(custom)]
}

/// Every scheme defined for the mass (hybrid and the reduced formulation need w_0 = 0).
pub fn schemes_for(mass: &MassKind) -> Vec<SchemeSpec> {
    let mut v = vec![
        CN,
        SchemeSpec::Newmark { beta: Beta::new(0.3), gamma: Gamma::new(0.6), formulation: Formulation::Full },
        SchemeSpec::BackwardEuler,
        PS,
        SchemeSpec::PaoliSchatzman { beta: Beta::new(0.25), restitution: Restitution::new(0.0) },
    ];
    if !matches!(mass, MassKind::Standard) {
        v.push(CN_REDUCED);
        v.push(SchemeSpec::Hybrid);
    }
    v
}

pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// Least-squares slope of log(err) against log(step).
pub fn fitted_slope(steps: &[f64], errs: &[f64]) -> f64 {
    let xs: Vec<f64> = steps.iter().map(|s| s.ln()).collect();
    let ys: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// A pid that is certainly not running: a child that has exited and been reaped.
pub fn dead_pid() -> u32 {
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    pid
}

/// A command's standard error as text.
pub fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts a refusal: exit code 2, a message containing every needle, and no run computed.
pub fn assert_refused(o: &std::process::Output, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    for n in needles {
        assert!(err.contains(n), "message lacks {n:?}: {err}");
    }
    assert!(!err.contains(" steps in "), "the run was computed before the refusal: {err}");
}

/// A solid scene's problem with the whole system (its consistent mass, its whole stiffness), as
/// every scheme but central differences gets it: what tests that read the matrices start from
/// (`run::setup` gives central differences the lean system of `solid::lean`, whose stiffness
/// matrix holds only the massless unknowns' rows and columns).
pub fn whole_problem(s: &massredist::scene::SolidScene) -> massredist::solid::SolidProblem {
    s.geometry.problem_directed(&s.mass, s.contact_directions, s.time.exact_end()).unwrap()
}

/// The stored entries of `a` as (row, column, bits of the value), only those where
/// `keep(i, j)`: for bit-for-bit comparisons of assembled matrices.
pub fn bits_of(a: &massredist::linalg::sparse::SpMat, keep: impl Fn(usize, usize) -> bool) -> Vec<(usize, usize, u64)> {
    massredist::linalg::sparse::triplets(a)
        .filter(|&(i, j, _)| keep(i, j))
        .map(|(i, j, v)| (i, j, v.to_bits()))
        .collect()
}

/// Steps two central-difference runs of one scene `steps` times in lockstep, asserting that no
/// contact happens (λ = 0 in both at every step), and returns the largest |Δu|, |Δv| between
/// them and the largest |u|, |v| of the first (the operator checks: `tests/stencil.rs`,
/// `tests/kernel.rs`).
pub fn contact_free_lockstep(
    runs: &mut [massredist::run::Setup<massredist::solid::SolidSystem>; 2],
    steps: usize,
    what: &str,
) -> [f64; 4] {
    let (mut du, mut dv, mut su, mut sv) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for _ in 0..steps {
        for r in runs.iter_mut() {
            r.scheme.step().unwrap();
        }
        let (a, b) = (runs[0].scheme.state(), runs[1].scheme.state());
        assert!(a.lambda.iter().chain(b.lambda).all(|&l| l == 0.0), "{what}: no contact");
        for i in 0..a.u.len() {
            du = du.max((a.u[i] - b.u[i]).abs());
            dv = dv.max((a.v[i] - b.v[i]).abs());
            su = su.max(a.u[i].abs());
            sv = sv.max(a.v[i].abs());
        }
    }
    [du, dv, su, sv]
}
