//! The solids of the elastic Table 1 ([`super::elastic_table`]) and of its fine-mesh reference
//! ([`super::elastic_reference`]): the materials, the 2D solid on n × n cells, and the error type.

use massredist::characteristics::CharacteristicsError;
use massredist::fem::Cell;
use massredist::models::PlaneWaveSolid;
use massredist::schemes::SchemeError;
use massredist::solid::{Lame, Lateral, SolidError, SolidSpec};
use serde::Serialize;
use thiserror::Error;

/// Cells per side (Δx₁ = Δx₂ = 0.05, the paper's).
pub const N: usize = 20;

/// The elastic material and lateral condition of a candidate (module docs for the choice).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Material {
    /// λ = 0, μ = ½, free lateral faces: the paper's bar as a solid.
    LambdaZeroFree,
    /// λ = 3/7, μ = 2/7 (ν = 0.3, λ + 2μ = 1), free lateral faces.
    PoissonFree,
    /// λ = 3/7, μ = 2/7, roller lateral faces (u_y = 0 on y = 0, 1).
    PoissonRoller,
}

impl Material {
    pub const ALL: [Material; 3] = [Material::LambdaZeroFree, Material::PoissonFree, Material::PoissonRoller];

    /// μ = 2/7 and λ = 1 − 2μ (exactly: 2μ ∈ [½, 1], so the subtraction is exact by Sterbenz's
    /// lemma and λ + 2μ rounds to 1 exactly, which selects the paper's closed form).
    pub fn lame(self) -> Lame {
        const MU: f64 = 2.0 / 7.0;
        match self {
            Material::LambdaZeroFree => Lame::PAPER,
            Material::PoissonFree | Material::PoissonRoller => Lame { lambda: 1.0 - 2.0 * MU, mu: MU, density: 1.0 },
        }
    }

    pub fn lateral(self) -> Lateral {
        match self {
            Material::PoissonRoller => Lateral::Roller,
            _ => Lateral::Free,
        }
    }

    /// Whether the plane wave U is the solution of the continuous problem.
    pub fn plane_wave_is_solution(self) -> bool {
        self != Material::PoissonFree
    }
}

#[derive(Debug, Error)]
pub enum ElasticError {
    #[error(transparent)]
    Solid(#[from] SolidError),
    #[error(transparent)]
    Scheme(#[from] SchemeError),
    #[error("the 1D exact solution for the triangle error: {0}")]
    Exact(#[from] CharacteristicsError),
    #[error("{0}")]
    Diverged(massredist::driver::Divergence),
}

/// The 2D solid of a candidate.
pub fn spec(cells: Cell, material: Material) -> SolidSpec {
    spec_on(cells, material, N)
}

/// The same solid on `n` × `n` cells (the fine-mesh reference, [`super::elastic_reference`]).
pub fn spec_on(cells: Cell, material: Material, n: usize) -> SolidSpec {
    let support = massredist::solid::Support::Face { gap: 0.0, lateral: material.lateral(), force: [0.0; 3] };
    SolidSpec { cells, lame: material.lame(), support, ..PlaneWaveSolid { dim: 2, cells: [n, n, 1] }.spec() }
}
