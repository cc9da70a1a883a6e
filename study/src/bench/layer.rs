//! `massredist bench --layer CSV`: the massless contact layer of central differences against
//! the number of contact nodes (issue 31, item 0), written as CSV and its `.md` beside it.
//!
//! Cases: 3D Q1 slabs of 3 × N × N cubic cells (h = 1/N, `SolidSpec::paper` with length 3/N),
//! whose contact face x = 0 has (N + 1)² nodes, N = 9, 20, 31, 63, 99 (10² … 10⁴ nodes), on the
//! lean box system ([`massredist::solid::lean`]), once with mod3 (the face's nodes massless in
//! every component: a layer of 3 (N + 1)² unknowns, [`massredist::contact::layer::Layer`]) and
//! once with the standard mass (no layer: the forward-increment multipliers), one after the
//! other in this process. The slab starts at rest in the static state of the bar under the body
//! force (−[`FORCE`], 0, 0), its face pressed on the obstacle, so every timed step solves a contact
//! problem.
//!
//! Per case: the layer's set-up alone (`Layer::new`: AMD ordering, symbolic analysis, one
//! numeric factorisation of S_LL; its factor's stored entries), the scheme's construction
//! (`CentralDifference::from_system`: the layer again, Δt_c by Lanczos), the median of 21
//! steps (one rayon thread, wall) at Δt = 0.9 Δt_c, and the largest number of pivots of a step.
//! The table gives mod3's step and construction against the standard mass's on the same slab.
//! An edge: it times and writes.

use super::explicit_scaling::median;
use crate::paper::methods::SAFETY;
use massredist::contact::exact::Split;
use massredist::contact::law::ContactLaw;
use massredist::contact::layer::Layer;
use massredist::expr::Expr;
use massredist::mass::MassKind;
use massredist::schemes::central_difference::stable_limit_of;
use massredist::schemes::{CentralDifference, Scheme};
use massredist::solid::{Lateral, SolidInitial, SolidSpec, Support};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Steps timed per case (their median is reported).
const STEPS: usize = 21;
/// The body force towards the obstacle (per unit volume; λ + 2μ = 1): the slab starts at rest
/// in the bar's static state under it, `u_x = −F x (L − x)/2`, pressed on the obstacle with the
/// force F L/2 per unit area, and stays pressed (the lateral faces' Poisson motion is a small
/// oscillation about it).
const FORCE: f64 = 100.0;

/// One measured case.
#[derive(Debug, Clone)]
pub struct Row {
    pub n: usize,
    pub mass: &'static str,
    pub face_nodes: usize,
    pub unknowns: usize,
    /// Unknowns of the layer and stored entries of its factor (0 without a layer).
    pub layer_unknowns: usize,
    pub factor_entries: usize,
    pub layer_s: f64,
    pub scheme_s: f64,
    /// Median step of the pressed slab (the contact set does not change: no factorisation).
    pub pressed_ms: f64,
    /// Median step of the impact over the steps whose contact set changed (pivots > 0; all
    /// steps for the standard mass, which has no pivots), their number, and the largest pivot
    /// count of a step.
    pub change_ms: f64,
    pub change_steps: usize,
    pub max_pivots: usize,
}

/// The slab 3 × N × N, pressed (at rest in the static state under the body force) or hitting
/// the obstacle (u = 0, v = (−1, 0, 0), no force: the face lands at once and lifts after the
/// wave's transit 2L/c, about 6 steps, its edges first).
fn spec(n: usize, pressed: bool) -> Result<SolidSpec, String> {
    let mut s = SolidSpec::paper(3, [3, n, n]);
    s.extent[0] = 3.0 / n as f64;
    let consts = [("L", s.extent[0]), ("F", FORCE)];
    let e = |t: &str| Expr::parse("solid.initial", t, &["x", "y", "z"], &consts).map_err(|e| e.to_string());
    let (ux, vx, f) = if pressed { ("-F/2*x*(L-x)", "0", FORCE) } else { ("0", "-1", 0.0) };
    s.initial =
        SolidInitial::Fields { displacement: vec![e(ux)?, e("0")?, e("0")?], velocity: vec![e(vx)?, e("0")?, e("0")?] };
    s.support = Support::Face { gap: 0.0, lateral: Lateral::Free, force: [-f, 0.0, 0.0] };
    Ok(s)
}

/// `STEPS` steps of central differences at 0.9 Δt_c on one thread: (wall ms, pivots) per step,
/// and the scheme's construction time.
fn steps(n: usize, mass: &MassKind, pressed: bool) -> Result<(Vec<(f64, usize)>, f64), String> {
    let b = spec(n, pressed)?.explicit_box(mass).map_err(|e| e.to_string())?;
    let (limit, _, _) = stable_limit_of(&b.system, &b.lumped, None);
    let t = Instant::now();
    let mut cd = CentralDifference::from_system(b.system, b.lumped, &ContactLaw::Exact, SAFETY * limit, b.u0, b.v0)
        .map_err(|e| e.to_string())?;
    let scheme_s = t.elapsed().as_secs_f64();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().map_err(|e| e.to_string())?;
    let mut out = Vec::with_capacity(STEPS);
    for k in 0..STEPS {
        let t = Instant::now();
        pool.install(|| cd.step()).map_err(|e| e.to_string())?;
        out.push((t.elapsed().as_secs_f64() * 1e3, cd.pivots()));
        if pressed && cd.state().lambda.iter().all(|&l| l == 0.0) {
            return Err(format!("N = {n}: the pressed slab lifted off at step {}", k + 1));
        }
    }
    Ok((out, scheme_s))
}

fn case(n: usize, mass: MassKind, name: &'static str) -> Result<Row, String> {
    let b = spec(n, true)?.explicit_box(&mass).map_err(|e| e.to_string())?;
    let split = Split::new(&b.system, &b.lumped);
    let (mut layer_unknowns, mut factor_entries, mut layer_s) = (0, 0, 0.0);
    if !split.massless.is_empty() {
        let t = Instant::now();
        let layer =
            Layer::new(&b.system.stiffness, &b.system.load, &split.massless, &split.free).map_err(|e| e.to_string())?;
        layer_s = t.elapsed().as_secs_f64();
        (layer_unknowns, factor_entries) = (layer.len(), layer.factor_len());
    }
    let (unknowns, face_nodes) = (b.lumped.len(), b.system.contact.len());
    drop(b);
    let (pressed, scheme_s) = steps(n, &mass, true)?;
    let (impact, _) = steps(n, &mass, false)?;
    let has_layer = layer_unknowns > 0;
    let change: Vec<f64> = impact.iter().filter(|s| s.1 > 0 || !has_layer).map(|s| s.0).collect();
    Ok(Row {
        n,
        mass: name,
        face_nodes,
        unknowns,
        layer_unknowns,
        factor_entries,
        layer_s,
        scheme_s,
        pressed_ms: median(pressed.iter().map(|s| s.0).collect()),
        change_steps: change.len(),
        change_ms: median(change),
        max_pivots: impact.iter().chain(&pressed).map(|s| s.1).max().unwrap_or(0),
    })
}

/// The slabs' N (quick: the two smallest).
pub fn sizes(quick: bool) -> Vec<usize> {
    if quick { vec![9, 20] } else { vec![9, 20, 31, 63, 99] }
}

/// Measures every case and writes `csv` and its `.md`; returns the paths written.
pub fn run(csv: &Path, quick: bool) -> Result<Vec<PathBuf>, String> {
    let mut rows = Vec::new();
    for n in sizes(quick) {
        for (mass, name) in [(MassKind::Mod3, "mod3"), (MassKind::Standard, "standard")] {
            let r = case(n, mass, name)?;
            eprintln!(
                "N = {n} {name}: pressed {:.2} ms, changing {:.2} ms ({} steps), scheme {:.3} s, layer {:.3} s",
                r.pressed_ms, r.change_ms, r.change_steps, r.scheme_s, r.layer_s
            );
            rows.push(r);
        }
    }
    std::fs::write(csv, to_csv(&rows)).map_err(|e| format!("{}: {e}", csv.display()))?;
    let md = csv.with_extension("md");
    std::fs::write(&md, to_markdown(&rows)).map_err(|e| format!("{}: {e}", md.display()))?;
    Ok(vec![csv.to_path_buf(), md])
}

pub fn to_csv(rows: &[Row]) -> String {
    let mut s = String::from(
        "n,mass,face_nodes,unknowns,layer_unknowns,factor_entries,layer_setup_s,scheme_setup_s,pressed_step_ms,changing_step_ms,changing_steps,max_pivots\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{:.5},{:.5},{:.4},{:.4},{},{}",
            r.n,
            r.mass,
            r.face_nodes,
            r.unknowns,
            r.layer_unknowns,
            r.factor_entries,
            r.layer_s,
            r.scheme_s,
            r.pressed_ms,
            r.change_ms,
            r.change_steps,
            r.max_pivots
        );
    }
    s
}

/// One line per slab: mod3 against the standard mass.
pub fn to_markdown(rows: &[Row]) -> String {
    let mut s = String::from(
        "| slab cells | contact nodes | unknowns | layer unknowns | factor entries | layer set-up s | scheme set-up s, mod3 / standard | pressed step ms, mod3 / standard (ratio) | step with a pivot ms, mod3 / standard step (ratio) | steps with a pivot | pivots per step (max) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for pair in rows.chunks(2) {
        let [m, st] = pair else { continue };
        let _ = writeln!(
            s,
            "| 3×{n}×{n} | {} | {} | {} | {} | {:.4} | {:.3} / {:.3} | {:.2} / {:.2} ({:.2}) | {:.2} / {:.2} ({:.2}) | {} of {STEPS} | {} |",
            m.face_nodes,
            m.unknowns,
            m.layer_unknowns,
            m.factor_entries,
            m.layer_s,
            m.scheme_s,
            st.scheme_s,
            m.pressed_ms,
            st.pressed_ms,
            m.pressed_ms / st.pressed_ms,
            m.change_ms,
            st.change_ms,
            m.change_ms / st.change_ms,
            m.change_steps,
            m.max_pivots,
            n = m.n
        );
    }
    s
}
