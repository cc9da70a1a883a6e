//! Which geometry, mass, scheme and contact law go together: said once.
//!
//! Each geometry declares what it offers ([`Offer`], built by
//! [`super::SceneGeometry::offer`] from its table and the mass), each scheme what it needs
//! ([`SchemeSpec::needs`]), each law what it needs ([`ContactLaw::needs`]); `check` compares
//! them when a scene is validated, so the CLI (`check`, `run`) and the Python package (`load`,
//! `replace`, `check`, `run`) refuse the same scenes at the same moment, and nothing after
//! validation refuses a combination again (a scheme's constructor keeps only its guard for
//! callers of the library).
//!
//! **Which key a refusal names.** The parties rank geometry > scheme > mass > law: the
//! geometry is what is modelled, the scheme the user's main choice, the mass chosen for the
//! scheme, the law last. A conflict names the key of the lower-ranked party, with the values of
//! that key that go with the higher-ranked ones:
//! - scheme × geometry: `scheme.kind` (`scheme.formulation` for the reduced formulation), e.g.
//!   Paoli–Schatzman on a plate;
//! - scheme × mass: `mass.kind`, e.g. Moreau–Jean with mod3 (it needs w_0 > 0), hybrid with the
//!   standard mass (it needs w_0 = 0);
//! - law × anything: `contact.method`, e.g. penalty with the hybrid scheme, Nitsche on a solid.
//!
//! A scheme's own option that the geometry cannot carry names that option: `scheme.operator =
//! "matrix-free"` on a geometry without a matrix-free operator.

use super::error::{SceneError, short};
use crate::contact::law::{ContactLaw, Treatment};
use crate::mass::MassKind;
use crate::schemes::{SchemeSpec, StiffnessOperator};

/// What a geometry offers the schemes and laws, for one mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Offer {
    /// The tridiagonal one-node contact system of a bar (Paoli–Schatzman, the reduced
    /// formulation).
    pub one_node_system: bool,
    /// A lumped mass (central differences).
    pub lumped_mass: bool,
    /// The largest weight of the cells at the contact boundary: 0 iff the contact unknowns are
    /// massless (w_0 = 0).
    pub w0: f64,
    /// Massless unknowns beside the contact unknowns (a contact layer: a solid's tangential
    /// components at the contact face when w_0 = 0).
    pub contact_layer: bool,
    /// One contact unknown whose stiffness row is one P1 cell (a bar: Nitsche's σ_n).
    pub one_cell_contact_row: bool,
    /// The obstacle at gap 0.
    pub zero_gap: bool,
    /// The contact nodes massless in every direction (a solid with w_0 = 0 and
    /// `mass.contact_directions = "all"`): the hybrid scheme takes friction only on massive
    /// tangential unknowns.
    pub massless_tangents: bool,
    /// Tangential directions at a contact node (a solid's d − 1; 0 for bars and plates).
    pub tangential_dims: usize,
    /// Contact between bodies (`[[pair]]`s), not against an obstacle.
    pub pairs: bool,
    /// A matrix-free stiffness operator (a structured Q1 box's stencil, `crate::solid::stencil`;
    /// any other box or body against one obstacle, `crate::solid::kernel`):
    /// `scheme.operator = "matrix-free"`.
    pub matrix_free: bool,
    /// The contact nodes and the keys that set them, where the rule checks the size of their
    /// dense Schur complement ([`crate::spec::check_contact_memory`]) for the schemes and laws
    /// that form one: all but central differences with the exact law (forward increments on
    /// massive contact nodes, the sparse layer of `crate::contact::layer` on massless ones).
    /// None: the geometry checks it itself when it is validated.
    pub dense_contact: Option<(usize, &'static str)>,
}

/// The one compatibility rule (module docs): Ok, or the one key to change with its allowed
/// values.
/// `table` is the geometry's table (`bar`, `plate`, `solid`), for messages.
pub(crate) fn check(
    table: &str,
    offer: &Offer,
    mass: &MassKind,
    scheme: &SchemeSpec,
    law: &ContactLaw,
) -> Result<(), SceneError> {
    if let Some((contact, keys)) = offer.dense_contact
        && !(matches!(scheme, SchemeSpec::CentralDifference { .. }) && *law == ContactLaw::Exact)
    {
        super::check_contact_memory(contact, keys)?;
    }
    if let Some(why) = scheme_vs_geometry(offer, scheme) {
        let (key, value) = scheme.key_and_value();
        let allowed = if key == "scheme.kind" {
            let ok: Vec<&str> =
                SchemeSpec::ALL.iter().filter(|s| scheme_vs_geometry(offer, s).is_none()).map(|s| s.name()).collect();
            ok.join(" | ")
        } else {
            "full".into()
        };
        return Err(SceneError::Conflict {
            key,
            value: quoted(value),
            with: format!("a [{table}] scene"),
            why,
            allowed,
        });
    }
    if let SchemeSpec::CentralDifference { operator: StiffnessOperator::MatrixFree } = scheme
        && !offer.matrix_free
    {
        return Err(SceneError::Conflict {
            key: StiffnessOperator::KEY,
            value: quoted(StiffnessOperator::MatrixFree.name()),
            with: format!("a [{table}] scene"),
            why: "a matrix-free stiffness is built for boxes and for a body against one obstacle; several bodies in contact ([[pair]]) are assembled whole so far".into(),
            allowed: "auto | assembled".into(),
        });
    }
    if let Some(want) = scheme.needs().contact_mass {
        if want != (offer.w0 > 0.0) {
            let (skey, svalue) = scheme.key_and_value();
            let (why, allowed) = if want {
                (
                    format!(
                        "{svalue} needs mass at every contact node (an impact law has no meaning without inertia), this mass has w_0 = 0"
                    ),
                    "standard | custom with nonzero weights at the contact boundary",
                )
            } else {
                (
                    format!(
                        "{svalue} needs massless contact nodes (quasi-static contact rows), this mass has w_0 = {}",
                        short(offer.w0)
                    ),
                    "mod1 | mod2 | mod3 | custom with zero weights at the contact boundary",
                )
            };
            return Err(SceneError::Conflict {
                key: "mass.kind",
                value: quoted(mass.name()),
                with: format!("{skey} = \"{svalue}\" in a [{table}] scene"),
                why,
                allowed: allowed.into(),
            });
        }
    }
    if let Some(why) = friction_vs_rest(offer, scheme, law) {
        let (skey, svalue) = scheme.key_and_value();
        return Err(SceneError::Conflict {
            key: "contact.friction",
            value: quoted(law.friction().map_or("none", |f| f.name())),
            with: format!("{skey} = \"{svalue}\" in a [{table}] scene"),
            why,
            allowed: "none".into(),
        });
    }
    if let Some(why) = law_vs_rest(offer, scheme, law) {
        let ok: Vec<&str> =
            ContactLaw::ALL.iter().filter(|l| law_vs_rest(offer, scheme, l).is_none()).map(|l| l.method()).collect();
        let (skey, svalue) = scheme.key_and_value();
        return Err(SceneError::Conflict {
            key: "contact.method",
            value: quoted(law.method()),
            with: format!("{skey} = \"{svalue}\" with mass.kind = \"{}\" in a [{table}] scene", mass.name()),
            why,
            allowed: ok.join(" | "),
        });
    }
    Ok(())
}

fn quoted(s: &str) -> String {
    format!("\"{s}\"")
}

/// Why the geometry cannot carry the scheme (None: it can).
fn scheme_vs_geometry(offer: &Offer, scheme: &SchemeSpec) -> Option<String> {
    let needs = scheme.needs();
    let name = scheme.key_and_value().1;
    if needs.one_node_system && !offer.one_node_system {
        return Some(format!("{name} uses the one contact node of a bar's tridiagonal system"));
    }
    if needs.lumped_mass && !offer.lumped_mass {
        if offer.pairs {
            return Some(format!(
                "{name} needs a diagonal lumped mass, which two bodies with mass at their contact nodes do not have (a pair's change of variables couples the two sides); with mass.kind = mod1 | mod2 | mod3 it is diagonal"
            ));
        }
        return Some(format!("{name} needs a lumped mass, which this geometry does not build"));
    }
    if needs.zero_gap && !offer.zero_gap {
        return Some(format!("{name} writes u_0 = u_1⁺ for the obstacle at 0 (bar.gap = 0)"));
    }
    None
}

/// Why a friction law cannot go with the scheme on this geometry (None: it can, or no friction).
fn friction_vs_rest(offer: &Offer, scheme: &SchemeSpec, law: &ContactLaw) -> Option<String> {
    law.friction()?;
    let name = scheme.key_and_value().1;
    if offer.pairs {
        return Some(
            "friction between two bodies ([[pair]]) is not built; friction acts against rigid obstacles".into(),
        );
    }
    if offer.tangential_dims == 0 {
        return Some(
            "friction acts in the tangential directions of a solid's contact nodes; a bar or a plate has none".into(),
        );
    }
    let treatment = scheme.needs().contact;
    if !law.needs().treatments.contains(&treatment) {
        return Some(format!(
            "friction is built for the schemes that solve one implicit step with a law (backward_euler, crank_nicolson, newmark), central differences and the hybrid scheme, not for {name}"
        ));
    }
    if treatment == Treatment::Midpoint && offer.massless_tangents {
        return Some(format!(
            "{name} takes friction on massive tangential unknowns (mass.contact_directions = \"normal\"): with a contact layer massless in every direction its quasi-static map would need a frictional solve, which is not built"
        ));
    }
    None
}

/// Why the law cannot go with the scheme on this geometry and mass (None: it can).
fn law_vs_rest(offer: &Offer, scheme: &SchemeSpec, law: &ContactLaw) -> Option<String> {
    let (needs, treatment) = (law.needs(), scheme.needs().contact);
    let name = scheme.key_and_value().1;
    if !needs.treatments.contains(&treatment) {
        return Some(match treatment {
            Treatment::Own => format!("{name} treats contact itself, with the exact Signorini condition"),
            Treatment::Midpoint => {
                format!(
                    "{name} solves its midpoint step with the exact Signorini condition, frictionless or with friction"
                )
            }
            _ => format!("the {} law is not built for {name}", law.method()),
        });
    }
    if needs.one_cell_contact_row && !offer.one_cell_contact_row {
        return Some(format!(
            "the {} law needs one contact node whose stiffness row is one P1 cell (a bar; Chouly–Hild–Renard 2015)",
            law.method()
        ));
    }
    if needs.explicit_without_layer && treatment == Treatment::Explicit && offer.contact_layer {
        return Some(format!(
            "the {} law has no quasi-static map for the massless unknowns beside the contact nodes (this mass's contact layer)",
            law.method()
        ));
    }
    None
}
