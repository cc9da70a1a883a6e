//! Moreau–Jean's time-stepping scheme (Jean, CMAME 177, 1999; Acary–Brogliato, *Numerical
//! Methods for Nonsmooth Dynamical Systems*, 2008, §10.1; Siconos `MoreauJeanOSI`): a θ-method on
//! the velocities with Newton's impact law, the contact impulses P solved exactly.
//!
//! ```text
//! M (V^{n+1} − Vⁿ) = Δt (F^{n+θ} − K U^{n+θ}) + P,     U^{n+1} = Uⁿ + Δt ((1−θ) Vⁿ + θ V^{n+1}),
//! F^{n+θ} = (1−θ) F(t_n) + θ F(t_{n+1}),  U^{n+θ} = (1−θ) Uⁿ + θ U^{n+1},
//! active set 𝒜 = {c : u_cⁿ + ½Δt v_cⁿ − lb_c ≤ 0}   (½Δt whatever θ is; 0 counts as active),
//! c ∈ 𝒜: 0 ≤ v_c^{n+1} + e v_cⁿ ⊥ P_c ≥ 0;   c ∉ 𝒜: P_c = 0.
//! ```
//!
//! Eliminating U^{n+1}: `W V^{n+1} = M Vⁿ + Δt (F^{n+θ} − K Uⁿ) − θ(1−θ) Δt² K Vⁿ + P` with
//! `W = M + θ² Δt² K` (SPD), factored once per active set (a bar has one contact node, so one
//! factor): the velocity problem is the exact contact solve of [`crate::contact`] with the bound
//! `v_c ≥ −e v_cⁿ` on 𝒜 and σ = Δt, so λ_c = −P_c/Δt is the mean contact force of the step
//! (reported as λ, ≤ 0). M is the consistent weighted mass; a massless contact node is refused
//! (an impact law has no meaning without inertia). Positions are not constrained: penetration
//! of O(Δt) is allowed and reported (`min_u0` below −gap for bars).
//!
//! θ = ½ is second order without contact and conserves `½V·MV + ½U·KU − F·U` (the midpoint
//! rule); θ = 1 is first order and dissipative.

use super::{ImpactRestitution, SchemeError, StateView, Theta, check_finite, check_range, contact_err};
use crate::contact::{Backend, ContactSolver};
use crate::system::ContactSystem;

/// Factors kept for recurring active sets (a bar's two, a resting body's few): a set seen again
/// within this many distinct sets is not factored again.
pub const SOLVERS_KEPT: usize = 4;

#[derive(Debug)]
pub struct MoreauJean<A: Backend> {
    theta: f64,
    restitution: f64,
    dt: f64,
    mass: A,
    stiffness: A,
    /// W = M + θ²Δt² K, kept to factor it for new active sets.
    w: A,
    load: Vec<f64>,
    load_next: Vec<f64>,
    forcing: Option<crate::system::Forcing>,
    contact: Vec<usize>,
    obstacle: Vec<f64>,
    /// Exact velocity solvers of the last [`SOLVERS_KEPT`] active sets (contact-order flags),
    /// the most recent first; the empty set uses the solver of every node with unreachable
    /// bounds when the back-end has no solver without contact nodes (the bar's one-node closed
    /// form), else its own. Bounded: a body's active set changes in most steps of an impact, and
    /// a factor kept per set grew without limit (20 GB for the tetra10 sphere of 13 218
    /// unknowns, standard mass, 1100 steps).
    solvers: Vec<(Vec<bool>, (A::Solver, Vec<usize>))>,
    n: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    lambda: Vec<f64>,
    rhs: Vec<f64>,
    tmp: Vec<f64>,
    bounds: Vec<f64>,
    sub_lambda: Vec<f64>,
    pivots: usize,
}

impl<A: Backend> MoreauJean<A> {
    pub const NAME: &'static str = super::SchemeSpec::MOREAU_JEAN.name();

    pub fn new(
        system: &ContactSystem<A>,
        theta: Theta,
        restitution: ImpactRestitution,
        dt: f64,
        u0: Vec<f64>,
        v0: Vec<f64>,
    ) -> Result<Self, SchemeError> {
        check_range(Self::NAME, "dt", dt, dt > 0.0, "(0, ∞)")?;
        if let Some(&c) = system.contact.iter().find(|&&c| system.massless[c]) {
            return Err(SchemeError::Needs {
                scheme: Self::NAME,
                key: "mass.kind",
                what: "mass at every contact node (w_0 > 0: mass.kind = \"standard\" or custom weights)",
                value: system.mass.diag(c),
                reason: "an impact law has no meaning without inertia",
            });
        }
        let theta = theta.get();
        let w = system.mass.combine(1.0, &system.stiffness, theta * theta * dt * dt, "M + θ²Δt² K")?;
        let n = system.n();
        let nc = system.contact.len();
        Ok(Self {
            theta,
            restitution: restitution.get(),
            dt,
            mass: system.mass.clone(),
            stiffness: system.stiffness.clone(),
            w,
            load: system.load.clone(),
            load_next: system.load.clone(),
            forcing: system.forcing.clone(),
            contact: system.contact.clone(),
            obstacle: system.lower.clone(),
            solvers: Vec::with_capacity(SOLVERS_KEPT),
            n: 0,
            u: u0,
            v: v0,
            lambda: vec![0.0; nc],
            rhs: vec![0.0; n],
            tmp: vec![0.0; n],
            bounds: Vec::with_capacity(nc),
            sub_lambda: Vec::with_capacity(nc),
            pivots: 0,
        })
    }

    /// The solver of an active set, factored unless one of the last [`SOLVERS_KEPT`] sets was
    /// the same (the factor then moves to the front; the oldest is dropped).
    fn solver(&mut self, active: &[bool]) -> Result<&mut (A::Solver, Vec<usize>), SchemeError> {
        if let Some(k) = self.solvers.iter().position(|(set, _)| set == active) {
            self.solvers[..=k].rotate_right(1);
        } else {
            let name = "M + θ²Δt² K";
            let mut nodes: Vec<usize> = self.contact.iter().zip(active).filter(|(_, a)| **a).map(|(&c, _)| c).collect();
            let solver = match self.w.contact_solver(&nodes, name) {
                Ok(s) => s,
                // No solver without contact nodes (the bar): all nodes, bounds −∞ (module docs).
                Err(_) if nodes.is_empty() => {
                    nodes = self.contact.clone();
                    self.w.contact_solver(&nodes, name)?
                }
                Err(e) => return Err(e.into()),
            };
            self.solvers.truncate(SOLVERS_KEPT - 1);
            self.solvers.insert(0, (active.to_vec(), (solver, nodes)));
        }
        Ok(&mut self.solvers[0].1)
    }
}

impl<A: Backend> super::Scheme for MoreauJean<A> {
    fn state(&self) -> StateView<'_> {
        StateView { n: self.n, t: self.n as f64 * self.dt, u: &self.u, v: &self.v, lambda: &self.lambda }
    }

    fn pivots(&self) -> usize {
        self.pivots
    }

    fn step(&mut self) -> Result<(), SchemeError> {
        let (dt, th) = (self.dt, self.theta);
        let (step, time) = (self.n + 1, (self.n + 1) as f64 * dt);
        if let Some(f) = &self.forcing {
            (f.0)(time, &mut self.load_next);
        }
        // rhs = M Vⁿ + Δt F^{n+θ} − Δt K (Uⁿ + θ(1−θ)Δt Vⁿ).
        for i in 0..self.u.len() {
            self.tmp[i] = self.u[i] + th * (1.0 - th) * dt * self.v[i];
        }
        self.stiffness.mul_into(&self.tmp, &mut self.rhs);
        for i in 0..self.u.len() {
            let f = (1.0 - th) * self.load[i] + th * self.load_next[i];
            self.tmp[i] = dt * (f - self.rhs[i]);
        }
        let tmp = std::mem::take(&mut self.tmp);
        self.mass.mul_add_into(&self.v, 1.0, &tmp, &mut self.rhs);
        self.tmp = tmp;
        let active: Vec<bool> = self
            .contact
            .iter()
            .zip(&self.obstacle)
            .map(|(&c, lb)| self.u[c] + 0.5 * dt * self.v[c] - lb <= 0.0)
            .collect();
        let e = self.restitution;
        let v_old: Vec<f64> = self.contact.iter().map(|&c| self.v[c]).collect();
        let (rhs, mut bounds, mut sub) =
            (std::mem::take(&mut self.rhs), std::mem::take(&mut self.bounds), std::mem::take(&mut self.sub_lambda));
        let contact = self.contact.clone();
        let (solver, nodes) = self.solver(&active)?;
        bounds.clear();
        for &c in nodes.iter() {
            let k = contact.iter().position(|&x| x == c).expect("a contact node");
            bounds.push(if active[k] { -e * v_old[k] } else { f64::NEG_INFINITY });
        }
        sub.clear();
        sub.resize(nodes.len(), 0.0);
        let mut rhs = rhs;
        let pivots = solver.solve(&mut rhs, &bounds, dt, &mut sub).map_err(contact_err(step, time))?;
        let nodes = nodes.clone();
        self.lambda.iter_mut().for_each(|l| *l = 0.0);
        for (&c, &l) in nodes.iter().zip(&sub) {
            let k = contact.iter().position(|&x| x == c).expect("a contact node");
            self.lambda[k] = l;
        }
        // U^{n+1} = Uⁿ + Δt((1−θ)Vⁿ + θV^{n+1}); V^{n+1} = rhs.
        for i in 0..self.u.len() {
            self.u[i] += dt * ((1.0 - th) * self.v[i] + th * rhs[i]);
            self.v[i] = rhs[i];
        }
        self.rhs = rhs;
        self.bounds = bounds;
        self.sub_lambda = sub;
        std::mem::swap(&mut self.load, &mut self.load_next);
        if self.forcing.is_none() {
            self.load_next.copy_from_slice(&self.load);
        }
        self.pivots = pivots;
        self.n = step;
        check_finite(&self.u, &self.lambda, A::SOLVE_SPREADS_NAN, step, time)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Geometry;
    use crate::scene::{AnyScene, Registered};
    use crate::schemes::Scheme;
    use crate::solid::SolidSpec;
    use crate::spec::GeometrySpec;
    use std::collections::HashSet;

    /// GetFEM's P2 disc (h = 8) dropped on the plane with the standard mass: its active set
    /// changes through the impact, and the scheme keeps at most [`SOLVERS_KEPT`] factors (a
    /// factor per set seen grew to 20 GB on the tetra10 sphere of 13 218 unknowns).
    /// mutation: no `truncate` → fails (a fifth factor kept).
    #[test]
    fn the_factors_kept_are_bounded_whatever_the_sets_seen() {
        let text = "[solid]\ndim = 2\nmesh = \"disc_p2_22a.msh\"\nlame_lambda = 20.0\nlame_mu = 20.0\ndensity = 1.0\n\
                    force = [\"0\", \"0\"]\ninitial = { displacement = [\"0\", \"0\"], velocity = [\"0\", \"-1.0\"] }\n\
                    [obstacle]\nnormal = [0.0, 1.0]\npoint = [0.0, -0.02]\ncontact = \"auto\"\n\
                    [mass]\nkind = \"standard\"\n[scheme]\nkind = \"moreau-jean\"\n[time]\ndt = 0.01\nend = 3.0\n";
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes");
        let scene = AnyScene::from_toml_at(text, &dir).and_then(SolidSpec::from_any).expect("the disc scene");
        let problem = <SolidSpec as GeometrySpec>::problem(&scene).expect("the disc's problem");
        let system = problem.system.system();
        let (theta, e) = (Theta::new(0.5), ImpactRestitution::new(0.0));
        let mut s =
            MoreauJean::new(system, theta, e, 0.01, problem.u0.clone(), problem.v0.clone()).expect("the scheme");
        let mut sets = HashSet::new();
        for _ in 0..300 {
            let active: Vec<bool> =
                s.contact.iter().zip(&s.obstacle).map(|(&c, lb)| s.u[c] + 0.5 * s.dt * s.v[c] - lb <= 0.0).collect();
            sets.insert(active);
            s.step().expect("a step");
            assert!(s.solvers.len() <= SOLVERS_KEPT, "{} factors kept", s.solvers.len());
        }
        // The bound is exercised: more distinct sets than factors kept.
        assert!(sets.len() > SOLVERS_KEPT, "{} sets seen", sets.len());
    }
}
