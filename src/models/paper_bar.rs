//! The paper's benchmark bar (§6): (0, L), ρ = E = 1, clamped at L, obstacle at x = 0,
//! u⁰ = (L − x)/2, v⁰ = 0; its exact solution is [`ImpactingBar`] (period 3L, energy L/8).
//! Also the Q1 plate with the same data, whose reference solution is this bar.

use crate::bar::{BarError, BarProblem};
use crate::exact::ImpactingBar;
use crate::fem::Cell;
use crate::mass::MassKind;
use crate::plate::{PlateError, PlateProblem};
use crate::scene::{PlateInitial, PlateSpec};

/// The paper's bar with `elements` P1 elements (h = L/m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperBar {
    pub length: f64,
    pub elements: usize,
}

impl PaperBar {
    /// The paper's figures: L = 1, m = 6 (h = 1/6).
    pub const FIGURES: PaperBar = PaperBar { length: 1.0, elements: 6 };

    /// The unit bar with m elements.
    pub const fn unit(elements: usize) -> Self {
        PaperBar { length: 1.0, elements }
    }

    /// The discretised problem for a mass redistribution (exact solution attached).
    pub fn problem(&self, mass: &MassKind) -> Result<BarProblem, BarError> {
        BarProblem::benchmark(self.length, self.elements, mass)
    }

    /// The exact solution (paper §6, by d'Alembert's formula).
    pub fn exact(&self) -> ImpactingBar {
        ImpactingBar { length: self.length }
    }
}

/// How far two discretisations that perform the same arithmetic up to its order (a Q1 plate or
/// solid with x-only data and the bar) may drift apart in `steps` steps of Δt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoundOffGrowth {
    /// Displacements: each step adds a few ulps per operation of a solve with condition number
    /// ≈ 1.1 (Δt²/4 · 12/h² ≈ 0.12 beyond M), u is O(1), and the difference grows at most
    /// linearly (the w_0 = 0 dynamics is not chaotic): steps · 64 ε.
    pub u: f64,
    /// Velocities: v = 2(u_new − u)/Δt − v (hybrid) or a σ-scaled update (Newmark) amplifies the
    /// displacement difference by up to 2/Δt.
    pub v: f64,
}

impl RoundOffGrowth {
    pub fn new(steps: usize, dt: f64) -> Self {
        let u = steps as f64 * 64.0 * f64::EPSILON;
        RoundOffGrowth { u, v: u * 2.0 / dt }
    }
}

/// The paper's data on the Q1 plate (0, 1) × (0, H) with nx × ny cells: with x-only weights
/// `M = Mx^w ⊗ My`, `S = Kx ⊗ My + Mx ⊗ Ky`, and the contact LCP has the y-constant solution
/// `λ_c = λ_1D ∫φ_c`, so each step is the step of [`PaperPlate::reference`] (the bar with nx
/// elements), to [`RoundOffGrowth`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperPlate {
    pub height: f64,
    pub nx: usize,
    pub ny: usize,
    pub cells: Cell,
}

impl PaperPlate {
    /// The unit square with n × n cells.
    pub const fn square(n: usize, cells: Cell) -> Self {
        PaperPlate { height: 1.0, nx: n, ny: n, cells }
    }

    pub fn spec(&self) -> PlateSpec {
        PlateSpec::structured(1.0, self.height, self.nx, self.ny, self.cells, PlateInitial::Paper)
    }

    pub fn problem(&self, mass: &MassKind) -> Result<PlateProblem, PlateError> {
        PlateProblem::new(&self.spec(), mass)
    }

    /// The bar it reduces to (Q1 cells; P1 triangles on one-diagonal meshes do not).
    pub fn reference(&self) -> PaperBar {
        PaperBar::unit(self.nx)
    }

    /// The tolerance of the comparison with the reference over `steps` steps of Δt.
    pub fn tolerance(steps: usize, dt: f64) -> RoundOffGrowth {
        RoundOffGrowth::new(steps, dt)
    }
}
