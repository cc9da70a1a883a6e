//! The exact solution of the impacting-bar benchmark (paper §4.1), for any length L.
//!
//! For L = 1, u⁰ = (1−x)/2, v⁰ = 0, f = 0 the solution is piecewise affine and 3-periodic. With
//! τ = t mod 3:
//!
//! ```text
//! τ ∈ [0,1] (free flight):  u = (1 − max(x, τ))/2                        regions I–IV of (4.1)
//! τ ∈ [1,2] (contact):      u = −min(x, 1−x, s, 1−s)/2,   s = τ − 1      regions I–IV of (4.2)
//! τ ∈ [2,3] (release):      u = min(r, 1−x)/2,            r = τ − 2      regions I–IV of (4.3)
//! ```
//!
//! The contact force is `λ(t) = u_x(0,t) = −1/2` for τ ∈ (1,2), else 0; the energy
//! `½∫(u_t² + u_x²)` is 1/8 at all times.
//!
//! **Correction of the paper.** Eq. (4.2) gives `(t − t₁)/2` in region I of the contact phase; the
//! bar moves towards the obstacle there (`u_t(·,1) = −1/2`), so region I is `−(t − t₁)/2`. This
//! is the only sign that is continuous with region II (`−x/2` on the characteristic x = t − t₁)
//! and with region III (`(x−1)/2` on x = 1 − (t − t₁)), and the tests check the wave equation,
//! both boundary conditions, complementarity and the energy on the corrected formula.
//!
//! For another length L the solution is `u_L(x,t) = L u_1(x/L, t/L)` (the wave equation and the
//! Signorini conditions are invariant under this scaling), with u⁰ = (L−x)/2, period 3L,
//! λ = −1/2 on (L, 2L) and energy L/8.

/// The impacting bar of length L with u⁰ = (L−x)/2, v⁰ = 0, f = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactingBar {
    pub length: f64,
}

/// Phase of the reference (L = 1) solution at reduced time τ ∈ [0, 3).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    Flight(f64),
    Contact(f64),
    Release(f64),
}

impl ImpactingBar {
    pub fn period(&self) -> f64 {
        3.0 * self.length
    }

    /// Exact energy `½∫₀ᴸ (u_t² + u_x²) dx = L/8`.
    pub fn energy(&self) -> f64 {
        self.length / 8.0
    }

    pub fn initial_displacement(&self, x: f64) -> f64 {
        (self.length - x) / 2.0
    }

    fn phase(&self, t: f64) -> Phase {
        let tau = (t / self.length).rem_euclid(3.0);
        if tau <= 1.0 {
            Phase::Flight(tau)
        } else if tau <= 2.0 {
            Phase::Contact(tau - 1.0)
        } else {
            Phase::Release(tau - 2.0)
        }
    }

    /// Displacement u(x, t).
    pub fn u(&self, x: f64, t: f64) -> f64 {
        let y = x / self.length;
        let v = match self.phase(t) {
            Phase::Flight(tau) => (1.0 - y.max(tau)) / 2.0,
            Phase::Contact(s) => -y.min(1.0 - y).min(s).min(1.0 - s) / 2.0,
            Phase::Release(r) => r.min(1.0 - y) / 2.0,
        };
        self.length * v
    }

    /// Velocity u_t(x, t) (one-sided at kinks: the value of the region that contains x + 0).
    pub fn u_t(&self, x: f64, t: f64) -> f64 {
        let y = x / self.length;
        match self.phase(t) {
            Phase::Flight(tau) => {
                if y < tau {
                    -0.5
                } else {
                    0.0
                }
            }
            Phase::Contact(s) => {
                let d = y.min(1.0 - y);
                if s < d.min(0.5) {
                    -0.5 // region I: −s/2
                } else if 1.0 - s < d {
                    0.5 // region IV: (s−1)/2
                } else {
                    0.0 // regions II, III
                }
            }
            Phase::Release(r) => {
                if r < 1.0 - y {
                    0.5
                } else {
                    0.0
                }
            }
        }
    }

    /// Strain u_x(x, t) (one-sided at kinks, as [`Self::u_t`]).
    pub fn u_x(&self, x: f64, t: f64) -> f64 {
        let y = x / self.length;
        match self.phase(t) {
            Phase::Flight(tau) => {
                if y < tau {
                    0.0
                } else {
                    -0.5
                }
            }
            Phase::Contact(s) => {
                let d = y.min(1.0 - y);
                if d < s.min(1.0 - s) { if y < 0.5 { -0.5 } else { 0.5 } } else { 0.0 }
            }
            Phase::Release(r) => {
                if r < 1.0 - y {
                    0.0
                } else {
                    -0.5
                }
            }
        }
    }

    /// Contact force λ(t) = u_x(0, t): −1/2 on the open contact interval, 0 elsewhere.
    pub fn lambda(&self, t: f64) -> f64 {
        match self.phase(t) {
            Phase::Contact(s) if s > 0.0 && s < 1.0 => -0.5,
            _ => 0.0,
        }
    }

    /// `u(x, t)` at every x of `xs` into `out`, with the phase found once (not per node, as
    /// [`Self::u`] does): the same closed forms, so the same values bit for bit. The loop is
    /// branch-free (min/max), for the per-step exact L² error of long runs.
    #[inline(always)]
    pub fn nodal_values(&self, t: f64, xs: &[f64], out: &mut [f64]) {
        let l = self.length;
        let ys = xs.iter().map(|&x| x / l);
        match self.phase(t) {
            Phase::Flight(tau) => out.iter_mut().zip(ys).for_each(|(o, y)| *o = l * ((1.0 - y.max(tau)) / 2.0)),
            Phase::Contact(s) => {
                out.iter_mut().zip(ys).for_each(|(o, y)| *o = l * (-y.min(1.0 - y).min(s).min(1.0 - s) / 2.0));
            }
            Phase::Release(r) => out.iter_mut().zip(ys).for_each(|(o, y)| *o = l * (r.min(1.0 - y) / 2.0)),
        }
    }

    /// Contact-node displacement u(0, t).
    pub fn u0(&self, t: f64) -> f64 {
        self.u(0.0, t)
    }

    /// The x-coordinates in (0, L) where u(·, t) may have a kink; between two consecutive ones
    /// (and the mesh nodes) u(·, t) is affine. Writes up to 3 values into `out`, returns the count.
    pub fn kinks(&self, t: f64, out: &mut [f64; 3]) -> usize {
        let l = self.length;
        let ys: &[f64] = match self.phase(t) {
            Phase::Flight(tau) => &[tau],
            Phase::Contact(s) => &[s, 1.0 - s, 0.5],
            Phase::Release(r) => &[1.0 - r],
        };
        let mut k = 0;
        for &y in ys {
            if y > 0.0 && y < 1.0 {
                out[k] = y * l;
                k += 1;
            }
        }
        k
    }
}

/// The exact solution by characteristics of a body without force (bar, or a plate with
/// y-independent data: a plane wave), for its material, far end and gap.
pub fn by_characteristics(
    length: f64,
    material: crate::material::Material,
    far_end: crate::material::FarEnd,
    gap: f64,
    initial: crate::characteristics::InitialData<'_>,
    t_end: f64,
) -> Result<crate::characteristics::Characteristics, crate::characteristics::CharacteristicsError> {
    use crate::characteristics::{BarData, Characteristics, FarEnd};
    let far_end = match far_end {
        crate::material::FarEnd::Clamped => FarEnd::Clamped,
        crate::material::FarEnd::Free => FarEnd::Free,
    };
    let data = BarData { length, density: material.density, modulus: material.modulus, far_end, gap };
    Characteristics::new(&data, initial, t_end)
}

/// The paper's initial data u⁰ = (L − x)/2, v⁰ = 0 as piecewise-linear data for
/// [`by_characteristics`]: (x, u, v) at the two ends.
pub fn paper_data(length: f64) -> ([f64; 2], [f64; 2], [f64; 2]) {
    ([0.0, length], [length / 2.0, 0.0], [0.0, 0.0])
}

/// The exact solution a run is measured against: the paper's closed form ([`ImpactingBar`]), or
/// the general solution by characteristics ([`crate::characteristics::Characteristics`]) for
/// any material, far end, gap and initial data without body force. Both are x-only, so a plate
/// with y-independent data is measured against them too.
#[derive(Debug, Clone)]
pub enum Exact {
    Paper(ImpactingBar),
    General(std::sync::Arc<crate::characteristics::Characteristics>),
}

impl Exact {
    pub fn u(&self, x: f64, t: f64) -> f64 {
        match self {
            Exact::Paper(e) => e.u(x, t),
            Exact::General(c) => c.u(x, t),
        }
    }

    /// u(0, t).
    pub fn u0(&self, t: f64) -> f64 {
        match self {
            Exact::Paper(e) => e.u0(t),
            Exact::General(c) => c.u0(t),
        }
    }

    /// The contact force λ(t) = E u_x(0+, t).
    pub fn lambda(&self, t: f64) -> f64 {
        match self {
            Exact::Paper(e) => e.lambda(t),
            Exact::General(c) => c.lambda(t),
        }
    }

    /// Start and end of the first contact phase (the paper's: [L, 2L]).
    pub fn first_contact(&self) -> Option<(f64, f64)> {
        match self {
            Exact::Paper(e) => Some((e.length, 2.0 * e.length)),
            Exact::General(c) => c.contact_intervals().first().copied(),
        }
    }

    /// The energy `½∫ρu_t² + ½∫E u_x²` (constant in time) per unit cross-section.
    pub fn energy(&self) -> f64 {
        match self {
            Exact::Paper(e) => e.energy(),
            Exact::General(c) => c.energy(0.0),
        }
    }

    /// The paper's closed form, if that is what this is.
    pub fn paper(&self) -> Option<&ImpactingBar> {
        match self {
            Exact::Paper(e) => Some(e),
            Exact::General(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn initial_data_and_periodicity() {
        let b = ImpactingBar { length: 1.0 };
        for i in 0..=10 {
            let x = i as f64 / 10.0;
            assert_eq!(b.u(x, 0.0), (1.0 - x) / 2.0);
            assert!((b.u(x, 3.0) - b.u(x, 0.0)).abs() < 1e-15);
        }
    }
}
