//! Central differences with friction on massive tangential unknowns: the standard mass (every
//! component of a contact node massive), and mod1/mod2/mod3 with `mass.contact_directions =
//! "normal"` (the normal component massless and quasi-static, the tangential ones keeping the
//! standard mass). [`FrictionMassive`].
//!
//! **The forward increment, tangentially.** The normal contact is the exact law's
//! ([`ExactExplicit`]): the forward-increment multiplier on a massive normal unknown, the
//! layer's quasi-static Signorini solve at the current time on a massless one. The friction
//! force of a contact node is the forward-increment multiplier of its tangential unknowns
//! (Carpenter, Taylor & Katona, IJNME 32 (1991) 103–128, §4, their Coulomb friction in the
//! forward-increment method): with the lumped mass m of the node's tangential unknowns (one
//! value: the mass is a scalar field times the identity), `A = M_L⁻¹ (F − K U)` without friction
//! and the scheme's increment over the next step without friction
//!
//! ```text
//! Δũ_t = Δt v_t + κ Δt² a_t        (κ = 1 in a step, ½ at n = 0: central_difference's docs),
//! ```
//!
//! the force that makes the node stick, `f* = −m Δũ_t/(κ Δt²)`, is taken where `|f*| ≤ g`
//! (stick: the next increment Δu_t is 0), else its radial return `f = g f*/|f*|` (slip: Δu_t =
//! Δũ_t (1 − g κΔt²/(m |Δũ_t|)), a positive multiple of Δũ_t, so f is opposite to the step's
//! tangential velocity and at the bound). In 3D the return is onto the disc |f| ≤ g: the
//! isotropic cone, exact in closed form because the mass is diagonal and the same in both
//! tangential components. Each node is its own problem: no solve, O(1) per contact node.
//!
//! **Time levels.** The friction force at level n acts on the increment from t_n to t_{n+1}, as
//! the normal forward increment does. Its bound g uses the normal force of the same level:
//! Coulomb `g = μ r_n` with `r_n = −λ` of the forward increment at t_n (standard mass) or of the
//! layer's quasi-static solve at t_n (massless normal unknowns; solved before the accelerations
//! of t_n); Tresca `g = s a_i` on the nodes whose normal force at that level is positive (the
//! nodes in contact at the start of the increment), 0 on the others.
//!
//! **What is recorded.** `friction_dissipation` adds `−f · Δu_t` when the increment that the
//! force governs is known (at the next level: `Δu_t = u_t^{n+1} − u_tⁿ` as stepped), so the
//! last level's force, which governs no step of the run, adds nothing; the impulse adds
//! `Δt Σ_i r_t,i` at t_1 … t_N (the massless layer's convention, [`super::FrictionExplicit`]);
//! velocity Verlet then gives `ΔP_t = ½ Δt (Σ r_tⁿ + Σ r_t^{n+1})` per step.

use super::{Friction, FrictionRecord, SetupError};
use crate::contact::exact::ExactExplicit;
use crate::contact::lcp::LcpError;
use crate::contact::{ExplicitLaw, Massive};

/// A contact node's tangential unknowns (one in 2D, two in 3D).
#[derive(Debug, Clone)]
struct Node {
    /// The unknowns and, per unknown, its axis (an index into `axes`).
    unknowns: Vec<usize>,
    axis: Vec<usize>,
    area: f64,
}

/// The exact normal law with friction on massive tangential unknowns (module docs).
#[derive(Debug)]
pub struct FrictionMassive {
    exact: ExactExplicit,
    friction: Friction,
    /// Per contact node (contact order).
    nodes: Vec<Node>,
    axes: Vec<[f64; 3]>,
    record: FrictionRecord,
    /// Per contact node, the tangential displacement when the last force was set and that force
    /// (per tangential unknown): the dissipation is added when the increment is known.
    pending: Vec<([f64; 2], [f64; 2])>,
    /// The levels seen so far (0: `pending` holds no force yet).
    levels: usize,
}

impl FrictionMassive {
    /// On `system` with the lumped mass `lumped`: refused unless every tangential unknown of a
    /// contact node is massive, with one mass per node.
    pub fn new<A: crate::linalg::SymMatrix>(
        system: &crate::system::ContactSystem<A>,
        lumped: &[f64],
        friction: Friction,
    ) -> Result<Self, SetupError> {
        let tangential =
            system.tangential.as_ref().ok_or(SetupError::Shape("friction needs tangential directions (a solid)"))?;
        let mut nodes = Vec::with_capacity(system.contact.len());
        for k in 0..system.contact.len() {
            let unknowns = tangential.unknowns[k].clone();
            let masses: Vec<f64> = unknowns.iter().map(|&t| lumped[t]).collect();
            if masses.iter().any(|&m| m <= 0.0) {
                return Err(SetupError::Shape(
                    "friction on massive tangential unknowns needs every tangential component of a contact node massive",
                ));
            }
            if masses.iter().any(|&m| (m - masses[0]).abs() > 1e-12 * masses[0]) {
                return Err(SetupError::Shape(
                    "friction on massive tangential unknowns needs one lumped mass per contact node (a scalar mass field)",
                ));
            }
            nodes.push(Node { unknowns, axis: tangential.components[k].clone(), area: tangential.areas[k] });
        }
        let m = nodes.len();
        let record = FrictionRecord { state: vec![0; m], traction: vec![[0.0; 3]; m], ..FrictionRecord::default() };
        Ok(Self {
            exact: ExactExplicit::new(system, lumped)?,
            friction,
            nodes,
            axes: tangential.axes.clone(),
            record,
            pending: vec![([0.0; 2], [0.0; 2]); m],
            levels: 0,
        })
    }
}

impl ExplicitLaw for FrictionMassive {
    fn massive(&mut self, s: Massive<'_>) {
        let Massive { u, v, a, lumped, inv_mass, dt, kappa, lambda } = s;
        // The last level's forces: their increments are known now.
        if self.levels > 0 {
            for (node, (u0, r)) in self.nodes.iter().zip(&self.pending) {
                for (j, &t) in node.unknowns.iter().enumerate() {
                    self.record.dissipation -= r[j] * (u[t] - u0[j]);
                }
            }
        }
        self.exact.massive(Massive { u, v, a: &mut *a, lumped, inv_mass, dt, kappa, lambda: &mut *lambda });
        let dt2 = kappa * dt * dt;
        let mut force = [0.0; 3];
        let (mut stick, mut slip) = (0, 0);
        for (k, node) in self.nodes.iter().enumerate() {
            let r_n = -lambda[k];
            let (u0, r) = &mut self.pending[k];
            self.record.state[k] = 0;
            self.record.traction[k] = [0.0; 3];
            if node.unknowns.is_empty() {
                continue;
            }
            let bound = match self.friction {
                Friction::Coulomb { mu } => mu * r_n.max(0.0),
                Friction::Tresca { threshold } if r_n > 0.0 => threshold * node.area,
                Friction::Tresca { .. } => 0.0,
            };
            // The stick force f* = −m Δũ_t/(κΔt²), and its radial return onto |f| ≤ bound.
            let mut f = [0.0; 2];
            for (j, &t) in node.unknowns.iter().enumerate() {
                f[j] = -lumped[t] * (dt * v[t] + dt2 * a[t]) / dt2;
            }
            let size = f[0].hypot(f[1]);
            let sliding = size > bound;
            if sliding {
                let scale = if size > 0.0 { bound / size } else { 0.0 };
                f = [f[0] * scale, f[1] * scale];
            }
            for (j, &t) in node.unknowns.iter().enumerate() {
                a[t] += f[j] * inv_mass[t];
                (u0[j], r[j]) = (u[t], f[j]);
                let axis = self.axes[node.axis[j]];
                for c in 0..3 {
                    force[c] += f[j] * axis[c];
                    self.record.traction[k][c] += f[j] * axis[c] / node.area;
                }
            }
            self.record.max_cone_excess = self.record.max_cone_excess.max(f[0].hypot(f[1]) - bound);
            // A node without normal force or with bound 0 carries no friction: neither state.
            if r_n > 0.0 && bound > 0.0 {
                if sliding {
                    slip += 1;
                    self.record.state[k] = 2;
                } else {
                    stick += 1;
                    self.record.state[k] = 1;
                }
            }
        }
        if self.levels > 0 {
            for (imp, fw) in self.record.impulse.iter_mut().zip(force) {
                *imp += dt * fw;
            }
        }
        (self.record.force, self.record.stick, self.record.slip) = (force, stick, slip);
        self.levels += 1;
    }

    fn quasi_static(
        &mut self,
        u: &mut [f64],
        load: &[f64],
        forced: bool,
        lambda: &mut [f64],
    ) -> Result<usize, LcpError> {
        self.exact.quasi_static(u, load, forced, lambda)
    }

    fn friction(&self) -> Option<&FrictionRecord> {
        Some(&self.record)
    }
}
