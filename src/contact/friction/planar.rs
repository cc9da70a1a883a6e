//! The 2D path of the frictional step (`friction`'s module docs, steps 1–3): block Gauss–Seidel
//! sweeps with each node's 2 × 2 problem solved exactly ([`local_solve`]), the states' linear
//! system solved and checked ([`Dense::polish`]), primal–dual active-set iterations
//! ([`Dense::active_set`]), and the verified states solved again in displacement form
//! ([`Dense::settle`]).

use super::super::lcp::LcpError;
use super::{Dense, Friction, MAX_SWEEPS, NodeState, Slots, Tangent};
use faer::Mat;
use faer::linalg::solvers::Solve;

/// Active-set iterations per try ([`Dense::active_set`]).
const MAX_ACTIVE_SET: usize = 50;

impl Dense {
    /// `(q + D f)_k` without node i's own columns.
    fn rest(&self, k: usize, own: Slots) -> f64 {
        let m = self.q.len();
        let row = &self.d[k * m..(k + 1) * m];
        let mut s = self.q[k];
        for (b, (&dk, &fb)) in row.iter().zip(&self.f).enumerate() {
            if b != own.n && Some(b) != own.t && Some(b) != own.t2 {
                s += dk * fb;
            }
        }
        s
    }

    /// Node i's own problem solved exactly for the others' forces fixed; returns its state.
    pub(super) fn local(&mut self, i: usize) -> NodeState {
        let s = self.slots[i];
        if let (Some(t), Some(t2)) = (s.t, s.t2) {
            return self.local_cone(i, t, t2);
        }
        let m = self.q.len();
        let rn = self.rest(s.n, s);
        let a = self.d[s.n * m + s.n];
        let Some(t) = s.t else {
            let (fn_, closed) = normal_alone(a, rn);
            self.f[s.n] = fn_;
            return NodeState { closed, tangent: Tangent::Zero };
        };
        let rt = self.rest(t, s);
        let (b, c) = (self.d[s.n * m + t], self.d[t * m + t]);
        let (fn_, ft, state) = local_solve(a, b, c, rn, rt, self.friction, self.tresca_bound(i));
        self.f[s.n] = fn_;
        self.f[t] = ft;
        state
    }

    /// The linear system of the current states solved exactly into `self.f`; true if every
    /// inequality holds within the round-off allowance.
    fn polish(&mut self) -> bool {
        let Some((f, y)) = self.linear() else { return false };
        if !self.holds(&f, &y) {
            return false;
        }
        self.f = f;
        self.y = y;
        true
    }

    /// The forces and values `(f, y)` of the current states' linear system (forces fixed by a
    /// state set exactly); None if the solve is not finite.
    fn linear(&self) -> Option<(Vec<f64>, Vec<f64>)> {
        let m = self.q.len();
        let mut a = Mat::<f64>::zeros(m, m);
        let mut rhs = Mat::<f64>::zeros(m, 1);
        let row_of_d = |a: &mut Mat<f64>, k: usize, d: &[f64]| {
            for b in 0..m {
                a[(k, b)] = d[k * m + b];
            }
        };
        for (i, (&s, st)) in self.slots.iter().zip(&self.states).enumerate() {
            if st.closed {
                row_of_d(&mut a, s.n, &self.d);
                rhs[(s.n, 0)] = -self.q[s.n];
            } else {
                a[(s.n, s.n)] = 1.0;
            }
            let Some(t) = s.t else { continue };
            match st.tangent {
                // (Slide is a 3D node's state, never this 2D path's.)
                Tangent::Zero | Tangent::Slide(_) => a[(t, t)] = 1.0,
                Tangent::Stick => {
                    row_of_d(&mut a, t, &self.d);
                    rhs[(t, 0)] = -self.q[t];
                }
                Tangent::Slip(sign) => {
                    a[(t, t)] = 1.0;
                    match self.friction {
                        Friction::Tresca { .. } => rhs[(t, 0)] = -sign * self.tresca_bound(i),
                        Friction::Coulomb { mu } => a[(t, s.n)] = sign * mu,
                    }
                }
            }
        }
        let x = a.partial_piv_lu().solve(&rhs);
        let mut f: Vec<f64> = (0..m).map(|k| x[(k, 0)]).collect();
        // The rows that fix a force are set exactly (the LU leaves round-off there, which would
        // otherwise count an open node as pressing).
        self.fix_forces(&mut f);
        if f.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let y: Vec<f64> = (0..m).map(|k| self.q[k] + (0..m).map(|b| self.d[k * m + b] * f[b]).sum::<f64>()).collect();
        Some((f, y))
    }

    /// The forces the current states fix, set exactly in `f`: 0 on open nodes and without
    /// friction, `−s g` on sliding ones.
    fn fix_forces(&self, f: &mut [f64]) {
        for (i, (&s, st)) in self.slots.iter().zip(&self.states).enumerate() {
            if !st.closed {
                f[s.n] = 0.0;
            }
            let Some(t) = s.t else { continue };
            match (st.tangent, self.friction) {
                (Tangent::Zero, _) | (Tangent::Slide(_), _) => f[t] = 0.0,
                (Tangent::Slip(sign), Friction::Tresca { .. }) => f[t] = -sign * self.tresca_bound(i),
                (Tangent::Slip(sign), Friction::Coulomb { mu }) => f[t] = -sign * mu * f[s.n],
                (Tangent::Stick, _) => {}
            }
        }
    }

    /// Whether every inequality of the current states holds at `(f, y)` within the round-off
    /// allowance of a backward-stable dense solve of size m: a few m ε of the scale.
    fn holds(&self, f: &[f64], y: &[f64]) -> bool {
        let m = self.q.len();
        let dmax = self.d.iter().fold(0.0f64, |x, v| x.max(v.abs()));
        let (qmax, fsum) = (self.q.iter().fold(0.0f64, |x, v| x.max(v.abs())), f.iter().map(|v| v.abs()).sum::<f64>());
        let tol_y = 64.0 * m as f64 * f64::EPSILON * (qmax + dmax * fsum);
        let tol_f = 64.0 * m as f64 * f64::EPSILON * f.iter().fold(0.0f64, |x, v| x.max(v.abs()));
        for (i, (&s, st)) in self.slots.iter().zip(&self.states).enumerate() {
            if st.closed && f[s.n] < -tol_f || !st.closed && y[s.n] < -tol_y {
                return false;
            }
            let Some(t) = s.t else { continue };
            let g = self.bound(i, f);
            match st.tangent {
                Tangent::Zero | Tangent::Slide(_) => {}
                Tangent::Stick if f[t].abs() > g + tol_f => return false,
                Tangent::Slip(sign) if sign * y[t] < -tol_y => return false,
                _ => {}
            }
        }
        true
    }

    /// Primal–dual active-set iterations from the current states (Hintermüller, Ito and
    /// Kunisch, SIAM J. Optim. 13 (2002); for Coulomb friction Hüeber, Stadler and Wohlmuth,
    /// SIAM J. Sci. Comput. 30 (2008)): solve the states' linear system, take the states
    /// `f − c y` predicts (c = 1/D_kk per row: closed where `f_n − c y_n > 0`; stick where
    /// `|f_t − c y_t|` is within the bound, else slide opposite to it), until they repeat; then
    /// the same check as [`Self::polish`]. For the nearly singular D of a free body with a long
    /// step (the Gauss–Seidel sweeps then converge slowly: 8840 sweeps for a free P1 disc with
    /// Δt = 1e3), where a few iterations suffice. True if the states verified.
    fn active_set(&mut self) -> bool {
        let m = self.q.len();
        for _ in 0..MAX_ACTIVE_SET {
            let Some((f, y)) = self.linear() else { return false };
            let mut next = self.states.clone();
            for (i, s) in self.slots.iter().enumerate() {
                let c = |k: usize| 1.0 / self.d[k * m + k];
                let pressed = f[s.n] - c(s.n) * y[s.n];
                let closed = pressed > 0.0;
                let tangent = match s.t {
                    None => Tangent::Zero,
                    Some(t) => {
                        let g = match self.friction {
                            Friction::Tresca { .. } => self.tresca_bound(i),
                            Friction::Coulomb { mu } => mu * pressed.max(0.0),
                        };
                        let trial = f[t] - c(t) * y[t];
                        if g <= 0.0 {
                            Tangent::Zero
                        } else if trial.abs() <= g {
                            Tangent::Stick
                        } else {
                            Tangent::Slip(-trial.signum())
                        }
                    }
                };
                next[i] = NodeState { closed, tangent };
            }
            if next == self.states {
                return self.holds(&f, &y) && {
                    self.f = f;
                    self.y = y;
                    true
                };
            }
            self.states = next;
        }
        false
    }

    /// Solves the frictional problem for the current q (module docs) into f and y.
    pub(super) fn solve_forces(&mut self) -> Result<usize, LcpError> {
        if self.is_cone() {
            return self.solve_cone();
        }
        let nc = self.slots.len();
        let mut previous: Vec<NodeState> = self.states.clone();
        let mut repeats = 0;
        for sweep in 1..=MAX_SWEEPS {
            for i in 0..nc {
                self.states[i] = self.local(i);
            }
            repeats = if self.states == previous { repeats + 1 } else { 0 };
            previous.clone_from(&self.states);
            // The states repeated over two sweeps (or every 50 sweeps): try them exactly; every
            // 50 sweeps, active-set iterations from them.
            if (repeats >= 2 || sweep % 50 == 0) && self.polish() {
                return Ok(sweep);
            }
            if sweep % 50 == 0 && self.active_set() {
                return Ok(sweep);
            }
        }
        let m = self.q.len();
        let residual =
            (0..m).map(|k| self.q[k] + (0..m).map(|b| self.d[k * m + b] * self.f[b]).sum::<f64>()).fold(0.0, f64::max);
        Err(LcpError::NotConverged { pivots: MAX_SWEEPS, residual })
    }
}

/// A node's normal problem alone, `y_n = r_n + a f_n ≥ 0 ⊥ f_n ≥ 0`: its force and whether it
/// is closed.
pub(super) fn normal_alone(a: f64, rn: f64) -> (f64, bool) {
    let closed = rn < 0.0;
    (if closed { -rn / a } else { 0.0 }, closed)
}

/// Node i's 2 × 2 problem `y = r + [[a, b], [b, c]] f` (module docs) solved exactly: the first
/// candidate state whose inequalities hold (one does: Tresca's problem is a strictly convex QP,
/// Coulomb's has one solution for μ |b| < a), else the one that violates them least.
fn local_solve(a: f64, b: f64, c: f64, rn: f64, rt: f64, friction: Friction, tresca: f64) -> (f64, f64, NodeState) {
    let det = a * c - b * b;
    let stick = ((-rn * c + rt * b) / det, (-rt * a + rn * b) / det);
    let mut best = (f64::INFINITY, (0.0, 0.0, NodeState { closed: false, tangent: Tangent::Zero }));
    let mut offer = |fn_: f64, ft: f64, st: NodeState, violation: f64| {
        if violation < best.0 {
            best = (violation, (fn_, ft, st));
        }
        violation <= 0.0
    };
    let neg = |x: f64| (-x).max(0.0);
    match friction {
        Friction::Tresca { .. } => {
            let g = tresca;
            if g == 0.0 {
                // No tangential force: the normal problem alone.
                let (fn_, closed) = normal_alone(a, rn);
                return (fn_, 0.0, NodeState { closed, tangent: Tangent::Zero });
            }
            // Open: f_n = 0, the tangential problem alone.
            let ft_stick = -rt / c;
            let (ft, tangent) = if ft_stick.abs() <= g {
                (ft_stick, Tangent::Stick)
            } else {
                let s = rt.signum();
                (-s * g, Tangent::Slip(s))
            };
            if offer(0.0, ft, NodeState { closed: false, tangent }, neg(rn + b * ft)) {
                return best.1;
            }
            let (fn_, ft) = stick;
            if offer(fn_, ft, NodeState { closed: true, tangent: Tangent::Stick }, neg(fn_) + neg(g - ft.abs())) {
                return best.1;
            }
            for s in [1.0, -1.0] {
                let ft = -s * g;
                let fn_ = -(rn + b * ft) / a;
                let yt = rt + b * fn_ + c * ft;
                if offer(fn_, ft, NodeState { closed: true, tangent: Tangent::Slip(s) }, neg(fn_) + neg(s * yt)) {
                    return best.1;
                }
            }
        }
        Friction::Coulomb { mu } => {
            if offer(0.0, 0.0, NodeState { closed: false, tangent: Tangent::Zero }, neg(rn)) {
                return best.1;
            }
            let (fn_, ft) = stick;
            if offer(fn_, ft, NodeState { closed: true, tangent: Tangent::Stick }, neg(fn_) + neg(mu * fn_ - ft.abs()))
            {
                return best.1;
            }
            for s in [1.0, -1.0] {
                let den = a - s * mu * b;
                if !(den > 0.0) {
                    continue;
                }
                let fn_ = -rn / den;
                let ft = -s * mu * fn_;
                let yt = rt + b * fn_ + c * ft;
                if offer(fn_, ft, NodeState { closed: true, tangent: Tangent::Slip(s) }, neg(fn_) + neg(s * yt)) {
                    return best.1;
                }
            }
        }
    }
    best.1
}

impl Dense {
    /// The verified states' values solved again in displacement form: the unknowns are the
    /// contact-node values z, each row either fixes one (closed: z_n = lb; stick: z_t = u_tⁿ) or
    /// states a force of `f = S z − S U*_T` (open: f_n = 0; no friction: f_t = 0; slip:
    /// f_t = −s g), solved by a dense LU. D has the huge entries of a free body's rigid motions
    /// held by little inertia (1/λ_min: 1e12 of the stiffness for a free disc with Δt = 1e6), so
    /// that y = q + D f carries ε‖D‖‖f‖ of round-off and the open nodes' values then imply
    /// forces (measured on that disc: up to 4.3e-3, 3.5e-5 of the total reaction 124), where S
    /// is the stiffness seen through the fixed rows and these values satisfy the equations to
    /// the factor's round-off (measured against GetFEM on that disc: 5e-14 of the displacement,
    /// `crosscheck`). Kept where the forces its values imply are closer to the forces it reports
    /// than the force form's (a well-conditioned D keeps the force form: its reported forces are
    /// then the applied ones to round-off), and the states' inequalities still hold.
    pub(super) fn settle(&mut self, w: &[f64], upper: &[f64]) {
        let m = self.q.len();
        let (s, target) = (&self.schur, &self.target);
        // S U*_T = L_TT L_TTᵀ U*_T = L_TT w (w the forward substitution's trailing block): U*_T
        // itself is not formed, its rigid part can be 1e11 (a free body's load over its inertia).
        let su: Vec<f64> = (0..m).map(|a| (0..=a).map(|b| upper[b * m + a] * w[b]).sum()).collect();
        let mut a = Mat::<f64>::zeros(m, m);
        let mut rhs = Mat::<f64>::zeros(m, 1);
        let fix = |a: &mut Mat<f64>, rhs: &mut Mat<f64>, k: usize| {
            a[(k, k)] = 1.0;
            rhs[(k, 0)] = target[k];
        };
        // Row k of the force f_k = (S z − S U*)_k, times c, added to row `row`.
        let force = |a: &mut Mat<f64>, rhs: &mut Mat<f64>, row: usize, k: usize, c: f64| {
            for b in 0..m {
                a[(row, b)] += c * s[k * m + b];
            }
            rhs[(row, 0)] += c * su[k];
        };
        for (i, (&sl, st)) in self.slots.iter().zip(&self.states).enumerate() {
            if st.closed {
                fix(&mut a, &mut rhs, sl.n);
            } else {
                force(&mut a, &mut rhs, sl.n, sl.n, 1.0);
            }
            let Some(t) = sl.t else { continue };
            match st.tangent {
                Tangent::Stick => fix(&mut a, &mut rhs, t),
                Tangent::Zero | Tangent::Slide(_) => force(&mut a, &mut rhs, t, t, 1.0),
                Tangent::Slip(sign) => {
                    force(&mut a, &mut rhs, t, t, 1.0);
                    match self.friction {
                        Friction::Coulomb { mu } => force(&mut a, &mut rhs, t, sl.n, sign * mu),
                        Friction::Tresca { .. } => rhs[(t, 0)] -= sign * self.tresca_bound(i),
                    }
                }
            }
        }
        let x = a.partial_piv_lu().solve(&rhs);
        let mut z: Vec<f64> = (0..m).map(|k| x[(k, 0)]).collect();
        for (&sl, st) in self.slots.iter().zip(&self.states) {
            if st.closed {
                z[sl.n] = target[sl.n];
            }
            if let (Some(t), Tangent::Stick) = (sl.t, st.tangent) {
                z[t] = target[t];
            }
        }
        let mut f: Vec<f64> = (0..m).map(|k| (0..m).map(|b| s[k * m + b] * z[b]).sum::<f64>() - su[k]).collect();
        // The forces the states fix, exactly (as the force form sets them).
        self.fix_forces(&mut f);
        let y: Vec<f64> = (0..m).map(|k| z[k] - target[k]).collect();
        // How far the forces the values imply, S z − S U*_T, are from the forces reported: the
        // force form's answer against this one; the smaller wins.
        let mismatch = |f: &[f64], y: &[f64]| {
            (0..m)
                .map(|k| ((0..m).map(|b| s[k * m + b] * (y[b] + target[b])).sum::<f64>() - su[k] - f[k]).abs())
                .fold(0.0, f64::max)
        };
        if f.iter().chain(&y).all(|v| v.is_finite())
            && mismatch(&f, &y) < mismatch(&self.f, &self.y)
            && self.holds(&f, &y)
        {
            self.f = f;
            self.y = y;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 2 × 2 problem's states: with D = I and r = (−1, t), Coulomb μ = ½ sticks for
    /// |t| ≤ ½ (f = −r) and slides beyond with f_t = −sign(t) μ f_n.
    #[test]
    fn one_node_sticks_inside_the_cone_and_slides_on_it() {
        let coulomb = Friction::Coulomb { mu: 0.5 };
        let (fn_, ft, st) = local_solve(1.0, 0.0, 1.0, -1.0, 0.3, coulomb, 0.0);
        assert_eq!((fn_, ft, st), (1.0, -0.3, NodeState { closed: true, tangent: Tangent::Stick }));
        let (fn_, ft, st) = local_solve(1.0, 0.0, 1.0, -1.0, 0.8, coulomb, 0.0);
        assert_eq!((fn_, ft, st), (1.0, -0.5, NodeState { closed: true, tangent: Tangent::Slip(1.0) }));
        let (fn_, ft, st) = local_solve(1.0, 0.0, 1.0, 0.2, 0.8, coulomb, 0.0);
        assert_eq!((fn_, ft, st.closed), (0.0, 0.0, false));
        // Tresca with bound 0.25 on an open node: the tangential problem alone.
        let tresca = Friction::Tresca { threshold: 1.0 };
        let (fn_, ft, st) = local_solve(1.0, 0.0, 1.0, 0.2, -0.8, tresca, 0.25);
        assert_eq!((fn_, ft, st), (0.0, 0.25, NodeState { closed: false, tangent: Tangent::Slip(-1.0) }));
    }
}
