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
use serde::{Deserialize, Serialize};

mod cone;
mod cone_node;
mod layer;
mod massive;
mod planar;
mod record;

pub use layer::FrictionExplicit;
pub use massive::FrictionMassive;
pub use record::FrictionRecord;

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

    /// Tresca's bound of node i (σ s a_i if it was in contact, else 0); 0 for Coulomb.
    fn tresca_bound(&self, i: usize) -> f64 {
        match self.friction {
            Friction::Tresca { .. } => self.bound(i, &self.f),
            Friction::Coulomb { .. } => 0.0,
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
