//! The scene as the FEniCSx engine reads it: one JSON document (`scene.engine.json` in the run
//! folder) holding the resolved, validated scene with every value written out, so that
//! python/engine/scene.py takes values and decides nothing: no default, no refusal of its own.
//!
//! ```json
//! {"format": 1,
//!  "geometry": {"kind": "plate", "length": 1.0, "height": 0.25, "nx": 40, "ny": 10, "cells": "quad",
//!               "density": 1.0, "modulus": 1.0, "far_end": "clamped", "gap": 0.0,
//!               "initial": "paper", "force": 0.0},
//!  "mass": {"kind": "mod3", "weights": null},
//!  "scheme": {"kind": "crank-nicolson", "beta": 0.25, "gamma": 0.5},
//!  "time": {"dt": 0.01, "end": 3.0, "steps": 300},
//!  "output": {"series": ["u0", "energy"], "every": 1, "summary_l2": true, "vtu_every": null,
//!             "divergence_factor": 1000000.0}}
//! ```
//!
//! `geometry.kind` is `plate`, `solid` (the structured box) or `body` (a body against a plane,
//! whose mesh and fields travel in `body.json`, [`super::body`]); a `null` means "does not apply"
//! (the depth of a 2D solid, the weights of a named mass), never "take a default". `format`
//! changes whenever a key changes meaning or goes; the engine refuses any other.
//!
//! What the engine cannot run is refused here, in Rust, where the scene is validated
//! ([`document`]; `super::validate`), each refusal naming the key to change: a scheme the engine
//! does not step (`scheme.kind`), the reduced formulation (`scheme.formulation`), a plate force
//! that depends on t (`plate.force`), besides `super::EngineGeometry::engine_refusal`'s and the
//! contact law's.

use super::{EngineError, EngineGeometry};
use crate::medium::Force;
use crate::plate::spec::{PlateInitial, PlateSpec};
use crate::scene::{Formulation, Scene, SchemeSpec};
use crate::solid::{SolidInitial, SolidSpec};
use serde::Serialize;

/// The version of the document's shape (python/engine/scene.py's `FORMAT` must equal it).
pub const FORMAT: u32 = 1;

/// The file the engine reads, in the run folder.
pub const FILE: &str = "scene.engine.json";

/// The whole document (module docs).
#[derive(Debug, Serialize)]
pub struct EngineScene {
    pub format: u32,
    pub geometry: GeometryDoc,
    pub mass: MassDoc,
    pub scheme: SchemeDoc,
    pub time: TimeDoc,
    pub output: OutputDoc,
}

/// The geometry, tagged by `kind`.
#[derive(Debug, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum GeometryDoc {
    Plate(PlateDoc),
    Solid(SolidDoc),
    Body(BodyDoc),
}

/// A structured plate (`[plate]`, `crate::plate::spec`).
#[derive(Debug, Serialize)]
pub struct PlateDoc {
    pub length: f64,
    pub height: f64,
    pub nx: usize,
    pub ny: usize,
    /// "quad" | "triangle".
    pub cells: &'static str,
    pub density: f64,
    pub modulus: f64,
    /// "clamped" | "free".
    pub far_end: &'static str,
    pub gap: f64,
    pub initial: PlateInitialDoc,
    pub force: PlateForceDoc,
}

/// `"paper"`, `"bump"`, or the two expressions in x, y, L, H, pi.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum PlateInitialDoc {
    Named(&'static str),
    Fields { displacement: String, velocity: String },
}

/// A constant, or an expression in x, y, L, H, pi (constant in time).
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum PlateForceDoc {
    Constant(f64),
    Expression(String),
}

/// A structured box (`[solid]` without `[obstacle]`, `crate::solid::spec`).
#[derive(Debug, Serialize)]
pub struct SolidDoc {
    /// 2 | 3.
    pub dim: usize,
    pub length: f64,
    pub height: f64,
    /// None in 2D.
    pub depth: Option<f64>,
    pub nx: usize,
    pub ny: usize,
    /// None in 2D.
    pub nz: Option<usize>,
    /// "quad" | "triangle" (2D), "hex" | "tet" (3D).
    pub cells: &'static str,
    pub density: f64,
    pub lame_lambda: f64,
    pub lame_mu: f64,
    pub gap: f64,
    /// "free" | "roller".
    pub lateral: &'static str,
    /// One number per component.
    pub force: Vec<f64>,
    pub initial: SolidInitialDoc,
}

/// `"paper"`, or one expression per component for each field.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum SolidInitialDoc {
    Named(&'static str),
    Fields { displacement: Vec<String>, velocity: Vec<String> },
}

/// A body against a plane: the material; mesh, weights, contact set and fields are `body.json`'s.
#[derive(Debug, Serialize)]
pub struct BodyDoc {
    pub dim: usize,
    pub density: f64,
    pub lame_lambda: f64,
    pub lame_mu: f64,
}

/// `mass.kind` and, for `custom`, its cell weights (None otherwise).
#[derive(Debug, Serialize)]
pub struct MassDoc {
    pub kind: &'static str,
    pub weights: Option<Vec<f64>>,
}

/// The schemes the engine steps (python/engine/schemes.py), each with its parameters.
#[derive(Debug, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum SchemeDoc {
    CrankNicolson { beta: f64, gamma: f64 },
    Newmark { beta: f64, gamma: f64 },
    BackwardEuler,
    Hybrid,
}

#[derive(Debug, Serialize)]
pub struct TimeDoc {
    pub dt: f64,
    pub end: f64,
    pub steps: usize,
}

#[derive(Debug, Serialize)]
pub struct OutputDoc {
    pub series: Vec<&'static str>,
    pub every: usize,
    pub summary_l2: bool,
    /// Steps between the XDMF frames (None: the last state only).
    pub vtu_every: Option<usize>,
    pub divergence_factor: f64,
}

/// The engine's document of a validated scene, or the refusal of what the engine cannot run
/// (module docs), naming the key.
pub fn document<G: EngineGeometry>(scene: &Scene<G>) -> Result<EngineScene, EngineError> {
    if let Some(f) = scene.contact.friction() {
        return Err(EngineError::Scene(format!(
            "contact.friction = \"{}\": the fenicsx engine runs frictionless contact only (friction is Rust-only)",
            f.name()
        )));
    }
    if scene.contact_directions != crate::mass::ContactDirections::All {
        return Err(EngineError::Scene(format!(
            "mass.contact_directions = \"{}\": the fenicsx engine redistributes every component of the contact layer (\"all\"; \"normal\" is Rust-only)",
            scene.contact_directions.name()
        )));
    }
    if scene.contact != crate::contact::law::ContactLaw::Exact {
        let method = scene.contact.method();
        return Err(EngineError::Scene(format!(
            "contact.method = \"{method}\": the fenicsx engine runs exact contact only (issue 20's laws are Rust-only)"
        )));
    }
    if let Some(m) = scene.geometry.engine_refusal() {
        return Err(EngineError::Scene(m));
    }
    let o = &scene.output;
    Ok(EngineScene {
        format: FORMAT,
        geometry: scene.geometry.document().map_err(EngineError::Scene)?,
        mass: MassDoc {
            kind: scene.mass.name(),
            weights: match &scene.mass {
                crate::mass::MassKind::Custom(w) => Some(w.clone()),
                _ => None,
            },
        },
        scheme: scheme(&scene.scheme)?,
        time: TimeDoc { dt: scene.time.dt, end: scene.time.end, steps: scene.time.steps },
        output: OutputDoc {
            series: o.series.iter().map(|c| c.name()).collect(),
            every: o.every,
            summary_l2: o.summary_l2,
            vtu_every: o.vtu_every,
            divergence_factor: o.divergence_factor,
        },
    })
}

/// The document as the JSON text the engine reads.
pub fn to_json(doc: &EngineScene) -> String {
    serde_json::to_string_pretty(doc).expect("an engine document always serialises") + "\n"
}

/// The dotted path of every key of a document (`geometry.length`, `format`; a table is not a
/// key, its keys are).
pub fn key_paths(doc: &serde_json::Value) -> Vec<String> {
    fn walk(v: &serde_json::Value, prefix: &str, out: &mut Vec<String>) {
        let serde_json::Value::Object(map) = v else { return };
        for (k, x) in map {
            let path = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
            match x {
                serde_json::Value::Object(_) => walk(x, &path, out),
                _ => out.push(path),
            }
        }
    }
    let mut out = Vec::new();
    walk(doc, "", &mut out);
    out
}

/// The engine's schemes: Newmark (Crank–Nicolson its β = ¼, γ = ½), backward Euler, hybrid, in
/// the full formulation.
fn scheme(spec: &SchemeSpec) -> Result<SchemeDoc, EngineError> {
    const RUNS: &str = "crank-nicolson | newmark | backward-euler | hybrid";
    let full = |f: &Formulation| match f {
        Formulation::Full => Ok(()),
        other => Err(EngineError::Scene(format!(
            "scheme.formulation = \"{}\": the fenicsx engine runs \"full\" only",
            other.name()
        ))),
    };
    match spec {
        SchemeSpec::CrankNicolson { formulation } => {
            full(formulation)?;
            Ok(SchemeDoc::CrankNicolson { beta: 0.25, gamma: 0.5 })
        }
        SchemeSpec::Newmark { beta, gamma, formulation } => {
            full(formulation)?;
            Ok(SchemeDoc::Newmark { beta: beta.get(), gamma: gamma.get() })
        }
        SchemeSpec::BackwardEuler => Ok(SchemeDoc::BackwardEuler),
        SchemeSpec::Hybrid => Ok(SchemeDoc::Hybrid),
        other => Err(EngineError::Scene(format!(
            "scheme.kind = \"{}\": the fenicsx engine runs {RUNS} (this scheme runs in Rust: drop --engine)",
            other.name()
        ))),
    }
}

/// A plate's document (structured: `engine_refusal` has refused mesh files).
pub(super) fn plate(p: &PlateSpec) -> Result<GeometryDoc, String> {
    let initial = match &p.initial {
        PlateInitial::Fields { displacement, velocity } => {
            PlateInitialDoc::Fields { displacement: displacement.text().into(), velocity: velocity.text().into() }
        }
        named => PlateInitialDoc::Named(named.name()),
    };
    let force = match &p.medium.force {
        Force::Constant(f) => PlateForceDoc::Constant(*f),
        Force::Field(e) => PlateForceDoc::Expression(e.text().into()),
        Force::Transient(e) => {
            return Err(format!(
                "plate.force = \"{}\": the fenicsx engine runs forces that do not depend on t only",
                e.text()
            ));
        }
    };
    Ok(GeometryDoc::Plate(PlateDoc {
        length: p.length,
        height: p.height,
        nx: p.nx,
        ny: p.ny,
        cells: p.cells.name(),
        density: p.medium.material.density,
        modulus: p.medium.material.modulus,
        far_end: p.medium.far_end.name(),
        gap: p.medium.gap,
        initial,
        force,
    }))
}

/// A solid's document: the box, or a body (`body.json` holds the rest).
pub(super) fn solid(s: &SolidSpec) -> GeometryDoc {
    let (d, [l, h, depth], [nx, ny, nz]) = (s.dim, s.extent, s.cells_per_axis);
    let (lambda, mu, density) = (s.lame.lambda, s.lame.mu, s.lame.density);
    let crate::solid::Support::Face { gap, lateral, force } = &s.support else {
        return GeometryDoc::Body(BodyDoc { dim: d, density, lame_lambda: lambda, lame_mu: mu });
    };
    let texts = |f: &[crate::expr::Expr]| -> Vec<String> { f.iter().map(|e| e.text().to_string()).collect() };
    GeometryDoc::Solid(SolidDoc {
        dim: d,
        length: l,
        height: h,
        depth: (d == 3).then_some(depth),
        nx,
        ny,
        nz: (d == 3).then_some(nz),
        cells: s.cells.name(),
        density,
        lame_lambda: lambda,
        lame_mu: mu,
        gap: *gap,
        lateral: lateral.name(),
        force: force[..d].to_vec(),
        initial: match &s.initial {
            SolidInitial::Paper => SolidInitialDoc::Named("paper"),
            SolidInitial::Fields { displacement, velocity } => {
                SolidInitialDoc::Fields { displacement: texts(displacement), velocity: texts(velocity) }
            }
        },
    })
}

#[cfg(test)]
mod tests {
    use super::{FORMAT, document, key_paths, to_json};
    use crate::scene::{PlateScene, SolidScene};
    use serde_json::Value;

    fn json_of(doc: &super::EngineScene) -> Value {
        serde_json::from_str(&to_json(doc)).unwrap()
    }

    const COMMON: [&str; 14] = [
        "format",
        "mass.kind",
        "mass.weights",
        "scheme.kind",
        "scheme.beta",
        "scheme.gamma",
        "time.dt",
        "time.end",
        "time.steps",
        "output.series",
        "output.every",
        "output.summary_l2",
        "output.vtu_every",
        "output.divergence_factor",
    ];

    fn sorted(mut v: Vec<String>) -> Vec<String> {
        v.sort();
        v
    }

    /// A plate scene of one table and no key writes every key python/engine/scene.py reads, each
    /// with the value the scene documents as its default (src/scene/mod.rs, src/plate/spec.rs).
    // mutation: `depth: (d == 3).then_some(depth)` → skip_serializing_if on the depth (the 2D
    // solid's key absent) fails the solid's key list below; `gap` dropped from PlateDoc fails here.
    #[test]
    fn a_scene_without_optional_keys_writes_every_key() {
        let plate = PlateScene::from_toml("[plate]\n").unwrap();
        let v = json_of(&document(&plate).unwrap());
        let keys = key_paths(&v);
        let geometry = ["kind", "length", "height", "nx", "ny", "cells", "density", "modulus", "far_end", "gap"]
            .iter()
            .chain(&["initial", "force"])
            .map(|k| format!("geometry.{k}"));
        let want: Vec<String> = COMMON.iter().map(|s| s.to_string()).chain(geometry).collect();
        assert_eq!(sorted(keys), sorted(want));
        assert_eq!(v["format"], FORMAT);
        assert_eq!(v["geometry"]["kind"], "plate");
        assert_eq!(v["geometry"]["initial"], "paper");
        assert_eq!(v["geometry"]["force"], 0.0);
        assert_eq!(v["geometry"]["far_end"], "clamped");
        assert_eq!(v["mass"]["kind"], "mod3");
        assert_eq!(v["mass"]["weights"], Value::Null);
        assert_eq!(v["scheme"]["kind"], "crank-nicolson");
        assert_eq!((v["scheme"]["beta"].as_f64(), v["scheme"]["gamma"].as_f64()), (Some(0.25), Some(0.5)));
        assert_eq!(v["output"]["divergence_factor"], crate::scene::DEFAULT_DIVERGENCE_FACTOR);
        assert_eq!(v["output"]["vtu_every"], Value::Null);
        let (dt, end, steps) = (
            v["time"]["dt"].as_f64().unwrap(),
            v["time"]["end"].as_f64().unwrap(),
            v["time"]["steps"].as_u64().unwrap(),
        );
        assert_eq!((end / dt).round() as u64, steps);

        let solid = SolidScene::from_toml("[solid]\n").unwrap();
        let v = json_of(&document(&solid).unwrap());
        let keys = key_paths(&v);
        let geometry = ["kind", "dim", "length", "height", "depth", "nx", "ny", "nz", "cells", "density"]
            .iter()
            .chain(&["lame_lambda", "lame_mu", "gap", "lateral", "force", "initial"])
            .map(|k| format!("geometry.{k}"));
        let want: Vec<String> = COMMON.iter().map(|s| s.to_string()).chain(geometry).collect();
        assert_eq!(sorted(keys), sorted(want));
        let g = &v["geometry"];
        assert_eq!(
            (g["kind"].as_str(), g["dim"].as_u64(), g["cells"].as_str()),
            (Some("solid"), Some(2), Some("quad"))
        );
        assert_eq!((&g["depth"], &g["nz"]), (&Value::Null, &Value::Null), "a 2D solid has no depth");
        assert_eq!(g["force"], serde_json::json!([0.0, 0.0]));
        assert_eq!((g["lame_lambda"].as_f64(), g["lame_mu"].as_f64()), (Some(0.0), Some(0.5)));
        assert_eq!(g["lateral"], "free");
    }

    /// What the engine does not run is refused in Rust, naming the one key to change; what it
    /// runs passes. (mutation: the `other =>` arm of `scheme` returning Hybrid → the first
    /// assertion fails.)
    #[test]
    fn the_engine_refuses_by_key_what_it_does_not_run() {
        let refusal = |text: &str| match document(&PlateScene::from_toml(text).unwrap()) {
            Ok(_) => None,
            Err(e) => Some(e.to_string()),
        };
        let cd = refusal("[plate]\n[scheme]\nkind = \"central-difference\"\n[time]\ndt = 0.001\nend = 0.1\n").unwrap();
        assert!(cd.starts_with("scheme.kind = \"central-difference\""), "{cd}");
        let mj = refusal("[plate]\n[mass]\nkind = \"standard\"\n[scheme]\nkind = \"moreau-jean\"\n").unwrap();
        assert!(mj.starts_with("scheme.kind = \"moreau-jean\""), "{mj}");
        let t = refusal("[plate]\nforce = \"sin(t)\"\n").unwrap();
        assert!(t.starts_with("plate.force"), "{t}");
        for kind in ["crank-nicolson", "newmark", "backward-euler", "hybrid"] {
            assert_eq!(refusal(&format!("[plate]\n[scheme]\nkind = \"{kind}\"\n")), None, "{kind}");
        }
        assert_eq!(refusal("[plate]\nforce = \"x*y\"\n"), None);
    }
}
