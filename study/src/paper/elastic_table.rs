//! The paper's 2D table (§6, "Total error rates for the displacement": Mod1 0.0104, Mod2 0.0046,
//! Mod3 0.0038 for `‖U_hⁿ − U‖_{L∞(0,T;L²((0,1)²))}` with Δx₁ = Δx₂ = 0.05) tried with vector
//! linear elasticity (issue 11, item 6): the scalar plates ([`super::plate_table`]) do not
//! reproduce it, and the paper's `U` is a displacement, so the likely set-up is an elastic solid.
//!
//! Candidates, all on 20 × 20 cells of (0, 1)², clamped at x = 1, contact at x = 0, ρ = 1, the
//! paper's data u⁰ = ((1 − x)/2, 0), v⁰ = 0 ([`massredist::solid::SolidSpec`]):
//! - cells: Q1 quadrilaterals | P1 triangles (the structured split of [`massredist::fem::mesh`]);
//! - material ([`Material`]): λ = 0, μ = ½ with free lateral faces (the paper's bar as a solid:
//!   its x-rows are the scalar plate's); λ = 3/7, μ = 2/7 with free or roller lateral faces.
//!   Why these λ > 0: Poisson's ratio ν = λ/(2(λ + μ)) = 0.3 (a common engineering material)
//!   with the P-wave modulus λ + 2μ = 1 kept equal to the paper's bar modulus, so that the
//!   plane wave is still the paper's exact solution (wave speed 1, period 3): T = 1, 3, 10 mean
//!   the same phases of the motion as in the scalar sweep, and only the lateral coupling changes;
//! - schemes: Crank–Nicolson, backward Euler, hybrid; Δt ∈ {0.05, 0.025, 0.02, 0.01, 0.005};
//!   T ∈ {1, 2, 3, 10} (the scalar sweep's values; one run to the largest T per Δt, the running
//!   maximum read at each T); mod1, mod2, mod3.
//!
//! **The error** is `max_n ‖u_h(t_n) − U(t_n)‖_{L²((0,1)²)²}` with `U = (u¹ᴰ(x, t), 0)` the
//! paper's closed-form plane wave, computed exactly (round-off only) at every step; nothing is
//! tuned. For λ = 0 and for roller faces U is the solution of the continuous problem
//! ([`massredist::solid`] module docs), so this is the true error. For λ > 0 with free faces it is
//! not (the Poisson effect makes the motion two-dimensional): those rows are measured against a
//! fine-mesh reference instead ([`super::elastic_reference`]: 160² Q1 cells, Δt = h/5, the
//! distance exact on the fine mesh), marked `reference = fine mesh` (issue 22).
//!
//! Q1 cells use the solid's own exact error ([`massredist::problem::GeometryView::l2_error`]). On
//! triangles the solid offers none (NaN); [`simplex_l2_error`] adds one, exact as well: the
//! x-component is integrated in y cut by cut and in x by the 1D solution split at its kinks
//! ([`Characteristics::integrate`]), the transverse component is the quadratic form of the
//! unit mass. The Q1 numbers are untouched.

use super::band::PERTURBATIONS;
use super::elastic_reference::{Reference, cached_reference};
pub use super::elastic_setup::{ElasticError, Material, N, spec, spec_on};
use super::plate_table::{PAPER_TABLE, paper_value};
use massredist::characteristics::{Characteristics, InitialData};
use massredist::driver::{DivergenceCriterion, Needs, Observer, Sample, integrate_watched};
use massredist::exact::{Exact, ImpactingBar, by_characteristics, paper_data};
use massredist::fem::Cell;
use massredist::fem::Mesh;
use massredist::fem::columns::Columns;
use massredist::linalg::sparse;
use massredist::mass::MassKind;
use massredist::material::FarEnd;
use massredist::observe::SummaryObserver;
use massredist::problem::GeometryView;
use massredist::scene::{Formulation, SchemeSpec};
use massredist::solid::SolidError;
use massredist::solid::SolidSystem;
use rayon::prelude::*;
use serde::Serialize;
use std::sync::Arc;

/// The CSV written by `reproduce`.
pub const ELASTIC_TABLE: &str = "table-2d-elastic.csv";

/// The paper's "within 10 %" test: a configuration matches if its worst factor is at most this.
pub const MATCH_FACTOR: f64 = 1.1;

/// One computed entry.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ElasticRow {
    pub cells: &'static str,
    pub material: Material,
    pub lambda: f64,
    pub mu: f64,
    pub lateral: &'static str,
    /// What the error is measured against: `plane wave` (the exact solution: λ = 0, or roller
    /// faces) or `fine mesh` (λ > 0 with free faces: [`super::elastic_reference`]).
    pub reference: &'static str,
    /// For `fine mesh` rows: the reference's cells per side and its own error estimate up to T
    /// (`max_{t_k ≤ T} ‖u_{n/2} − u_n‖`).
    pub reference_cells: Option<usize>,
    pub reference_difference: Option<f64>,
    pub scheme: &'static str,
    pub mass: &'static str,
    pub dt: f64,
    pub end: f64,
    /// `max_n ‖u_h(t_n) − U(t_n)‖_{L²((0,1)²)²}` over t_n ≤ end, None if the run failed or
    /// diverged before `end` (`failure` says why).
    pub linf_l2_error: Option<f64>,
    pub paper: Option<f64>,
    pub failure: Option<String>,
    /// The same error from U⁰ perturbed by ≤ 1e-13 ([`super::band::perturbed`], 4 copies) for
    /// the configurations the report prints ([`printed_configurations`]); empty for the others.
    pub perturbed: Vec<Option<f64>>,
}

impl ElasticRow {
    /// The error over this run and its perturbed copies.
    pub fn over_runs(&self) -> Vec<Option<f64>> {
        std::iter::once(self.linf_l2_error).chain(self.perturbed.iter().copied()).collect()
    }
}

/// `‖u_h − (u(·, t), 0)‖_{L²(Ω)²}` for a 2D solid on P1 triangles, exactly (module docs).
///
/// At fixed x the error `e = u_{h,x} − u(x, t)` is affine in y on each triangle, so over the
/// triangle's vertical cut [y_lo, y_hi] `∫ e² dy = ℓ (e_lo² + e_lo e_hi + e_hi²)/3`, ℓ = y_hi −
/// y_lo; as a function of x this is a polynomial of degree ≤ 3 between the kinks of u (affine
/// between kinks for the paper's data) and the vertex abscissae, which
/// [`Characteristics::integrate`] integrates over the columns of `columns` with its 3-point
/// Gauss rule (exact to degree 5). The transverse part is `U_yᵀ M₁ U_y` (exact). NaN for
/// tensor cells.
pub fn simplex_l2_error(solid: &SolidSystem, columns: &Columns, u: &[f64], exact: &Characteristics, t: f64) -> f64 {
    let (mesh, d) = (&solid.mesh, solid.mesh.dim);
    if mesh.kind != Cell::Triangle {
        return f64::NAN;
    }
    let ux = |v: usize| solid.dof_of.get(v * d).map_or(0.0, |k| u[k]);
    let x_part = exact.integrate(&columns.xs, t, |j, x, ue| {
        let mut sum = 0.0;
        for &c in columns.of(j) {
            let cell = mesh.cell(c);
            // The two points where the vertical line at x leaves the triangle (lowest, highest).
            let (mut lo, mut hi) = ((f64::INFINITY, 0.0), (f64::NEG_INFINITY, 0.0));
            for a in 0..3 {
                let (p, q) = (cell[a], cell[(a + 1) % 3]);
                let (xp, xq) = (mesh.points[p][0], mesh.points[q][0]);
                if xp == xq || x < xp.min(xq) || x > xp.max(xq) {
                    continue;
                }
                let s = (x - xp) / (xq - xp);
                let y = mesh.points[p][1] + s * (mesh.points[q][1] - mesh.points[p][1]);
                let e = ux(p) + s * (ux(q) - ux(p)) - ue;
                if y < lo.0 {
                    lo = (y, e);
                }
                if y > hi.0 {
                    hi = (y, e);
                }
            }
            sum += (hi.0 - lo.0) * (lo.1 * lo.1 + lo.1 * hi.1 + hi.1 * hi.1) / 3.0;
        }
        sum
    });
    let transverse: Vec<f64> = u.iter().zip(&solid.dofs).map(|(&x, &g)| if g % d == 0 { 0.0 } else { x }).collect();
    (x_part.max(0.0) + sparse::quad_form(solid.mass_unit(), &transverse).max(0.0)).sqrt()
}

/// The running maximum of the error against the plane wave (or the fine-mesh reference), read at
/// the steps `marks`.
struct MaxError<'a> {
    solid: &'a SolidSystem,
    /// The fine-mesh reference, if the error is measured against it (free faces, λ > 0).
    reference: Option<&'a Reference>,
    /// Triangles: their columns and the 1D solution; None for Q1 (the solid's own exact error).
    simplex: Option<(&'a Columns, &'a Characteristics)>,
    exact: &'a Exact,
    marks: &'a [usize],
    running: f64,
    at_marks: Vec<Option<f64>>,
}

impl Observer for MaxError<'_> {
    fn needs(&self) -> Needs {
        Needs::default()
    }

    fn observe(&mut self, s: &Sample) {
        let (u, t) = (s.state.u, s.state.t);
        let e = match (self.reference, self.simplex) {
            // Every t_n of the table's Δt is a snapshot time; NaN (never the maximum) otherwise.
            (Some(r), _) => r.error(self.solid, u, t).unwrap_or(f64::NAN),
            (None, Some((columns, c))) => simplex_l2_error(self.solid, columns, u, c, t),
            (None, None) => GeometryView::l2_error(self.solid, u, self.exact, t),
        };
        self.running = self.running.max(e);
        for (k, &m) in self.marks.iter().enumerate() {
            if m == s.state.n {
                self.at_marks[k] = Some(self.running);
            }
        }
    }
}

/// `max_{t_n ≤ T} ‖u_h(t_n) − U(t_n)‖_{L²(Ω)²}` for each T of `ends` (whole multiples of `dt`),
/// from one run to the largest, against the plane wave U; None for the T a diverged run did not
/// reach.
pub fn linf_l2_errors(
    cells: Cell,
    material: Material,
    mass: &MassKind,
    scheme: &SchemeSpec,
    dt: f64,
    ends: &[f64],
) -> Result<Vec<Option<f64>>, ElasticError> {
    linf_l2_errors_against(Candidate { cells, material, mass, scheme, dt }, ends, None, None)
}

/// One elastic run of the table: cells, material, mass, scheme, Δt.
#[derive(Debug, Clone, Copy)]
pub struct Candidate<'a> {
    pub cells: Cell,
    pub material: Material,
    pub mass: &'a MassKind,
    pub scheme: &'a SchemeSpec,
    pub dt: f64,
}

/// [`linf_l2_errors`] against `reference` if given (else the plane wave), from U⁰ perturbed as
/// copy `copy` of [`super::band::perturbed`] if given (the round-off check of the printed digits).
pub fn linf_l2_errors_against(
    c: Candidate,
    ends: &[f64],
    reference: Option<&Reference>,
    copy: Option<usize>,
) -> Result<Vec<Option<f64>>, ElasticError> {
    let Candidate { cells, material, mass, scheme, dt } = c;
    let marks: Vec<usize> = ends.iter().map(|&e| (e / dt).round() as usize).collect();
    let steps = marks.iter().copied().max().unwrap_or(0);
    let t_end = steps as f64 * dt * (1.0 + 1e-9);
    let mut problem = spec(cells, material).problem(mass, t_end)?;
    if let Some(k) = copy {
        problem.u0 = super::band::perturbed(&problem.u0, k);
    }
    let exact = Exact::Paper(ImpactingBar { length: 1.0 });
    let (columns, wave);
    let simplex = if cells == Cell::Triangle && reference.is_none() {
        columns = Columns::new(&Mesh::structured_2d(1.0, 1.0, N, N, Cell::Triangle).map_err(SolidError::from)?);
        let (x, u, v) = paper_data(1.0);
        let data = InitialData::PiecewiseLinear { x: &x, u: &u, v: &v };
        let unit = massredist::material::Material { density: 1.0, modulus: 1.0 };
        wave = by_characteristics(1.0, unit, FarEnd::Clamped, 0.0, data, t_end)?;
        Some((&columns, &wave))
    } else {
        None
    };
    let mut observer = MaxError {
        solid: &problem.system,
        reference,
        simplex,
        exact: &exact,
        marks: &marks,
        running: 0.0,
        at_marks: vec![None; marks.len()],
    };
    let mut summary = SummaryObserver::new(&problem, steps, dt, false);
    let mut s = problem.scheme(scheme, dt)?;
    let outcome = integrate_watched(
        &problem,
        s.as_mut(),
        steps,
        &DivergenceCriterion::default(),
        &mut [&mut observer, &mut summary],
    )?;
    match outcome.divergence() {
        // A divergence before the first mark is this candidate's failure, reported as such.
        Some(d) if observer.at_marks.iter().all(Option::is_none) => Err(ElasticError::Diverged(*d)),
        _ => Ok(observer.at_marks),
    }
}

/// The schemes, Δt and T of the candidates (`quick`: CN, Δt = 0.01, T = 3 only).
pub(super) fn grid(quick: bool) -> (Vec<SchemeSpec>, &'static [f64], &'static [f64]) {
    let cn = SchemeSpec::CrankNicolson { formulation: Formulation::Full };
    if quick {
        (vec![cn], &[0.01], &[3.0])
    } else {
        // The scalar sweep's Δt and T (issue 22: Δt = h/2 and T = 2 added).
        (
            vec![cn, SchemeSpec::BackwardEuler, SchemeSpec::Hybrid],
            &[0.05, 0.025, 0.02, 0.01, 0.005],
            &[1.0, 2.0, 3.0, 10.0],
        )
    }
}

/// Every candidate (module docs; `quick` keeps cells × material × mass with CN, Δt = 0.01,
/// T = 3), run in parallel (rayon), in the order cells, material, scheme, Δt, T, mass; the
/// free-face λ > 0 rows against the fine-mesh reference ([`cached_reference`]); the
/// configurations the report prints rerun from perturbed U⁰ ([`ElasticRow::perturbed`]).
pub fn elastic_table(quick: bool) -> Vec<ElasticRow> {
    table(quick, &Fine::Live(cached_reference(quick)))
}

/// The full table ([`elastic_table`]) with the free-face rows read from `stored` (the fixture of
/// the 160² reference, [`super::elastic_fixture`]) instead of a reference computed now.
pub fn elastic_table_stored(stored: Result<&dyn StoredFine, String>) -> Vec<ElasticRow> {
    table(false, &Fine::Stored(stored))
}

/// The free-face rows' errors when the reference is not computed in this process.
pub trait StoredFine: Sync {
    /// The errors of a candidate's run (copy None: unperturbed) at each T of the grid.
    fn errors(&self, c: &Candidate, copy: Option<usize>) -> Result<Vec<Option<f64>>, String>;
    /// The reference's cells per side.
    fn cells(&self) -> usize;
    /// The reference's own error estimate up to `end`.
    fn self_difference(&self, end: f64) -> Option<f64>;
}

fn table(quick: bool, fine: &Fine) -> Vec<ElasticRow> {
    let (schemes, dts, ends) = grid(quick);
    let masses = [MassKind::Mod1, MassKind::Mod2, MassKind::Mod3];
    let mut runs = Vec::new();
    for cells in [Cell::Quad, Cell::Triangle] {
        for material in Material::ALL {
            for scheme in &schemes {
                for &dt in dts {
                    for mass in &masses {
                        runs.push(Candidate { cells, material, mass, scheme, dt });
                    }
                }
            }
        }
    }
    let run = |c: Candidate, copy: Option<usize>| -> Result<Vec<Option<f64>>, String> {
        if c.material.plane_wave_is_solution() {
            return linf_l2_errors_against(c, ends, None, copy).map_err(|e| e.to_string());
        }
        match fine {
            Fine::Live(r) => match r.as_ref() {
                Ok(r) => linf_l2_errors_against(c, ends, Some(r), copy).map_err(|e| e.to_string()),
                Err(e) => Err(format!("the fine-mesh reference: {e}")),
            },
            Fine::Stored(Ok(f)) => f.errors(&c, copy),
            Fine::Stored(Err(e)) => Err(format!("the fine-mesh reference's fixture: {e}")),
        }
    };
    let results: Vec<_> = runs.par_iter().map(|&c| run(c, None)).collect();
    let mut rows = Vec::with_capacity(runs.len() * ends.len());
    for (c, result) in runs.iter().zip(&results) {
        for (k, &end) in ends.iter().enumerate() {
            rows.push(row(c, end, result.as_ref().map(|v| v[k]), fine.info(end)));
        }
    }
    // Sorted by configuration, then mass (the runs were per mass with all T).
    rows.sort_by(|a, b| {
        let key = |r: &ElasticRow| (r.cells, r.material as u8, r.scheme, r.dt.to_bits(), r.end.to_bits(), r.mass);
        key(a).cmp(&key(b))
    });
    // The round-off check of what the report prints: those configurations' runs again, from
    // U⁰ perturbed by ≤ 1e-13 (one run per mass and copy gives every T of the configuration).
    let printed: Vec<(usize, usize)> = printed_configurations(&rows)
        .iter()
        .flat_map(|g| {
            let r = g[0];
            let c = runs.iter().position(|c| {
                c.cells.name() == r.cells && c.material == r.material && c.scheme.name() == r.scheme && c.dt == r.dt
            });
            let k = ends.iter().position(|&e| e == r.end);
            c.zip(k).into_iter().flat_map(move |(c, k)| (0..3).map(move |m| (c - c % 3 + m, k)))
        })
        .collect();
    let copies: Vec<Vec<Option<f64>>> = printed
        .par_iter()
        .map(|&(c, k)| (0..PERTURBATIONS).map(|copy| run(runs[c], Some(copy)).ok().and_then(|v| v[k])).collect())
        .collect();
    for (&(c, k), values) in printed.iter().zip(copies) {
        let (c, end) = (&runs[c], ends[k]);
        if let Some(r) = rows.iter_mut().find(|r| {
            r.cells == c.cells.name()
                && r.material == c.material
                && r.scheme == c.scheme.name()
                && r.dt == c.dt
                && r.end == end
                && r.mass == c.mass.name()
        }) {
            r.perturbed = values;
        }
    }
    rows
}

/// What the free-face rows are measured against: the reference computed in this process, or the
/// fixture of the full one ([`super::elastic_fixture`]).
enum Fine<'a> {
    Live(Arc<Result<Reference, String>>),
    Stored(Result<&'a dyn StoredFine, String>),
}

impl Fine<'_> {
    /// The reference's cells per side and its own error estimate up to `end`, if it is there.
    fn info(&self, end: f64) -> Option<(usize, Option<f64>)> {
        match self {
            Fine::Live(r) => r.as_ref().as_ref().ok().map(|r| (r.cells, r.self_difference(end))),
            Fine::Stored(f) => f.as_ref().ok().map(|f| (f.cells(), f.self_difference(end))),
        }
    }
}

/// One row of the table from a run's value at `end` (or its failure).
fn row(
    c: &Candidate,
    end: f64,
    value: Result<Option<f64>, &String>,
    reference: Option<(usize, Option<f64>)>,
) -> ElasticRow {
    let lame = c.material.lame();
    let (value, failure) = match value {
        Ok(v) => (v, v.is_none().then(|| "diverged before T".to_string())),
        Err(e) => (None, Some(e.clone())),
    };
    let fine = !c.material.plane_wave_is_solution();
    ElasticRow {
        cells: c.cells.name(),
        material: c.material,
        lambda: lame.lambda,
        mu: lame.mu,
        lateral: c.material.lateral().name(),
        reference: if fine { "fine mesh" } else { "plane wave" },
        reference_cells: reference.filter(|_| fine).map(|r| r.0),
        reference_difference: reference.filter(|_| fine).and_then(|r| r.1),
        scheme: c.scheme.name(),
        mass: c.mass.name(),
        dt: c.dt,
        end,
        linf_l2_error: value,
        paper: paper_value(c.mass),
        failure,
        perturbed: Vec::new(),
    }
}
/// `max_mass max(ours/paper, paper/ours)` of one configuration's rows (∞ if one is missing).
pub fn worst_factor(group: &[&ElasticRow]) -> f64 {
    if group.len() != PAPER_TABLE.len() {
        return f64::INFINITY;
    }
    group
        .iter()
        .map(|r| match (r.linf_l2_error, r.paper) {
            (Some(e), Some(p)) if e > 0.0 => (e / p).max(p / e),
            _ => f64::INFINITY,
        })
        .fold(1.0, f64::max)
}

/// The rows grouped by configuration (cells, material, scheme, Δt, T), with their worst factor,
/// best first.
pub fn configurations(rows: &[ElasticRow]) -> Vec<(Vec<&ElasticRow>, f64)> {
    let mut groups: Vec<Vec<&ElasticRow>> = Vec::new();
    for r in rows {
        let same = |q: &&ElasticRow| {
            q.cells == r.cells && q.material == r.material && q.scheme == r.scheme && q.dt == r.dt && q.end == r.end
        };
        match groups.iter_mut().find(|g| same(&g[0])) {
            Some(g) => g.push(r),
            None => groups.push(vec![r]),
        }
    }
    let mut out: Vec<(Vec<&ElasticRow>, f64)> = groups.into_iter().map(|g| (g.clone(), worst_factor(&g))).collect();
    out.sort_by(|a, b| a.1.total_cmp(&b.1));
    out
}

/// The free-face set-up the section prints against the reference: CN, Δt = 0.01, T = 3 (the
/// judged scalar configuration, and the reading: 0.0440 / 0.0294 / 0.0154 on quads).
pub const FREE_FACE_SHOWN: (&str, f64, f64) = ("crank-nicolson", 0.01, 3.0);

/// The configurations (one group of three masses each) whose numbers the section prints: the
/// closest per cells × material (the first of them overall is the verdict's), and the free-face
/// rows of [`FREE_FACE_SHOWN`] per cells.
pub fn printed_configurations(rows: &[ElasticRow]) -> Vec<Vec<&ElasticRow>> {
    let configs = configurations(rows);
    let mut out: Vec<Vec<&ElasticRow>> = Vec::new();
    for cells in ["quad", "triangle"] {
        for m in Material::ALL {
            if let Some((g, _)) = configs.iter().find(|(g, _)| g[0].cells == cells && g[0].material == m) {
                out.push(g.clone());
            }
        }
        let (scheme, dt, end) = FREE_FACE_SHOWN;
        if let Some((g, _)) = configs.iter().find(|(g, _)| {
            let r = g[0];
            r.cells == cells && r.material == Material::PoissonFree && r.scheme == scheme && r.dt == dt && r.end == end
        }) && !out.iter().any(|p| std::ptr::eq(p[0], g[0]))
        {
            out.push(g.clone());
        }
    }
    out
}
