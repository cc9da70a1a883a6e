//! The `[contact]` table: the contact law of every scheme of the scene
//! ([`crate::contact::law::ContactLaw`], serde internally tagged by `method`).
//!
//! ```toml
//! [contact]                     # default: method = "exact"
//! method = "exact"              # exact | penalty | nitsche
//! penalty = 1e4                 # penalty (required): R_i = penalty * max(0, -d_i), in (0, ∞)
//! nitsche_theta = 1             # nitsche: 1 | 0 | -1 (default 1)
//! nitsche_gamma0 = 100.0        # nitsche: gamma = gamma0 * E / h, in (1, ∞) (default 100)
//! ```
//!
//! A key of another method is refused naming it (`contact.nitsche_theta does not apply to
//! contact.method = "penalty"`), an unknown key as unknown: the reader of every tagged table
//! (`super::common::read_tagged`). A scene without the table, or with `method = "exact"` alone,
//! is a scene of before the table existed: its resolved file does not write it.

use super::SceneError;
use super::tagged::{RawSection, Tagged, read_tagged};
use crate::contact::law::{ContactLaw, Friction};

/// The `[contact]` table as read, and as resolved.
pub(crate) type RawContact = RawSection<ContactLaw>;

impl Tagged for ContactLaw {
    const SECTION: &'static str = "contact";
    const KIND_KEY: &'static str = "contact.method";
    const TAG: &'static str = "method";
    fn kinds() -> Vec<Self> {
        ContactLaw::ALL.to_vec()
    }
    fn default_kind() -> Self {
        ContactLaw::Exact
    }
    fn kind_name(&self) -> &'static str {
        self.method()
    }
    fn kind_list() -> &'static str {
        "exact | penalty | nitsche"
    }
    fn optional_keys(&self) -> &'static [&'static str] {
        match self {
            ContactLaw::Exact | ContactLaw::Frictional(_) => &["friction", "mu", "threshold"],
            _ => &[],
        }
    }
}

/// The law of a `[contact]` table; every error names its key and allowed range.
pub(crate) fn parse_contact(raw: Option<RawContact>) -> Result<ContactLaw, SceneError> {
    if let Some(RawSection::Read(t)) = &raw {
        check_friction_keys(t)?;
        if t.get("method").and_then(|m| m.as_str()) == Some("penalty") && !t.contains_key("penalty") {
            return Err(SceneError::Missing {
                key: ContactLaw::PENALTY_KEY,
                hint: " for contact.method = \"penalty\" (the spring stiffness per contact node, in (0, ∞))",
            });
        }
    }
    read_tagged(raw)
}

/// The law of `[contact]` (`raw`) and of the pairs' own `contact` tables (`pairs`: each pair's
/// name and table, several bodies' `pair.contact`): one law for all. Each pair's table is read
/// as `[contact]` is (its errors prefixed with the pair); pairs that name a law name the same
/// one, and `[contact]`, if given, and every pair without its own (which takes `[contact]`'s)
/// agree with it; each refusal names `pair.contact`.
pub(crate) fn pair_law(
    raw: Option<RawContact>,
    pairs: &[(String, Option<toml::Table>)],
) -> Result<ContactLaw, SceneError> {
    let given = raw.is_some();
    let contact = parse_contact(raw)?;
    let mut named: Option<(&str, ContactLaw)> = None;
    for (name, table) in pairs {
        let Some(t) = table else { continue };
        let law = parse_contact(Some(RawSection::Read(t.clone()))).map_err(|e| {
            SceneError::Parse(format!("[[pair]] \"{name}\": pair.contact (the keys of [contact]): {e}"))
        })?;
        match named {
            None => named = Some((name, law)),
            Some((first, first_law)) if first_law != law => {
                return Err(SceneError::Conflict {
                    key: "pair.contact",
                    value: format!("method = \"{}\" in pair \"{name}\"", law.method()),
                    with: format!("method = \"{}\" in pair \"{first}\"", first_law.method()),
                    why: "one contact law for every pair (a law per pair is not built yet)".into(),
                    allowed: format!("the table of pair \"{first}\""),
                });
            }
            Some(_) => {}
        }
    }
    let Some((_, law)) = named else { return Ok(contact) };
    let every = pairs.iter().all(|(_, t)| t.is_some());
    if (given || !every) && contact != law {
        return Err(SceneError::Conflict {
            key: "pair.contact",
            value: format!("method = \"{}\"", law.method()),
            with: if given {
                format!("[contact] method = \"{}\"", contact.method())
            } else {
                "a pair without its own contact, which takes [contact]'s (method = \"exact\" by default)".into()
            },
            why: "one contact law for every pair (a law per pair is not built yet)".into(),
            allowed: "the same law as [contact] (or [contact] left out and the law given in every pair)".into(),
        });
    }
    Ok(law)
}

/// Which friction keys go together (issue 29): `mu` with `friction = "coulomb"` (required
/// there), `threshold` with `friction = "tresca"` (required there), neither without friction;
/// each refusal names its key. Their ranges are checked when the table is read.
fn check_friction_keys(t: &toml::Table) -> Result<(), SceneError> {
    let method = t.get("method").and_then(|m| m.as_str()).unwrap_or("exact");
    let Some(value) = t.get("friction") else {
        for key in ["mu", "threshold"] {
            if t.contains_key(key) && method == "exact" {
                let (name, only) =
                    if key == "mu" { (Friction::MU_KEY, "coulomb") } else { (Friction::THRESHOLD_KEY, "tresca") };
                return Err(SceneError::Inapplicable {
                    key: name,
                    context: format!("contact.friction = \"none\" (the default; only to \"{only}\")"),
                });
            }
        }
        return Ok(());
    };
    if method != "exact" {
        return Ok(()); // refused by the tagged reader: friction applies to "exact" only
    }
    let name = value
        .as_str()
        .filter(|v| ["none", "tresca", "coulomb"].contains(v))
        .ok_or_else(|| SceneError::Range { key: Friction::KEY, value: value.to_string(), range: Friction::NAMES })?;
    let (wants, refuses) = match name {
        "coulomb" => (Some(("mu", Friction::MU_KEY)), [("threshold", Friction::THRESHOLD_KEY, "tresca")].as_slice()),
        "tresca" => (Some(("threshold", Friction::THRESHOLD_KEY)), [("mu", Friction::MU_KEY, "coulomb")].as_slice()),
        _ => (None, [("mu", Friction::MU_KEY, "coulomb"), ("threshold", Friction::THRESHOLD_KEY, "tresca")].as_slice()),
    };
    for &(key, full, only) in refuses {
        if t.contains_key(key) {
            return Err(SceneError::Inapplicable {
                key: full,
                context: format!("contact.friction = \"{name}\" (only to \"{only}\")"),
            });
        }
    }
    if let Some((key, full)) = wants {
        if !t.contains_key(key) {
            return Err(SceneError::Missing {
                key: full,
                hint: if key == "mu" {
                    " for contact.friction = \"coulomb\" (the friction coefficient, in [0, ∞))"
                } else {
                    " for contact.friction = \"tresca\" (the slip threshold per unit contact area, in [0, ∞))"
                },
            });
        }
    }
    Ok(())
}

/// The resolved `[contact]` table: None for the exact law (the default; such scenes resolve as
/// before the table existed).
pub(crate) fn raw_contact(law: &ContactLaw) -> Option<RawContact> {
    (*law != ContactLaw::Exact).then_some(RawSection::Resolved(*law))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(text: &str) -> Result<ContactLaw, String> {
        let raw: RawContact = toml::from_str(text).map_err(|e| e.to_string())?;
        parse_contact(Some(raw)).map_err(|e| e.to_string())
    }

    /// Defaults, ranges and keys of other methods, each naming its key. (Mutation: `p > 0.0` ->
    /// `p >= 0.0` in `ContactLaw::penalty` -> the `penalty = 0` line fails.)
    #[test]
    fn the_contact_table_names_its_keys() {
        assert_eq!(parse_contact(None).unwrap(), ContactLaw::Exact);
        assert_eq!(law("method = \"penalty\"\npenalty = 1e4"), Ok(ContactLaw::Penalty { penalty: 1e4 }));
        assert_eq!(
            law("method = \"penalty\"\npenalty = 0").unwrap_err(),
            "contact.penalty = 0: allowed range is (0, ∞)"
        );
        assert!(law("method = \"penalty\"").unwrap_err().starts_with("contact.penalty is required"));
        assert_eq!(law("method = \"nitsche\""), Ok(ContactLaw::Nitsche { theta: 1, gamma0: 100.0 }));
        assert_eq!(
            law("method = \"nitsche\"\nnitsche_theta = 2").unwrap_err(),
            "contact.nitsche_theta = 2: allowed range is 1 | 0 | -1"
        );
        assert_eq!(
            law("method = \"nitsche\"\nnitsche_gamma0 = 1").unwrap_err(),
            "contact.nitsche_gamma0 = 1: allowed range is (1, ∞)"
        );
        assert_eq!(
            law("penalty = 3").unwrap_err(),
            "contact.penalty does not apply to contact.method = \"exact\" (only to \"penalty\")"
        );
        assert_eq!(
            law("method = \"penalty\"\npenalty = 3\nnitsche_theta = 1").unwrap_err(),
            "contact.nitsche_theta does not apply to contact.method = \"penalty\" (only to \"nitsche\")"
        );
        assert_eq!(
            law("method = \"lagrange\"").unwrap_err(),
            "contact.method = \"lagrange\": allowed range is exact | penalty | nitsche"
        );
        assert!(law("gamma = 1").unwrap_err().starts_with("contact.gamma: unknown field `gamma`"));
        // Resolved tables read back to the same law; the exact law writes none.
        for l in [ContactLaw::Penalty { penalty: 2.5 }, ContactLaw::Nitsche { theta: -1, gamma0: 7.0 }] {
            let text = toml::to_string(&raw_contact(&l).unwrap()).unwrap();
            assert_eq!(law(&text), Ok(l), "{text}");
        }
        assert!(raw_contact(&ContactLaw::Exact).is_none());
    }
}
