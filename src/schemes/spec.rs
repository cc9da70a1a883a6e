//! What a scene asks of a time scheme: its kind and parameters ([`SchemeSpec`]), built into a
//! [`super::Scheme`] by [`crate::problem::Problem::scheme`].
//!
//! The `[scheme]` table of a scene is this enum, serde internally tagged by `kind`. Its names are
//! written once ([`SchemeSpec::name`]; serde spells the variants the same way, kebab-case, and a
//! test checks that both agree); the ranges of its parameters are written once, in the types
//! that hold them ([`Beta`], [`Gamma`], [`Restitution`]), and checked once, where a value of such
//! a type is built (from a scene, or from a number in code).

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use thiserror::Error;

/// A scheme parameter outside its allowed range. The message is the scenes' own
/// (`scheme.beta = 0: allowed range is (0, 1]`).
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{key} = {value}: allowed range is {range}", value = crate::numfmt::fmt_f64(*value))]
pub struct ParamError {
    pub key: &'static str,
    pub value: f64,
    pub range: &'static str,
}

/// A number in a fixed range, checked once when the value is built: `try_from` for input
/// (scenes, callers' numbers), `new` for constants in code (out of range there is a bug: a
/// compile error in a `const`, a panic otherwise). Serialised as the plain number.
macro_rules! bounded {
    ($(#[$doc:meta])* $name:ident, key = $key:literal, range = $range:literal, default = $default:expr,
     |$x:ident| $ok:expr) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
        pub struct $name(f64);

        impl $name {
            /// The scene key, for messages.
            pub const KEY: &'static str = $key;
            /// The allowed range, as messages show it.
            pub const RANGE: &'static str = $range;
            pub const DEFAULT: Self = Self::new($default);

            /// Whether `x` lies in the range: the one place it is decided.
            pub const fn contains($x: f64) -> bool {
                $x.is_finite() && $ok
            }

            /// A constant in range (see the macro's doc: out of range is a bug).
            pub const fn new(x: f64) -> Self {
                assert!(Self::contains(x), concat!($key, " outside ", $range));
                Self(x)
            }

            pub const fn get(self) -> f64 {
                self.0
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                self.0.fmt(f)
            }
        }

        impl Default for $name {
            fn default() -> Self {
                Self::DEFAULT
            }
        }

        impl TryFrom<f64> for $name {
            type Error = ParamError;
            fn try_from(x: f64) -> Result<Self, ParamError> {
                if Self::contains(x) { Ok(Self(x)) } else { Err(ParamError { key: Self::KEY, value: x, range: Self::RANGE }) }
            }
        }

        impl Serialize for $name {
            fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_f64(self.0)
            }
        }

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                // serde's f64 accepts integers (`beta = 1`) as the scenes' numbers do.
                let x = f64::deserialize(d)?;
                Self::try_from(x).map_err(serde::de::Error::custom)
            }
        }
    };
}

bounded!(
    /// Newmark's β in (0, 1] (paper eq. (4.4); β > 0 keeps `M + β Δt² S` definite with M
    /// singular). Default ¼ (with γ = ½: Crank–Nicolson).
    Beta, key = "scheme.beta", range = "(0, 1]", default = 0.25, |b| b > 0.0 && b <= 1.0
);
bounded!(
    /// Newmark's γ in [0, 1] (paper eq. (4.4)). Default ½.
    Gamma, key = "scheme.gamma", range = "[0, 1]", default = 0.5, |g| g >= 0.0 && g <= 1.0
);
bounded!(
    /// Paoli–Schatzman's restitution coefficient e in [0, 1] (paper §5: the impact law
    /// `u_0^{n+1} + e u_0^{n−1}`). Default 1 (elastic impact).
    Restitution, key = "scheme.restitution", range = "[0, 1]", default = 1.0, |e| e >= 0.0 && e <= 1.0
);

bounded!(
    /// Moreau–Jean's θ in [½, 1] (Jean 1999: the θ-method on the velocities; ½ is second order
    /// and conserves the energy without contact, 1 is first order and dissipative). Default ½.
    Theta, key = "scheme.theta", range = "[0.5, 1]", default = 0.5, |t| t >= 0.5 && t <= 1.0
);
bounded!(
    /// Moreau–Jean's restitution coefficient e in [0, 1] (Newton's impact law on the contact
    /// velocities, `v_n^{n+1} + e v_nⁿ ≥ 0`). Default 0 (inelastic impact, as Siconos's default).
    ImpactRestitution, key = "scheme.restitution", range = "[0, 1]", default = 0.0, |e| e >= 0.0 && e <= 1.0
);

/// Which form of Newmark to solve: the full m-unknown system with the contact multiplier, or the
/// reduced (P^mod_U) system of a massless contact node.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Formulation {
    #[default]
    Full,
    Reduced,
}

impl Formulation {
    /// Every formulation, in the order messages list them.
    pub const ALL: [Formulation; 2] = [Formulation::Full, Formulation::Reduced];
    pub const KEY: &'static str = "scheme.formulation";

    /// The scene name: the one list of formulation names.
    pub const fn name(self) -> &'static str {
        match self {
            Formulation::Full => "full",
            Formulation::Reduced => "reduced",
        }
    }
}

impl Serialize for Formulation {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Formulation {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        Formulation::ALL.into_iter().find(|f| f.name() == name).ok_or_else(|| {
            let list: Vec<&str> = Formulation::ALL.iter().map(|f| f.name()).collect();
            serde::de::Error::custom(format!("{} = \"{name}\": allowed range is {}", Self::KEY, list.join(" | ")))
        })
    }
}

/// How central differences apply the stiffness (`scheme.operator`, issue 31): `auto` (the
/// default) matrix-free where the geometry has a matrix-free operator (a structured Q1 box:
/// [`crate::solid::stencil`]; any other box or body against one obstacle:
/// [`crate::solid::kernel`]), else the assembled matrix; `assembled` always the matrix;
/// `matrix-free` the operator, refused by name on a geometry without one. Only the product K u
/// changes: the lumped mass, the quasi-static contact layer, the law and the stable limit are
/// the same.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StiffnessOperator {
    #[default]
    Auto,
    Assembled,
    MatrixFree,
}

impl StiffnessOperator {
    /// Every choice, in the order messages list them.
    pub const ALL: [StiffnessOperator; 3] =
        [StiffnessOperator::Auto, StiffnessOperator::Assembled, StiffnessOperator::MatrixFree];
    pub const KEY: &'static str = "scheme.operator";

    /// The scene name: the one list of operator names.
    pub const fn name(self) -> &'static str {
        match self {
            StiffnessOperator::Auto => "auto",
            StiffnessOperator::Assembled => "assembled",
            StiffnessOperator::MatrixFree => "matrix-free",
        }
    }
}

impl Serialize for StiffnessOperator {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for StiffnessOperator {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        StiffnessOperator::ALL.into_iter().find(|f| f.name() == name).ok_or_else(|| {
            let list: Vec<&str> = StiffnessOperator::ALL.iter().map(|f| f.name()).collect();
            serde::de::Error::custom(format!("{} = \"{name}\": allowed range is {}", Self::KEY, list.join(" | ")))
        })
    }
}

/// A time scheme and its parameters: the `[scheme]` table, tagged by `kind`. A missing key takes
/// its default (the serde defaults below, those of the parameter types).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum SchemeSpec {
    CrankNicolson {
        #[serde(default)]
        formulation: Formulation,
    },
    Newmark {
        #[serde(default)]
        beta: Beta,
        #[serde(default)]
        gamma: Gamma,
        #[serde(default)]
        formulation: Formulation,
    },
    /// (serde ignores unknown keys of unit variants even with `deny_unknown_fields`: the scenes
    /// refuse them before, from the keys each kind writes.)
    BackwardEuler,
    PaoliSchatzman {
        #[serde(default)]
        beta: Beta,
        #[serde(default)]
        restitution: Restitution,
    },
    Hybrid,
    /// Explicit central differences on the lumped weighted mass, with quasi-static massless
    /// unknowns (`super::central_difference`).
    CentralDifference {
        #[serde(default)]
        operator: StiffnessOperator,
    },
    /// Moreau–Jean's θ-scheme with an impact law on the velocities (`super::moreau_jean`).
    MoreauJean {
        #[serde(default)]
        theta: Theta,
        #[serde(default)]
        restitution: ImpactRestitution,
    },
}

impl SchemeSpec {
    /// Crank–Nicolson, full formulation: the scenes' default scheme.
    pub const CRANK_NICOLSON: SchemeSpec = SchemeSpec::CrankNicolson { formulation: Formulation::Full };
    /// Newmark with its default (β, γ) = (¼, ½).
    pub const NEWMARK: SchemeSpec =
        SchemeSpec::Newmark { beta: Beta::DEFAULT, gamma: Gamma::DEFAULT, formulation: Formulation::Full };
    /// Paoli–Schatzman with its default β = ¼, e = 1.
    pub const PAOLI_SCHATZMAN: SchemeSpec =
        SchemeSpec::PaoliSchatzman { beta: Beta::DEFAULT, restitution: Restitution::DEFAULT };
    /// Central differences with its default operator (`auto`).
    pub const CENTRAL_DIFFERENCE: SchemeSpec = SchemeSpec::CentralDifference { operator: StiffnessOperator::Auto };
    /// Moreau–Jean with its default θ = ½, e = 0.
    pub const MOREAU_JEAN: SchemeSpec =
        SchemeSpec::MoreauJean { theta: Theta::DEFAULT, restitution: ImpactRestitution::DEFAULT };
    /// One scheme of every kind with its defaults, in the order messages list them.
    pub const ALL: [SchemeSpec; 7] = [
        SchemeSpec::CRANK_NICOLSON,
        SchemeSpec::NEWMARK,
        SchemeSpec::BackwardEuler,
        SchemeSpec::PAOLI_SCHATZMAN,
        SchemeSpec::Hybrid,
        SchemeSpec::CENTRAL_DIFFERENCE,
        SchemeSpec::MOREAU_JEAN,
    ];

    /// The scene name (`scheme.kind`): the one list of scheme names.
    pub const fn name(&self) -> &'static str {
        match self {
            SchemeSpec::CrankNicolson { .. } => "crank-nicolson",
            SchemeSpec::Newmark { .. } => "newmark",
            SchemeSpec::BackwardEuler => "backward-euler",
            SchemeSpec::PaoliSchatzman { .. } => "paoli-schatzman",
            SchemeSpec::Hybrid => "hybrid",
            SchemeSpec::CentralDifference { .. } => "central-difference",
            SchemeSpec::MoreauJean { .. } => "moreau-jean",
        }
    }

    /// The scheme of kind `name` with its defaults.
    pub fn from_name(name: &str) -> Option<SchemeSpec> {
        SchemeSpec::ALL.into_iter().find(|s| s.name() == name)
    }

    /// What the scheme needs of the geometry, the mass and the contact law: declared here once,
    /// checked once by the scene's compatibility rule (`crate::scene`'s `compat`).
    pub const fn needs(&self) -> SchemeNeeds {
        use crate::contact::law::Treatment::*;
        let base = SchemeNeeds {
            one_node_system: false,
            lumped_mass: false,
            contact_mass: None,
            zero_gap: false,
            contact: ImplicitStep,
        };
        match self {
            SchemeSpec::CrankNicolson { formulation: Formulation::Full }
            | SchemeSpec::Newmark { formulation: Formulation::Full, .. }
            | SchemeSpec::BackwardEuler => base,
            // The reduced unknowns 1..m−1 of the bar's tridiagonal system, u_0 = u_1⁺.
            SchemeSpec::CrankNicolson { formulation: Formulation::Reduced }
            | SchemeSpec::Newmark { formulation: Formulation::Reduced, .. } => {
                SchemeNeeds { one_node_system: true, contact_mass: Some(false), zero_gap: true, contact: Own, ..base }
            }
            // Its projection of S on (ker M)^⊥ and its one-node impact law.
            SchemeSpec::PaoliSchatzman { .. } => SchemeNeeds { one_node_system: true, contact: Own, ..base },
            SchemeSpec::Hybrid => SchemeNeeds { contact_mass: Some(false), contact: Midpoint, ..base },
            SchemeSpec::CentralDifference { .. } => SchemeNeeds { lumped_mass: true, contact: Explicit, ..base },
            // An impact law has no meaning without inertia.
            SchemeSpec::MoreauJean { .. } => SchemeNeeds { contact_mass: Some(true), contact: Own, ..base },
        }
    }

    /// The key a conflict with the geometry names, and its value: `scheme.formulation` for the
    /// reduced formulation (its kind works in full form), `scheme.kind` otherwise.
    pub fn key_and_value(&self) -> (&'static str, &'static str) {
        match self {
            SchemeSpec::CrankNicolson { formulation: Formulation::Reduced }
            | SchemeSpec::Newmark { formulation: Formulation::Reduced, .. } => {
                (Formulation::KEY, Formulation::Reduced.name())
            }
            _ => ("scheme.kind", self.name()),
        }
    }
}

/// What a scheme needs ([`SchemeSpec::needs`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SchemeNeeds {
    /// The bar's tridiagonal one-node contact system ([`super::OneNodeContact`]).
    pub one_node_system: bool,
    /// A lumped mass (explicit schemes).
    pub lumped_mass: bool,
    /// `Some(true)`: mass at every contact node (w_0 > 0); `Some(false)`: massless contact
    /// nodes (w_0 = 0); None: either.
    pub contact_mass: Option<bool>,
    /// The obstacle at gap 0 (`bar.gap = 0`).
    pub zero_gap: bool,
    /// How it treats contact (which laws it takes).
    pub contact: crate::contact::law::Treatment,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// serde's spelling of every kind (kebab-case of the variant) is [`SchemeSpec::name`], and a
    /// table with only `kind` gives the defaults of [`SchemeSpec::ALL`]. (Mutation:
    /// `#[serde(rename = "paoli-schatzmann")]` on that variant -> fails at its kind.)
    #[test]
    fn serde_names_are_the_written_names() {
        for spec in SchemeSpec::ALL {
            let table = toml::Table::try_from(spec).unwrap();
            assert_eq!(table["kind"].as_str(), Some(spec.name()));
            let back: SchemeSpec = toml::from_str(&format!("kind = \"{}\"", spec.name())).expect(spec.name());
            assert_eq!(back, spec, "{}", spec.name());
        }
        assert_eq!(SchemeSpec::from_name("newmark"), Some(SchemeSpec::NEWMARK));
        assert_eq!(SchemeSpec::from_name("euler"), None);
    }

    #[test]
    fn ranges_are_checked_where_the_values_are_built() {
        assert_eq!(Beta::try_from(1.0).map(Beta::get), Ok(1.0));
        let e = Beta::try_from(0.0).unwrap_err();
        assert_eq!(e.to_string(), "scheme.beta = 0: allowed range is (0, 1]");
        assert!(Beta::try_from(f64::NAN).is_err() && Gamma::try_from(1.5).is_err());
        assert_eq!(Gamma::try_from(0.0).map(Gamma::get), Ok(0.0));
        assert!(Restitution::try_from(-0.1).is_err() && Restitution::try_from(0.0).is_ok());
        assert!(Theta::try_from(0.49).is_err() && Theta::try_from(1.01).is_err() && Theta::try_from(0.5).is_ok());
        assert!(ImpactRestitution::try_from(1.5).is_err() && ImpactRestitution::DEFAULT.get() == 0.0);
        let e = toml::from_str::<SchemeSpec>("kind = \"moreau-jean\"\ntheta = 0.4").unwrap_err();
        assert_eq!(e.message(), "scheme.theta = 0.4: allowed range is [0.5, 1]");
        let s: SchemeSpec = toml::from_str("kind = \"moreau-jean\"\ntheta = 1\nrestitution = 0.5").unwrap();
        assert_eq!(s, SchemeSpec::MoreauJean { theta: Theta::new(1.0), restitution: ImpactRestitution::new(0.5) });
        // From a table: the same message, integers accepted.
        let e = toml::from_str::<SchemeSpec>("kind = \"newmark\"\nbeta = 0").unwrap_err();
        assert_eq!(e.message(), "scheme.beta = 0: allowed range is (0, 1]");
        let s: SchemeSpec = toml::from_str("kind = \"newmark\"\nbeta = 1\ngamma = 0.6").unwrap();
        assert_eq!(
            s,
            SchemeSpec::Newmark { beta: Beta::new(1.0), gamma: Gamma::new(0.6), formulation: Formulation::Full }
        );
        let e = toml::from_str::<SchemeSpec>("kind = \"newmark\"\nformulation = \"half\"").unwrap_err();
        assert_eq!(e.message(), "scheme.formulation = \"half\": allowed range is full | reduced");
    }
}
