//! The body's physical data shared by every geometry, its exact solutions and its scenes:
//! density and modulus, and the condition at the far end x = L.

/// Density ρ > 0 and Young's modulus E > 0 (wave speed `c = sqrt(E/ρ)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    pub density: f64,
    pub modulus: f64,
}

impl Material {
    /// ρ = E = 1: the paper's bar.
    pub const UNIT: Material = Material { density: 1.0, modulus: 1.0 };

    pub fn wave_speed(&self) -> f64 {
        (self.modulus / self.density).sqrt()
    }
}

/// The condition at x = L.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FarEnd {
    /// u(L, t) = 0.
    Clamped,
    /// E u_x(L, t) = 0.
    Free,
}

impl FarEnd {
    pub fn name(self) -> &'static str {
        match self {
            FarEnd::Clamped => "clamped",
            FarEnd::Free => "free",
        }
    }
}

/// The Lamé coefficients λ ≥ 0, μ > 0 and the density ρ > 0 (P-wave speed sqrt((λ+2μ)/ρ)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lame {
    pub lambda: f64,
    pub mu: f64,
    pub density: f64,
}

impl Lame {
    /// The paper's bar as a solid: λ = 0, μ = ½, ρ = 1 (so λ + 2μ = 1).
    pub const PAPER: Lame = Lame { lambda: 0.0, mu: 0.5, density: 1.0 };

    /// The P-wave modulus λ + 2μ (the modulus of the plane wave's 1D bar).
    pub fn p_modulus(&self) -> f64 {
        self.lambda + 2.0 * self.mu
    }
}
