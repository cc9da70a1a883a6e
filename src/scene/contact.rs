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
use crate::contact::law::ContactLaw;

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
}

/// The law of a `[contact]` table; every error names its key and allowed range.
pub(crate) fn parse_contact(raw: Option<RawContact>) -> Result<ContactLaw, SceneError> {
    if let Some(RawSection::Read(t)) = &raw {
        if t.get("method").and_then(|m| m.as_str()) == Some("penalty") && !t.contains_key("penalty") {
            return Err(SceneError::Missing {
                key: ContactLaw::PENALTY_KEY,
                hint: " for contact.method = \"penalty\" (the spring stiffness per contact node, in (0, ∞))",
            });
        }
    }
    read_tagged(raw)
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
