//! The fine-mesh reference of the elastic table as a fixture (issue 28): what the free-face
//! λ > 0 rows of [`super::elastic_table`] read from [`super::elastic_reference`], stored.
//!
//! The reference of the full `reproduce` (160² Q1 cells, Crank–Nicolson, Δt = h/5, T = 10, and
//! its check on 80²) is one long sequential run, and it never changes between runs: nothing of
//! it depends on the report's other sections. Its fields (2·21² + 1 numbers per snapshot, 2001
//! snapshots) are too large to keep, so the fixture keeps what the table reads off it: for every
//! free-face candidate (cells × scheme × Δt × mass) and for its unperturbed run and its
//! [`super::band::PERTURBATIONS`] perturbed copies, the running maximum of the error against the
//! reference at each T of the table, and the reference's own error estimate at each T. The
//! table computed from the fixture is the table computed with the reference, bit for bit
//! (serde_json's `float_roundtrip` writes and reads every f64 exactly).
//!
//! `fixtures/elastic-reference.json` holds the full set and a coarse one (the same code on a
//! 40² reference up to T = 3, the quick grid); `cargo run --release -p massredist-study --bin
//! elastic-fixture` regenerates both (minutes: it is deliberate, never a side effect), and
//! `study/tests/elastic_fixture.rs` recomputes the coarse set and compares.

use super::elastic_reference::reference;
use super::elastic_setup::Material;
use super::elastic_table::{Candidate, StoredFine, grid, linf_l2_errors_against};
use massredist::fem::Cell;
use massredist::mass::MassKind;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The fixture's file, under the repository's `fixtures/`.
pub const FIXTURE: &str = "elastic-reference.json";

/// Cells per side and end time of the coarse set (the CI check's cost: seconds).
pub const COARSE: (usize, f64) = (40, 3.0);

/// Where a fixture came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// The command that wrote it.
    pub command: String,
    /// `git rev-parse HEAD` of the tree that computed it, and whether it had uncommitted changes.
    pub commit: String,
    pub dirty: bool,
    /// `rustc --version`.
    pub rustc: String,
    /// What was computed (module docs of `elastic_reference`).
    pub what: String,
}

/// The errors of one free-face run against a reference.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredRun {
    pub cells: String,
    pub scheme: String,
    pub dt: f64,
    pub mass: String,
    /// None: the unperturbed run; Some(k): perturbed copy k ([`super::band::perturbed`]).
    pub copy: Option<usize>,
    /// The running maximum of the error at each T of [`ReferenceSet::ends`] (None past a
    /// divergence), or why the run failed.
    pub errors: Result<Vec<Option<f64>>, String>,
}

/// One reference as the table sees it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReferenceSet {
    /// Cells per side of the reference, and its end time.
    pub cells: usize,
    pub end: f64,
    /// The T of the table (the grid's ends).
    pub ends: Vec<f64>,
    /// The reference's own error estimate at each T of `ends`.
    pub self_difference: Vec<Option<f64>>,
    pub runs: Vec<StoredRun>,
}

impl StoredFine for ReferenceSet {
    /// The stored errors of a candidate's run (copy as in [`StoredRun::copy`]).
    fn errors(&self, c: &Candidate, copy: Option<usize>) -> Result<Vec<Option<f64>>, String> {
        let found = self.runs.iter().find(|r| {
            r.cells == c.cells.name()
                && r.scheme == c.scheme.name()
                && r.dt == c.dt
                && r.mass == c.mass.name()
                && r.copy == copy
        });
        match found {
            Some(r) => r.errors.clone(),
            None => Err(format!(
                "{} {} Δt = {} {} (copy {copy:?}) is not in fixtures/{FIXTURE}; regenerate it \
                 (cargo run --release -p massredist-study --bin elastic-fixture)",
                c.cells.name(),
                c.scheme.name(),
                c.dt,
                c.mass.name()
            )),
        }
    }

    fn cells(&self) -> usize {
        self.cells
    }

    /// The reference's own error estimate up to T (one of [`ReferenceSet::ends`]).
    fn self_difference(&self, end: f64) -> Option<f64> {
        self.ends.iter().position(|&e| e == end).and_then(|k| self.self_difference[k])
    }
}

/// The fixture file: the full set (what `reproduce` reads) and the coarse one (what CI checks).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ElasticFixture {
    pub provenance: Provenance,
    pub full: ReferenceSet,
    pub coarse: ReferenceSet,
}

/// The fixture's path.
pub fn path() -> PathBuf {
    crate::repo::root().join("fixtures").join(FIXTURE)
}

/// Reads the fixture.
pub fn load() -> Result<ElasticFixture, String> {
    let p = path();
    let text = std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", p.display()))
}

/// Computes a reference of `cells`² cells up to `end` and the errors of every free-face
/// candidate of the grid (`quick`: the quick grid) against it, unperturbed and in every
/// perturbed copy, in parallel (rayon).
pub fn compute_set(cells: usize, end: f64, quick: bool) -> Result<ReferenceSet, String> {
    let (schemes, dts, ends) = grid(quick);
    let r = reference(cells, end).map_err(|e| e.to_string())?;
    let masses = [MassKind::Mod1, MassKind::Mod2, MassKind::Mod3];
    let mut runs = Vec::new();
    for cells in [Cell::Quad, Cell::Triangle] {
        for scheme in &schemes {
            for &dt in dts {
                for mass in &masses {
                    for copy in std::iter::once(None).chain((0..super::band::PERTURBATIONS).map(Some)) {
                        runs.push((Candidate { cells, material: Material::PoissonFree, mass, scheme, dt }, copy));
                    }
                }
            }
        }
    }
    let stored = runs
        .par_iter()
        .map(|&(c, copy)| StoredRun {
            cells: c.cells.name().into(),
            scheme: c.scheme.name().into(),
            dt: c.dt,
            mass: c.mass.name().into(),
            copy,
            errors: linf_l2_errors_against(c, ends, Some(&r), copy).map_err(|e| e.to_string()),
        })
        .collect();
    Ok(ReferenceSet {
        cells,
        end,
        ends: ends.to_vec(),
        self_difference: ends.iter().map(|&t| r.self_difference(t)).collect(),
        runs: stored,
    })
}

/// Both sets of the fixture: the full one ([`super::elastic_reference::REFERENCE_CELLS`], T = 10,
/// the full grid) and the coarse one ([`COARSE`], the quick grid).
pub fn compute(provenance: Provenance) -> Result<ElasticFixture, String> {
    let full = compute_set(super::elastic_reference::REFERENCE_CELLS, 10.0, false)?;
    let coarse = compute_set(COARSE.0, COARSE.1, true)?;
    Ok(ElasticFixture { provenance, full, coarse })
}
