//! The reader of every tagged table (`[scheme]` and `[mass]` by `kind`, `[contact]` by
//! `method`): the kind first, then its keys (a key of another kind refused naming it, an
//! unknown one as unknown), then the value by serde, every message naming its key.

use super::SceneError;
use serde::{Deserialize, Serialize};

/// A section that is a serde internally tagged enum (`kind = "…"`): as read, the TOML table
/// (validated by [`read_tagged`], whose messages name the key); as resolved, the value itself
/// (serde writes every key of its kind).
#[derive(Debug)]
pub(crate) enum RawSection<T> {
    Read(toml::Table),
    Resolved(T),
}

impl<'de, T> Deserialize<'de> for RawSection<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        toml::Table::deserialize(d).map(RawSection::Read)
    }
}

impl<T: Serialize> Serialize for RawSection<T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            RawSection::Read(t) => t.serialize(s),
            RawSection::Resolved(v) => v.serialize(s),
        }
    }
}

/// A section read by [`read_tagged`]: a serde internally tagged enum with one value of each kind
/// (its defaults) and a name per kind.
pub(crate) trait Tagged: Serialize + serde::de::DeserializeOwned + Sized {
    /// The section (`scheme`), and its tag key (`scheme.kind`).
    const SECTION: &'static str;
    const KIND_KEY: &'static str;
    /// The tag key inside the table (`kind`; `[contact]`'s is `method`).
    const TAG: &'static str = "kind";
    /// One value of every kind, in the order messages list them.
    fn kinds() -> Vec<Self>;
    /// The kind of a section without `kind`.
    fn default_kind() -> Self;
    fn kind_name(&self) -> &'static str;
    /// The kinds as messages list them (`standard | mod1 | …`).
    fn kind_list() -> &'static str;
    /// Keys a value of this kind may have beside those it writes (optional keys its resolved
    /// form leaves out: `[contact]`'s friction keys on `method = "exact"`).
    fn optional_keys(&self) -> &'static [&'static str] {
        &[]
    }
}

pub(crate) fn list_of<T: Tagged>() -> String {
    T::kinds().iter().map(T::kind_name).collect::<Vec<_>>().join(" | ")
}

/// The keys a value writes (its kind's keys: the resolved scene writes every key).
fn keys_of<T: Tagged>(value: &T) -> Vec<String> {
    let mut keys: Vec<String> = toml::Table::try_from(value).map(|t| t.keys().cloned().collect()).unwrap_or_default();
    for k in value.optional_keys() {
        if !keys.iter().any(|x| x == k) {
            keys.push((*k).to_string());
        }
    }
    keys
}

/// Reads a tagged section: its kind (default [`Tagged::default_kind`]), then its keys (those of
/// another kind refused as not applying to this one, unknown ones as unknown), then the value by
/// serde (parameter ranges checked by their types). Every message names the key and its allowed
/// range or values.
pub(crate) fn read_tagged<T: Tagged>(raw: Option<RawSection<T>>) -> Result<T, SceneError> {
    let mut table = match raw {
        None => toml::Table::new(),
        Some(RawSection::Read(t)) => t,
        Some(RawSection::Resolved(v)) => return Ok(v),
    };
    let section = T::SECTION;
    let tag = T::TAG;
    let kind = match table.get(tag) {
        None => T::default_kind(),
        Some(v) => T::kinds()
            .into_iter()
            .find(|k| v.as_str() == Some(k.kind_name()))
            .ok_or_else(|| SceneError::Range { key: T::KIND_KEY, value: v.to_string(), range: T::kind_list() })?,
    };
    let name = kind.kind_name();
    let own = keys_of(&kind);
    let kinds = T::kinds();
    let mut all: Vec<String> = vec![tag.into()];
    for k in kinds.iter().flat_map(keys_of) {
        if !all.contains(&k) {
            all.push(k);
        }
    }
    for key in table.keys().filter(|k| !own.contains(k)) {
        if !all.contains(key) {
            return Err(SceneError::Parse(format!(
                "{section}.{key}: unknown field `{key}` in [{section}], expected one of {}",
                all.join(", ")
            )));
        }
        let takers: Vec<String> =
            kinds.iter().filter(|k| keys_of(*k).contains(key)).map(|k| format!("\"{}\"", k.kind_name())).collect();
        return Err(SceneError::Parse(format!(
            "{section}.{key} does not apply to {} = \"{name}\" (only to {})",
            T::KIND_KEY,
            takers.join(" | ")
        )));
    }
    table.insert(tag.into(), toml::Value::String(name.into()));
    toml::Value::Table(table.clone()).try_into::<T>().map_err(|e| {
        // The key at fault: the first whose value alone, on the kind's defaults, fails.
        let defaults = toml::Table::try_from(&kind).unwrap_or_default();
        let culprit = table.iter().filter(|(k, _)| *k != tag).find(|(k, v)| {
            let mut one = defaults.clone();
            one.insert((*k).clone(), (*v).clone());
            toml::Value::Table(one).try_into::<T>().is_err()
        });
        let message = e.message().trim_end().to_string();
        match culprit {
            Some((k, _)) if !message.starts_with(&format!("{section}.{k}")) => {
                SceneError::Parse(format!("{section}.{k}: {message}"))
            }
            _ => SceneError::Parse(message),
        }
    })
}
