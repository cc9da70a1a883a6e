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
//!   `γ = γ₀ E / h`; built for bars ([`crate::contact::nitsche`]: one contact point whose σ_n
//!   comes from its P1 cell, γ₀ > 1).
//!
//! Each law is one file of `crate::contact` implementing [`StepLaw`] and [`ExplicitLaw`];
//! [`ContactLaw::step_law`] and [`ContactLaw::explicit_law`] build them, [`ContactLaw::needs`]
//! declares what each needs of the scheme and the geometry (checked once, by the scenes'
//! compatibility rule).

use super::exact::{ExactExplicit, ExactStep};
pub use super::friction::Friction;
use super::nitsche::{NitscheExplicit, NitscheShape, NitscheStep, NitscheTerm};
use super::penalty::{PenaltyExplicit, PenaltySolver};
use super::{Backend, ExplicitLaw, StepLaw};
use crate::linalg::SymMatrix;
use crate::system::ContactSystem;
use serde::{Deserialize, Deserializer, Serialize};
use thiserror::Error;

/// The contact law (module docs): the `[contact]` table, serde internally tagged by `method`
/// (through [`LawTable`]), each variant with its own keys (a key of another method is refused
/// naming it, by the scene reader `crate::scene`'s `read_tagged`). Ranges are checked where a
/// value is read.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(into = "LawTable", from = "LawTable")]
pub enum ContactLaw {
    /// The Signorini condition, frictionless (`method = "exact"`, `friction = "none"`).
    #[default]
    Exact,
    /// The Signorini condition with a friction law (`method = "exact"` with `friction`,
    /// [`super::friction`]).
    Frictional(Friction),
    /// `R_i = penalty · max(0, −d_i)`, penalty > 0 and finite (required).
    Penalty { penalty: f64 },
    /// Nitsche with `nitsche_theta` ∈ {1, 0, −1} (default 1) and `nitsche_gamma0` > 1
    /// (default [`ContactLaw::DEFAULT_GAMMA0`]).
    Nitsche { theta: i8, gamma0: f64 },
}

/// The `[contact]` table as serde reads and writes it: `method = "exact"` carries the friction
/// keys (`friction`, `mu`, `threshold`); the scene reader has checked which go together
/// (`crate::scene`'s `parse_contact`) before this type reads them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "method", rename_all = "lowercase", deny_unknown_fields)]
enum LawTable {
    Exact {
        #[serde(default, skip_serializing_if = "FrictionName::is_none")]
        friction: FrictionName,
        #[serde(default, skip_serializing_if = "Option::is_none", deserialize_with = "coefficient_in_range")]
        mu: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none", deserialize_with = "coefficient_in_range")]
        threshold: Option<f64>,
    },
    Penalty {
        #[serde(deserialize_with = "penalty_in_range")]
        penalty: f64,
    },
    Nitsche {
        #[serde(rename = "nitsche_theta", default = "theta_default", deserialize_with = "theta_in_range")]
        theta: i8,
        #[serde(rename = "nitsche_gamma0", default = "gamma0_default", deserialize_with = "gamma0_in_range")]
        gamma0: f64,
    },
}

/// `contact.friction`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum FrictionName {
    #[default]
    None,
    Tresca,
    Coulomb,
}

impl FrictionName {
    fn is_none(&self) -> bool {
        *self == FrictionName::None
    }
}

fn coefficient_in_range<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    let x = f64::deserialize(d)?;
    if Friction::in_range(x) {
        Ok(Some(x))
    } else {
        Err(serde::de::Error::custom(format!(
            "{} is outside the allowed range {}",
            crate::numfmt::fmt_f64(x),
            Friction::RANGE
        )))
    }
}

impl From<LawTable> for ContactLaw {
    /// A coefficient the friction law does not take is ignored here and a missing one read as
    /// 0: the scene reader refuses both by name before (`crate::scene`'s `parse_contact`).
    fn from(t: LawTable) -> Self {
        match t {
            LawTable::Exact { friction: FrictionName::None, .. } => ContactLaw::Exact,
            LawTable::Exact { friction: FrictionName::Tresca, threshold, .. } => {
                ContactLaw::Frictional(Friction::Tresca { threshold: threshold.unwrap_or(0.0) })
            }
            LawTable::Exact { friction: FrictionName::Coulomb, mu, .. } => {
                ContactLaw::Frictional(Friction::Coulomb { mu: mu.unwrap_or(0.0) })
            }
            LawTable::Penalty { penalty } => ContactLaw::Penalty { penalty },
            LawTable::Nitsche { theta, gamma0 } => ContactLaw::Nitsche { theta, gamma0 },
        }
    }
}

impl From<ContactLaw> for LawTable {
    fn from(l: ContactLaw) -> Self {
        match l {
            ContactLaw::Exact => LawTable::Exact { friction: FrictionName::None, mu: None, threshold: None },
            ContactLaw::Frictional(Friction::Tresca { threshold }) => {
                LawTable::Exact { friction: FrictionName::Tresca, mu: None, threshold: Some(threshold) }
            }
            ContactLaw::Frictional(Friction::Coulomb { mu }) => {
                LawTable::Exact { friction: FrictionName::Coulomb, mu: Some(mu), threshold: None }
            }
            ContactLaw::Penalty { penalty } => LawTable::Penalty { penalty },
            ContactLaw::Nitsche { theta, gamma0 } => LawTable::Nitsche { theta, gamma0 },
        }
    }
}

fn theta_default() -> i8 {
    1
}

fn gamma0_default() -> f64 {
    ContactLaw::DEFAULT_GAMMA0
}

fn penalty_in_range<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    let p = f64::deserialize(d)?;
    ContactLaw::penalty(p).map(|_| p).map_err(serde::de::Error::custom)
}

fn theta_in_range<'de, D: Deserializer<'de>>(d: D) -> Result<i8, D::Error> {
    let t = f64::deserialize(d)?;
    match ContactLaw::nitsche(t, ContactLaw::DEFAULT_GAMMA0) {
        Ok(ContactLaw::Nitsche { theta, .. }) => Ok(theta),
        Ok(_) => unreachable!("nitsche() builds a Nitsche law"),
        Err(e) => Err(serde::de::Error::custom(e)),
    }
}

fn gamma0_in_range<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    let g = f64::deserialize(d)?;
    ContactLaw::nitsche(1.0, g).map(|_| g).map_err(serde::de::Error::custom)
}

/// How a scheme treats contact, which decides the laws it takes (the scheme declares it:
/// `crate::schemes::SchemeSpec::needs`; the law says which it is built for: [`LawNeeds`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Treatment {
    /// One implicit solve per step, `K U = r − σ Σ_c λ_c(U) e_c` with the law's λ (Newmark,
    /// Crank–Nicolson, backward Euler: generic over the law).
    ImplicitStep,
    /// The law's force of the current state on massive contact nodes and its quasi-static rows
    /// on massless ones (central differences: generic over the law).
    Explicit,
    /// The scheme's own contact treatment of the exact condition (Paoli–Schatzman's and
    /// Moreau–Jean's impact laws, the reduced scheme's `u_0 = u_1⁺`).
    Own,
    /// The hybrid scheme: its midpoint step with the law ([`ContactLaw::midpoint_law`]: the
    /// exact condition, frictionless or with friction), then its own quasi-static map Φ.
    Midpoint,
}

/// What a law needs of the scheme and the geometry (checked once, by the scene's compatibility
/// rule, `crate::scene`'s `compat`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LawNeeds {
    /// The scheme treatments it is built for.
    pub treatments: &'static [Treatment],
    /// A contact unknown whose stiffness row is one P1 cell (Nitsche's σ_n: a bar).
    pub one_cell_contact_row: bool,
    /// With [`Treatment::Explicit`]: no massless unknown beside the contact unknowns (a contact
    /// layer's free massless unknowns have no quasi-static map with this law).
    pub explicit_without_layer: bool,
    /// Tangential directions at the contact nodes (friction: a solid in 2D).
    pub tangential: bool,
}

pub use super::SetupError;

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
    pub const GAMMA0_KEY: &'static str = super::nitsche::GAMMA0_KEY;
    /// γ₀ > 1: the coercivity of Nitsche's term for θ = 1 and the monotonicity of its contact
    /// rows for every θ ([`crate::contact::nitsche`]).
    pub const GAMMA0_RANGE: &'static str = super::nitsche::GAMMA0_RANGE;
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

    /// Every law, one of each method (the penalty's value is a placeholder), in the order
    /// messages list them.
    pub const ALL: [ContactLaw; 3] = [
        ContactLaw::Exact,
        ContactLaw::Penalty { penalty: 1.0 },
        ContactLaw::Nitsche { theta: 1, gamma0: Self::DEFAULT_GAMMA0 },
    ];

    /// What the law needs (the compatibility rule reads it).
    pub const fn needs(&self) -> LawNeeds {
        use Treatment::*;
        match self {
            ContactLaw::Exact => LawNeeds {
                treatments: &[ImplicitStep, Explicit, Own, Midpoint],
                one_cell_contact_row: false,
                explicit_without_layer: false,
                tangential: false,
            },
            // The schemes that take a law in one implicit step (backward Euler,
            // Newmark/Crank–Nicolson), central differences (massive or massless tangential
            // unknowns) and the hybrid scheme's midpoint step (massive tangential unknowns).
            ContactLaw::Frictional(_) => LawNeeds {
                treatments: &[ImplicitStep, Explicit, Midpoint],
                one_cell_contact_row: false,
                explicit_without_layer: false,
                tangential: true,
            },
            ContactLaw::Penalty { .. } => LawNeeds {
                treatments: &[ImplicitStep, Explicit],
                one_cell_contact_row: false,
                explicit_without_layer: true,
                tangential: false,
            },
            ContactLaw::Nitsche { .. } => LawNeeds {
                treatments: &[ImplicitStep, Explicit],
                one_cell_contact_row: true,
                explicit_without_layer: true,
                tangential: false,
            },
        }
    }

    /// The law's implicit step on `system` for `K = k` (factored here once), the scheme's σ
    /// (`K U = r − σ Σ λ_c(U) e_c`) and its step Δt (friction's impulse).
    pub fn step_law<A: Backend>(
        &self,
        system: &ContactSystem<A>,
        k: &A,
        matrix: &'static str,
        sigma: f64,
        dt: f64,
    ) -> Result<Box<dyn StepLaw>, SetupError> {
        if let ContactLaw::Frictional(friction) = *self {
            return friction_step(system, k, friction, matrix, (sigma, dt, false));
        }
        let plain = k.contact_solver(&system.contact, matrix)?;
        Ok(match *self {
            ContactLaw::Exact => Box::new(ExactStep { solver: plain, sigma }),
            ContactLaw::Frictional(_) => unreachable!("built above"),
            ContactLaw::Penalty { penalty } => {
                Box::new(PenaltySolver::new(plain, system.n(), &system.contact, sigma, penalty)?)
            }
            ContactLaw::Nitsche { .. } => {
                Box::new(NitscheStep::new(plain, system.n(), self.nitsche_term(system)?, sigma)?)
            }
        })
    }

    /// The law in the hybrid scheme's midpoint step on `system` for `K = k = M + Δt²/4 S`
    /// (`K X̄ = r − σ Σ λ̄_c e_c`, σ = Δt²/4, for the midpoint X̄; `crate::schemes::hybrid`):
    /// the exact condition, frictionless or with friction (whose increment is twice the
    /// midpoint's, [`super::friction::FrictionStep::midpoint`]; its Coulomb bound takes the
    /// midpoint force λ̄, the time level of the scheme's contact force).
    pub fn midpoint_law<A: Backend>(
        &self,
        system: &ContactSystem<A>,
        k: &A,
        matrix: &'static str,
        sigma: f64,
        dt: f64,
    ) -> Result<Box<dyn StepLaw>, SetupError> {
        match *self {
            ContactLaw::Exact => self.step_law(system, k, matrix, sigma, dt),
            ContactLaw::Frictional(friction) => friction_step(system, k, friction, matrix, (sigma, dt, true)),
            ContactLaw::Penalty { .. } | ContactLaw::Nitsche { .. } => {
                Err(SetupError::Shape("the hybrid scheme takes the exact law, frictionless or with friction"))
            }
        }
    }

    /// The law in central differences on `system` with the lumped mass `lumped`.
    pub fn explicit_law<A: SymMatrix>(
        &self,
        system: &ContactSystem<A>,
        lumped: &[f64],
        dt: f64,
    ) -> Result<Box<dyn ExplicitLaw>, SetupError> {
        Ok(match *self {
            ContactLaw::Exact => Box::new(ExactExplicit::new(system, lumped)?),
            // The contact nodes' tangential unknowns massless (`contact_directions = "all"`
            // with w_0 = 0): the layer's quasi-static frictional problem; massive (the standard
            // mass, or `"normal"`): the forward increment, node by node.
            ContactLaw::Frictional(f) if massless_tangents(system, lumped) => {
                Box::new(super::friction::FrictionExplicit::new(system, lumped, f, dt)?)
            }
            ContactLaw::Frictional(f) => Box::new(super::friction::FrictionMassive::new(system, lumped, f)?),
            ContactLaw::Penalty { penalty } => Box::new(PenaltyExplicit::new(system, lumped, penalty)?),
            ContactLaw::Nitsche { .. } => Box::new(NitscheExplicit::new(self.nitsche_term(system)?, lumped)?),
        })
    }

    /// Nitsche's term on a system: its contact row must be one P1 cell.
    fn nitsche_term<A: SymMatrix>(&self, system: &ContactSystem<A>) -> Result<NitscheTerm, SetupError> {
        let ContactLaw::Nitsche { theta, gamma0 } = *self else {
            return Err(SetupError::Shape("not a Nitsche law"));
        };
        NitscheTerm::new(&system.stiffness, &system.contact, &system.lower, f64::from(theta), gamma0).map_err(|e| {
            match e {
                NitscheShape::Gamma0(g) => super::nitsche::gamma0_error(g, Self::GAMMA0_RANGE),
                NitscheShape::ContactCount(_) | NitscheShape::NotOneCell => {
                    SetupError::Shape("Nitsche contact needs one contact node whose stiffness row is one P1 cell")
                }
            }
        })
    }

    /// The scene name (`contact.method`).
    pub const fn method(&self) -> &'static str {
        match self {
            ContactLaw::Exact | ContactLaw::Frictional(_) => "exact",
            ContactLaw::Penalty { .. } => "penalty",
            ContactLaw::Nitsche { .. } => "nitsche",
        }
    }

    /// The friction law (None: frictionless).
    pub fn friction(&self) -> Option<Friction> {
        match *self {
            ContactLaw::Frictional(f) => Some(f),
            _ => None,
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
            ContactLaw::Penalty { penalty } => super::penalty::spring_energy(penalty, uc, lower),
            _ => 0.0,
        }
    }
}

/// The frictional step on `system` for `K = k` (`Backend::friction_step`).
fn friction_step<A: Backend>(
    system: &ContactSystem<A>,
    k: &A,
    friction: Friction,
    matrix: &'static str,
    sigma_dt_midpoint: (f64, f64, bool),
) -> Result<Box<dyn StepLaw>, SetupError> {
    let tangential =
        system.tangential.as_ref().ok_or(SetupError::Shape("friction needs a solid's tangential directions"))?;
    k.friction_step(&system.contact, tangential, friction, matrix, sigma_dt_midpoint)
}

/// Whether every tangential unknown of the contact nodes is massless (friction's quasi-static
/// rows in central differences); false without tangential unknowns.
fn massless_tangents<A>(system: &ContactSystem<A>, lumped: &[f64]) -> bool {
    let mut tangents = system.tangential.iter().flat_map(|t| t.unknowns.iter().flatten()).peekable();
    tangents.peek().is_some() && tangents.all(|&t| lumped[t] <= 0.0)
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
