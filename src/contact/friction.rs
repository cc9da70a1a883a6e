//! Friction on the exact Signorini condition (issue 29): Tresca and Coulomb inside one implicit
//! step, solved to round-off in 2D (below) and in 3D, where the bound is the isotropic disc
//! `|f_t| ≤ g` ([`cone`]: the same sweeps, then a semi-smooth Newton method, its answer checked
//! as here).
//!
//! Each implicit scheme (backward Euler, Newmark/Crank–Nicolson) solves per step
//!
//! ```text
//! K U = r + E_n f_n + E_t f_t,     f = σ · (the nodal reactions on the body),
//! normal:      d_i = u_n,i − lb_i ≥ 0,   f_n,i ≥ 0,   d_i f_n,i = 0,
//! tangential:  |f_t,i| ≤ g_i;   |f_t,i| < g_i ⇒ Δu_t,i = 0;   |f_t,i| = g_i ⇒ f_t,i = −g_i Δu_t,i/|Δu_t,i|,
//! ```
//!
//! with `Δu_t,i = u_t,i^{n+1} − u_t,iⁿ` the step's increment of the tangential displacement (the
//! slip velocity times Δt; the unknown is the increment, not a difference of positions: the
//! target of the tangential rows is `u_tⁿ`), and the bound
//! - Tresca: `g_i = σ s a_i` (s = `contact.threshold`, a_i the node's share of the contact area)
//!   on the nodes in contact at the start of the step (`f_n,i > 0` in the previous step), 0 on
//!   the others, so that each step's problem is convex (a strictly convex QP: `min ½ fᵀ D f + qᵀ f`
//!   over `f_n ≥ 0, |f_t| ≤ g`);
//! - Coulomb: `g_i = μ f_n,i` with the step's own normal force: the force at the time level of
//!   the step's equation, t_{n+1} for backward Euler and Newmark (the implicit treatment of
//!   Laursen & Simo, IJNME 36 (1993), and of Wriggers, *Computational Contact Mechanics*, §10.4).
//!
//! Central differences take friction two ways: on a contact layer massless in every component,
//! the same solve on the layer's quasi-static rows ([`FrictionExplicit`], `layer.rs`); on
//! massive tangential unknowns (the standard mass, `contact_directions = "normal"`), the
//! forward-increment multiplier node by node, in closed form ([`FrictionMassive`], `massive.rs`).
//!
//! **The frame.** The unknowns are a body's components in the obstacle's frame
//! (`crate::solid::body`): component 0 of a contact node is normal, components 1.. tangential
//! ([`Tangential`]).
//!
//! **The solve.** All contact-node unknowns are eliminated last in the factor of K, so with
//! `U* = K⁻¹ r` and the dense `D = Eᵀ K⁻¹ E` (E the columns of the contact-node unknowns, n_c·d of
//! them) the contact values are `y = q + D f`, `q = U*_T − target` (target: lb for a normal
//! unknown, `u_tⁿ` for a tangential one). In 2D the conditions are piecewise linear in f:
//! 1. block Gauss–Seidel sweeps, each node's 2 × 2 problem solved exactly (its states: open or
//!    closed, and stick or slip with a direction), until the states repeat;
//! 2. the linear system of those states solved exactly (dense LU with partial pivoting) and every
//!    inequality checked against a round-off allowance; if one fails, more sweeps, then again;
//!    every 50 sweeps, primal–dual active-set iterations from the sweeps' states
//!    (`Dense::active_set`: the sweeps converge slowly when D is nearly singular);
//! 3. the verified states' values solved again in displacement form, `f = S z − S U*` with
//!    `S = D⁻¹` from the factor (`Dense::settle`), kept where its implied forces match its
//!    reported ones better (a free body with a long step: D's rigid-motion entries make the
//!    force form's values err by ε‖D‖‖f‖).
//!
//! The answer is the exact solution of the piecewise-linear system (round-off only); on closed
//! nodes `u_n = lb` and on sticking nodes `u_t = u_tⁿ` are set exactly. The stopping rule is the
//! sign check, never a tolerance on the iterates. Cost per step: one forward and one backward
//! substitution with the factor, O(n_c²) per sweep, one O(n_c³) LU per check.

use super::lcp::LcpError;
use super::{SetupError, StepLaw};
use crate::linalg::sparse::SparseLlt;
pub use crate::system::Tangential;
use faer::Mat;
use faer::linalg::solvers::Solve;
use serde::{Deserialize, Serialize};

mod cone;
mod layer;
mod massive;

pub use layer::FrictionExplicit;
pub use massive::FrictionMassive;

/// A friction law on the exact Signorini condition (`contact.friction`, module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Friction {
    /// `|r_t,i| ≤ s a_i` on the nodes in contact at the start of the step.
    Tresca { threshold: f64 },
    /// `|r_t,i| ≤ μ r_n,i`.
    Coulomb { mu: f64 },
}

impl Friction {
    pub const KEY: &'static str = "contact.friction";
    /// The values of `contact.friction`, as messages list them.
    pub const NAMES: &'static str = "none | tresca | coulomb";
    pub const MU_KEY: &'static str = "contact.mu";
    pub const THRESHOLD_KEY: &'static str = "contact.threshold";
    pub const RANGE: &'static str = "[0, ∞)";

    /// The scene name (`contact.friction`).
    pub const fn name(&self) -> &'static str {
        match self {
            Friction::Tresca { .. } => "tresca",
            Friction::Coulomb { .. } => "coulomb",
        }
    }

    /// Whether a coefficient is in its range: finite and ≥ 0.
    pub fn in_range(x: f64) -> bool {
        x.is_finite() && x >= 0.0
    }
}

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
    /// force ([`cone`]'s module docs; 3D only, 0 in 2D where the states are solved exactly).
    pub residual: f64,
    /// Per contact node at the last step: 0 free, 1 stick, 2 slip.
    pub state: Vec<u8>,
    /// Per contact node at the last step: the friction traction `r_t,i / a_i` (world
    /// components; entries beyond dim are 0).
    pub traction: Vec<[f64; 3]>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Tangent {
    /// No tangential force (no tangential unknown, Coulomb on an open node, Tresca's bound 0).
    Zero,
    Stick,
    /// Sliding with `Δu_t` of sign s: `f_t = −s g` (a node with one tangential unknown).
    Slip(f64),
    /// Sliding with `Δu_t` along the unit e of the node's two tangential components:
    /// `f_t = −g e` (3D, [`cone`]).
    Slide([f64; 2]),
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct NodeState {
    closed: bool,
    tangent: Tangent,
}

/// One node's slots in the trailing unknowns: its normal one and its tangential ones (one in
/// 2D, two in 3D unless a roller eliminates one), with the axis (an index into the frame's
/// tangential axes) of each.
#[derive(Debug, Clone, Copy)]
struct Slots {
    n: usize,
    t: Option<usize>,
    t2: Option<usize>,
    axis: [usize; 2],
}

/// Sweeps before giving up (each costs O(n_c²)); the states of a well-posed 2D problem settle
/// in far fewer.
const MAX_SWEEPS: usize = 20_000;

/// Active-set iterations per try ([`Dense::active_set`]).
const MAX_ACTIVE_SET: usize = 50;

/// The frictional implicit step (module docs).
#[derive(Debug)]
pub struct FrictionStep {
    factor: SparseLlt,
    /// `L_TTᵀ`, row-major upper triangular m × m (m the contact-node unknowns).
    upper: Vec<f64>,
    /// Full index of each trailing unknown.
    unknowns: Vec<usize>,
    dense: Dense,
}

/// The step's problem on the contact-node unknowns (module docs).
#[derive(Debug)]
struct Dense {
    /// `D = Eᵀ K⁻¹ E`, row-major m × m.
    d: Vec<f64>,
    /// `S = D⁻¹ = L_TT L_TTᵀ` (the Schur complement of K on the contact-node unknowns, from the
    /// factor's trailing block), row-major m × m.
    schur: Vec<f64>,
    slots: Vec<Slots>,
    areas: Vec<f64>,
    axes: Vec<[f64; 3]>,
    friction: Friction,
    sigma: f64,
    dt: f64,
    /// The step's increment over the solved value's: `Δu_t = span (u_t − u_tⁿ)`; 1 where the
    /// solve gives U^{n+1}, 2 for the hybrid scheme's midpoint `Ū = (Uⁿ + U^{n+1})/2`.
    span: f64,
    /// Targets: lb on normal slots, `u_tⁿ` on tangential ones.
    target: Vec<f64>,
    /// Whether each node carried normal force in the previous step (Tresca's active set).
    was_closed: Vec<bool>,
    f: Vec<f64>,
    q: Vec<f64>,
    /// `U*_T`, then `y = q + D f`.
    y: Vec<f64>,
    /// `u_T = y + target`.
    u: Vec<f64>,
    states: Vec<NodeState>,
    record: FrictionRecord,
    /// The last step's Gauss–Seidel sweeps (reported as its pivots).
    sweeps: usize,
}

impl FrictionStep {
    /// Factors `k` with the contact-node unknowns last and builds D (O(m³) once); the solve
    /// gives U^{n+1} (`span` 1, [`Self::midpoint`] for the hybrid scheme's).
    pub fn new(
        k: &crate::linalg::sparse::SpMat,
        contact: &[usize],
        tangential: &Tangential,
        friction: Friction,
        matrix: &'static str,
        sigma: f64,
        dt: f64,
    ) -> Result<Self, SetupError> {
        let mut unknowns = Vec::new();
        let mut slots = Vec::new();
        for ((&c, t), axis) in contact.iter().zip(&tangential.unknowns).zip(&tangential.components) {
            let n = unknowns.len();
            unknowns.push(c);
            let mut slot = |k: usize| {
                t.get(k).map(|&j| {
                    unknowns.push(j);
                    unknowns.len() - 1
                })
            };
            let (t, t2) = (slot(0), slot(1));
            let axis = [axis.first().copied().unwrap_or(0), axis.get(1).copied().unwrap_or(0)];
            slots.push(Slots { n, t, t2, axis });
        }
        let m = unknowns.len();
        let factor = SparseLlt::with_trailing(k, &unknowns, matrix).map_err(crate::linalg::LinalgError::from)?;
        let upper = factor.trailing_upper();
        let d = super::schur::trailing_inverse(&upper, m);
        let mut schur = vec![0.0; m * m];
        for k in 0..m {
            for a in k..m {
                let ua = upper[k * m + a];
                for b in k..m {
                    schur[a * m + b] += ua * upper[k * m + b];
                }
            }
        }
        let nc = contact.len();
        let dense = Dense {
            d,
            schur,
            slots,
            areas: tangential.areas.clone(),
            axes: tangential.axes.clone(),
            friction,
            sigma,
            dt,
            span: 1.0,
            target: vec![0.0; m],
            was_closed: vec![false; nc],
            f: vec![0.0; m],
            q: vec![0.0; m],
            y: vec![0.0; m],
            u: vec![0.0; m],
            states: vec![NodeState { closed: false, tangent: Tangent::Zero }; nc],
            record: FrictionRecord { state: vec![0; nc], traction: vec![[0.0; 3]; nc], ..Default::default() },
            sweeps: 0,
        };
        Ok(Self { factor, upper, unknowns, dense })
    }

    /// The law in the hybrid scheme's midpoint step: the solve gives `Ū = (Uⁿ + U^{n+1})/2`,
    /// so the stick condition `ū_t = u_tⁿ` is `Δu_t = 0`, a slide's `ū_t − u_tⁿ` points along
    /// `Δu_t = 2 (ū_t − u_tⁿ)` (the conditions hold for any positive multiple of the increment),
    /// and the record and the next targets take `Δu_t` and `u_t^{n+1} = 2ū_t − u_tⁿ`.
    pub fn midpoint(mut self) -> Self {
        self.dense.span = 2.0;
        self
    }
}

impl Dense {
    /// The tangential bound g_i (scaled by σ) of node i at the forces f.
    fn bound(&self, i: usize, f: &[f64]) -> f64 {
        match self.friction {
            Friction::Tresca { threshold } => {
                if self.was_closed[i] {
                    self.sigma * threshold * self.areas[i]
                } else {
                    0.0
                }
            }
            Friction::Coulomb { mu } => mu * f[self.slots[i].n],
        }
    }

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
    fn local(&mut self, i: usize) -> NodeState {
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

    /// Tresca's bound of node i (σ s a_i if it was in contact, else 0); 0 for Coulomb.
    fn tresca_bound(&self, i: usize) -> f64 {
        match self.friction {
            Friction::Tresca { .. } => self.bound(i, &self.f),
            Friction::Coulomb { .. } => 0.0,
        }
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
    fn solve_forces(&mut self) -> Result<usize, LcpError> {
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

    /// The record of the step just solved (forces r = f/σ on the body).
    fn update_record(&mut self) {
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

/// A node's normal problem alone, `y_n = r_n + a f_n ≥ 0 ⊥ f_n ≥ 0`: its force and whether it
/// is closed.
fn normal_alone(a: f64, rn: f64) -> (f64, bool) {
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
    fn settle(&mut self, w: &[f64], upper: &[f64]) {
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

    /// From the forward substitution's trailing block `y` (elimination order): `U*_T`, q, the
    /// forces, the exact values on closed and sticking nodes, and `y ← L_TTᵀ u_T` (the forward
    /// substitution of `r + E f`).
    fn step(&mut self, y: &mut [f64], upper: &[f64]) -> Result<(), LcpError> {
        let m = self.q.len();
        for a in (0..m).rev() {
            let row = &upper[a * m..(a + 1) * m];
            let s: f64 = (a + 1..m).map(|b| row[b] * self.y[b]).sum();
            self.y[a] = (y[a] - s) / row[a];
        }
        for k in 0..m {
            self.q[k] = self.y[k] - self.target[k];
        }
        self.sweeps = self.solve_forces()?;
        if !self.is_cone() {
            self.settle(y, upper);
        }
        for (s, st) in self.slots.iter().zip(&self.states) {
            if st.closed {
                self.y[s.n] = 0.0;
            }
            if st.tangent == Tangent::Stick {
                for t in [s.t, s.t2].into_iter().flatten() {
                    self.y[t] = 0.0;
                }
            }
        }
        for k in 0..m {
            self.u[k] = self.y[k] + self.target[k];
        }
        for a in 0..m {
            let row = &upper[a * m..(a + 1) * m];
            y[a] = (a..m).map(|b| row[b] * self.u[b]).sum();
        }
        Ok(())
    }
}

impl StepLaw for FrictionStep {
    fn solve(&mut self, rhs: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError> {
        let Self { factor, upper, unknowns, dense } = self;
        // Targets: lb on normal slots (u_tⁿ on tangential ones is kept from the last step).
        for (s, &lb) in dense.slots.iter().zip(lower) {
            dense.target[s.n] = lb;
        }
        factor.solve_split(rhs, |y| dense.step(y, upper))?;
        for (c, (s, st)) in dense.slots.iter().zip(&dense.states).enumerate() {
            let fn_ = dense.f[s.n];
            lambda[c] = if st.closed && fn_ > 0.0 { -fn_ / dense.sigma } else { 0.0 };
        }
        // Exact values: u_n = lb on closed nodes, u_t = u_tⁿ on sticking ones.
        for (k, &i) in unknowns.iter().enumerate() {
            rhs[i] = dense.u[k];
        }
        dense.update_record();
        // The next step's tangential targets: u_t^{n+1} (`2ū_t − u_tⁿ` from the midpoint, as
        // the hybrid scheme forms it).
        for t in dense.slots.iter().flat_map(|s| [s.t, s.t2]).flatten() {
            dense.target[t] = if dense.span == 1.0 { dense.u[t] } else { 2.0 * dense.u[t] - dense.target[t] };
        }
        Ok(dense.sweeps)
    }

    fn start(&mut self, u0: &[f64]) {
        for t in self.dense.slots.iter().flat_map(|s| [s.t, s.t2]).flatten() {
            self.dense.target[t] = u0[self.unknowns[t]];
        }
    }

    fn friction(&self) -> Option<&FrictionRecord> {
        Some(&self.dense.record)
    }

    fn reciprocal_sigma(&self) -> bool {
        true
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
