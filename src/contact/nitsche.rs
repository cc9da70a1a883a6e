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

use super::lcp::LcpError;
use super::{ContactSolver, ExplicitLaw, Massive, SetupError, StepLaw};

/// The scene key of γ₀, and its range: γ₀ > 1 is the coercivity of Nitsche's term for θ = 1 and
/// the monotonicity of its contact rows for every θ (module docs).
pub const GAMMA0_KEY: &str = "contact.nitsche_gamma0";
pub const GAMMA0_RANGE: &str = "(1, ∞)";

/// γ₀ out of the range this system allows.
pub(crate) fn gamma0_error(value: f64, range: &'static str) -> SetupError {
    SetupError::Parameter { key: GAMMA0_KEY, value, range }
}

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

/// The Nitsche law's implicit step (Newmark, CN, backward Euler: `(M + σK) U + σ N(U) = r`):
///
/// **The step, exactly.** With `A = M + σK − σ(θ/γ)ssᵀ` it reads `A U = r + σ[P(U)]_+ w`. Let
/// `y = A⁻¹ r`, `z = A⁻¹ w` (once), `c = σ qᵀz` (once) and the trial `p* = P(y) = −qᵀy + γ lb`.
/// Then `U = y + σ[p]_+ z` with p = P(U) solving the scalar piecewise-linear equation
/// `p + c [p]_+ = p*`; for `1 + c > 0` its left side is strictly increasing, so its one root is
/// `p = p*` if p* ≤ 0 and `p = p*/(1 + c)` otherwise: semismooth Newton on the single contact
/// dof from the inactive guess, converged after one correction (finite termination, and no
/// second solve: z is stored). 1 + c > 0 holds for θ = 1 (c = (σ/γ) qᵀA⁻¹q ≥ 0) and is checked
/// at construction for θ = 0, −1 (refused otherwise, naming γ₀).
///
/// **Energy** (θ = 1, CN, F constant): summing the scheme's identities, `E^{n+1} − Eⁿ = −δ_n`
/// with `δ_n = (1/2γ)[(p_{n+1} − p_n)([p_n]_+ + [p_{n+1}]_+) − [p_{n+1}]_+² + [p_n]_+²]`
/// ([`trapezoid_defect`]: the trapezoidal rule on Φ's piecewise-quadratic part): δ_n = 0 unless
/// P changes sign in the step; at an impact (p_n ≤ 0 < p_{n+1}) `δ_n = −p_n p_{n+1}/2γ ≥ 0`
/// (dissipated), at a release `δ_n = p_n p_{n+1}/2γ ≤ 0` (gained). So the energy is conserved
/// exactly between sign changes (`tests/nitsche.rs` checks the identity step by step). The
/// energy is CHR's `E^θ = ½V·MV + ½U·KU − F·U + θΦ(U)`, θ-weighted as GetFEM's
/// `demo_dynamic_contact_1D.py` computes it; N = ∇Φ only for θ = 1.
#[derive(Debug)]
pub struct NitscheStep<S: ContactSolver> {
    solver: RankOne<S>,
    term: NitscheTerm,
    sigma: f64,
    z: Vec<f64>,
    c: f64,
}

impl<S: ContactSolver> NitscheStep<S> {
    /// From the exact solver `plain` of `B = M + σK` (n unknowns).
    pub fn new(plain: S, n: usize, term: NitscheTerm, sigma: f64) -> Result<Self, SetupError> {
        let mut solver = RankOne::new(plain, n, term, sigma)?;
        let [_, q, w] = term.vectors();
        let mut z = vec![0.0; n];
        (z[term.c], z[term.j]) = w;
        solver.solve(&mut z)?;
        let c = sigma * (q.0 * z[term.c] + q.1 * z[term.j]);
        if !(1.0 + c > 0.0) {
            return Err(gamma0_error(term.gamma / term.k, "(1, ∞) with 1 + σqᵀA⁻¹w > 0"));
        }
        Ok(Self { solver, term, sigma, z, c })
    }

    /// `c = σ qᵀA⁻¹w` of the closed-form step (struct docs).
    pub fn coupling(&self) -> f64 {
        self.c
    }
}

impl<S: ContactSolver> StepLaw for NitscheStep<S> {
    fn solve(&mut self, rhs: &mut [f64], _lower: &[f64], lambda: &mut [f64]) -> Result<usize, LcpError> {
        self.solver.solve(rhs)?;
        // The closed form of the step (struct docs): p* = P(y), [p]_+ = [p*]_+/(1 + c).
        let p_plus = self.term.p(rhs).max(0.0) / (1.0 + self.c);
        if p_plus > 0.0 {
            let f = self.sigma * p_plus;
            rhs.iter_mut().zip(&self.z).for_each(|(u, z)| *u += f * z);
        }
        lambda[0] = -p_plus;
        Ok(0)
    }

    fn has_force(&self) -> bool {
        true
    }

    fn add_force(&self, u: &[f64], _lower: &[f64], scale: f64, out: &mut [f64]) {
        self.term.add_force(u, scale, out);
    }

    fn lambda_of(&self, u: &[f64], _lower: &[f64], lambda: &mut [f64]) {
        lambda[0] = self.term.lambda(u);
    }

    fn energy(&self, u: &[f64], _lower: &[f64]) -> Option<f64> {
        Some(self.term.theta * self.term.potential(u))
    }
}

/// δ of the trapezoidal rule on `½[p]_+²/γ` between p0 and p1 (energy docs of [`NitscheStep`]).
pub fn trapezoid_defect(p0: f64, p1: f64, gamma: f64) -> f64 {
    let (a, b) = (p0.max(0.0), p1.max(0.0));
    ((p1 - p0) * (a + b) - b * b + a * a) / (2.0 * gamma)
}

/// Plain solves `x ← (M + σK − σ(θ/γ)ssᵀ)⁻¹ x`: the factor of B = M + σK and Sherman–Morrison
/// for the rank-one Nitsche term, `A⁻¹x = B⁻¹x + α (sᵀB⁻¹x)/(1 − α sᵀB⁻¹s) B⁻¹s`, α = σθ/γ.
#[derive(Debug)]
struct RankOne<S: ContactSolver> {
    plain: S,
    floor: [f64; 1],
    unused: [f64; 1],
    term: NitscheTerm,
    /// α / (1 − α sᵀB⁻¹s) and B⁻¹s.
    coef: f64,
    b_inv_s: Vec<f64>,
}

impl<S: ContactSolver> RankOne<S> {
    fn new(mut plain: S, n: usize, term: NitscheTerm, sigma: f64) -> Result<Self, SetupError> {
        let (floor, mut unused) = ([f64::MIN], [0.0]);
        let mut b_inv_s = vec![0.0; n];
        let s = term.vectors()[0];
        b_inv_s[term.c] = s.0;
        b_inv_s[term.j] = s.1;
        plain.solve(&mut b_inv_s, &floor, 1.0, &mut unused)?;
        let alpha = sigma * term.theta / term.gamma;
        let den = 1.0 - alpha * term.sigma_n(&b_inv_s);
        // den > 0 iff A = B − α ssᵀ is SPD (B SPD): true for γ₀ > 1 (module docs).
        if !(den > 0.0) {
            return Err(gamma0_error(term.gamma / term.k, GAMMA0_RANGE));
        }
        Ok(Self { plain, floor, unused, term, coef: alpha / den, b_inv_s })
    }

    fn solve(&mut self, x: &mut [f64]) -> Result<(), LcpError> {
        self.plain.solve(x, &self.floor, 1.0, &mut self.unused)?;
        let f = self.coef * self.term.sigma_n(x);
        x.iter_mut().zip(&self.b_inv_s).for_each(|(x, y)| *x += f * y);
        Ok(())
    }
}

/// The Nitsche law in explicit central differences (Verlet; Chouly–Renard, AMSES 5:31, 2018),
/// the contact term at t_n: `Aⁿ_I = M_L,II⁻¹ (F_I − (K Uⁿ)_I − N_I(Uⁿ))`. A massless contact node
/// (redistributed mass) is quasi-static at t_{n+1}: `(KU)_0 + N_0(U) = F_0`, which is
/// `σ_n + [P]_+ = −f̃`, `f̃ = F_0/(1 − θ/γ₀)`, decreasing in u_0 for γ₀ > 1, so its one root is
/// `u_0 = u_1 + f̃/(E/h)` if P ≤ 0 there, else `u_0 = lb + f̃/γ` (closed form; no load:
/// `u_0 = max(lb, u_1)`, exact contact). Every other unknown must have mass.
///
/// **Stable step.** Δt ≤ Δt_c = 2/√λ_max(M_L,II⁻¹ B_II) with
/// `B = K + 2γ e_0e_0ᵀ + (1/γ)ssᵀ` (Lanczos, its Gershgorin bound when unconverged). How B
/// bounds the Nitsche term: the tangent of K + N is `K − (θ/γ)ssᵀ` out of contact and
/// `K + γe_0e_0ᵀ + e_0sᵀ + θ se_0ᵀ` in contact; by `2|x_0 sᵀx| ≤ γx_0² + (sᵀx)²/γ` the symmetric
/// part of each is ≤ B for every θ ∈ {1, 0, −1}. For θ = 1 the tangents are symmetric, so B
/// bounds their λ_max in every contact state (the linearised step is stable); for θ = 0, −1 it
/// bounds only their symmetric parts, and we claim no stability proof (we have not checked
/// Chouly–Renard's analysis for them; measured bounded at Δt_c in `tests/nitsche.rs`). With a
/// massless contact node the γ e_0e_0ᵀ term sits on a row outside I: the condensed stiffness is
/// then ≤ B_II, whose only addition to K_II is (E/h)²/γ on node 1 (Δt_c within a factor
/// (1 + 1/γ₀)^{1/2} of the exact-contact one). With a massive contact node the bound is of
/// order 2/√(2γ/m_0) ~ h/(c√γ₀): the known cost of an explicit penalty-like term.
#[derive(Debug)]
pub struct NitscheExplicit {
    term: NitscheTerm,
    /// Whether the contact node is massless (quasi-static).
    quasi: bool,
}

impl NitscheExplicit {
    /// Fails if an unknown other than the contact node is massless.
    pub fn new(term: NitscheTerm, lumped: &[f64]) -> Result<Self, SetupError> {
        if (0..lumped.len()).any(|i| i != term.c && lumped[i] <= 0.0) {
            return Err(SetupError::Shape(
                "Nitsche with central differences needs mass on every unknown but the contact node",
            ));
        }
        Ok(Self { term, quasi: lumped[term.c] <= 0.0 })
    }
}

impl ExplicitLaw for NitscheExplicit {
    fn stiffen(&self, x: &[f64], y: &mut [f64]) {
        let (t, s, g) = (self.term, self.term.vectors()[0], self.term.gamma);
        y[t.c] += 2.0 * g * x[t.c];
        let sx = s.0 * x[t.c] + s.1 * x[t.j];
        y[t.c] += sx * s.0 / g;
        y[t.j] += sx * s.1 / g;
    }

    /// B = 2γ e_c e_cᵀ + ssᵀ/γ with s = k(−e_c + e_j) ([`NitscheTerm::vectors`]): |B| has row
    /// sums 2γ + 2k²/γ (node c) and 2k²/γ (node j); the larger bounds both (the trait's contract).
    fn gershgorin(&self) -> (Vec<usize>, f64) {
        let (t, g) = (self.term, self.term.gamma);
        (vec![t.c, t.j], 2.0 * g + 2.0 * t.k * t.k / g)
    }

    fn bound(&self) -> &'static str {
        " + 2γ e_0e_0ᵀ + ssᵀ/γ"
    }

    fn has_residual(&self) -> bool {
        true
    }

    fn add_residual(&self, u: &[f64], r: &mut [f64]) {
        self.term.add_force(u, -1.0, r);
    }

    /// λ = −[P(U)]_+ (the force itself is in the residual).
    fn massive(&mut self, s: Massive<'_>) {
        s.lambda[0] = self.term.lambda(s.u);
    }

    fn quasi_static(
        &mut self,
        u: &mut [f64],
        load: &[f64],
        _forced: bool,
        _lambda: &mut [f64],
    ) -> Result<usize, LcpError> {
        if self.quasi {
            let t = self.term;
            let f = load[t.c] / (1.0 - t.theta * t.k / t.gamma);
            u[t.c] = u[t.j] + f / t.k;
            if t.p(u) > 0.0 {
                u[t.c] = t.lower + f / t.gamma;
            }
        }
        Ok(0)
    }

    fn energy(&self, u: &[f64]) -> f64 {
        self.term.theta * self.term.potential(u)
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
