//! The isotropic cone of 3D (issue 29): a contact node with two tangential unknowns, whose
//! friction force is bounded by a disc, `|f_t| ≤ g` (g = μ f_n for Coulomb, σ s a_i for
//! Tresca), not by a pyramid.
//!
//! Its conditions are no longer piecewise linear: a sliding node's force `f_t = −g e` points
//! against the unit direction `e = Δu_t/|Δu_t|` of its slip, which the solve finds. The solve:
//! 1. block Gauss–Seidel sweeps ([`Dense::sweep_cone`]), each node's 3 × 3 problem solved to
//!    round-off ([`super::cone_node::node_cone`]: open, stick, or slide along the e that makes `y_t` parallel to
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
use super::cone_node::node_cone;
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
