//! The sections every scene shares: `[mass]`, `[scheme]`, `[time]` (and the output's
//! divergence factor): raw tables, validation, and the resolved form.

use super::*;
use crate::mass::MassKind;

/// The `[mass]` table (every scene has one).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMass {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) kind: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) weights: Option<Vec<Number>>,
}

/// The `[scheme]` table (shared with the plate scenes).
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawScheme {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) kind: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) beta: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) gamma: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) restitution: Option<Number>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) formulation: Option<String>,
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

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeSpec {
    pub dt: f64,
    pub end: f64,
    pub steps: usize,
}

/// The `[mass]` table as a [`MassKind`] (its weights are validated by the caller, who knows the
/// mesh).
pub(crate) fn parse_mass(raw: Option<RawMass>) -> Result<MassKind, SceneError> {
    let mass = raw.unwrap_or_default();
    let kind = mass.kind.as_deref().unwrap_or("mod3");
    let mass = match kind {
        "custom" => {
            let w = mass.weights.ok_or(SceneError::Missing {
                key: "mass.weights",
                hint: " for mass.kind = \"custom\" (one weight >= 0 per element, element 0 at the contact node)",
            })?;
            MassKind::Custom(w.into_iter().map(Number::get).collect())
        }
        "standard" | "mod1" | "mod2" | "mod3" => {
            forbid("mass.weights", &mass.weights, &format!("mass.kind = \"{kind}\" (only to \"custom\")"))?;
            match kind {
                "standard" => MassKind::Standard,
                "mod1" => MassKind::Mod1,
                "mod2" => MassKind::Mod2,
                _ => MassKind::Mod3,
            }
        }
        other => {
            return Err(SceneError::Range {
                key: "mass.kind",
                value: format!("\"{other}\""),
                range: "standard | mod1 | mod2 | mod3 | custom",
            });
        }
    };
    Ok(mass)
}

/// The `[scheme]` table; `w0` is the weight of the cells at the contact node (0 iff it is
/// massless), which the reduced formulation and the hybrid scheme need.
pub(crate) fn parse_scheme(raw: Option<RawScheme>, w0: f64, mass: &MassKind) -> Result<SchemeSpec, SceneError> {
    let s = raw.unwrap_or_default();
    let kind = s.kind.clone().unwrap_or_else(|| "crank-nicolson".into());
    let ctx = format!("scheme.kind = \"{kind}\"");
    let formulation = |s: &RawScheme| -> Result<Formulation, SceneError> {
        match s.formulation.as_deref().unwrap_or("full") {
            "full" => Ok(Formulation::Full),
            "reduced" if w0 == 0.0 => Ok(Formulation::Reduced),
            "reduced" => Err(SceneError::Inapplicable {
                key: "scheme.formulation = \"reduced\"",
                context: format!("a mass with w_0 = {} (it needs a massless contact node: mod1, mod2, mod3)", w0),
            }),
            other => Err(SceneError::Range {
                key: "scheme.formulation",
                value: format!("\"{other}\""),
                range: "full | reduced",
            }),
        }
    };
    let beta_range = "(0, 1]";
    let scheme = match kind.as_str() {
        "crank-nicolson" => {
            forbid("scheme.beta", &s.beta, &ctx)?;
            forbid("scheme.gamma", &s.gamma, &ctx)?;
            forbid("scheme.restitution", &s.restitution, &ctx)?;
            SchemeSpec::CrankNicolson { formulation: formulation(&s)? }
        }
        "newmark" => {
            forbid("scheme.restitution", &s.restitution, &ctx)?;
            let beta = s.beta.map_or(0.25, Number::get);
            let gamma = s.gamma.map_or(0.5, Number::get);
            finite_in("scheme.beta", beta, beta > 0.0 && beta <= 1.0, beta_range)?;
            finite_in("scheme.gamma", gamma, (0.0..=1.0).contains(&gamma), "[0, 1]")?;
            SchemeSpec::Newmark { beta, gamma, formulation: formulation(&s)? }
        }
        "backward-euler" | "hybrid" => {
            forbid("scheme.beta", &s.beta, &ctx)?;
            forbid("scheme.gamma", &s.gamma, &ctx)?;
            forbid("scheme.restitution", &s.restitution, &ctx)?;
            forbid("scheme.formulation", &s.formulation, &ctx)?;
            if kind == "hybrid" {
                if w0 != 0.0 {
                    return Err(SceneError::Inapplicable {
                        key: "scheme.kind = \"hybrid\"",
                        context: format!(
                            "mass.kind = \"{}\" (w_0 = {}): the hybrid scheme works on the reduced system and needs w_0 = 0 (mod1, mod2, mod3 or custom with weights[0] = 0)",
                            mass.name(),
                            w0
                        ),
                    });
                }
                SchemeSpec::Hybrid
            } else {
                SchemeSpec::BackwardEuler
            }
        }
        "paoli-schatzman" => {
            forbid("scheme.gamma", &s.gamma, &ctx)?;
            forbid("scheme.formulation", &s.formulation, &ctx)?;
            let beta = s.beta.map_or(0.25, Number::get);
            let restitution = s.restitution.map_or(1.0, Number::get);
            finite_in("scheme.beta", beta, beta > 0.0 && beta <= 1.0, beta_range)?;
            finite_in("scheme.restitution", restitution, (0.0..=1.0).contains(&restitution), "[0, 1]")?;
            SchemeSpec::PaoliSchatzman { beta, restitution }
        }
        other => {
            return Err(SceneError::Range {
                key: "scheme.kind",
                value: format!("\"{other}\""),
                range: "crank-nicolson | newmark | backward-euler | paoli-schatzman | hybrid",
            });
        }
    };
    Ok(scheme)
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

/// The resolved `[mass]` table of a mass redistribution.
/// The resolved `[mass]`, `[scheme]`, `[time]` and `[output]` tables of any scene (`plate`:
/// write the VTU keys).
pub(crate) fn raw_sections(
    mass: &MassKind,
    scheme: &SchemeSpec,
    time: &TimeSpec,
    output: &OutputSpec,
    plate: bool,
) -> (Option<RawMass>, Option<RawScheme>, Option<RawTime>, Option<RawOutput>) {
    let vtu = plate.then_some(output.vtu_every);
    let out = RawOutput::resolved(&output.series, output.every, output.summary_l2, vtu, output.divergence_factor);
    (Some(raw_mass(mass)), Some(raw_scheme(scheme)), Some(raw_time(time)), Some(out))
}

pub(crate) fn raw_mass(mass: &MassKind) -> RawMass {
    RawMass {
        kind: Some(mass.name().into()),
        weights: match mass {
            MassKind::Custom(w) => Some(w.iter().copied().map(Number::Float).collect()),
            _ => None,
        },
    }
}

/// The resolved `[scheme]` table of a scheme.
pub(crate) fn raw_scheme(scheme: &SchemeSpec) -> RawScheme {
    let f = Number::Float;
    let (kind, beta, gamma, restitution, formulation) = match scheme {
        SchemeSpec::CrankNicolson { formulation } => ("crank-nicolson", None, None, None, Some(*formulation)),
        SchemeSpec::Newmark { beta, gamma, formulation } => {
            ("newmark", Some(*beta), Some(*gamma), None, Some(*formulation))
        }
        SchemeSpec::BackwardEuler => ("backward-euler", None, None, None, None),
        SchemeSpec::PaoliSchatzman { beta, restitution } => {
            ("paoli-schatzman", Some(*beta), None, Some(*restitution), None)
        }
        SchemeSpec::Hybrid => ("hybrid", None, None, None, None),
    };
    RawScheme {
        kind: Some(kind.into()),
        beta: beta.map(f),
        gamma: gamma.map(f),
        restitution: restitution.map(f),
        formulation: formulation.map(|x| match x {
            Formulation::Full => "full".into(),
            Formulation::Reduced => "reduced".into(),
        }),
    }
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
) -> Result<Vec<Column>, SceneError> {
    let mut series = Vec::new();
    for name in names {
        let col = allowed.iter().copied().find(|c| c.name() == name).ok_or_else(|| SceneError::Range {
            key: "output.series",
            value: format!("\"{name}\""),
            range,
        })?;
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
/// mesh), `[scheme]` (bar-only schemes refused for other geometries, the one place scenes do it),
/// `[time]` (the work limit over the geometry's unknowns) and `[output]` (the geometry's columns,
/// those its exact solution allows, VTU frames where the geometry writes them).
pub(crate) fn validate_sections<G: SceneGeometry>(geometry: G, raw: RawScene) -> Result<Scene<G>, SceneError> {
    let mass = parse_mass(raw.mass)?;
    let w0 = geometry.contact_weight(&mass)?;
    let scheme = parse_scheme(raw.scheme, w0, &mass)?;
    if !G::BAR_ONLY_SCHEMES {
        if let Some((key, why)) = scheme.bar_only() {
            return Err(SceneError::Inapplicable { key, context: format!("[{}] scenes ({why})", G::TABLE) });
        }
    }
    let time = parse_time(raw.time, 3.0 * geometry.length(), geometry.unknowns(), G::SIZE_KEYS)?;
    let o = raw.output.unwrap_or_default();
    let series = match o.series {
        Some(names) => parse_series(names, G::COLUMNS, G::COLUMN_LIST)?,
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
    Ok(Scene { geometry, mass, scheme, time, output })
}
