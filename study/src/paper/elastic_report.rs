//! The report section and the CSV of the elastic Table 1 ([`super::elastic_table`]): the closest
//! configuration per cells × material, the 10 % verdict, the free-face rows against the
//! fine-mesh reference ([`super::elastic_reference`]) and which set-ups keep the paper's ranking.
//! Every value printed here carries only the digits its five runs (U⁰ perturbed by ≤ 1e-13,
//! [`super::band`]) agree on ([`printed_configurations`] are the rerun ones).

use super::band::stable_digits;
use super::elastic_table::{
    ELASTIC_TABLE, ElasticRow, FREE_FACE_SHOWN, MATCH_FACTOR, Material, N, configurations, printed_configurations,
};
use super::plate_table::PAPER_TABLE;
use super::tables::write_csv;
use std::fmt::Write as _;
use std::path::Path;

/// Digits of an error in the section (at most; fewer if the perturbed runs disagree).
const DIGITS: usize = 3;

fn describe(r: &ElasticRow) -> String {
    let lambda = if r.lambda == 0.0 { "λ = 0" } else { "λ = 3/7, μ = 2/7" };
    format!("{} cells, {lambda}, {} faces, {}, Δt = {}, T = {}", r.cells, r.lateral, r.scheme, r.dt, r.end)
}

/// The error of a row over its runs, agreed digits only.
fn value(r: &ElasticRow) -> String {
    stable_digits(&r.over_runs(), DIGITS)
}

/// The worst factor of a configuration over its runs: run k's factor from the masses' run k.
fn factor(group: &[&ElasticRow]) -> String {
    let runs = group.iter().map(|r| r.over_runs().len()).min().unwrap_or(0);
    let per_run: Vec<Option<f64>> = (0..runs)
        .map(|k| {
            group
                .iter()
                .map(|r| match (r.over_runs()[k], r.paper) {
                    (Some(e), Some(p)) if e > 0.0 => Some((e / p).max(p / e)),
                    _ => None,
                })
                .try_fold(1.0_f64, |acc, f| f.map(|f| acc.max(f)))
        })
        .collect();
    stable_digits(&per_run, DIGITS)
}

fn value_cells(group: &[&ElasticRow]) -> String {
    group.iter().map(|q| value(q)).collect::<Vec<_>>().join(" | ")
}

/// The report section: the paper's row, the closest elastic configuration per cells × material,
/// the free-face rows against the reference, the 10 % verdict and the paper's ranking per T.
pub fn elastic_section(rows: &[ElasticRow]) -> String {
    let mut s = String::from("## Table 1 of the paper (2D) with vector elasticity\n\n");
    let configs = configurations(rows);
    let _ = writeln!(
        s,
        "{} elastic configurations (cells × material × scheme × Δt × T) × mod1, mod2, mod3 ({} rows, `{ELASTIC_TABLE}`) on 20×20 cells of (0,1)², clamped at x = 1, contact at x = 0, \
         u⁰ = ((1−x)/2, 0), v⁰ = 0. Error: max over t_n ≤ T of ‖u_h − U‖_{{L²((0,1)²)²}}, integrated exactly. \
         λ > 0 is λ = 3/7, μ = 2/7 (ν = 0.3, λ + 2μ = 1: the plane wave keeps the paper's speed 1). For λ = 0 and for \
         roller faces U is the paper's plane wave U = (u¹ᴰ(x, t), 0), the exact solution. For λ > 0 with free faces the plane wave is not \
         the solution (Poisson effect), and U is {}. \
         The norm is not tuned. Every value below is the same to the digits shown in five runs from U⁰ perturbed by ≤ 1e-13 (else a band).\n",
        configs.len(),
        rows.len(),
        reference_text(rows)
    );
    s.push_str("| configuration | Mod1 | Mod2 | Mod3 | worst factor |\n|---|---|---|---|---|\n");
    let paper: Vec<String> = PAPER_TABLE.iter().map(|(_, v)| format!("{v}")).collect();
    let _ = writeln!(s, "| paper | {} | 1 |", paper.join(" | "));
    let printed = printed_configurations(rows);
    for g in &printed {
        let what = if g[0].material == Material::PoissonFree && is_free_face_shown(g[0]) {
            "elastic, against the reference"
        } else {
            "elastic, closest"
        };
        let _ = writeln!(s, "| {what}: {} | {} | {} |", describe(g[0]), value_cells(g), factor(g));
    }
    s.push('\n');
    s.push_str(&verdict(&configs, &printed));
    s.push_str(&ranking_text(&configs));
    s
}

fn is_free_face_shown(r: &ElasticRow) -> bool {
    let (scheme, dt, end) = FREE_FACE_SHOWN;
    r.scheme == scheme && r.dt == dt && r.end == end
}

/// The reference's own error estimate per T (`max_{t_k ≤ T} ‖u_{n/2} − u_n‖`), from its rows.
fn reference_differences(rows: &[ElasticRow]) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    for r in rows.iter().filter(|r| r.reference == "fine mesh") {
        if let Some(d) = r.reference_difference.filter(|_| !out.iter().any(|(e, _)| *e == r.end)) {
            out.push((r.end, d));
        }
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// What the free-face rows are measured against, with the reference's own error.
fn reference_text(rows: &[ElasticRow]) -> String {
    let Some(cells) = rows.iter().filter(|r| r.reference == "fine mesh").find_map(|r| r.reference_cells) else {
        return "a fine-mesh reference that could not be computed (see the CSV's failure column)".into();
    };
    // One run each (the reference is not rerun from perturbed data): one significant digit,
    // rounded up, as a bound.
    let own: Vec<String> = reference_differences(rows)
        .iter()
        .map(|(end, d)| format!("≤ {} at T = {end}", super::tables::sig(round_up_1(*d), 1)))
        .collect();
    format!(
        "a fine-mesh reference: the same problem on {cells}² Q1 cells (nested {}× in the 20² mesh), Crank–Nicolson with mod2, \
         Δt = h/5, the coarse solution integrated against it exactly on the fine cells at every t_n. Its own error is estimated by the same run \
         on {}² cells: max over t_k ≤ T (t_k = 0.005 k) of ‖u_{} − u_{cells}‖ is {} (one significant digit, rounded up)",
        cells / N,
        cells / 2,
        cells / 2,
        own.join(", ")
    )
}

/// `x` rounded up to one significant digit (a bound that the digit shown does not undercut).
fn round_up_1(x: f64) -> f64 {
    let p = 10f64.powi(x.abs().log10().floor() as i32);
    (x / p).ceil() * p
}

/// The closest configuration and the plain 10 % verdict.
fn verdict(configs: &[(Vec<&ElasticRow>, f64)], printed: &[Vec<&ElasticRow>]) -> String {
    let Some((g, _)) = configs.first().filter(|(_, f)| f.is_finite()) else {
        return "No elastic configuration gave all three values.\n".into();
    };
    // The closest overall is one of the printed ones (the closest of its cells × material).
    let shown = printed.iter().find(|p| std::ptr::eq(p[0], g[0])).unwrap_or(g);
    let matching = configs.iter().filter(|(_, f)| *f <= MATCH_FACTOR).count();
    let head = format!(
        "The elastic configuration closest to all three values is {}: {} (worst factor {} from the paper).",
        describe(shown[0]),
        shown.iter().map(|q| format!("{} {}", q.mass, value(q))).collect::<Vec<_>>().join(", "),
        factor(shown)
    );
    if matching > 0 {
        format!(
            "{head} {matching} of the {} configurations match all three values within 10 % (worst factor ≤ {MATCH_FACTOR}); the closest is the one above.\n",
            configs.len()
        )
    } else {
        format!("{head} None of the {} elastic configurations matches all three values within 10 %.\n", configs.len())
    }
}

/// Per material and T: how many (cells, scheme, Δt) set-ups keep the paper's ranking
/// mod3 < mod2 < mod1, and the smallest relative gap among them (how far from a tie).
fn ranking_text(configs: &[(Vec<&ElasticRow>, f64)]) -> String {
    let mut s = String::from(
        "\nSet-ups (cells, scheme, Δt) with the paper's ranking mod3 < mod2 < mod1, per material and T (smallest relative gap between neighbours among them):",
    );
    let mut ends: Vec<f64> = configs.iter().map(|(g, _)| g[0].end).collect();
    ends.sort_by(f64::total_cmp);
    ends.dedup();
    for m in Material::ALL {
        let parts: Vec<String> = ends
            .iter()
            .map(|&end| {
                let at: Vec<&Vec<&ElasticRow>> =
                    configs.iter().map(|(g, _)| g).filter(|g| g[0].material == m && g[0].end == end).collect();
                let gaps: Vec<f64> = at.iter().filter_map(|g| ranked_gap(g)).collect();
                let min = gaps.iter().copied().fold(f64::INFINITY, f64::min);
                let gap = if gaps.is_empty() { String::new() } else { format!(" ({:.0} %)", 100.0 * min) };
                // Against the reference: also how many keep the ranking by more than twice the
                // reference's own error estimate (a ranking its error cannot flip).
                let robust = at
                    .iter()
                    .filter(|g| g[0].reference == "fine mesh")
                    .filter_map(|g| Some((absolute_gap(g)?, g[0].reference_difference?)))
                    .filter(|(gap, d)| *gap > 2.0 * d)
                    .count();
                let robust = if m == Material::PoissonFree {
                    format!(", {robust} by more than twice the reference's own error")
                } else {
                    String::new()
                };
                format!("T = {end}: {} of {}{gap}{robust}", gaps.len(), at.len())
            })
            .collect();
        let what = match m {
            Material::LambdaZeroFree => "λ = 0, free faces (plane wave)",
            Material::PoissonFree => "λ > 0, free faces (fine-mesh reference)",
            Material::PoissonRoller => "λ > 0, roller faces (plane wave)",
        };
        let _ = write!(s, "\n- {what}: {}", parts.join(", "));
    }
    s.push_str(".\n");
    s
}

/// If the group (mod1, mod2, mod3) has the paper's ranking: the smaller of (mod1 − mod2)/mod2 and
/// (mod2 − mod3)/mod3.
fn ranked_gap(g: &[&ElasticRow]) -> Option<f64> {
    let v = |m: &str| g.iter().find(|r| r.mass == m).and_then(|r| r.linf_l2_error);
    let (a, b, c) = (v("mod1")?, v("mod2")?, v("mod3")?);
    (c < b && b < a).then(|| ((a - b) / b).min((b - c) / c))
}

/// If the group has the paper's ranking: the smaller of mod1 − mod2 and mod2 − mod3.
fn absolute_gap(g: &[&ElasticRow]) -> Option<f64> {
    let v = |m: &str| g.iter().find(|r| r.mass == m).and_then(|r| r.linf_l2_error);
    let (a, b, c) = (v("mod1")?, v("mod2")?, v("mod3")?);
    (c < b && b < a).then(|| (a - b).min(b - c))
}

/// Writes `table-2d-elastic.csv` (every row) into `dir`.
pub fn write_elastic_csv(dir: &Path, rows: &[ElasticRow]) -> std::io::Result<()> {
    use massredist::output::fmt_f64;
    let header = [
        "cells",
        "lame_lambda",
        "lame_mu",
        "lateral",
        "reference",
        "reference_cells",
        "reference_self_difference",
        "scheme",
        "mass",
        "nx",
        "ny",
        "dt",
        "end",
        "linf_l2_error",
        "paper",
        "failure",
    ];
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            vec![
                r.cells.to_string(),
                fmt_f64(r.lambda),
                fmt_f64(r.mu),
                r.lateral.to_string(),
                r.reference.to_string(),
                r.reference_cells.map_or(String::new(), |c| c.to_string()),
                r.reference_difference.map_or(String::new(), fmt_f64),
                r.scheme.to_string(),
                r.mass.to_string(),
                N.to_string(),
                N.to_string(),
                fmt_f64(r.dt),
                fmt_f64(r.end),
                r.linf_l2_error.map_or(String::new(), fmt_f64),
                r.paper.map_or(String::new(), fmt_f64),
                r.failure.clone().unwrap_or_default(),
            ]
        })
        .collect();
    write_csv(&dir.join(ELASTIC_TABLE), &header.map(String::from), &body)
}
