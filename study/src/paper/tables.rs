//! The result tables (CSV with full precision, Markdown for the report) and the number formats
//! of the report text.

pub use super::band::sig;
use super::band::{PERTURBATION, Verdict};
use super::runs::{CaseResult, events, runs_of};
use super::{Config, Experiment, Purpose};
use massredist::mass::MassKind;
use massredist::observe::Summary;
use massredist::output::fmt_f64;
use std::fmt::Write as _;
use std::path::Path;

/// `x` to `digits` significant digits, or a dash.
pub(super) fn opt(x: Option<f64>, digits: usize) -> String {
    x.map_or("—".into(), |v| sig(v, digits))
}

/// A grid time t_n with as many decimals as Δt has.
pub(super) fn time(t: f64, dt: f64) -> String {
    let d = (-(dt.log10().floor())).max(0.0) as usize;
    format!("{t:.d$}")
}

/// A time shift, with as many decimals as Δt has (shifts are multiples of Δt), signed.
pub(super) fn shift(x: Option<f64>, dt: f64) -> String {
    let d = (-(dt.log10().floor())).max(0.0) as usize;
    x.map_or("—".into(), |v| {
        let v = if v.abs() < 0.5 * dt { 0.0 } else { v };
        format!("{v:+.d$}")
    })
}

/// `x` as a percentage, 3 significant digits.
/// `T3`, `T9`, `T2.5`: the horizon in file names.
pub fn horizon_tag(end: f64) -> String {
    if end.fract() == 0.0 && end.abs() < 1e15 { format!("T{}", end as i64) } else { format!("T{end}") }
}

/// Header of the result table CSVs. The last two say how far a row's digits are results:
/// `perturbed_runs` is the number of runs behind the row (5: every case is rerun from U⁰ perturbed
/// by ≤ 1e-13, [`super::band`]); `agreed_digits` is the fewest significant digits on which its
/// runs agree over the row's numbers (the rest of the 16 are one run's round-off).
pub const TABLE_COLUMNS: [&str; 15] = [
    "scheme",
    "mass",
    "end",
    "status",
    "linf_l2_error",
    "linf_l2_error_relative",
    "max_contact_error",
    "l2_lambda_error",
    "energy_min",
    "energy_max",
    "energy_final",
    "impact_time_shift",
    "release_time_shift",
    "perturbed_runs",
    "agreed_digits",
];

/// Header of the per-period contact events CSVs (`events-T*.csv`).
/// (`last_contact`: the last t_n of the period in contact, [`super::PeriodEvents::last_contact`].)
pub const EVENT_COLUMNS: [&str; 6] = ["scheme", "mass", "period", "impact_shift", "release_shift", "last_contact"];

fn status(r: &CaseResult) -> String {
    match &r.failure {
        None => "ok".into(),
        Some(d) => d.to_string(),
    }
}

/// The first cells of a result row ([`TABLE_COLUMNS`] up to `l2_lambda_error`, full precision):
/// scheme, mass, end, status and the summary's four errors.
pub(super) fn leading_cells(e: Experiment, mass: &MassKind, end: f64, status: String, s: &Summary) -> Vec<String> {
    let o = |x: Option<f64>| x.map_or(String::new(), fmt_f64);
    vec![
        e.slug().to_string(),
        mass.name().into(),
        fmt_f64(end),
        status,
        o(s.linf_l2_error),
        o(s.linf_l2_error_relative),
        o(s.max_contact_error),
        o(s.l2_lambda_error),
    ]
}

/// The rows of a result table CSV ([`TABLE_COLUMNS`]), full precision.
fn table_csv_rows(rows: &[&CaseResult]) -> Vec<Vec<String>> {
    let o = |x: Option<f64>| x.map_or(String::new(), fmt_f64);
    rows.iter()
        .map(|r| {
            let s = &r.summary;
            let c = &r.case;
            let mut row = leading_cells(c.experiment, &c.mass, c.end, status(r), s);
            row.extend([
                fmt_f64(s.energy_min),
                fmt_f64(s.energy_max),
                fmt_f64(s.energy_final),
                o(s.impact_time_shift),
                o(s.release_time_shift),
                (r.copies.len() + 1).to_string(),
                agreed_digits_of(r).map_or(String::new(), |d| d.to_string()),
            ]);
            row
        })
        .collect()
}

/// The fewest significant digits on which the runs of a rerun case agree over the numbers of its
/// CSV row (errors, energies, shifts); None for a case without reruns.
fn agreed_digits_of(r: &CaseResult) -> Option<usize> {
    if r.copies.is_empty() {
        return None;
    }
    let columns: [&dyn Fn(&Summary) -> Option<f64>; 9] = [
        &|s| s.linf_l2_error,
        &|s| s.linf_l2_error_relative,
        &|s| s.max_contact_error,
        &|s| s.l2_lambda_error,
        &|s| Some(s.energy_min),
        &|s| Some(s.energy_max),
        &|s| Some(s.energy_final),
        &|s| s.impact_time_shift,
        &|s| s.release_time_shift,
    ];
    columns.iter().map(|f| super::band::agreed_digits(&r.over_runs(f))).min()
}

/// The rows of an events CSV ([`EVENT_COLUMNS`]): one per case and period.
fn events_csv_rows(config: &Config, rows: &[&CaseResult]) -> Vec<Vec<String>> {
    let o = |x: Option<f64>| x.map_or(String::new(), fmt_f64);
    rows.iter()
        .flat_map(|r| {
            events(config, r).into_iter().map(|p| {
                vec![
                    r.case.experiment.slug().to_string(),
                    r.case.mass.name().into(),
                    p.period.to_string(),
                    o(p.impact_shift),
                    o(p.release_shift),
                    o(p.last_contact),
                ]
            })
        })
        .collect()
}

/// A result table in Markdown, with the per-period shifts where the cases recorded u_0.
pub(super) fn table_markdown(config: &Config, rows: &[&CaseResult]) -> String {
    let with_events = rows.iter().any(|r| !events(config, r).is_empty());
    let mut s = String::from(
        "| scheme | mass | L∞(0,T;L²) error | relative | max \\|u_0 − u(0,t)\\| | L²(0,T) error of λ | E min | E max | E final | impact shift | release shift |",
    );
    s.push_str(if with_events { " shifts per period (impact / release) | status |\n" } else { " status |\n" });
    s.push_str(&"|---".repeat(if with_events { 13 } else { 12 }));
    s.push_str("|\n");
    for r in rows {
        let e = |f: fn(&Summary) -> f64| r.stable(|s| Some(f(s)), 6);
        let _ = write!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.case.experiment.title(),
            r.case.mass.name(),
            r.stable(|s| s.linf_l2_error, 4),
            r.stable(|s| s.linf_l2_error_relative, 3),
            r.stable(|s| s.max_contact_error, 4),
            r.stable(|s| s.l2_lambda_error, 4),
            e(|s| s.energy_min),
            e(|s| s.energy_max),
            e(|s| s.energy_final),
            shifts(r, |s| s.impact_time_shift, config.dt),
            shifts(r, |s| s.release_time_shift, config.dt),
        );
        if with_events {
            let _ = write!(s, " {} |", all_period_shifts(config, r, " / "));
        }
        let status = if r.failure.is_some() { "**diverged**" } else { "ok" };
        let _ = writeln!(s, " {status}{} |", verdict_note(r));
    }
    s
}

/// A value over the runs of a case, shown by `show`: the one text if every run shows the same,
/// else the band `min to max`.
pub(super) fn agreed(
    r: &CaseResult,
    f: impl Fn(&Summary) -> Option<f64>,
    show: impl Fn(Option<f64>) -> String,
) -> String {
    agreed_values(&r.over_runs(f), show)
}

/// [`agreed`] of values already taken over the runs.
pub(super) fn agreed_values(v: &[Option<f64>], show: impl Fn(Option<f64>) -> String) -> String {
    let shown: Vec<String> = v.iter().map(|x| show(*x)).collect();
    if shown.iter().all(|x| *x == shown[0]) {
        return shown.first().cloned().unwrap_or_default();
    }
    let (lo, hi) = super::band::band(&v.iter().flatten().copied().collect::<Vec<_>>());
    format!("{} to {}", show(Some(lo)), show(Some(hi)))
}

/// Period j's impact and release shifts over the runs of a case, "impact{sep}release" (each
/// [`agreed_values`]); None past the runs' last full period.
pub(super) fn period_shifts(config: &Config, r: &CaseResult, j: usize, sep: &str) -> Option<String> {
    let ev = super::runs::period_over_runs(config, r, j);
    if ev.len() < 1 + r.copies.len() {
        return None;
    }
    let show = |x: Option<f64>| shift(x, config.dt);
    let impact: Vec<Option<f64>> = ev.iter().map(|p| p.impact_shift).collect();
    let release: Vec<Option<f64>> = ev.iter().map(|p| p.release_shift).collect();
    Some(format!("{}{sep}{}", agreed_values(&impact, show), agreed_values(&release, show)))
}

/// Energy variation over the runs of a case ([`super::runs::variation_after_impact`]) as
/// (Σ(ΔE)⁺, Σ(ΔE)⁻, steps up, steps down): each sum with the digits all runs share (else their
/// band), or "round-off" where no run has a step above the round-off floor in that direction
/// (the sum is then round-off, and so are its digits); step counts as the one count or `a–b`.
/// None if a run had no impact.
pub(super) fn variation_cells(v: &[Option<super::runs::EnergyVariation>]) -> Option<[String; 4]> {
    let v: Vec<super::runs::EnergyVariation> = v.iter().copied().collect::<Option<_>>()?;
    let sum = |f: fn(&super::runs::EnergyVariation) -> (f64, usize), sign: &str| {
        if v.iter().all(|x| f(x).1 == 0) {
            "round-off".to_string()
        } else {
            format!("{sign}{}", super::band::stable_digits(&v.iter().map(|x| Some(f(x).0)).collect::<Vec<_>>(), 2))
        }
    };
    let count =
        |f: fn(&super::runs::EnergyVariation) -> usize| super::band::count_band(&v.iter().map(f).collect::<Vec<_>>());
    Some([
        sum(|x| (x.up, x.up_steps), "+"),
        sum(|x| (x.down, x.down_steps), "−"),
        count(|x| x.up_steps),
        count(|x| x.down_steps),
    ])
}

/// Every full period's [`period_shifts`], joined by ", ".
pub(super) fn all_period_shifts(config: &Config, r: &CaseResult, sep: &str) -> String {
    (0..).map_while(|j| period_shifts(config, r, j, sep)).collect::<Vec<_>>().join(", ")
}

/// A time shift over the runs of a case ([`agreed`]).
pub(super) fn shifts(r: &CaseResult, f: impl Fn(&Summary) -> Option<f64>, dt: f64) -> String {
    agreed(r, f, |x| shift(x, dt))
}

/// For a case with perturbed copies: "; 5 runs from U⁰ perturbed by ≤ 1e-13", and for a long run
/// their verdicts (a verdict needs several periods): the one verdict all runs share, else the
/// range of them, `bounded–grows` (round-off decides between them; how many runs fall on each
/// side is itself round-off).
pub(super) fn verdict_note(r: &CaseResult) -> String {
    // Every case is rerun (the intro says so); the note marks the known round-off amplifiers.
    if r.copies.is_empty() || !super::band::is_sensitive(&r.case) {
        return String::new();
    }
    let v = r.verdicts();
    let runs = format!("; {} runs from U⁰ perturbed by ≤ {:e}", v.len(), PERTURBATION);
    if r.case.purpose != Purpose::LongEnergy {
        return runs;
    }
    format!("{runs}: {}", verdict_range(&v.iter().map(|(x, _)| *x).collect::<Vec<_>>()))
}

/// The verdict all runs share, else `lowest–highest` on bounded < grows < diverged.
pub(super) fn verdict_range(v: &[Verdict]) -> String {
    match (v.iter().min(), v.iter().max()) {
        (Some(lo), Some(hi)) if lo == hi => lo.name().to_string(),
        (Some(lo), Some(hi)) => format!("{}–{}", lo.name(), hi.name()),
        _ => "—".into(),
    }
}

/// The result tables, each under its CSV name: `table-T*.csv` per horizon, then
/// `table-long-T*.csv` per long run.
pub(super) fn result_tables<'a>(config: &Config, results: &'a [CaseResult]) -> Vec<(String, Vec<&'a CaseResult>)> {
    let short = config
        .horizons
        .iter()
        .map(|&end| (format!("table-{}.csv", horizon_tag(end)), runs_of(results, Purpose::Figures, end)));
    let long = config
        .long_ends
        .iter()
        .map(|&end| (format!("table-long-{}.csv", horizon_tag(end)), runs_of(results, Purpose::LongEnergy, end)));
    short.chain(long).collect()
}

/// The per-period contact events CSV of horizon `end`.
pub(super) fn events_file(end: f64) -> String {
    format!("events-{}.csv", horizon_tag(end))
}

/// Writes the result `tables` and, per horizon, [`events_file`] into `dir`.
pub(super) fn write_tables(
    dir: &Path,
    config: &Config,
    results: &[CaseResult],
    tables: &[(String, Vec<&CaseResult>)],
) -> std::io::Result<()> {
    let header: Vec<String> = TABLE_COLUMNS.iter().map(|s| s.to_string()).collect();
    for (name, rows) in tables {
        write_csv(&dir.join(name), &header, &table_csv_rows(rows))?;
    }
    let header: Vec<String> = EVENT_COLUMNS.iter().map(|s| s.to_string()).collect();
    for &end in &config.horizons {
        let rows = runs_of(results, Purpose::Figures, end);
        write_csv(&dir.join(events_file(end)), &header, &events_csv_rows(config, &rows))?;
    }
    Ok(())
}

/// Writes one CSV file: `header`, then `rows`.
pub(super) fn write_csv(path: &Path, header: &[String], rows: &[Vec<String>]) -> std::io::Result<()> {
    let mut w = csv::Writer::from_path(path).map_err(std::io::Error::other)?;
    w.write_record(header).map_err(std::io::Error::other)?;
    for r in rows {
        w.write_record(r).map_err(std::io::Error::other)?;
    }
    w.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_digits() {
        assert_eq!(sig(0.041641900, 4), "0.04164");
        assert_eq!(sig(11.42214, 4), "11.42");
        assert_eq!(sig(2.5e-6, 2), "2.5e-6");
        assert_eq!(shift(Some(0.010000000000000231), 0.01), "+0.01");
        assert_eq!(shift(Some(-1e-17), 0.01), "+0.00");
    }
}
