//! The `[contact]` table: the contact law of every scheme of the scene
//! ([`crate::contact::law::ContactLaw`]).
//!
//! ```toml
//! [contact]                     # default: method = "exact"
//! method = "exact"              # exact | penalty | nitsche
//! penalty = 1e4                 # penalty (required): R_i = penalty * max(0, -d_i), in (0, ∞)
//! nitsche_theta = 1             # nitsche: 1 | 0 | -1 (default 1)
//! nitsche_gamma0 = 100.0        # nitsche: gamma = gamma0 * E / h, in (1, ∞) (default 100)
//! ```
//!
//! A scene without the table, or with `method = "exact"` alone, is a scene of before the table
//! existed: its resolved file does not write it.

use super::{Number, SceneError, forbid};
use crate::contact::law::ContactLaw;
use serde::{Deserialize, Serialize};

/// The `[contact]` table as read, and as resolved.
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawContact {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) method: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) penalty: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) nitsche_theta: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) nitsche_gamma0: Option<Number>,
}

/// The law of a `[contact]` table; every error names its key and allowed range.
pub(crate) fn parse_contact(raw: Option<RawContact>) -> Result<ContactLaw, SceneError> {
    let raw = raw.unwrap_or_default();
    let method = raw.method.as_deref().unwrap_or("exact");
    let law_err = |e: crate::contact::law::LawError| SceneError::Range {
        key: e.key,
        value: super::short(e.value),
        range: e.range,
    };
    let context = |m: &str| format!("contact.method = \"{m}\"");
    match method {
        "exact" => {
            forbid("contact.penalty", &raw.penalty, &context(method))?;
            forbid("contact.nitsche_theta", &raw.nitsche_theta, &context(method))?;
            forbid("contact.nitsche_gamma0", &raw.nitsche_gamma0, &context(method))?;
            Ok(ContactLaw::Exact)
        }
        "penalty" => {
            forbid("contact.nitsche_theta", &raw.nitsche_theta, &context(method))?;
            forbid("contact.nitsche_gamma0", &raw.nitsche_gamma0, &context(method))?;
            let Some(p) = raw.penalty else {
                return Err(SceneError::Missing {
                    key: "contact.penalty",
                    hint: " for contact.method = \"penalty\" (the spring stiffness per contact node, in (0, ∞))",
                });
            };
            ContactLaw::penalty(p.get()).map_err(law_err)
        }
        "nitsche" => {
            forbid("contact.penalty", &raw.penalty, &context(method))?;
            let theta = raw.nitsche_theta.map_or(1.0, Number::get);
            let gamma0 = raw.nitsche_gamma0.map_or(ContactLaw::DEFAULT_GAMMA0, Number::get);
            ContactLaw::nitsche(theta, gamma0).map_err(law_err)
        }
        other => Err(SceneError::Range {
            key: "contact.method",
            value: format!("\"{other}\""),
            range: "exact | penalty | nitsche",
        }),
    }
}

/// The resolved `[contact]` table: None for the exact law (the default; such scenes resolve as
/// before the table existed).
pub(crate) fn raw_contact(law: &ContactLaw) -> Option<RawContact> {
    let method = Some(law.method().to_string());
    match *law {
        ContactLaw::Exact => None,
        ContactLaw::Penalty { penalty } => {
            Some(RawContact { method, penalty: Some(Number::Float(penalty)), ..Default::default() })
        }
        ContactLaw::Nitsche { theta, gamma0 } => Some(RawContact {
            method,
            nitsche_theta: Some(Number::Int(theta as i64)),
            nitsche_gamma0: Some(Number::Float(gamma0)),
            ..Default::default()
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(text: &str) -> Result<ContactLaw, String> {
        let raw: RawContact = toml::from_str(text).map_err(|e| e.to_string())?;
        parse_contact(Some(raw)).map_err(|e| e.to_string())
    }

    /// Defaults, ranges and inapplicable keys, each naming its key. (Mutation: `p > 0.0` ->
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
        assert!(
            law("penalty = 3").unwrap_err().starts_with("contact.penalty does not apply to contact.method = \"exact\"")
        );
        assert_eq!(
            law("method = \"lagrange\"").unwrap_err(),
            "contact.method = \"lagrange\": allowed range is exact | penalty | nitsche"
        );
        assert!(law("gamma = 1").is_err());
        // Resolved tables read back to the same law; the exact law writes none.
        for l in [ContactLaw::Penalty { penalty: 2.5 }, ContactLaw::Nitsche { theta: -1, gamma0: 7.0 }] {
            let text = toml::to_string(&raw_contact(&l).unwrap()).unwrap();
            assert_eq!(law(&text), Ok(l), "{text}");
        }
        assert!(raw_contact(&ContactLaw::Exact).is_none());
    }
}
