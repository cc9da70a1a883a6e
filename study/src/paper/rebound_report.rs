//! The rebounding bar's outputs ([`super::rebound`]): `rebound.csv` (one row per scheme ×
//! mass), the figure `rebound-u0` (u_0 and λ of every mass with Crank–Nicolson against the
//! exact solution by characteristics) and the report section with its verdict. Pure: strings
//! and figure data from the results.

use super::band;
use super::figures::{FigureFile, clamped_range, dx_dt, grid_rows, mass_style, off_scale, points};
use super::rebound::{REBOUND_END, REBOUND_WINDOW, Rebound, ReboundResult};
use super::tables::{leading_cells, opt, shift, sig, time};
use super::{Config, Experiment};
use crate::plot::{self, Curve, Panel, Style};
use massredist::mass::MassKind;
use massredist::observe::Summary;
use massredist::output::fmt_f64;
use std::fmt::Write as _;

/// Stem of the section's figure files (`.png`, `.svg`, `.csv`).
pub const REBOUND_FIGURE: &str = "rebound-u0";

/// The section's table file.
pub const REBOUND_TABLE: &str = "rebound.csv";

/// Header of `rebound.csv`.
pub const REBOUND_COLUMNS: [&str; 20] = [
    "scheme",
    "mass",
    "end",
    "status",
    "linf_l2_error",
    "linf_l2_error_relative",
    "max_contact_error",
    "l2_lambda_error",
    "energy_initial",
    "energy_min",
    "energy_max",
    "energy_final",
    "first_impact_time",
    "impact_time_shift",
    "first_release_time",
    "release_time_shift",
    "last_contact_time",
    "last_contact_shift",
    "contact_episodes",
    "rebound_velocity",
];

/// The rows of `rebound.csv` ([`REBOUND_COLUMNS`]), full precision; empty cells for what a
/// run does not have (no release, no exact value).
pub(super) fn rebound_csv_rows(rb: &Rebound) -> Vec<Vec<String>> {
    let o = |x: Option<f64>| x.map_or(String::new(), fmt_f64);
    rb.runs
        .iter()
        .map(|r| {
            let s = &r.summary;
            let status = r.failure.as_ref().map_or("ok".into(), |e| format!("stopped: {e}"));
            let mut row = leading_cells(r.experiment, &r.mass, REBOUND_END, status, s);
            row.extend([
                fmt_f64(s.energy_initial),
                fmt_f64(s.energy_min),
                fmt_f64(s.energy_max),
                fmt_f64(s.energy_final),
                o(s.first_impact_time),
                o(s.impact_time_shift),
                o(s.first_release_time),
                o(s.release_time_shift),
                o(r.last_contact_time),
                o(r.last_contact_shift),
                r.contact_episodes.to_string(),
                o(r.rebound_velocity),
            ]);
            row
        })
        .collect()
}

/// "t (shift)" of an event on the grid, or a dash.
fn event(t: Option<f64>, shift_: Option<f64>, dt: f64) -> String {
    t.map_or("—".into(), |t| format!("{} ({})", time(t, dt), shift(shift_, dt)))
}

/// The section's table in Markdown. A round-off sensitive row (one with reruns) shows each value
/// with the digits its five runs share, else their band ([`band::stable_digits`]).
fn rebound_table(config: &Config, rb: &Rebound) -> String {
    let mut s = String::from(
        "| scheme | mass | L∞(0,T;L²) error | max \\|u_0 − u(0,t)\\| | L²(0,T) error of λ | E(0) | E min | E max | E final | first impact (shift) | first release (shift) | last contact (shift) | contact episodes | rebound velocity | status |\n",
    );
    s.push_str(&"|---".repeat(15));
    s.push_str("|\n");
    for r in &rb.runs {
        let _ = writeln!(s, "| {} | {} | {} |", r.experiment.title(), r.mass.name(), row_cells(config, r).join(" | "));
    }
    s
}

/// The cells of a row of [`rebound_table`] after scheme and mass.
fn row_cells(config: &Config, r: &ReboundResult) -> Vec<String> {
    let dt = config.dt;
    let m = &r.summary;
    if r.copies.is_empty() {
        return vec![
            opt(m.linf_l2_error, 4),
            opt(m.max_contact_error, 4),
            opt(m.l2_lambda_error, 4),
            sig(m.energy_initial, 6),
            sig(m.energy_min, 6),
            sig(m.energy_max, 6),
            sig(m.energy_final, 6),
            event(m.first_impact_time, m.impact_time_shift, dt),
            event(m.first_release_time, m.release_time_shift, dt),
            event(r.last_contact_time, r.last_contact_shift, dt),
            r.contact_episodes.to_string(),
            opt(r.rebound_velocity, 4),
            status(r),
        ];
    }
    let num = |f: &dyn Fn(&Summary) -> Option<f64>, d: usize| band::stable_digits(&r.over_runs(|s, _, _, _| f(s)), d);
    // An event time: the grid time if all runs agree, else their band (no shift).
    let at = |v: Vec<Option<f64>>, first: String| {
        if v.iter().all(|x| *x == v[0]) {
            return first;
        }
        let (lo, hi) = band::band(&v.iter().flatten().copied().collect::<Vec<_>>());
        format!("{}–{}", time(lo, dt), time(hi, dt))
    };
    let episodes = r.over_runs(|_, _, n, _| n as f64);
    let (lo, hi) = band::band(&episodes);
    vec![
        num(&|s| s.linf_l2_error, 4),
        num(&|s| s.max_contact_error, 4),
        num(&|s| s.l2_lambda_error, 4),
        num(&|s| Some(s.energy_initial), 6),
        num(&|s| Some(s.energy_min), 6),
        num(&|s| Some(s.energy_max), 6),
        num(&|s| Some(s.energy_final), 6),
        at(r.over_runs(|s, _, _, _| s.first_impact_time), event(m.first_impact_time, m.impact_time_shift, dt)),
        at(r.over_runs(|s, _, _, _| s.first_release_time), event(m.first_release_time, m.release_time_shift, dt)),
        at(r.over_runs(|_, t, _, _| t), event(r.last_contact_time, r.last_contact_shift, dt)),
        if lo == hi { r.contact_episodes.to_string() } else { format!("{lo}–{hi}") },
        band::stable_digits(&r.over_runs(|_, _, _, v| v), 4),
        status(r),
    ]
}

/// "ok" or "**non-finite**"; for a row with reruns, how many and by how much v⁰ changed.
fn status(r: &ReboundResult) -> String {
    let base = if r.failure.is_some() { "**non-finite**" } else { "ok" };
    if r.copies.is_empty() {
        return base.into();
    }
    format!("{base}; {} runs from v⁰ changed by 0, ±1e-13, ±2e-13: round-off sensitive, bands", r.copies.len() + 1)
}

/// The L∞(0,T;L²) error of a run as the report shows it: with the digits all its runs share.
fn shown_error(r: &ReboundResult) -> String {
    if r.failure.is_some() {
        return sig(f64::INFINITY, 4);
    }
    band::stable_digits(&r.over_runs(|s, _, _, _| s.linf_l2_error), 4)
}

/// The L∞(0,T;L²) error a ranking uses: infinite for a run that failed or has none.
fn error_of(r: &ReboundResult) -> f64 {
    if r.failure.is_some() { f64::INFINITY } else { r.summary.linf_l2_error.unwrap_or(f64::INFINITY) }
}

/// The line of scheme `e` in [`verdict`]: its masses ranked by L∞(0,T;L²) error and the rebound
/// velocity closest to the exact one; with the best mass.
fn scheme_line(rb: &Rebound, e: Experiment) -> Option<(String, Vec<&ReboundResult>)> {
    let mut ranked: Vec<&ReboundResult> = rb.runs.iter().filter(|r| r.experiment == e).collect();
    ranked.sort_by(|a, b| error_of(a).total_cmp(&error_of(b)));
    ranked.first()?;
    let list: Vec<String> = ranked.iter().map(|r| format!("{} {}", r.mass.name(), shown_error(r))).collect();
    let v_exact = rb.exact.rebound_velocity;
    let closest = ranked
        .iter()
        .filter_map(|r| Some((r, r.rebound_velocity?)))
        .min_by(|a, b| (a.1 - v_exact).abs().total_cmp(&(b.1 - v_exact).abs()));
    let v = closest.map_or("none".into(), |(r, v)| format!("{} {}", r.mass.name(), sig(v, 4)));
    let line = format!(
        "- {}: L∞(0,T;L²) error, smallest first: {}. Rebound velocity closest to the exact {}: {v}.\n",
        e.title(),
        list.join(" < "),
        sig(v_exact, 4)
    );
    Some((line, ranked))
}

/// One line per scheme ([`scheme_line`]), then the answer to "does mod3 still win?" read off
/// those rankings: yes only if mod3 has the smallest L∞(0,T;L²) error with every scheme.
fn verdict(rb: &Rebound) -> String {
    let mut s = String::new();
    let (mut wins, mut loses) = (Vec::new(), Vec::new());
    for e in Experiment::ALL {
        let Some((line, ranked)) = scheme_line(rb, e) else { continue };
        s.push_str(&line);
        let best = ranked[0];
        if best.mass == MassKind::Mod3 {
            wins.push(e.title().to_string());
        } else {
            let mod3 = ranked.iter().find(|r| r.mass == MassKind::Mod3).map_or("none".into(), |r| shown_error(r));
            let (m, err) = (best.mass.name(), shown_error(best));
            loses.push(format!("{} ({m} {err} against mod3 {mod3})", e.title()));
        }
    }
    s.push('\n');
    s.push_str(&if loses.is_empty() {
        "**Yes, mod3 still wins**: it has the smallest L∞(0,T;L²) error with every scheme when the bar arrives with a velocity.\n".to_string()
    } else if wins.is_empty() {
        format!(
            "**No, mod3 does not win here**: with no scheme does it have the smallest L∞(0,T;L²) error; the smallest is {}.\n",
            loses.join("; ")
        )
    } else {
        format!(
            "**Not everywhere**: mod3 has the smallest L∞(0,T;L²) error with {}, but not with {}.\n",
            wins.join(", "),
            loses.join("; ")
        )
    });
    s
}

/// The section of `report.md`: the set-up with the exact facts, the table, the figure, the
/// verdict.
pub(super) fn rebound_section(config: &Config, rb: &Rebound) -> String {
    let x = &rb.exact;
    let gap = rb.runs.first().map_or(f64::NAN, |r| -r.motion.lower);
    let (start, stop) = x.contacts.first().copied().unwrap_or((f64::NAN, f64::NAN));
    let mut s = String::from("\n## Beyond the paper: the rebounding bar\n\n");
    let _ = writeln!(
        s,
        "A free bar (`scenes/rebound-free-bar.toml`: L = {}, ρ = E = 1, far end free) at rest shape moves at v⁰ = −1 towards the obstacle at gap {}; \
         on this report's mesh and step ({}), T = {}, every scheme with each of its masses. Exact solution by characteristics: {} contact phase(s) up to T, \
         the first on [{}, {}) (gap and gap + 2L/c); contact force λ(t_n) in [{}, {}] at every t_n inside it (−√(Eρ)); rebound velocity {} \
         (mean velocity of its nodal interpolant over [T − {}, T]); energy {}.\n",
        fmt_f64(config.length),
        fmt_f64(gap),
        dx_dt(config),
        fmt_f64(REBOUND_END),
        x.contacts.len(),
        fmt_f64(start),
        fmt_f64(stop),
        fmt_f64(x.force.0),
        fmt_f64(x.force.1),
        fmt_f64(x.rebound_velocity),
        fmt_f64(REBOUND_WINDOW),
        fmt_f64(x.energy)
    );
    s.push_str(
        "Columns: the errors of the tables above, against that solution; every contact event is read off the force: first impact = first t_n with λ < 0, first release = \
         first later t_n with λ = 0 (so chatter counts), last contact = last t_n with λ < 0 before the bar leaves, each with \
         its shift from the exact start or end of the contact; contact episodes = runs of consecutive steps with λ < 0; rebound \
         velocity = slope of the discrete bar's centre of mass ū = 1ᵀMU / 1ᵀM1 over [T − 0.5, T] (momentum over mass; exact +1).\n\n(`rebound.csv`)\n\n",
    );
    s.push_str(&rebound_table(config, rb));
    let _ = writeln!(
        s,
        "\n![{REBOUND_FIGURE}]({REBOUND_FIGURE}.png)\n\nu_0(t) (left) and λ(t) (right) of each mass with Crank–Nicolson, against the exact solution (black dashed).\n"
    );
    s.push_str(&chatter_note(rb));
    s.push_str("### Does mod3 still win when the bar arrives with a velocity?\n\n");
    s.push_str(&verdict(rb));
    s
}

/// A note on the runs whose contact node leaves the obstacle more than once before it is
/// released for good (more than one contact episode), empty if there are none.
fn chatter_note(rb: &Rebound) -> String {
    let chatter: Vec<String> = rb
        .runs
        .iter()
        .filter(|r| r.contact_episodes > 1)
        .map(|r| {
            let (lo, hi) = band::band(&r.over_runs(|_, _, n, _| n as f64));
            let n = if lo == hi { r.contact_episodes.to_string() } else { format!("{lo}–{hi} over its runs") };
            format!("{} {} ({n})", r.experiment.title(), r.mass.name())
        })
        .collect();
    if chatter.is_empty() {
        return String::new();
    }
    let mut s = format!(
        "More than one contact episode (the first release is then a chatter, not the end of the contact; the last contact is): {}.",
        chatter.join(", ")
    );
    if rb.runs.iter().any(|r| r.experiment == Experiment::PaoliSchatzman && r.contact_episodes > 1) {
        s.push_str(
            " Paoli–Schatzman imposes the contact on (u_0^{n+1} + u_0^{n−1})/2, so its u_0 alternates around −gap during the contact.",
        );
    }
    s.push_str("\n\n");
    s
}

/// One panel of [`rebound_figure`]: each mass's curve and the exact one, on the exact curve's
/// range widened as in the paper figures; masses that leave it are named in the title.
fn panel(what: &str, y_label: &str, exact: Vec<(f64, f64)>, curves: Vec<(&MassKind, Vec<(f64, f64)>)>) -> Panel {
    let exact_range = plot::data_range(exact.iter().map(|p| p.1), 0.0);
    let all = curves.iter().flat_map(|(_, c)| c.iter().map(|p| p.1)).chain(exact.iter().map(|p| p.1));
    let y_range = clamped_range(plot::data_range(all, 0.0), exact_range);
    let mut notes = Vec::new();
    let mut out: Vec<Curve> = curves
        .into_iter()
        .map(|(m, pts)| {
            let values: Vec<f64> = pts.iter().map(|p| p.1).collect();
            notes.extend(off_scale(
                m.name(),
                &values,
                y_range,
                super::rebound::rebound_sensitive(Experiment::CrankNicolson, m),
            ));
            Curve { label: m.name().into(), points: pts, style: mass_style(m) }
        })
        .collect();
    out.push(Curve { label: "exact".into(), points: exact, style: Style::Exact });
    let title = if notes.is_empty() { what.to_string() } else { format!("{what}; off-scale: {}", notes.join("; ")) };
    Panel {
        title,
        x_label: "t".into(),
        y_label: y_label.into(),
        curves: out,
        x_range: Some((0.0, REBOUND_END)),
        y_range: Some(y_range),
    }
}

/// `rebound-u0`: u_0(t) and λ(t) of every mass with Crank–Nicolson and the exact solution by
/// characteristics, sampled at the grid times (its kinks, t = gap and gap + 2L/c, are grid
/// times here); the CSV holds t, the exact values and each mass's.
pub(super) fn rebound_figure(config: &Config, rb: &Rebound) -> FigureFile {
    let group: Vec<&ReboundResult> = rb.runs.iter().filter(|r| r.experiment == Experiment::CrankNicolson).collect();
    let times = group.iter().map(|r| r.motion.t.clone()).max_by_key(Vec::len).unwrap_or_default();
    let exact_u0: Vec<f64> = times.iter().map(|&t| rb.solution.u0(t)).collect();
    let exact_lambda: Vec<f64> = times.iter().map(|&t| rb.solution.lambda(t)).collect();
    let mut header = vec!["t".to_string(), "exact_u0".into(), "exact_lambda".into()];
    let mut columns = vec![exact_u0.clone(), exact_lambda.clone()];
    for r in &group {
        header.push(format!("u0_{}", r.mass.name()));
        header.push(format!("lambda_{}", r.mass.name()));
        columns.push(r.motion.u0.clone());
        columns.push(r.motion.lambda.clone());
    }
    let u0 = group.iter().map(|r| (&r.mass, points(&r.motion.t, &r.motion.u0))).collect();
    let lambda = group.iter().map(|r| (&r.mass, points(&r.motion.t, &r.motion.lambda))).collect();
    let panels = vec![
        panel("contact-node displacement u_0(t)", "u_0", points(&times, &exact_u0), u0),
        panel("contact force λ(t)", "λ", points(&times, &exact_lambda), lambda),
    ];
    let title =
        format!("Rebounding bar (beyond the paper): Crank–Nicolson, {}, T = {}", dx_dt(config), fmt_f64(REBOUND_END));
    FigureFile::two_panels(REBOUND_FIGURE.into(), title, panels, (header, grid_rows(&times, &columns)))
}
