//! P1 finite elements on a uniform mesh of (0, L): weighted mass, stiffness and load (paper §3).
//!
//! Nodes `x_i = i h`, `h = L/m`, i = 0..m. Node 0 is the contact node (Signorini), node m carries
//! the Dirichlet condition `u(L) = 0` and is eliminated, so the unknowns are nodes 0..m−1:
//!
//! ```text
//! M_00 = h/3 w_0,  M_ii = h/3 (w_{i−1} + w_i),  M_{i,i+1} = h/6 w_i,
//! S_00 = 1/h,      S_ii = 2/h,                  S_{i,i+1} = −1/h,
//! F_i  = ∫ f w_h φ_i = f h/2 (w_{i−1} + w_i)   (constant f; F_0 = f h/2 w_0).
//! ```
//!
//! (The paper writes `M_{i,i−1} = h/6 w_i`; the integral `∫ w φ_i φ_{i+1}` over element i gives
//! `M_{i,i+1} = h/6 w_i`, which is also what its matrix display shows.)

use crate::linalg::tridiag::SymTridiag;
use crate::mass::{MassError, MassKind};
pub use crate::material::{FarEnd, Material};
use crate::system::ContactSystem;
use thiserror::Error;

/// A uniform mesh of the bar (0, L) with m elements.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bar {
    pub length: f64,
    pub elements: usize,
}

impl Bar {
    pub fn h(&self) -> f64 {
        self.length / self.elements as f64
    }

    /// Coordinate of node i (0 ≤ i ≤ m).
    pub fn x(&self, i: usize) -> f64 {
        // i·h would round differently from L·i/m at the last node; keep x_m = L exactly.
        self.length * i as f64 / self.elements as f64
    }
}

#[derive(Debug, Clone, PartialEq, Error)]
pub enum AssemblyError {
    #[error("bar.length = {0}: must be finite and > 0")]
    Length(f64),
    #[error("bar.elements = {0}: must be >= 2")]
    Elements(usize),
    #[error(transparent)]
    Mass(#[from] MassError),
}

/// The bar's semi-discrete system `M Ü + S U = F − λ e_0` on the free nodes 0..m−1: the
/// mesh, its element weights and the [`ContactSystem`] over tridiagonal matrices (contact
/// unknown 0).
#[derive(Debug, Clone)]
pub struct BarSystem {
    pub bar: Bar,
    /// Element weights `w_0 … w_{m−1}`.
    pub weights: Vec<f64>,
    pub system: ContactSystem<SymTridiag>,
    pub far_end: FarEnd,
    /// The lumped mass on the unknowns: row sums of ρ M_w over all nodes 0..m (node m included
    /// before it is eliminated), `ρh/2 (w_{i−1} + w_i)` (explicit schemes).
    pub lumped: Vec<f64>,
}

/// The body force f of the bar.
pub enum Load<'a> {
    Constant(f64),
    /// f(x), time-independent.
    Field(&'a dyn Fn(f64) -> f64),
}

/// 3-point Gauss–Legendre nodes on (0, 1) and weights (summing to 1).
const GAUSS3: [(f64, f64); 3] =
    [(0.5 - 0.387_298_334_620_741_7, 5.0 / 18.0), (0.5, 8.0 / 18.0), (0.5 + 0.387_298_334_620_741_7, 5.0 / 18.0)];

/// The points where [`load_into`] evaluates a force field f(x): the 3 Gauss points of each
/// element, computed as there (scenes check f at them: issue 22, D12).
pub fn load_points(bar: Bar) -> impl Iterator<Item = f64> {
    let h = bar.h();
    (0..bar.elements).flat_map(move |j| GAUSS3.map(|(g, _)| bar.x(j) + g * h))
}

/// The load `F_i = ∫ f w_h φ_i` into `load` (one entry per unknown: m clamped, m + 1 free): a
/// constant f in closed form `f h/2 (w_{j} + w_{j+1})`, f(x) by 3-point Gauss–Legendre on each
/// element (exact for f of degree ≤ 4). No allocation (a time-dependent load calls it per step).
pub fn load_into(bar: &Bar, weights: &[f64], force: &Load, load: &mut [f64]) {
    let (h, n) = (bar.h(), load.len());
    load.fill(0.0);
    for (j, &w) in weights.iter().enumerate() {
        let (fa, fb) = match force {
            Load::Constant(f) => (f * h / 2.0 * w, f * h / 2.0 * w),
            Load::Field(f) => {
                let (xa, mut a, mut b) = (bar.x(j), 0.0, 0.0);
                for (g, gw) in GAUSS3 {
                    let fx = f(xa + g * h);
                    a += gw * h * fx * (1.0 - g);
                    b += gw * h * fx * g;
                }
                (w * a, w * b)
            }
        };
        load[j] += fa;
        if j + 1 < n {
            load[j + 1] += fb;
        }
    }
}

impl BarSystem {
    /// Assembles M, S and F for the given mass redistribution and a constant body force f.
    pub fn new(bar: Bar, mass: &MassKind, force: f64) -> Result<Self, AssemblyError> {
        Ok(Self::from_weights(bar, Self::weights(bar, mass)?, force))
    }

    /// Checks the mesh and returns the element weights of a mass redistribution on it.
    pub fn weights(bar: Bar, mass: &MassKind) -> Result<Vec<f64>, AssemblyError> {
        if !(bar.length.is_finite() && bar.length > 0.0) {
            return Err(AssemblyError::Length(bar.length));
        }
        if bar.elements < 2 {
            return Err(AssemblyError::Elements(bar.elements));
        }
        Ok(mass.weights(bar.elements)?)
    }

    /// Assembly from already validated weights (one per element): the leading m×m block of
    /// [`full_matrices`] (node m is Dirichlet), unit density and modulus, constant force.
    pub fn from_weights(bar: Bar, weights: Vec<f64>, force: f64) -> Self {
        Self::assemble(bar, weights, Material::UNIT, FarEnd::Clamped, &Load::Constant(force))
    }

    /// The general bar: `ρ u_tt − E u_xx = f` with weighted mass `ρ ∫ w_h u v`, stiffness
    /// `E ∫ u' v'` and load `∫ f w_h φ_i`. A clamped far end eliminates node m (unknowns
    /// 0..m−1); a free one keeps it (unknowns 0..m, natural condition `E u_x(L) = 0`).
    ///
    /// The load: a constant f gives the closed form `F_i = f h/2 (w_{i−1} + w_i)`; f(x) is
    /// integrated by 3-point Gauss–Legendre on each element (exact for f of degree ≤ 4).
    pub fn assemble(bar: Bar, weights: Vec<f64>, material: Material, far_end: FarEnd, force: &Load) -> Self {
        let m = bar.elements;
        let n = match far_end {
            FarEnd::Clamped => m,
            FarEnd::Free => m + 1,
        };
        let (mass, stiffness) = full_matrices(&bar, &weights);
        let row = |i: usize| {
            let off = |k: usize| mass.off.get(k).copied().unwrap_or(0.0);
            mass.diag[i] + if i > 0 { off(i - 1) } else { 0.0 } + off(i)
        };
        let lumped = (0..n).map(|i| material.density * row(i)).collect();
        let (mut mass, mut stiffness) = (mass.leading(n), stiffness.leading(n));
        if material != Material::UNIT {
            mass = mass.combine(material.density, &mass, 0.0);
            stiffness = stiffness.combine(material.modulus, &stiffness, 0.0);
        }
        let mut load = vec![0.0; n];
        load_into(&bar, &weights, force, &mut load);
        Self { bar, weights, system: ContactSystem::new(mass, stiffness, load, vec![0], 0.0), far_end, lumped }
    }

    /// Number of unknowns (m clamped, m + 1 free).
    pub fn n(&self) -> usize {
        self.system.n()
    }

    /// The same system with the obstacle at `u_0 = −gap` (gap ≥ 0).
    pub fn with_gap(mut self, gap: f64) -> Self {
        self.system.lower = vec![0.0 - gap];
        self
    }

    /// The obstacle's gap (`u_0 ≥ −gap`).
    pub fn gap(&self) -> f64 {
        -self.system.lower[0]
    }

    pub fn m(&self) -> usize {
        self.bar.elements
    }

    pub fn h(&self) -> f64 {
        self.bar.h()
    }

    /// True when the contact node carries no inertia (`w_0 = 0`, so `M_00 = 0`).
    pub fn massless_contact(&self) -> bool {
        self.weights[0] == 0.0
    }

    /// Total mass `1ᵀ M_full 1 = ∫ w_h`: the sum of all entries of the mass matrix over all
    /// nodes, the Dirichlet node m included (its row adds `M_mm + 2 M_{m−1,m} = 2h/3 w_{m−1}`).
    pub fn total_mass(&self) -> f64 {
        match self.far_end {
            FarEnd::Clamped => self.system.mass.total() + 2.0 * self.h() / 3.0 * self.weights[self.m() - 1],
            FarEnd::Free => self.system.mass.total(),
        }
    }

    /// Discrete energy `½ VᵀMV + ½ UᵀSU − UᵀF` (paper eq. (3.4) in full-system form; with
    /// `u_0 = u_1⁺` it equals the reduced energy `ℰ_h`).
    pub fn energy(&self, u: &[f64], v: &[f64]) -> f64 {
        self.system.energy(u, v)
    }

    /// Nodal interpolant of g at the free nodes 0..m−1.
    pub fn interpolate(&self, g: impl Fn(f64) -> f64) -> Vec<f64> {
        (0..self.n()).map(|i| g(self.bar.x(i))).collect()
    }
}

/// Weighted mass and stiffness over all m+1 nodes (no boundary condition), element by element:
/// element j adds `h w_j/6 [2 1; 1 2]` to M and `1/h [1 −1; −1 1]` to S on nodes (j, j+1).
pub fn full_matrices(bar: &Bar, weights: &[f64]) -> (SymTridiag, SymTridiag) {
    let n = bar.elements + 1;
    let h = bar.h();
    let mut mass = SymTridiag::zeros(n);
    let mut stiffness = SymTridiag::zeros(n);
    for (j, &w) in weights.iter().enumerate() {
        mass.diag[j] += h / 3.0 * w;
        mass.diag[j + 1] += h / 3.0 * w;
        mass.off[j] = h / 6.0 * w;
        stiffness.diag[j] += 1.0 / h;
        stiffness.diag[j + 1] += 1.0 / h;
        stiffness.off[j] = -1.0 / h;
    }
    (mass, stiffness)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn system(kind: MassKind, m: usize) -> ContactSystem<SymTridiag> {
        BarSystem::new(Bar { length: 1.0, elements: m }, &kind, 0.0).unwrap().system
    }

    #[test]
    fn matrices_match_the_closed_form() {
        let s = system(MassKind::Mod3, 6);
        let h = 1.0 / 6.0;
        assert_eq!(s.mass.diag[0], 0.0);
        assert_eq!(s.mass.diag[1], h / 3.0 * 2.0);
        assert_eq!(s.mass.off[1], h / 6.0 * 2.0);
        assert_eq!(s.stiffness.diag[0], 1.0 / h);
        assert_eq!(s.stiffness.diag[5], 2.0 / h);
    }
}
