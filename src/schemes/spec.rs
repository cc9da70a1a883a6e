//! What a scene asks of a time scheme: its kind and parameters ([`SchemeSpec`]), built into a
//! [`super::Scheme`] by [`crate::problem::Problem::scheme`].

/// Which form of Newmark to solve: the full m-unknown system with the contact multiplier, or the
/// reduced (P^mod_U) system of a massless contact node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Formulation {
    Full,
    Reduced,
}

#[derive(Debug, Clone, PartialEq)]
pub enum SchemeSpec {
    CrankNicolson { formulation: Formulation },
    Newmark { beta: f64, gamma: f64, formulation: Formulation },
    BackwardEuler,
    PaoliSchatzman { beta: f64, restitution: f64 },
    Hybrid,
}

impl SchemeSpec {
    /// Why other geometries reject this scheme, if it is bar-only (Paoli–Schatzman and the
    /// reduced Newmark formulation use the bar's one contact node): the scene key and the reason.
    /// The one place that decides it, for scenes (`crate::scene::validate_sections`) and problems
    /// ([`crate::problem::Problem::scheme`]) alike.
    pub fn bar_only(&self) -> Option<(&'static str, &'static str)> {
        const WHY: &str = "a bar-only scheme (it uses the bar's one contact node); use crank-nicolson, newmark, backward-euler or hybrid";
        match self {
            SchemeSpec::PaoliSchatzman { .. } => Some(("scheme.kind = \"paoli-schatzman\"", WHY)),
            SchemeSpec::CrankNicolson { formulation: Formulation::Reduced }
            | SchemeSpec::Newmark { formulation: Formulation::Reduced, .. } => {
                Some(("scheme.formulation = \"reduced\"", WHY))
            }
            _ => None,
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            SchemeSpec::CrankNicolson { .. } => "crank-nicolson",
            SchemeSpec::Newmark { .. } => "newmark",
            SchemeSpec::BackwardEuler => "backward-euler",
            SchemeSpec::PaoliSchatzman { .. } => "paoli-schatzman",
            SchemeSpec::Hybrid => "hybrid",
        }
    }
}
