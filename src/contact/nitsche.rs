//! Nitsche's contact term on the bar (Chouly–Hild–Renard, ESAIM M2AN 49(2), 2015; the
//! static method of Chouly–Hild, SIAM J. Numer. Anal. 51(2), 2013), at its contact point x = 0.
//!
//! **Sign conventions.** CHR write the condition on Γ_C as `u_n ≤ g`, `σ_n(u) ≤ 0`,
//! `σ_n(u)(u_n − g) = 0` with n the outward normal, and a *small* parameter γ_CHR proportional to
//! h. We use the *large* γ = 1/γ_CHR = γ₀ E/h (a stiffness, like the penalty; the issue's key;
//! GetFEM's `g_N = γ₀/h` for E = 1), so that
//! CHR's `P_γ(u) = u_n − g − γ_CHR σ_n(u)` becomes, multiplied by γ (force units),
//!
//! ```text
//! P(u) = γ (u_n − g) − σ_n(u),     σ_n(u) = −[P(u)]_+    (the Signorini condition, exactly).
//! ```
//!
//! (The brief's `σ_n(u) − γ(u_n − g)` is −P: with it the bracket would be [·]₋.) At x = 0,
//! n = −1: `u_n = −u_0`, `g = gap`, so `u_n − g = −(u_0 + gap) = −d` with d the distance to the
//! obstacle, and `σ_n(u) = E u'(0)` (n·n = 1), the paper's λ. On a P1 cell `E u_h'(0) =
//! (E/h)(u_1 − u_0) = sᵀU` with `s = (E/h)(e_1 − e_0)`. With `q = γ e_0 + s`:
//! `P(U) = −γ d − sᵀU = −qᵀU + γ lb` (lb = −gap).
//!
//! CHR's weak form, `θ ∈ {1, 0, −1}`, in these units (GetFEM's `demo_dynamic_contact_1D.py`, by
//! Renard and Chouly, assembles the same terms; `tests/nitsche.rs` steps it as a peer):
//!
//! ```text
//! (ρü, v) + a(u, v) − (θ/γ) σ_n(u) σ_n(v) + (1/γ) [P(u)]_+ (γ v_n − θ σ_n(v)) = L(v)
//! ```
//!
//! (the CHR term `−θγ_CHR σσ + (1/γ_CHR)[P_γ]_+ P_θγ(v)` with γ_CHR = 1/γ). As a force vector,
//! `M Ü + K U + N(U) = F` with
//!
//! ```text
//! N(U) = −(θ/γ)(sᵀU) s − [P(U)]_+ w,     w = e_0 + (θ/γ) s.
//! ```
//!
//! Out of contact ([P]_+ = 0) the term −(θ/γ)(sᵀU)s remains: Nitsche's consistency term. For
//! θ = 1, N = ∇Φ with `Φ(U) = −(1/2γ)(sᵀU)² + (1/2γ)[P(U)]_+²` ([`NitscheTerm::potential`]),
//! the contact part of CHR's energy. The reported contact stress is `λ = −[P(U)]_+ ≤ 0`.
//!
//! **Coercivity.** `K − (θ/γ)ssᵀ` changes the first cell's stiffness E/h into (E/h)(1 − θ/γ₀):
//! positive iff γ₀ > θ. Every quasi-static or implicit row below is monotone for γ₀ > 1
//! whatever θ, which is why [`NitscheTerm::new`] asks for γ₀ > 1.

/// The Nitsche term of the bar: contact unknown `c`, its P1 neighbour `j`, `k = E/h`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NitscheTerm {
    pub c: usize,
    pub j: usize,
    /// E/h of the contact cell (its stiffness, section 1).
    pub k: f64,
    /// γ = γ₀ E/h.
    pub gamma: f64,
    pub theta: f64,
    /// The obstacle bound lb = −gap.
    pub lower: f64,
}

/// Why a system has no Nitsche term (the caller turns it into a refusal naming the key).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NitscheShape {
    /// Not exactly one contact unknown.
    ContactCount(usize),
    /// The contact row of K is not that of one P1 cell, `(E/h)(u_c − u_j)`.
    NotOneCell,
    /// γ₀ ≤ 1 (module docs: coercivity).
    Gamma0(f64),
}

impl NitscheTerm {
    /// From the stiffness of a P1 bar: the contact row must be `(E/h)(u_c − u_j)` (one cell),
    /// from which E/h is read.
    pub fn new<A: crate::linalg::SymMatrix>(
        stiffness: &A,
        contact: &[usize],
        lower: &[f64],
        theta: f64,
        gamma0: f64,
    ) -> Result<Self, NitscheShape> {
        let [c] = *contact else { return Err(NitscheShape::ContactCount(contact.len())) };
        if !(gamma0 > 1.0) {
            return Err(NitscheShape::Gamma0(gamma0));
        }
        let mut row = Vec::new();
        stiffness.for_each_entry(&mut |i, j, v| {
            if i == c && j != c && v != 0.0 {
                row.push((j, v));
            }
        });
        let k = stiffness.diag(c);
        // One neighbour with K_cj = −K_cc (exactly, as the P1 element matrix is assembled).
        let &[(j, kcj)] = row.as_slice() else { return Err(NitscheShape::NotOneCell) };
        if !(k > 0.0 && kcj == -k) {
            return Err(NitscheShape::NotOneCell);
        }
        Ok(Self { c, j, k, gamma: gamma0 * k, theta, lower: lower[0] })
    }

    /// σ_n(U) = sᵀU = (E/h)(u_j − u_c).
    pub fn sigma_n(&self, u: &[f64]) -> f64 {
        self.k * (u[self.j] - u[self.c])
    }

    /// P(U) = −γ (u_c − lb) − σ_n(U).
    pub fn p(&self, u: &[f64]) -> f64 {
        -self.gamma * (u[self.c] - self.lower) - self.sigma_n(u)
    }

    /// The contact stress λ = −[P(U)]_+.
    pub fn lambda(&self, u: &[f64]) -> f64 {
        -self.p(u).max(0.0)
    }

    /// Adds `scale · N(U)` to `out` (module docs).
    pub fn add_force(&self, u: &[f64], scale: f64, out: &mut [f64]) {
        let sig = self.sigma_n(u);
        let pp = self.p(u).max(0.0);
        let t = self.theta / self.gamma;
        // N = −t σ s − [P]_+ (e_c + t s), s = k (e_j − e_c).
        let along_s = -t * sig - pp * t;
        out[self.j] += scale * along_s * self.k;
        out[self.c] += scale * (-along_s * self.k - pp);
    }

    /// `Φ(U) = −(1/2γ) σ_n(U)² + (1/2γ) [P(U)]_+²`: for θ = 1, N = ∇Φ (module docs).
    pub fn potential(&self, u: &[f64]) -> f64 {
        let (sig, pp) = (self.sigma_n(u), self.p(u).max(0.0));
        (pp * pp - sig * sig) / (2.0 * self.gamma)
    }

    /// The vectors s, q = γe_c + s and w = e_c + (θ/γ)s as (c-entry, j-entry) pairs.
    pub fn vectors(&self) -> [(f64, f64); 3] {
        let s = (-self.k, self.k);
        let t = self.theta / self.gamma;
        [s, (self.gamma + s.0, s.1), (1.0 + t * s.0, t * s.1)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::tridiag::SymTridiag;

    /// N(U) is the gradient of Φ for θ = 1 (central differences, 1e-6 relative: the step 1e-6
    /// away from the kink P = 0), and the P1 shape checks refuse a non-cell row.
    /// (Mutation: `- pp` -> `+ pp` in add_force -> the active gradient check fails.)
    #[test]
    fn the_force_is_the_gradient_of_the_potential() {
        let k = SymTridiag { diag: vec![4.0, 8.0, 8.0], off: vec![-4.0, -4.0] };
        let term = NitscheTerm::new(&k, &[0], &[-0.1], 1.0, 10.0).unwrap();
        assert_eq!((term.k, term.gamma, term.j), (4.0, 40.0, 1));
        for u in [[-0.3, 0.2, 0.0], [0.4, -0.2, 0.1]] {
            let mut n = [0.0; 3];
            term.add_force(&u, 1.0, &mut n);
            for i in 0..3 {
                let (mut up, mut dn) = (u, u);
                up[i] += 1e-6;
                dn[i] -= 1e-6;
                let g = (term.potential(&up) - term.potential(&dn)) / 2e-6;
                assert!((g - n[i]).abs() <= 1e-6 * (1.0 + g.abs()), "u {u:?}, i {i}: {g} vs {}", n[i]);
            }
        }
        let bad = SymTridiag { diag: vec![4.0, 8.0, 8.0], off: vec![-3.0, -4.0] };
        assert_eq!(NitscheTerm::new(&bad, &[0], &[0.0], 1.0, 10.0), Err(NitscheShape::NotOneCell));
        assert_eq!(NitscheTerm::new(&k, &[0], &[0.0], 1.0, 1.0), Err(NitscheShape::Gamma0(1.0)));
    }
}
