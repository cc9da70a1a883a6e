//! A plate with y-dependent data, the bump u⁰ = (1 − x)/2 · (1 + ½ cos(π y/H)): the contact state
//! varies along Γ_C, so it exercises the many-node contact solver. It has no exact solution; its
//! reference is what every run must satisfy: complementarity node by node (exactly) and the
//! energy identities of the schemes (to [`PlateBump::ENERGY_ROUND_OFF`]).

use crate::fem::Cell;
use crate::mass::MassKind;
use crate::plate::{PlateError, PlateProblem};
use crate::scene::{PlateInitial, PlateSpec};

/// The bump on (0, 1) × (0, H) with nx × ny cells.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlateBump {
    pub height: f64,
    pub nx: usize,
    pub ny: usize,
    pub cells: Cell,
}

impl PlateBump {
    /// Round-off of one step's energy change: E = O(0.1) is a sum of O(n) products (n ≤ 10³
    /// unknowns here), its evaluation error about n ε · 0.1, far below 1e4 ε.
    pub const ENERGY_ROUND_OFF: f64 = 1e4 * f64::EPSILON;

    /// The bump on the unit square's width with nx × ny cells (H = 1).
    pub const fn unit(nx: usize, ny: usize, cells: Cell) -> Self {
        PlateBump { height: 1.0, nx, ny, cells }
    }

    pub fn spec(&self) -> PlateSpec {
        PlateSpec::structured(1.0, self.height, self.nx, self.ny, self.cells, PlateInitial::Bump)
    }

    pub fn problem(&self, mass: &MassKind) -> Result<PlateProblem, PlateError> {
        PlateProblem::new(&self.spec(), mass)
    }
}
