//! The isotropic cone of 3D (issue 29): a contact node with two tangential unknowns, whose
//! friction force is bounded by a disc, `|f_t| ≤ g` (g = μ f_n for Coulomb, σ s a_i for
//! Tresca), not by a pyramid.
//!
//! Its conditions are no longer piecewise linear: a sliding node's force `f_t = −g e` points
//! against the unit direction `e = Δu_t/|Δu_t|` of its slip, which the solve finds. The solve:
//! 1. block Gauss–Seidel sweeps ([`Dense::sweep_cone`]), each node's 3 × 3 problem solved to
//!    round-off ([`node_cone`]: open, stick, or slide along the e that makes `y_t` parallel to
//!    e, a root of one smooth function of the angle);
//! 2. once the nodes' kinds (open/closed, zero/stick/slide) repeat over two sweeps, or every 50
//!    sweeps: the semi-smooth Newton method on the natural map `f − P(f − ρ y)` from the sweeps'
//!    forces ([`Dense::newton_cone`]), until the kinds repeat and its step is at round-off; its
//!    answer is kept when every condition holds within the 2D path's round-off allowance
//!    64 m ε ([`Dense::settled_cone`]);
//! 3. else, every 10 sweeps, the sweeps' own forces once their natural residual is within the
//!    same allowance.
//!
//! The stopping rule is that check; the answer is then the solution to round-off. Its natural
//! residual, `max_k |f_k − P(f − ρ y)_k|` (ρ from [`Dense::rhos`], P the projection on
//! `f_n ≥ 0` and on the disc of the bound) over the largest force, is recorded per run
//! ([`super::FrictionRecord::residual`]): the 3D tests measure it ≤ 1.2e-15. Cost per step: one
//! forward and one backward substitution, one O(m²) product `y = q + D f`, O(m) per node whose
//! forces change in a sweep, and per Newton iteration an LU over the unknowns of the nodes in
//! contact (m the contact-node unknowns).

use super::super::lcp::LcpError;
use super::{Dense, Friction, MAX_SWEEPS, NodeState, Tangent};
use faer::Mat;
use faer::linalg::solvers::Solve;

/// Newton iterations per try on the nodes' kinds.
const MAX_NEWTON: usize = 40;

/// A node's kind, for the repeat test of the sweeps (a slide's direction changes every sweep).
fn kind(st: &NodeState) -> (bool, i8) {
    let tangent = match st.tangent {
        Tangent::Zero => 0,
        Tangent::Stick => 1,
        Tangent::Slip(s) if s > 0.0 => 2,
        Tangent::Slip(_) => 3,
        Tangent::Slide(_) => 4,
    };
    (st.closed, tangent)
}

impl Dense {
    /// Whether a node has two tangential unknowns (the cone path).
    pub(super) fn is_cone(&self) -> bool {
        self.slots.iter().any(|s| s.t2.is_some())
    }

    /// Node i's 3 × 3 problem (slots n, t, t2) for the others' forces fixed; returns its state.
    /// Reads the others' forces through `y = q + D f`, which the cone's sweeps keep current
    /// ([`Dense::sweep_cone`]).
    pub(super) fn local_cone(&mut self, i: usize, t: usize, t2: usize) -> NodeState {
        let s = self.slots[i];
        let m = self.q.len();
        let d = |a: usize, b: usize| self.d[a * m + b];
        let own = |k: usize| self.y[k] - d(k, s.n) * self.f[s.n] - d(k, t) * self.f[t] - d(k, t2) * self.f[t2];
        let (rn, rt) = (own(s.n), [own(t), own(t2)]);
        let a = d(s.n, s.n);
        let b = [d(s.n, t), d(s.n, t2)];
        let c = [[d(t, t), d(t, t2)], [d(t2, t), d(t2, t2)]];
        let guess = match self.states[i].tangent {
            Tangent::Slide(e) => Some(e),
            _ => None,
        };
        let (f, state) = node_cone(a, b, c, rn, rt, self.friction, self.tresca_bound(i), guess);
        (self.f[s.n], self.f[t], self.f[t2]) = (f[0], f[1], f[2]);
        state
    }

    /// One sweep over the nodes, keeping `y = q + D f` current: a node whose forces change
    /// adds `D Δf` over its columns (O(m) each), so that a sweep costs O(m) for each node that
    /// moves and O(1) for the others: a curved body's many open candidate nodes cost nothing.
    fn sweep_cone(&mut self) {
        let m = self.q.len();
        for i in 0..self.slots.len() {
            let s = self.slots[i];
            let own = [Some(s.n), s.t, s.t2];
            let old = own.map(|k| k.map_or(0.0, |k| self.f[k]));
            self.states[i] = self.local(i);
            for (k, old) in own.into_iter().zip(old) {
                let Some(k) = k else { continue };
                let delta = self.f[k] - old;
                if delta != 0.0 {
                    // D is symmetric: its column k is its row k.
                    for (y, d) in self.y.iter_mut().zip(&self.d[k * m..(k + 1) * m]) {
                        *y += d * delta;
                    }
                }
            }
        }
    }

    /// The frictional problem with cone nodes (module docs) into f and y.
    pub(super) fn solve_cone(&mut self) -> Result<usize, LcpError> {
        let mut previous: Vec<(bool, i8)> = self.states.iter().map(kind).collect();
        let mut repeats = 0;
        self.y = self.values(&self.f);
        for sweep in 1..=MAX_SWEEPS {
            self.sweep_cone();
            let now: Vec<(bool, i8)> = self.states.iter().map(kind).collect();
            repeats = if now == previous { repeats + 1 } else { 0 };
            previous = now;
            if (repeats >= 2 || sweep % 50 == 0) && self.newton_cone() {
                self.record.residual = self.record.residual.max(self.natural_residual());
                return Ok(sweep);
            }
            // The sweeps themselves at round-off (Newton's answer refused by its check, e.g. a
            // node on the rim with |Δu_t| at the allowance): the same allowance on the residual.
            if sweep % 10 == 0 {
                self.y = self.values(&self.f);
                let residual = self.natural_residual();
                if residual <= 64.0 * self.q.len() as f64 * f64::EPSILON {
                    self.record.residual = self.record.residual.max(residual);
                    return Ok(sweep);
                }
            }
        }
        self.y = self.values(&self.f);
        Err(LcpError::NotConverged { pivots: MAX_SWEEPS, residual: self.natural_residual() })
    }

    /// `y = q + D f`.
    fn values(&self, f: &[f64]) -> Vec<f64> {
        let m = self.q.len();
        (0..m).map(|k| self.q[k] + (0..m).map(|b| self.d[k * m + b] * f[b]).sum::<f64>()).collect()
    }

    /// Node i's ρ (the natural map's scaling): `1/D_nn` for the normal force, `2/(D_tt + D_t₂t₂)`
    /// for the tangential ones (one value for both: the disc's projection stays isotropic).
    fn rhos(&self, i: usize) -> (f64, f64) {
        let (s, m) = (self.slots[i], self.q.len());
        let d = |k: usize| self.d[k * m + k];
        let rt = match (s.t, s.t2) {
            (Some(t), Some(t2)) => 2.0 / (d(t) + d(t2)),
            (Some(t), None) => 1.0 / d(t),
            _ => 0.0,
        };
        (1.0 / d(s.n), rt)
    }

    /// The semi-smooth Newton method on the natural map `F(f) = f − P(f − ρ y)` (Alart and
    /// Curnier, CMAME 92 (1991); the generalized Newton of Hüeber, Stadler and Wohlmuth, SIAM J.
    /// Sci. Comput. 30 (2008)), from the sweeps' forces: each iteration takes each node's kind
    /// from its trial `f − ρ y` (closed where `f_n − ρ y_n > 0`; stick where the tangential
    /// trial is inside the disc, else slide along it) and solves the kinds' linearised
    /// equations; a slide's direction is the trial's, never `y_t/|y_t|`, so a node coming to
    /// rest (|Δu_t| → 0) keeps a regular Jacobian. Stops when the kinds repeat and the step is
    /// at round-off; true (f, y and the states set) if every condition then holds
    /// ([`Dense::settled_cone`]).
    fn newton_cone(&mut self) -> bool {
        let m = self.q.len();
        let mut f = self.f.clone();
        let mut last_kinds: Vec<(bool, i8)> = Vec::new();
        let mut last = f64::INFINITY;
        let mut converged = false;
        // y = q + D f (the sweeps kept it current), kept current through the iterations (D δ
        // over the δ that are not 0); the answer's check forms it afresh.
        let mut y = self.y.clone();
        for iteration in 0..MAX_NEWTON {
            // The Jacobian's rows, stored for the unknowns that are not fixed (an empty row: an
            // identity row, δ_k = −f_k).
            let mut jac: Vec<Vec<f64>> = vec![Vec::new(); m];
            let mut rhs = vec![0.0; m];
            let d_row = |jac: &mut Vec<Vec<f64>>, row: usize, k: usize, c: f64| {
                let r = &mut jac[row];
                if r.is_empty() {
                    r.resize(m, 0.0);
                }
                for (x, d) in r.iter_mut().zip(&self.d[k * m..(k + 1) * m]) {
                    *x += c * d;
                }
            };
            let unit = |jac: &mut Vec<Vec<f64>>, row: usize, k: usize, c: f64| {
                let r = &mut jac[row];
                if r.is_empty() {
                    r.resize(m, 0.0);
                }
                r[k] += c;
            };
            let mut kinds = Vec::with_capacity(self.slots.len());
            let mut fixed = Vec::new();
            for (i, &s) in self.slots.iter().enumerate() {
                let (rn, rt) = self.rhos(i);
                let trial_n = f[s.n] - rn * y[s.n];
                let closed = trial_n > 0.0;
                if closed {
                    d_row(&mut jac, s.n, s.n, rn);
                    rhs[s.n] = -rn * y[s.n];
                } else {
                    rhs[s.n] = -f[s.n];
                    fixed.push(s.n);
                }
                let ts: Vec<usize> = [s.t, s.t2].into_iter().flatten().collect();
                if ts.is_empty() {
                    kinds.push((closed, 0));
                    continue;
                }
                // The bound at the trial and its derivative's factor along `df_n − ρ_n D_n df`.
                let (g, dg) = match self.friction {
                    Friction::Coulomb { mu } if closed => (mu * trial_n, mu),
                    Friction::Coulomb { .. } => (0.0, 0.0),
                    Friction::Tresca { .. } => (self.tresca_bound(i), 0.0),
                };
                let trial: Vec<f64> = ts.iter().map(|&k| f[k] - rt * y[k]).collect();
                let size = trial.iter().map(|v| v * v).sum::<f64>().sqrt();
                let tangent = if g <= 0.0 {
                    for &k in &ts {
                        rhs[k] = -f[k];
                        fixed.push(k);
                    }
                    0
                } else if size <= g {
                    for &k in &ts {
                        d_row(&mut jac, k, k, rt);
                        rhs[k] = -rt * y[k];
                    }
                    1
                } else {
                    // F_t = f_t − g w, w = trial/|trial|:
                    // dF_t = df_t − (g/|trial|)(I − wwᵀ)(df_t − ρ D_t df) − w dg.
                    let w: Vec<f64> = trial.iter().map(|v| v / size).collect();
                    for (a, &ka) in ts.iter().enumerate() {
                        unit(&mut jac, ka, ka, 1.0);
                        rhs[ka] = -(f[ka] - g * w[a]);
                        for (b, &kb) in ts.iter().enumerate() {
                            let p = g / size * (f64::from(u8::from(a == b)) - w[a] * w[b]);
                            unit(&mut jac, ka, kb, -p);
                            d_row(&mut jac, ka, kb, p * rt);
                        }
                        if dg != 0.0 {
                            unit(&mut jac, ka, s.n, -w[a] * dg);
                            d_row(&mut jac, ka, s.n, w[a] * dg * rn);
                        }
                    }
                    4
                };
                kinds.push((closed, tangent));
            }
            // The fixed rows are identity rows, δ_k = −f_k: the LU is of the other rows only
            // (the nodes in contact, few against the candidates of a curved body).
            let mut delta = vec![0.0; m];
            let mut is_fixed = vec![false; m];
            for &k in &fixed {
                (is_fixed[k], delta[k]) = (true, -f[k]);
            }
            let free: Vec<usize> = (0..m).filter(|&k| !is_fixed[k]).collect();
            let mut reduced = Mat::<f64>::zeros(free.len(), free.len());
            let mut reduced_rhs = Mat::<f64>::zeros(free.len(), 1);
            for (a, &ka) in free.iter().enumerate() {
                let row = &jac[ka];
                reduced_rhs[(a, 0)] = rhs[ka] - fixed.iter().map(|&kb| row[kb] * delta[kb]).sum::<f64>();
                for (b, &kb) in free.iter().enumerate() {
                    reduced[(a, b)] = row[kb];
                }
            }
            if !free.is_empty() {
                let x = reduced.partial_piv_lu().solve(&reduced_rhs);
                for (a, &ka) in free.iter().enumerate() {
                    delta[ka] = x[(a, 0)];
                }
            }
            let mut size = 0.0f64;
            for (k, (v, &d)) in f.iter_mut().zip(&delta).enumerate() {
                *v += d;
                size = size.max(d.abs());
                if d != 0.0 {
                    for (y, dk) in y.iter_mut().zip(&self.d[k * m..(k + 1) * m]) {
                        *y += dk * d;
                    }
                }
            }
            // The forces a kind fixes, exactly (the LU leaves round-off there).
            for k in fixed {
                f[k] = 0.0;
            }
            let scale = f.iter().fold(0.0f64, |x, v| x.max(v.abs()));
            if !(size.is_finite() && scale.is_finite()) {
                return false;
            }
            // At round-off with the kinds settled: the step below a few m ε of the forces, or
            // no longer halving once small (the equations' own rounding).
            let small = size <= 64.0 * m as f64 * f64::EPSILON * scale
                || (iteration >= 2 && size > 0.5 * last && size <= 1e-9 * scale);
            if small && kinds == last_kinds {
                converged = true;
                break;
            }
            (last, last_kinds) = (size, kinds);
        }
        converged && self.settled_cone(f)
    }

    /// Whether the forces f satisfy every condition within the round-off allowance of
    /// [`Dense::holds`] (normal complementarity; `|f_t| ≤ g`; a node with `|Δu_t|` above the
    /// allowance slides with `f_t |Δu_t| = −g Δu_t`, checked in that product form, which the
    /// rounding of a small Δu_t cannot spoil); if so, f, y and the states are set (a node with
    /// `|Δu_t|` within the allowance sticks).
    fn settled_cone(&mut self, f: Vec<f64>) -> bool {
        let m = self.q.len();
        let y = self.values(&f);
        let dmax = self.d.iter().fold(0.0f64, |x, v| x.max(v.abs()));
        let (qmax, fsum) = (self.q.iter().fold(0.0f64, |x, v| x.max(v.abs())), f.iter().map(|v| v.abs()).sum::<f64>());
        let tol_y = 64.0 * m as f64 * f64::EPSILON * (qmax + dmax * fsum);
        let tol_f = 64.0 * m as f64 * f64::EPSILON * f.iter().fold(0.0f64, |x, v| x.max(v.abs()));
        let mut states = Vec::with_capacity(self.slots.len());
        for (i, s) in self.slots.iter().enumerate() {
            let closed = f[s.n] > 0.0;
            if f[s.n] < -tol_f || y[s.n] < -tol_y || closed && y[s.n].abs() > tol_y {
                return false;
            }
            let ts: Vec<usize> = [s.t, s.t2].into_iter().flatten().collect();
            let g = if ts.is_empty() { 0.0 } else { self.bound(i, &f) };
            let ft: Vec<f64> = ts.iter().map(|&k| f[k]).collect();
            let du: Vec<f64> = ts.iter().map(|&k| y[k]).collect();
            let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
            let (size, speed) = (norm(&ft), norm(&du));
            let tangent = if ts.is_empty() || g <= 0.0 && size == 0.0 {
                Tangent::Zero
            } else if size > g + tol_f {
                return false;
            } else if speed <= tol_y {
                Tangent::Stick
            } else {
                let off: Vec<f64> = ft.iter().zip(&du).map(|(a, b)| a * speed + g * b).collect();
                if norm(&off) > tol_f * speed + g * tol_y {
                    return false;
                }
                if ts.len() == 2 {
                    Tangent::Slide([du[0] / speed, du[1] / speed])
                } else {
                    Tangent::Slip(du[0].signum())
                }
            };
            states.push(NodeState { closed, tangent });
        }
        self.states = states;
        self.f = f;
        self.y = y;
        true
    }

    /// The natural residual of the current (f, y) over the largest force (module docs).
    pub(super) fn natural_residual(&self) -> f64 {
        let (f, y) = (&self.f, &self.y);
        let mut worst = 0.0f64;
        for (i, s) in self.slots.iter().enumerate() {
            let (rn, rt) = self.rhos(i);
            let pn = (f[s.n] - rn * y[s.n]).max(0.0);
            worst = worst.max((f[s.n] - pn).abs());
            let Some(t) = s.t else { continue };
            let g = match self.friction {
                Friction::Coulomb { mu } => mu * pn,
                Friction::Tresca { .. } => self.tresca_bound(i),
            };
            let mut trial = [f[t] - rt * y[t], 0.0];
            let mut own = [f[t], 0.0];
            if let Some(t2) = s.t2 {
                (trial[1], own[1]) = (f[t2] - rt * y[t2], f[t2]);
            }
            let size = trial[0].hypot(trial[1]);
            let scale = if size > g { g / size } else { 1.0 };
            worst = worst.max((own[0] - scale * trial[0]).hypot(own[1] - scale * trial[1]));
        }
        let fmax = f.iter().fold(0.0f64, |x, v| x.max(v.abs()));
        if fmax > 0.0 { worst / fmax } else { worst }
    }
}

/// Node's 3 × 3 problem `y = r + [[a, bᵀ], [b, C]] f` with the disc `|f_t| ≤ g` solved to
/// round-off: the first candidate whose inequalities hold (open, stick, slide: the order of
/// the 2D [`super::planar::local_solve`]), else the one that violates them least. `tresca` is Tresca's
/// bound (0 for Coulomb); `guess` the last slide direction.
#[allow(clippy::too_many_arguments)]
fn node_cone(
    a: f64,
    b: [f64; 2],
    c: [[f64; 2]; 2],
    rn: f64,
    rt: [f64; 2],
    friction: Friction,
    tresca: f64,
    guess: Option<[f64; 2]>,
) -> ([f64; 3], NodeState) {
    let dot = |u: [f64; 2], v: [f64; 2]| u[0] * v[0] + u[1] * v[1];
    let times_c = |e: [f64; 2]| [c[0][0] * e[0] + c[0][1] * e[1], c[1][0] * e[0] + c[1][1] * e[1]];
    let neg = |x: f64| (-x).max(0.0);
    let state = |closed: bool, tangent: Tangent| NodeState { closed, tangent };
    let mut best = (f64::INFINITY, ([0.0; 3], state(false, Tangent::Zero)));
    let mut offer = |f: [f64; 3], st: NodeState, violation: f64| {
        if violation < best.0 {
            best = (violation, (f, st));
        }
        violation <= 0.0
    };
    let stick = solve3([[a, b[0], b[1]], [b[0], c[0][0], c[0][1]], [b[1], c[1][0], c[1][1]]], [-rn, -rt[0], -rt[1]]);
    // The slide is against the force that would stick it.
    let away = |ft: [f64; 2]| {
        let n = ft[0].hypot(ft[1]);
        (n > 0.0).then(|| [-ft[0] / n, -ft[1] / n])
    };
    let guess = guess.or_else(|| away([stick[1], stick[2]])).unwrap_or([1.0, 0.0]);
    match friction {
        Friction::Tresca { .. } => {
            let g = tresca;
            if g == 0.0 {
                let (fn_, closed) = super::planar::normal_alone(a, rn);
                return ([fn_, 0.0, 0.0], state(closed, Tangent::Zero));
            }
            // Open: f_n = 0 and the tangential problem on the disc alone.
            let det = c[0][0] * c[1][1] - c[0][1] * c[1][0];
            let ft = [(-rt[0] * c[1][1] + rt[1] * c[0][1]) / det, (-rt[1] * c[0][0] + rt[0] * c[1][0]) / det];
            if ft[0].hypot(ft[1]) <= g {
                if offer([0.0, ft[0], ft[1]], state(false, Tangent::Stick), neg(rn + dot(b, ft))) {
                    return best.1;
                }
            } else {
                let open_guess = away(ft).unwrap_or(guess);
                let yt = |e: [f64; 2]| {
                    let ce = times_c(e);
                    Some([rt[0] - g * ce[0], rt[1] - g * ce[1]])
                };
                if let Some(e) = slide_direction(yt, open_guess) {
                    let ft = [-g * e[0], -g * e[1]];
                    if offer([0.0, ft[0], ft[1]], state(false, Tangent::Slide(e)), neg(rn + dot(b, ft))) {
                        return best.1;
                    }
                }
            }
            let size = stick[1].hypot(stick[2]);
            if offer(stick, state(true, Tangent::Stick), neg(stick[0]) + neg(g - size)) {
                return best.1;
            }
            let normal = |e: [f64; 2]| -(rn - g * dot(b, e)) / a;
            let yt = |e: [f64; 2]| {
                let (fn_, ce) = (normal(e), times_c(e));
                Some([rt[0] + b[0] * fn_ - g * ce[0], rt[1] + b[1] * fn_ - g * ce[1]])
            };
            if let Some(e) = slide_direction(yt, guess) {
                let fn_ = normal(e);
                let y = yt(e).unwrap_or([0.0; 2]);
                offer([fn_, -g * e[0], -g * e[1]], state(true, Tangent::Slide(e)), neg(fn_) + neg(dot(e, y)));
            }
        }
        Friction::Coulomb { mu } => {
            if offer([0.0; 3], state(false, Tangent::Zero), neg(rn)) {
                return best.1;
            }
            let size = stick[1].hypot(stick[2]);
            if offer(stick, state(true, Tangent::Stick), neg(stick[0]) + neg(mu * stick[0] - size)) {
                return best.1;
            }
            let normal = |e: [f64; 2]| {
                let den = a - mu * dot(b, e);
                (den > 0.0).then(|| -rn / den)
            };
            let yt = |e: [f64; 2]| {
                let fn_ = normal(e)?;
                let ce = times_c(e);
                Some([rt[0] + b[0] * fn_ - mu * fn_ * ce[0], rt[1] + b[1] * fn_ - mu * fn_ * ce[1]])
            };
            if let Some(e) = slide_direction(yt, guess)
                && let (Some(fn_), Some(y)) = (normal(e), yt(e))
            {
                let g = mu * fn_;
                offer([fn_, -g * e[0], -g * e[1]], state(true, Tangent::Slide(e)), neg(fn_) + neg(dot(e, y)));
            }
        }
    }
    best.1
}

/// The slide direction e = (cos θ, sin θ): a root of `h(θ) = e⊥ · y_t(e)` (y_t parallel to e)
/// with `e · y_t ≥ 0` (the slip along e), `yt(e)` the values of the state sliding along e (None
/// where that state has no solution). Newton's method from the guess (its slope by central
/// differences), else a scan of 96 angles and bisection of every sign change, the admissible
/// root nearest the guess. None if there is none.
fn slide_direction(yt: impl Fn([f64; 2]) -> Option<[f64; 2]>, guess: [f64; 2]) -> Option<[f64; 2]> {
    let unit = |th: f64| [th.cos(), th.sin()];
    let h = |th: f64| {
        let (e, y) = (unit(th), yt(unit(th))?);
        Some((-e[1] * y[0] + e[0] * y[1], e[0] * y[0] + e[1] * y[1]))
    };
    let th0 = guess[1].atan2(guess[0]);
    let mut th = th0;
    for _ in 0..50 {
        let Some((hv, _)) = h(th) else { break };
        let (Some((hp, _)), Some((hm, _))) = (h(th + 1e-6), h(th - 1e-6)) else { break };
        let slope = (hp - hm) / 2e-6;
        if !(slope.is_finite() && slope != 0.0) {
            break;
        }
        let step = (hv / slope).clamp(-0.5, 0.5);
        th -= step;
        if step.abs() <= 1e-14 {
            if let Some((_, along)) = h(th)
                && along >= 0.0
            {
                return Some(unit(th));
            }
            break;
        }
    }
    // The scan: 96 angles from the guess, each sign change bisected.
    const N: usize = 96;
    let at = |k: usize| th0 + std::f64::consts::TAU * k as f64 / N as f64;
    let mut found: Option<(f64, f64)> = None;
    for k in 0..N {
        let (mut lo, mut hi) = (at(k), at(k + 1));
        let (Some((mut hlo, _)), Some((hhi, _))) = (h(lo), h(hi)) else { continue };
        if hlo * hhi > 0.0 {
            continue;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            let Some((hm, _)) = h(mid) else { break };
            if hm * hlo > 0.0 {
                (lo, hlo) = (mid, hm);
            } else {
                hi = mid;
            }
        }
        let root = 0.5 * (lo + hi);
        let Some((_, along)) = h(root) else { continue };
        // The angular distance to the guess.
        let dist = (root - th0).min(th0 + std::f64::consts::TAU - root);
        if along >= 0.0 && found.is_none_or(|(_, d)| dist < d) {
            found = Some((root, dist));
        }
    }
    found.map(|(root, _)| unit(root))
}

/// The 3 × 3 system `A x = r` by Cramer's rule (A symmetric positive definite: a node's block
/// of D).
fn solve3(a: [[f64; 3]; 3], r: [f64; 3]) -> [f64; 3] {
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let det = det3(a);
    let mut x = [0.0; 3];
    for (k, xk) in x.iter_mut().enumerate() {
        let mut m = a;
        for row in 0..3 {
            m[row][k] = r[row];
        }
        *xk = det3(m) / det;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With D = I, r = (−1, t₁, t₂), Coulomb μ = ½: the node sticks for |t| ≤ ½ (f = −r) and
    /// beyond slides along t/|t| with f_t = −½ t/|t| (isotropic: the direction is r_t's, not a
    /// pyramid's corner); open for r_n > 0.
    #[test]
    fn one_node_sticks_inside_the_disc_and_slides_on_its_rim() {
        let (id_b, id_c) = ([0.0; 2], [[1.0, 0.0], [0.0, 1.0]]);
        let coulomb = Friction::Coulomb { mu: 0.5 };
        let (f, st) = node_cone(1.0, id_b, id_c, -1.0, [0.3, 0.2], coulomb, 0.0, None);
        assert_eq!((f, st.tangent), ([1.0, -0.3, -0.2], Tangent::Stick));
        let (f, st) = node_cone(1.0, id_b, id_c, -1.0, [0.6, 0.8], coulomb, 0.0, None);
        let Tangent::Slide(e) = st.tangent else { panic!("{st:?}") };
        assert!((e[0] - 0.6).abs() <= 4.0 * f64::EPSILON && (e[1] - 0.8).abs() <= 4.0 * f64::EPSILON, "{e:?}");
        assert!((f[1] + 0.3).abs() <= 4.0 * f64::EPSILON && (f[2] + 0.4).abs() <= 4.0 * f64::EPSILON, "{f:?}");
        let (f, st) = node_cone(1.0, id_b, id_c, 0.2, [0.6, 0.8], coulomb, 0.0, None);
        assert_eq!((f, st.closed), ([0.0; 3], false));
    }

    /// An anisotropic block (coupled normal and tangential, C not a multiple of I): the slide
    /// found satisfies its equations to round-off, y_n = 0, |f_t| = μ f_n and y_t ∥ e, e·y_t > 0.
    #[test]
    fn a_coupled_node_slides_with_y_t_along_its_force() {
        let (a, b, c) = (2.0, [0.3, -0.2], [[1.5, 0.4], [0.4, 0.7]]);
        let (rn, rt) = (-1.0, [0.9, -1.3]);
        let (f, st) = node_cone(a, b, c, rn, rt, Friction::Coulomb { mu: 0.4 }, 0.0, None);
        let Tangent::Slide(e) = st.tangent else { panic!("{st:?}") };
        let yn = rn + a * f[0] + b[0] * f[1] + b[1] * f[2];
        let yt = [
            rt[0] + b[0] * f[0] + c[0][0] * f[1] + c[0][1] * f[2],
            rt[1] + b[1] * f[0] + c[1][0] * f[1] + c[1][1] * f[2],
        ];
        let tol = 16.0 * f64::EPSILON;
        assert!(yn.abs() <= tol, "y_n {yn:e}");
        assert!((f[1].hypot(f[2]) - 0.4 * f[0]).abs() <= tol, "on the rim");
        assert!((-e[1] * yt[0] + e[0] * yt[1]).abs() <= tol, "y_t ∥ e");
        assert!(e[0] * yt[0] + e[1] * yt[1] > 0.0);
        assert!((f[1] + 0.4 * f[0] * e[0]).abs() <= tol && (f[2] + 0.4 * f[0] * e[1]).abs() <= tol);
    }
}
