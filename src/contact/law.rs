//! The contact law of a scene (`[contact]`): how the Signorini condition
//! `0 ≤ d_i ⊥ R_i ≥ 0`, `d_i = u_n,i + g_i` (the distance of contact node i to the obstacle,
//! `R_i = −λ_i` its reaction) enters a scheme.
//!
//! - [`ContactLaw::Exact`]: the condition itself, solved exactly (every existing scheme; the
//!   default).
//! - [`ContactLaw::Penalty`]: a plain spring per contact node, `R_i = κ max(0, −d_i)` (no scaling
//!   by h: κ is a stiffness, force per length). Its energy `½ κ (d_i⁻)²` is part of the
//!   reported energy.
//! - [`ContactLaw::Nitsche`]: Nitsche's method (Chouly–Hild–Renard 2015), `θ ∈ {1, 0, −1}` and
//!   `γ = γ₀ E / h`; built for bars ([`crate::contact::nitsche`], [`crate::schemes::nitsche`]:
//!   Newmark/CN and explicit Verlet, γ₀ > 1), refused elsewhere in one place
//!   ([`crate::schemes::nitsche::build`]).

use thiserror::Error;

/// The contact law (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum ContactLaw {
    #[default]
    Exact,
    /// `R_i = penalty · max(0, −d_i)`, penalty > 0 and finite.
    Penalty { penalty: f64 },
    /// Nitsche with `nitsche_theta` ∈ {1, 0, −1} and `nitsche_gamma0` > 1.
    Nitsche { theta: i8, gamma0: f64 },
}

/// A contact law parameter outside its range (the message names the key and the range).
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{key} = {value}: allowed range is {range}", value = crate::numfmt::fmt_f64(*value))]
pub struct LawError {
    pub key: &'static str,
    pub value: f64,
    pub range: &'static str,
}

impl ContactLaw {
    /// The scene names of `contact.method`, in the order messages list them.
    pub const METHODS: [&'static str; 3] = ["exact", "penalty", "nitsche"];
    pub const PENALTY_KEY: &'static str = "contact.penalty";
    pub const PENALTY_RANGE: &'static str = "(0, ∞)";
    pub const THETA_KEY: &'static str = "contact.nitsche_theta";
    pub const THETA_RANGE: &'static str = "1 | 0 | -1";
    pub const GAMMA0_KEY: &'static str = "contact.nitsche_gamma0";
    /// γ₀ > 1: the coercivity of Nitsche's term for θ = 1 and the monotonicity of its contact
    /// rows for every θ ([`crate::contact::nitsche`]).
    pub const GAMMA0_RANGE: &'static str = "(1, ∞)";
    /// The default `nitsche_gamma0`.
    pub const DEFAULT_GAMMA0: f64 = 100.0;

    /// A penalty law: the one place its range is checked.
    pub fn penalty(penalty: f64) -> Result<Self, LawError> {
        if penalty.is_finite() && penalty > 0.0 {
            Ok(ContactLaw::Penalty { penalty })
        } else {
            Err(LawError { key: Self::PENALTY_KEY, value: penalty, range: Self::PENALTY_RANGE })
        }
    }

    /// A Nitsche law: the one place its ranges are checked.
    pub fn nitsche(theta: f64, gamma0: f64) -> Result<Self, LawError> {
        if ![1.0, 0.0, -1.0].contains(&theta) {
            return Err(LawError { key: Self::THETA_KEY, value: theta, range: Self::THETA_RANGE });
        }
        if !(gamma0.is_finite() && gamma0 > 1.0) {
            return Err(LawError { key: Self::GAMMA0_KEY, value: gamma0, range: Self::GAMMA0_RANGE });
        }
        Ok(ContactLaw::Nitsche { theta: theta as i8, gamma0 })
    }

    /// The scene name (`contact.method`).
    pub const fn method(&self) -> &'static str {
        match self {
            ContactLaw::Exact => "exact",
            ContactLaw::Penalty { .. } => "penalty",
            ContactLaw::Nitsche { .. } => "nitsche",
        }
    }

    /// The penalty stiffness κ (None for the other laws).
    pub fn penalty_stiffness(&self) -> Option<f64> {
        match *self {
            ContactLaw::Penalty { penalty } => Some(penalty),
            _ => None,
        }
    }

    /// The penalty energy `Σ ½ κ (d_i⁻)²` of the contact values `u_c` with bounds `lb_c = −g_c`
    /// (`d = u_c − lb_c`); 0 for the other laws.
    pub fn energy(&self, uc: impl Iterator<Item = f64>, lower: &[f64]) -> f64 {
        match *self {
            ContactLaw::Penalty { penalty } => {
                uc.zip(lower).map(|(u, lb)| (u - lb).min(0.0)).map(|d| 0.5 * penalty * d * d).sum()
            }
            _ => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_checked_where_laws_are_built() {
        assert_eq!(ContactLaw::penalty(1e4), Ok(ContactLaw::Penalty { penalty: 1e4 }));
        let e = ContactLaw::penalty(0.0).unwrap_err();
        assert_eq!(e.to_string(), "contact.penalty = 0: allowed range is (0, ∞)");
        assert!(ContactLaw::penalty(f64::INFINITY).is_err() && ContactLaw::penalty(-1.0).is_err());
        assert_eq!(ContactLaw::nitsche(-1.0, 100.0), Ok(ContactLaw::Nitsche { theta: -1, gamma0: 100.0 }));
        assert_eq!(ContactLaw::nitsche(0.5, 100.0).unwrap_err().key, "contact.nitsche_theta");
        assert_eq!(ContactLaw::nitsche(1.0, 0.0).unwrap_err().key, "contact.nitsche_gamma0");
        assert!(ContactLaw::nitsche(1.0, 1.0).is_err() && ContactLaw::nitsche(1.0, 1.5).is_ok());
        assert_eq!(ContactLaw::default().method(), "exact");
    }

    /// `½ κ (d⁻)²` per node: 0 for d ≥ 0, ½ · 10 · 0.2² = 0.2 for d = −0.2.
    #[test]
    fn penalty_energy_counts_penetration_only() {
        let law = ContactLaw::Penalty { penalty: 10.0 };
        let e = law.energy([-0.3, 0.5].into_iter(), &[-0.1, -0.1]);
        assert!((e - 0.2).abs() < 1e-15, "{e}");
        assert_eq!(ContactLaw::Exact.energy([-1.0].into_iter(), &[0.0]), 0.0);
    }
}
