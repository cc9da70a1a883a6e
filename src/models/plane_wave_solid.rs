//! The paper's bar as an elastic solid: (0, 1)^d, λ = 0, μ = ½ (modulus 2μ = 1), ρ = 1, free
//! lateral faces, u⁰ = ((1 − x)/2, 0[, 0]), v⁰ = 0, Q1 cells. The x-rows are Kx ⊗ My (⊗ Mz) + …
//! and the transverse rows vanish on (u_x(x), 0, 0) (module docs of [`crate::solid`]), so each
//! step is the step of the paper's bar with nx elements, to [`RoundOffGrowth`].

use super::{PaperBar, RoundOffGrowth};
use crate::mass::MassKind;
use crate::problem::Problem;
use crate::solid::SolidError;
use crate::solid::{SolidSpec, SolidSystem};

/// The plane-wave solid in `dim` = 2 or 3 dimensions with `cells` per axis (nz unused in 2D).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneWaveSolid {
    pub dim: usize,
    pub cells: [usize; 3],
}

impl PlaneWaveSolid {
    pub fn spec(&self) -> SolidSpec {
        SolidSpec::paper(self.dim, self.cells)
    }

    /// The problem on (0, t_end) (the exact solution is built for it).
    pub fn problem(&self, mass: &MassKind, t_end: f64) -> Result<Problem<SolidSystem>, SolidError> {
        self.spec().problem(mass, t_end)
    }

    /// The bar it reduces to.
    pub fn reference(&self) -> PaperBar {
        PaperBar::unit(self.cells[0])
    }

    /// The tolerance of the comparison with the reference over `steps` steps of Δt (the
    /// transverse components, 0 in the reference, are held to the displacement tolerance).
    pub fn tolerance(steps: usize, dt: f64) -> RoundOffGrowth {
        RoundOffGrowth::new(steps, dt)
    }
}
