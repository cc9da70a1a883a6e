//! The semi-discrete contact system shared by every geometry (paper §3, eq. (3.1)–(3.3)):
//!
//! ```text
//! M Ü + S U = F − Σ_c λ_c e_c,     0 ≤ u_c + g_c ⊥ λ_c ≤ 0   on the contact unknowns c,
//! ```
//!
//! with M the weighted (redistributed) mass, S the stiffness, F the load and g_c ≥ 0 the gap
//! between contact unknown c and the obstacle. A bar is an instance over a tridiagonal back-end,
//! a plate or a solid over a sparse one ([`crate::linalg::SymMatrix`]). Unknowns whose mass
//! diagonal vanishes are *massless*: their rows are quasi-static (paper §3: with w_0 = 0 the
//! contact node carries no inertia).

use crate::linalg::{LinalgError, SymMatrix};

/// A load that depends on time, `t ↦ F(t)`: writes F(t) into its argument (no allocation).
/// Built from a body force written as an expression in t (`bar.force = "sin(t)*x"`).
#[derive(Clone)]
pub struct Forcing(pub std::sync::Arc<dyn Fn(f64, &mut [f64]) + Send + Sync>);

impl std::fmt::Debug for Forcing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Forcing(t ↦ F(t))")
    }
}

/// `M Ü + S U = F − Σ_c λ_c e_c`, `0 ≤ u_c − lb_c ⊥ λ_c ≤ 0` (module docs), `lb_c = −g_c`.
#[derive(Debug, Clone)]
pub struct ContactSystem<A> {
    pub mass: A,
    pub stiffness: A,
    pub load: Vec<f64>,
    /// Unknowns carrying a Signorini condition (in the order of the λ vector).
    pub contact: Vec<usize>,
    /// Obstacle bound `lb_c = −gap_c ≤ 0` of each contact unknown (contact order).
    pub lower: Vec<f64>,
    /// Per unknown: `M_ii = 0` (the node has no inertia; its row is quasi-static).
    pub massless: Vec<bool>,
    /// The contact nodes' tangential unknowns, areas and directions (a solid's; None for bars
    /// and plates, which have no tangential direction). Friction acts on these.
    pub tangential: Option<Tangential>,
    /// A time-dependent load (None: `load` at every time). With one, `load` is F(0) and the
    /// schemes evaluate F at the time each of their equations is written at.
    pub forcing: Option<Forcing>,
}

impl<A: SymMatrix> ContactSystem<A> {
    /// From assembled matrices, with the obstacle at `u_c = −gap` for every contact unknown;
    /// massless unknowns are those with a zero mass diagonal.
    pub fn new(mass: A, stiffness: A, load: Vec<f64>, contact: Vec<usize>, gap: f64) -> Self {
        let massless = (0..mass.dim()).map(|i| mass.diag(i) == 0.0).collect();
        // 0 − gap, not −gap: no −0.0 bound (u_c = lb is then +0.0 as the closed forms give).
        let lower = vec![0.0 - gap; contact.len()];
        Self { mass, stiffness, load, contact, lower, massless, tangential: None, forcing: None }
    }

    /// The same system with a time-dependent load (its `load` becomes F(0)).
    pub fn with_forcing(mut self, forcing: Forcing) -> Self {
        (forcing.0)(0.0, &mut self.load);
        self.forcing = Some(forcing);
        self
    }

    /// Writes F(t) into `out`.
    pub fn load_at(&self, t: f64, out: &mut [f64]) {
        match &self.forcing {
            Some(f) => (f.0)(t, out),
            None => out.copy_from_slice(&self.load),
        }
    }

    /// The energy at time t, `½VᵀMV + ½UᵀSU − UᵀF(t)`; `scratch` holds F(t) when the load
    /// depends on time (reused between calls).
    pub fn energy_at(&self, u: &[f64], v: &[f64], t: f64, scratch: &mut Vec<f64>) -> f64 {
        if self.forcing.is_none() {
            return self.energy(u, v);
        }
        scratch.resize(self.n(), 0.0);
        self.load_at(t, scratch);
        let work: f64 = u.iter().zip(scratch.iter()).map(|(a, b)| a * b).sum();
        0.5 * self.mass.quad_form(v) + 0.5 * self.stiffness.quad_form(u) - work
    }

    pub fn n(&self) -> usize {
        self.load.len()
    }

    /// True when every contact unknown is massless.
    pub fn massless_contact(&self) -> bool {
        self.contact.iter().all(|&c| self.massless[c])
    }

    /// Largest mass diagonal among the contact unknowns (0 iff they are all massless).
    pub fn contact_mass(&self) -> f64 {
        self.contact.iter().map(|&c| self.mass.diag(c)).fold(0.0, f64::max)
    }

    /// Discrete energy `½ VᵀMV + ½ UᵀSU − UᵀF` (paper eq. (3.4) in full-system form; with
    /// quasi-static contact values it equals the reduced energy `ℰ_h`).
    pub fn energy(&self, u: &[f64], v: &[f64]) -> f64 {
        let work: f64 = u.iter().zip(&self.load).map(|(a, b)| a * b).sum();
        0.5 * self.mass.quad_form(v) + 0.5 * self.stiffness.quad_form(u) - work
    }

    /// A⁰ from the equation of motion `M A⁰ = F − S U⁰` (λ⁰ = 0) on the unknowns with mass
    /// (M is SPD there); 0 on massless ones, whose acceleration enters no equation.
    pub fn initial_acceleration(&self, u: &[f64]) -> Result<Vec<f64>, LinalgError> {
        let n = self.n();
        let mut r = vec![0.0; n];
        self.stiffness.mul_into(u, &mut r);
        let massive: Vec<usize> = (0..n).filter(|&i| !self.massless[i]).collect();
        let mut a = vec![0.0; n];
        if massive.is_empty() {
            return Ok(a);
        }
        let mut rp: Vec<f64> = massive.iter().map(|&i| self.load[i] - r[i]).collect();
        self.mass.solve_principal(&massive, &mut rp, "mass")?;
        for (k, &i) in massive.iter().enumerate() {
            a[i] = rp[k];
        }
        Ok(a)
    }
}

/// The tangential directions of a system's contact nodes (None for bars and plates).
#[derive(Debug, Clone, PartialEq)]
pub struct Tangential {
    /// Per contact unknown (contact order), the unknowns of its node's tangential components
    /// (components 1.. in the obstacle's frame that are not eliminated).
    pub unknowns: Vec<Vec<usize>>,
    /// Per contact unknown, the axis (an index into `axes`) of each of those unknowns.
    pub components: Vec<Vec<usize>>,
    /// a_i per contact node (Tresca's bound `s a_i`).
    pub areas: Vec<f64>,
    /// The world vectors of the frame's axes 1.. (the tangential components' directions).
    pub axes: Vec<[f64; 3]>,
}
