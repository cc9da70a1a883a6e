//! The sections every scene shares: `[mass]`, `[scheme]`, `[time]` (and the output's
//! divergence factor): raw tables, validation, and the resolved form.

use super::tagged::{RawSection, Tagged, list_of, read_tagged};
use super::*;
use crate::mass::{ContactDirections, MassKind};
use serde::{Deserialize, Serialize};

/// The `[mass]` table: read as a TOML table ([`read_tagged`]), written as the resolved
/// [`MassKind`].
pub(crate) type RawMass = RawSection<MassKind>;

/// The `[scheme]` table: read as a TOML table ([`read_tagged`]), written as the resolved
/// [`SchemeSpec`].
pub(crate) type RawScheme = RawSection<SchemeSpec>;

impl Tagged for SchemeSpec {
    const SECTION: &'static str = "scheme";
    const KIND_KEY: &'static str = "scheme.kind";
    fn kinds() -> Vec<Self> {
        SchemeSpec::ALL.to_vec()
    }
    fn default_kind() -> Self {
        SchemeSpec::CRANK_NICOLSON
    }
    fn kind_name(&self) -> &'static str {
        self.name()
    }
    fn kind_list() -> &'static str {
        static LIST: std::sync::LazyLock<String> = std::sync::LazyLock::new(|| list_of::<SchemeSpec>());
        &LIST
    }
}

impl Tagged for MassKind {
    const SECTION: &'static str = "mass";
    const KIND_KEY: &'static str = "mass.kind";
    fn kinds() -> Vec<Self> {
        MassKind::all().to_vec()
    }
    fn default_kind() -> Self {
        MassKind::Mod3
    }
    fn kind_name(&self) -> &'static str {
        self.name()
    }
    fn kind_list() -> &'static str {
        static LIST: std::sync::LazyLock<String> = std::sync::LazyLock::new(|| list_of::<MassKind>());
        &LIST
    }
    /// Read by [`parse_mass`] beside the kind (listed in the unknown-key message).
    fn optional_keys(&self) -> &'static [&'static str] {
        &["contact_directions"]
    }
}

/// The `[mass]` table as a [`MassKind`] (its weights are validated by the caller, who knows the
/// mesh) and its `contact_directions` (default `all`).
pub(crate) fn parse_mass(raw: Option<RawMass>) -> Result<(MassKind, ContactDirections), SceneError> {
    let mut directions = ContactDirections::All;
    let mut raw = raw;
    if let Some(RawSection::Read(t)) = &mut raw {
        let custom = MassKind::Custom(Vec::new());
        if t.get("kind").and_then(|k| k.as_str()) == Some(custom.name()) && !t.contains_key("weights") {
            return Err(SceneError::Missing {
                key: "mass.weights",
                hint: " for mass.kind = \"custom\" (one weight >= 0 per element, element 0 at the contact node)",
            });
        }
        if let Some(v) = t.remove("contact_directions") {
            directions = [ContactDirections::All, ContactDirections::Normal]
                .into_iter()
                .find(|d| v.as_str() == Some(d.name()))
                .ok_or_else(|| SceneError::Range {
                    key: "mass.contact_directions",
                    value: v.to_string(),
                    range: "all | normal",
                })?;
        }
    }
    Ok((read_tagged(raw)?, directions))
}

/// The `[scheme]` table (what goes with the geometry and the mass is the compatibility rule's:
/// [`crate::spec::compat`]).
pub(crate) fn parse_scheme(raw: Option<RawScheme>) -> Result<SchemeSpec, SceneError> {
    read_tagged(raw)
}

/// The `[time]` table (shared with the plate scenes).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTime {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) dt: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) end: Option<Number>,
}

/// The `[time]` table; `default_end` is used without `time.end`, `elements` (the unknowns per
/// step, set by the keys `size`) bounds the work.
pub(crate) fn parse_time(
    raw: Option<RawTime>,
    default_end: f64,
    elements: usize,
    size: &'static str,
) -> Result<TimeSpec, SceneError> {
    let t = raw.unwrap_or_default();
    let dt = t.dt.map_or(0.01, Number::get);
    let end = t.end.map_or(default_end, Number::get);
    finite_in("time.dt", dt, dt > 0.0, "(0, ∞)")?;
    finite_in("time.end", end, end > 0.0, "(0, ∞)")?;
    let ratio = end / dt;
    if !(ratio <= 1e15) {
        return Err(SceneError::TooMuchWork { work: ratio * elements as f64, limit: MAX_NODE_STEPS, size });
    }
    let steps = ratio.round();
    if steps < 1.0 || (steps - ratio).abs() > 1e-9 * ratio {
        return Err(SceneError::NotAnInteger { end, dt, ratio });
    }
    let work = steps * elements as f64;
    if work > MAX_NODE_STEPS {
        return Err(SceneError::TooMuchWork { work, limit: MAX_NODE_STEPS, size });
    }
    let time = TimeSpec { dt, end, steps: steps as usize };
    Ok(time)
}

/// `output.divergence_factor` (shared with the plate scenes): in (1, ∞), default
/// [`DEFAULT_DIVERGENCE_FACTOR`].
pub(crate) fn parse_divergence_factor(raw: Option<Number>) -> Result<f64, SceneError> {
    let factor = raw.map_or(DEFAULT_DIVERGENCE_FACTOR, Number::get);
    finite_in("output.divergence_factor", factor, factor > 1.0, "(1, ∞)")
}

/// The resolved `[mass]`, `[scheme]`, `[time]` and `[output]` tables of any scene (`plate`:
/// write the VTU keys).
pub(crate) fn raw_sections(
    mass: &MassKind,
    directions: ContactDirections,
    scheme: &SchemeSpec,
    time: &TimeSpec,
    output: &OutputSpec,
    plate: bool,
) -> (Option<RawMass>, Option<RawScheme>, Option<RawTime>, Option<RawOutput>) {
    let vtu = plate.then_some(output.vtu_every);
    let out = RawOutput::resolved(&output.series, output.every, output.summary_l2, vtu, output.divergence_factor);
    (Some(raw_mass(mass, directions)), Some(raw_scheme(scheme)), Some(raw_time(time)), Some(out))
}

/// The resolved `[mass]` table of a mass redistribution (`contact_directions` written where it
/// is not the default, so that the resolved scenes of the default read as before).
pub(crate) fn raw_mass(mass: &MassKind, directions: ContactDirections) -> RawMass {
    match directions {
        ContactDirections::All => RawSection::Resolved(mass.clone()),
        ContactDirections::Normal => {
            let mut table = toml::Table::try_from(mass).expect("a mass kind always serialises");
            table.insert("contact_directions".into(), directions.name().into());
            RawSection::Read(table)
        }
    }
}

/// The resolved `[scheme]` table of a scheme.
pub(crate) fn raw_scheme(scheme: &SchemeSpec) -> RawScheme {
    RawSection::Resolved(*scheme)
}

/// The resolved `[time]` table.
pub(crate) fn raw_time(time: &TimeSpec) -> RawTime {
    RawTime { dt: Some(Number::Float(time.dt)), end: Some(Number::Float(time.end)) }
}

/// `output.series`: known columns of the geometry (`allowed`, listed in `range`), each once.
pub(crate) fn parse_series(
    names: Vec<String>,
    allowed: &[Column],
    range: &'static str,
    named: impl Fn(&str) -> Option<Column>,
) -> Result<Vec<Column>, SceneError> {
    let mut series = Vec::new();
    for name in names {
        let col = allowed
            .iter()
            .copied()
            .find(|c| c.name() == name)
            .or_else(|| named(&name))
            .ok_or_else(|| SceneError::Range { key: "output.series", value: format!("\"{name}\""), range })?;
        if series.contains(&col) {
            return Err(SceneError::DuplicateColumn(name));
        }
        series.push(col);
    }
    Ok(series)
}

/// `output.every` (≥ 1), with the size limit of the recorded series for every geometry:
/// `(steps/every + 1)(columns + 1)` values at most [`MAX_SERIES_VALUES`] (its reason there).
pub(crate) fn parse_every(raw: Option<i64>, steps: usize, columns: usize) -> Result<usize, SceneError> {
    let every = raw.unwrap_or(1);
    if every < 1 {
        return Err(SceneError::Range { key: "output.every", value: every.to_string(), range: "integers >= 1" });
    }
    let every = every as usize;
    let values = ((steps / every + 1) * (columns + 1)) as f64;
    if columns > 0 && values > MAX_SERIES_VALUES {
        let min_every = (steps as f64 * (columns + 1) as f64 / MAX_SERIES_VALUES).ceil() as usize;
        return Err(SceneError::TooManyValues { values, limit: MAX_SERIES_VALUES, every: min_every });
    }
    Ok(every)
}

/// The `[output]` table of every scene (bars ignore nothing: they refuse the VTU keys).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOutput {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) series: Option<Vec<String>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) every: Option<i64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) summary_l2: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) vtu: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) vtu_every: Option<i64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) divergence_factor: Option<Number>,
}

impl RawOutput {
    /// The resolved table; `vtu_every` is `Some(frames)` for a plate (None: no VTU key written
    /// for bars, `vtu = false` for plates without frames is written by the caller).
    pub(crate) fn resolved(
        series: &[Column],
        every: usize,
        summary_l2: bool,
        vtu_every: Option<Option<usize>>,
        divergence_factor: f64,
    ) -> Self {
        RawOutput {
            series: Some(series.iter().map(|c| c.name().to_string()).collect()),
            every: Some(every as i64),
            summary_l2: Some(summary_l2),
            vtu: vtu_every.map(|k| k.is_some()),
            vtu_every: vtu_every.flatten().map(|k| k as i64),
            divergence_factor: Some(Number::Float(divergence_factor)),
        }
    }
}

/// The sections every scene shares, validated on its geometry: `[mass]` (weights checked on the
/// mesh), `[scheme]` and `[contact]` (with the geometry and the mass: the one compatibility rule,
/// [`crate::spec::compat::check`]),
/// `[time]` (the work limit over the geometry's unknowns) and `[output]` (the geometry's columns,
/// those its exact solution allows, VTU frames where the geometry writes them).
pub(crate) fn validate_sections<G: SceneGeometry>(geometry: G, raw: RawScene) -> Result<Scene<G>, SceneError> {
    let (mass, contact_directions) = parse_mass(raw.mass)?;
    let mut offer = geometry.offer(&mass)?;
    let scheme = parse_scheme(raw.scheme)?;
    let contact = super::contact::pair_law(raw.contact, &geometry.pair_laws())?;
    if contact_directions == ContactDirections::Normal {
        if offer.pairs {
            return Err(SceneError::Conflict {
                key: "mass.contact_directions",
                value: "\"normal\"".into(),
                with: format!("several [[{}]] bodies", G::TABLE),
                why: "the normal direction of the layer's inner nodes is not defined between two bodies".into(),
                allowed: "all".into(),
            });
        }
        if offer.tangential_dims == 0 {
            return Err(SceneError::Conflict {
                key: "mass.contact_directions",
                value: "\"normal\"".into(),
                with: format!("a [{}] scene", G::TABLE),
                why: "a bar's or a plate's contact node has only the normal direction".into(),
                allowed: "all".into(),
            });
        }
        // The tangential components keep their mass: no massless unknown beside the contact
        // rows but the normal components of the layer's inner nodes (P2's edge nodes).
        offer.contact_layer = offer.contact_layer && geometry.massless_inner_nodes(&mass)?;
        offer.massless_tangents = false;
    }
    crate::spec::compat::check(G::TABLE, &offer, &mass, &scheme, &contact)?;
    let time = parse_time(raw.time, 3.0 * geometry.length(), geometry.unknowns(), geometry.size_keys())?;
    let o = raw.output.unwrap_or_default();
    let series = match o.series {
        Some(names) => parse_series(names, G::COLUMNS, G::COLUMN_LIST, |n| geometry.named_column(n))?,
        None => geometry.default_series(),
    };
    if let Some((column, why)) = series.iter().find_map(|&c| geometry.unavailable(c).map(|why| (c, why))) {
        return Err(SceneError::Inapplicable {
            key: "output.series",
            context: format!("column \"{}\" of this scene: {why}", column.name()),
        });
    }
    let every = parse_every(o.every, time.steps, series.len())?;
    let vtu_every = if !G::VTU {
        let context = format!("[{}] scenes (VTU frames are written for plates)", G::TABLE);
        forbid("output.vtu", &o.vtu, &context)?;
        forbid("output.vtu_every", &o.vtu_every, &context)?;
        None
    } else if o.vtu.unwrap_or(false) {
        let k = o.vtu_every.unwrap_or(10);
        if k < 1 {
            return Err(SceneError::Range { key: "output.vtu_every", value: k.to_string(), range: "integers >= 1" });
        }
        let (k, nodes) = (k as usize, geometry.unknowns() as f64);
        let bytes = (time.steps / k + 1) as f64 * nodes * VTU_BYTES_PER_NODE;
        if bytes > MAX_VTU_BYTES {
            let every = (time.steps as f64 * nodes * VTU_BYTES_PER_NODE / MAX_VTU_BYTES).ceil() as usize;
            return Err(SceneError::TooManyFrames {
                given: k,
                gigabytes: bytes / 1e9,
                limit_gb: MAX_VTU_BYTES / 1e9,
                every,
            });
        }
        Some(k)
    } else {
        forbid("output.vtu_every", &o.vtu_every, "output.vtu = false (set vtu = true)")?;
        None
    };
    let divergence_factor = parse_divergence_factor(o.divergence_factor)?;
    let output = OutputSpec { series, every, summary_l2: o.summary_l2.unwrap_or(true), divergence_factor, vtu_every };
    Ok(Scene { geometry, mass, contact_directions, scheme, contact, time, output })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scheme(text: &str) -> Result<SchemeSpec, String> {
        let raw = toml::from_str::<RawScheme>(text).unwrap();
        parse_scheme(Some(raw)).map_err(|e| e.to_string())
    }

    /// serde ignores unknown keys of a unit variant (`BackwardEuler`, `Hybrid`) even with
    /// `deny_unknown_fields`; [`read_tagged`] refuses them from the keys each kind writes.
    /// Mutation: the key loop of `read_tagged` removed -> `backward-euler` with `beta` parses.
    #[test]
    fn keys_of_other_kinds_are_refused_by_name() {
        let e = scheme("kind = \"backward-euler\"\nbeta = 0.5").unwrap_err();
        assert_eq!(
            e,
            "scheme.beta does not apply to scheme.kind = \"backward-euler\" (only to \"newmark\" | \"paoli-schatzman\")"
        );
        let e = scheme("kind = \"hybrid\"\nrestitution = 0.5").unwrap_err();
        assert!(e.starts_with("scheme.restitution does not apply"), "{e}");
        let e = scheme("kind = \"newmark\"\nbeat = 0.5").unwrap_err();
        assert!(e.starts_with("scheme.beat: unknown field `beat` in [scheme], expected one of kind, "), "{e}");
    }

    #[test]
    fn kinds_default_and_keys_name_themselves_in_errors() {
        assert_eq!(scheme(""), Ok(SchemeSpec::CRANK_NICOLSON));
        assert_eq!(
            scheme("formulation = \"reduced\""),
            Ok(SchemeSpec::CrankNicolson { formulation: Formulation::Reduced })
        );
        assert_eq!(
            scheme("kind = \"euler\"").unwrap_err(),
            "scheme.kind = \"euler\": allowed range is crank-nicolson | newmark | backward-euler | paoli-schatzman | hybrid | central-difference | moreau-jean"
        );
        // A wrong type names the key (serde's message alone does not).
        assert_eq!(
            scheme("kind = \"newmark\"\ngamma = \"x\"").unwrap_err(),
            "scheme.gamma: invalid type: string \"x\", expected f64"
        );
        let read = |text: &str| parse_mass(Some(toml::from_str::<RawMass>(text).unwrap())).map_err(|e| e.to_string());
        let mass = |text: &str| read(text).map(|(m, _)| m);
        assert_eq!(mass(""), Ok(MassKind::Mod3));
        assert_eq!(mass("kind = \"custom\"\nweights = [0, 1.5]"), Ok(MassKind::Custom(vec![0.0, 1.5])));
        assert_eq!(read("contact_directions = \"normal\""), Ok((MassKind::Mod3, ContactDirections::Normal)));
        assert_eq!(read("kind = \"mod1\""), Ok((MassKind::Mod1, ContactDirections::All)));
        assert_eq!(
            read("contact_directions = \"tangential\"").unwrap_err(),
            "mass.contact_directions = \"tangential\": allowed range is all | normal"
        );
        assert!(mass("kind = \"custom\"").unwrap_err().starts_with("mass.weights is required"));
        assert_eq!(
            mass("kind = \"mod1\"\nweights = [1]").unwrap_err(),
            "mass.weights does not apply to mass.kind = \"mod1\" (only to \"custom\")"
        );
    }
}
