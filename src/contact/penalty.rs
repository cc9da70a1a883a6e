//! The penalty contact law inside one linear solve, solved exactly:
//!
//! ```text
//! K U = r − σ Σ_c λ_c e_c,     λ_c = κ min(0, u_c − lb_c)    (R_c = −λ_c = κ d_c⁻)
//! ```
//!
//! with K SPD factored once, σ > 0 the scheme's force scale and κ > 0 the penalty. The step is
//! piecewise linear in U. With `U* = K⁻¹ r`, `Z = (K⁻¹)_CC` and `μ = −σ λ ≥ 0`,
//! `u_C = U*_C + Z μ`, and the law is the complementarity `w = u_C − lb + μ/(σκ) ≥ 0 ⊥ μ ≥ 0`
//! (if u_c ≥ lb_c: μ_c = 0; else μ_c = σκ(lb_c − u_c) and w_c = 0), that is the LCP
//!
//! ```text
//! w = (U*_C − lb) + (Z + I/(σκ)) μ ≥ 0,   μ ≥ 0,   μᵀ w = 0,
//! ```
//!
//! with an SPD matrix: solved exactly by [`Lcp`] (Murty's principal pivoting, a finite
//! active-set method; on the active set it is the semismooth Newton step of the piecewise
//! linear equation). Then `U = K⁻¹ (r + E μ)`: a second solve when some μ > 0.
//!
//! The plain solves `K⁻¹ b` use the back-end's exact contact solver with unreachable bounds
//! (`f64::MIN`: no multiplier, the factor's solve untouched), so both back-ends (the bar's
//! closed form and the sparse Schur solver) serve unchanged. Z costs n_c solves once.

use super::exact::{MasslessRows, QuasiRows, Split};
use super::lcp::{Lcp, LcpError};
use super::{ContactSolver, ExplicitLaw, Massive, StepLaw};
use crate::linalg::{LinalgError, SymMatrix};
use crate::system::ContactSystem;

#[derive(Debug)]
pub struct PenaltySolver<S: ContactSolver> {
    plain: S,
    contact: Vec<usize>,
    lcp: Lcp,
    /// Unreachable bounds (`f64::MIN`), and their unused multipliers.
    floor: Vec<f64>,
    unused: Vec<f64>,
    r: Vec<f64>,
    q: Vec<f64>,
    sigma: f64,
    kappa: f64,
}

impl<S: ContactSolver> PenaltySolver<S> {
    /// From the exact solver `plain` of K on the unknowns `contact` (n unknowns), σ and κ.
    pub fn new(mut plain: S, n: usize, contact: &[usize], sigma: f64, kappa: f64) -> Result<Self, LcpError> {
        let nc = contact.len();
        let (floor, mut unused) = (vec![f64::MIN; nc], vec![0.0; nc]);
        let mut d = vec![0.0; nc * nc];
        let mut col = vec![0.0; n];
        for (b, &cb) in contact.iter().enumerate() {
            col.iter_mut().for_each(|x| *x = 0.0);
            col[cb] = 1.0;
            plain.solve(&mut col, &floor, 1.0, &mut unused)?;
            for (a, &ca) in contact.iter().enumerate() {
                d[a * nc + b] = col[ca];
            }
        }
        // Symmetrise Z (symmetric in exact arithmetic), add I/(σκ).
        for a in 0..nc {
            for b in 0..a {
                let m = 0.5 * (d[a * nc + b] + d[b * nc + a]);
                d[a * nc + b] = m;
                d[b * nc + a] = m;
            }
            d[a * nc + a] += 1.0 / (sigma * kappa);
        }
        Ok(Self {
            plain,
            contact: contact.to_vec(),
            lcp: Lcp::new(d, nc),
            floor,
            unused,
            r: vec![0.0; n],
            q: vec![0.0; nc],
            sigma,
            kappa,
        })
    }

    /// Solves `K U = r − σ Σ λ_c e_c`, `λ_c = κ min(0, u_c − lb_c)` in place (`rhs` = r on
    /// entry, U on exit) and writes λ; returns the pivots.
    pub fn solve(&mut self, rhs: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError> {
        self.r.copy_from_slice(rhs);
        self.plain.solve(rhs, &self.floor, 1.0, &mut self.unused)?;
        for ((q, &c), lb) in self.q.iter_mut().zip(&self.contact).zip(lower) {
            *q = rhs[c] - lb;
        }
        let (mu, _) = self.lcp.solve(&self.q)?;
        let mut any = false;
        for (l, &m) in lambda.iter_mut().zip(mu) {
            *l = if m > 0.0 { -m / self.sigma } else { 0.0 };
            any |= m > 0.0;
        }
        if any {
            rhs.copy_from_slice(&self.r);
            for (&c, &m) in self.contact.iter().zip(mu) {
                rhs[c] += m;
            }
            self.plain.solve(rhs, &self.floor, 1.0, &mut self.unused)?;
        }
        Ok(self.lcp.pivots())
    }
}

/// The springs' energy `Σ ½ κ (d_c⁻)²` of the contact values `u_c` with bounds `lb_c`
/// (`d = u_c − lb_c`).
pub fn spring_energy(kappa: f64, uc: impl Iterator<Item = f64>, lower: &[f64]) -> f64 {
    uc.zip(lower).map(|(u, lb)| (u - lb).min(0.0)).map(|d| 0.5 * kappa * d * d).sum()
}

/// The penalty law's implicit step (module docs); its force is the springs' `λ_c e_c`.
impl<S: ContactSolver> StepLaw for PenaltySolver<S> {
    fn solve(&mut self, rhs: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError> {
        PenaltySolver::solve(self, rhs, lower, lambda)
    }

    fn has_force(&self) -> bool {
        true
    }

    fn add_force(&self, u: &[f64], lower: &[f64], scale: f64, out: &mut [f64]) {
        for (&c, lb) in self.contact.iter().zip(lower) {
            out[c] += scale * (self.kappa * (u[c] - lb).min(0.0));
        }
    }

    fn lambda_of(&self, u: &[f64], lower: &[f64], lambda: &mut [f64]) {
        for ((l, &c), lb) in lambda.iter_mut().zip(&self.contact).zip(lower) {
            *l = self.kappa * (u[c] - lb).min(0.0);
        }
    }

    fn energy(&self, u: &[f64], lower: &[f64]) -> Option<f64> {
        Some(spring_energy(self.kappa, self.contact.iter().map(|&c| u[c]), lower))
    }
}

/// The penalty law in central differences: on a massive contact node the spring of the current
/// displacement (`λ_c = κ min(0, u_cⁿ − lb_c)`, force at t_n), on massless ones the quasi-static
/// rows with the spring ([`PenaltyQuasiStatic`]); the springs of the massive nodes enter the
/// stable limit (`K + κ Σ_{c massive} e_c e_cᵀ`: all engaged, which bounds every contact state).
#[derive(Debug)]
pub struct PenaltyExplicit {
    kappa: f64,
    massive: Vec<(usize, usize)>,
    contact: Vec<usize>,
    lower: Vec<f64>,
    springs: Vec<usize>,
    massless: MasslessRows<PenaltyQuasiStatic>,
}

impl PenaltyExplicit {
    /// Fails if a contact layer has free massless unknowns (no quasi-static map for them here;
    /// the scenes' compatibility rule refuses such a scene first) or K_CC is not definite.
    pub fn new<A: SymMatrix>(system: &ContactSystem<A>, lumped: &[f64], kappa: f64) -> Result<Self, LinalgError> {
        let split = Split::new(system, lumped);
        let any_massless = lumped.iter().any(|&m| m <= 0.0);
        let phi = if !any_massless {
            None
        } else if !split.free.is_empty() {
            let detail = "penalty contact with free massless unknowns (a contact layer) is not built".into();
            return Err(LinalgError::Unsupported { matrix: "stiffness", detail });
        } else {
            let q =
                PenaltyQuasiStatic::new(&system.stiffness, &system.load, &split.massless, kappa).map_err(|pivot| {
                    LinalgError::Unsupported {
                        matrix: "stiffness",
                        detail: format!("its contact block is not positive definite (pivot {pivot})"),
                    }
                })?;
            Some(q)
        };
        let springs = split.massive.iter().map(|&(_, c)| c).collect();
        Ok(Self {
            kappa,
            massless: MasslessRows::new(&split, phi),
            massive: split.massive,
            contact: system.contact.clone(),
            lower: system.lower.clone(),
            springs,
        })
    }
}

impl ExplicitLaw for PenaltyExplicit {
    fn stiffen(&self, x: &[f64], y: &mut [f64]) {
        self.springs.iter().for_each(|&c| y[c] += self.kappa * x[c]);
    }

    fn gershgorin(&self) -> (Vec<usize>, f64) {
        (self.springs.clone(), self.kappa)
    }

    fn bound(&self) -> &'static str {
        if self.springs.is_empty() { "" } else { " + κ E_Cᵀ E_C" }
    }

    fn massive(&mut self, s: Massive<'_>) {
        for &(k, c) in &self.massive {
            let l = self.kappa * (s.u[c] - self.lower[k]).min(0.0);
            s.lambda[k] = l;
            s.a[c] -= l * s.inv_mass[c];
        }
    }

    fn quasi_static(
        &mut self,
        u: &mut [f64],
        load: &[f64],
        forced: bool,
        lambda: &mut [f64],
    ) -> Result<usize, LcpError> {
        self.massless.solve(u, load, forced, lambda)
    }

    fn energy(&self, u: &[f64]) -> f64 {
        spring_energy(self.kappa, self.contact.iter().map(|&c| u[c]), &self.lower)
    }
}

/// The quasi-static rows of massless contact unknowns with the penalty law (explicit schemes):
///
/// ```text
/// K_CC u_C + K_CI U = F_C − λ,   λ_c = κ min(0, u_c − lb_c),
/// ```
///
/// with `b = F_C − K_CI U`, `Z = K_CC⁻¹` (dense, n_c × n_c) and `μ = −λ`: `u_C = Z (b + μ)` and
/// the LCP `w = (Z b − lb) + (Z + I/κ) μ ≥ 0 ⊥ μ ≥ 0`, solved exactly by [`Lcp`]. In 1D
/// (K_00 = E/h, K_01 = −E/h, F = 0): `u_0 = u_1` if `u_1 ≥ lb`, else
/// `u_0 = (E/h u_1 + κ lb)/(E/h + κ)`. Every massless unknown must be a contact unknown (a
/// contact layer's free massless unknowns are not handled here: the caller refuses them).
#[derive(Debug, Clone)]
pub struct PenaltyQuasiStatic {
    contact: Vec<usize>,
    /// `(c, j, K_{contact[c], j})` for j not a contact unknown.
    coupling: Vec<(usize, usize, f64)>,
    load: Vec<f64>,
    z: Vec<f64>,
    lcp: Lcp,
    b: Vec<f64>,
    q: Vec<f64>,
}

impl PenaltyQuasiStatic {
    /// Fails (with the pivot) if K_CC is not positive definite.
    pub fn new<A: SymMatrix>(stiffness: &A, load: &[f64], contact: &[usize], kappa: f64) -> Result<Self, usize> {
        let nc = contact.len();
        let mut slot = vec![usize::MAX; stiffness.dim()];
        for (c, &i) in contact.iter().enumerate() {
            slot[i] = c;
        }
        let mut k = vec![0.0; nc * nc];
        let mut coupling = Vec::new();
        stiffness.for_each_entry(&mut |i, j, v| match (slot[i], slot[j]) {
            (a, b) if a < nc && b < nc => k[a * nc + b] += v,
            (a, _) if a < nc => coupling.push((a, j, v)),
            _ => {}
        });
        let z = spd_inverse(k, nc)?;
        let mut d = z.clone();
        for a in 0..nc {
            d[a * nc + a] += 1.0 / kappa;
        }
        let load = contact.iter().map(|&i| load[i]).collect();
        Ok(Self {
            contact: contact.to_vec(),
            coupling,
            load,
            z,
            lcp: Lcp::new(d, nc),
            b: vec![0.0; nc],
            q: vec![0.0; nc],
        })
    }

    /// Takes the contact entries of a new load vector.
    pub fn set_load(&mut self, load: &[f64]) {
        for (f, &i) in self.load.iter_mut().zip(&self.contact) {
            *f = load[i];
        }
    }

    /// Overwrites the contact entries of `u` and writes λ; returns the pivots.
    pub fn apply(&mut self, u: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError> {
        let nc = self.contact.len();
        self.b.copy_from_slice(&self.load);
        for &(c, j, v) in &self.coupling {
            self.b[c] -= v * u[j];
        }
        for a in 0..nc {
            self.q[a] = (0..nc).map(|b| self.z[a * nc + b] * self.b[b]).sum::<f64>() - lower[a];
        }
        let (mu, _) = self.lcp.solve(&self.q)?;
        for (a, &i) in self.contact.iter().enumerate() {
            u[i] = (0..nc).map(|b| self.z[a * nc + b] * (self.b[b] + mu[b])).sum();
            lambda[a] = -mu[a];
        }
        Ok(self.lcp.pivots())
    }
}

impl QuasiRows for PenaltyQuasiStatic {
    fn set_load(&mut self, load: &[f64]) {
        PenaltyQuasiStatic::set_load(self, load)
    }

    fn apply(&mut self, u: &mut [f64], lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError> {
        PenaltyQuasiStatic::apply(self, u, lower, lambda)
    }
}

/// The inverse of a dense SPD row-major n × n matrix by Gauss–Jordan elimination without
/// pivoting (the pivots of an SPD matrix are positive); Err(pivot) if one is not.
fn spd_inverse(mut a: Vec<f64>, n: usize) -> Result<Vec<f64>, usize> {
    let mut inv = vec![0.0; n * n];
    (0..n).for_each(|i| inv[i * n + i] = 1.0);
    for p in 0..n {
        let d = a[p * n + p];
        if !(d > 0.0) {
            return Err(p);
        }
        for j in 0..n {
            a[p * n + j] /= d;
            inv[p * n + j] /= d;
        }
        for i in (0..n).filter(|&i| i != p) {
            let f = a[i * n + p];
            if f != 0.0 {
                for j in 0..n {
                    a[i * n + j] -= f * a[p * n + j];
                    inv[i * n + j] -= f * inv[p * n + j];
                }
            }
        }
    }
    Ok(inv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::Backend;
    use crate::linalg::tridiag::SymTridiag;

    /// On a tridiagonal K with contact node 0: the result solves `K U = r − σ λ e_0` with
    /// `λ = κ min(0, u_0 − lb)`, in the active and inactive case (residuals to 1e-12).
    /// (Mutation: `+= 1.0 / (sigma * kappa)` dropped -> the exact step: "-3.2847222222222228 vs 0".)
    #[test]
    fn the_penalty_step_meets_its_law() {
        let n = 6;
        let k = SymTridiag { diag: vec![3.0; n], off: vec![-1.0; n - 1] };
        let (sigma, kappa) = (0.5, 40.0);
        let plain = k.contact_solver(&[0], "K").unwrap();
        let mut p = PenaltySolver::new(plain, n, &[0], sigma, kappa).unwrap();
        for (r0, active) in [(-2.0, true), (2.0, false)] {
            let r: Vec<f64> = (0..n).map(|i| if i == 0 { r0 } else { 0.1 * i as f64 }).collect();
            let mut u = r.clone();
            let mut lambda = [0.0];
            p.solve(&mut u, &[-0.1], &mut lambda).unwrap();
            assert_eq!(lambda[0] < 0.0, active);
            let expect = kappa * (u[0] + 0.1).min(0.0);
            assert!((lambda[0] - expect).abs() <= 1e-12, "{} vs {expect}", lambda[0]);
            let mut ku = vec![0.0; n];
            k.mul_into(&u, &mut ku);
            for i in 0..n {
                let f = r[i] - if i == 0 { sigma * lambda[0] } else { 0.0 };
                assert!((ku[i] - f).abs() <= 1e-12, "row {i}: {} vs {f}", ku[i]);
            }
        }
    }

    /// The 1D closed form: `u_0 = u_1` above the obstacle, `(u_1 E/h + κ lb)/(E/h + κ)` below.
    #[test]
    fn the_quasi_static_penalty_row_has_its_closed_form() {
        let k = SymTridiag { diag: vec![4.0, 8.0, 8.0], off: vec![-4.0, -4.0] };
        let kappa = 12.0;
        let mut q = PenaltyQuasiStatic::new(&k, &[0.0; 3], &[0], kappa).unwrap();
        for u1 in [0.3, -0.5] {
            let mut u = vec![9.0, u1, 0.1];
            let mut l = [0.0];
            q.apply(&mut u, &[-0.2], &mut l).unwrap();
            let expect = if u1 >= -0.2 { u1 } else { (4.0 * u1 + kappa * -0.2) / (4.0 + kappa) };
            assert!((u[0] - expect).abs() <= 1e-15, "{} vs {expect}", u[0]);
            assert!((l[0] - kappa * (u[0] + 0.2).min(0.0)).abs() <= 1e-14);
        }
    }
}
