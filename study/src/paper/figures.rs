//! The figures, as data (drawing is in [`crate::plot`]): the paper's odd figures (u_0 and λ
//! against the exact solution), even figures (energy) and the long runs' energy, each with the
//! CSV behind it.

use super::experiments::massless_contact;
use super::runs::{CaseResult, groups};
use super::tables::{horizon_tag, sig, write_csv};
use super::{Config, Experiment, Purpose};
use crate::plot::{self, Curve, Figure, Panel, Style};
use massredist::exact::ImpactingBar;
use massredist::mass::MassKind;
use massredist::output::fmt_f64;
use massredist::scene::Column;
use std::path::Path;

/// The exact u(0, t) on [0, end]: affine between the multiples of L (flight, contact, release).
pub fn exact_u0_polyline(exact: &ImpactingBar, end: f64) -> Vec<(f64, f64)> {
    let l = exact.length;
    let mut pts: Vec<(f64, f64)> =
        (0..).map(|k| k as f64 * l).take_while(|&t| t < end).map(|t| (t, exact.u0(t))).collect();
    pts.push((end, exact.u0(end)));
    pts
}

/// The exact λ(t) on [0, end]: 0, with the value of the open contact intervals ((3j+1)L, (3j+2)L)
/// drawn as vertical jumps.
pub fn exact_lambda_polyline(exact: &ImpactingBar, end: f64) -> Vec<(f64, f64)> {
    let l = exact.length;
    let mut pts = vec![(0.0, exact.lambda(0.0))];
    let mut j = 0;
    loop {
        let (a, b) = ((3 * j + 1) as f64 * l, (3 * j + 2) as f64 * l);
        if a >= end {
            break;
        }
        let b = b.min(end);
        let v = exact.lambda(0.5 * (a + b));
        pts.extend([(a, 0.0), (a, v), (b, v), (b, exact.lambda(b))]);
        j += 1;
    }
    pts.push((end, exact.lambda(end)));
    pts
}

/// File stem of the odd (solution) figure of `e` at horizon `end`, e.g. `fig11-crank-nicolson-T3`.
pub(super) fn solution_stem(e: Experiment, end: f64) -> String {
    format!("fig{}-{}-{}", e.paper_figures().0, e.slug(), horizon_tag(end))
}

/// File stem of the even (energy) figure, long runs included, e.g. `fig12-crank-nicolson-energy-T3`.
pub(super) fn energy_stem(e: Experiment, end: f64) -> String {
    format!("fig{}-{}-energy-{}", e.paper_figures().1, e.slug(), horizon_tag(end))
}

/// A figure with the table behind it.
pub(super) struct FigureFile {
    pub(super) stem: String,
    pub(super) figure: Figure,
    pub(super) header: Vec<String>,
    pub(super) rows: Vec<Vec<String>>,
    /// The per-period table of a long run (`<stem>-periods.csv`).
    pub(super) periods: Option<(Vec<String>, Vec<Vec<String>>)>,
}

impl FigureFile {
    /// Two panels side by side, with the CSV (header, rows) behind them.
    pub(super) fn two_panels(
        stem: String,
        title: String,
        panels: Vec<Panel>,
        csv: (Vec<String>, Vec<Vec<String>>),
    ) -> Self {
        let (header, rows) = csv;
        let figure = Figure { title, panels, columns: 2, panel_size: (820, 520) };
        FigureFile { stem, figure, header, rows, periods: None }
    }

    /// The names of the files [`FigureFile::write`] writes.
    pub(super) fn file_names(&self) -> Vec<String> {
        let mut out: Vec<String> = ["png", "svg", "csv"].map(|x| format!("{}.{x}", self.stem)).into();
        if self.periods.is_some() {
            out.push(format!("{}-periods.csv", self.stem));
        }
        out
    }

    /// Writes `<stem>.png`, `<stem>.svg`, `<stem>.csv` and, for a long run, `<stem>-periods.csv`
    /// into `dir`.
    pub(super) fn write(&self, dir: &Path) -> std::io::Result<()> {
        plot::write_png(&self.figure, &dir.join(format!("{}.png", self.stem))).map_err(std::io::Error::other)?;
        plot::write_svg(&self.figure, &dir.join(format!("{}.svg", self.stem))).map_err(std::io::Error::other)?;
        write_csv(&dir.join(format!("{}.csv", self.stem)), &self.header, &self.rows)?;
        if let Some((header, rows)) = &self.periods {
            write_csv(&dir.join(format!("{}-periods.csv", self.stem)), header, rows)?;
        }
        Ok(())
    }
}

pub(super) fn points(t: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    t.iter().copied().zip(y.iter().copied()).collect()
}

/// CSV rows on the time grid of the longest series; a run that stopped early leaves its later
/// cells empty.
pub(super) fn grid_rows(times: &[f64], columns: &[Vec<f64>]) -> Vec<Vec<String>> {
    times
        .iter()
        .enumerate()
        .map(|(n, &t)| {
            std::iter::once(fmt_f64(t))
                .chain(columns.iter().map(|c| c.get(n).map_or(String::new(), |&v| fmt_f64(v))))
                .collect()
        })
        .collect()
}

fn longest_times(group: &[&CaseResult]) -> Vec<f64> {
    group.iter().map(|r| r.series.times()).max_by_key(|t| t.len()).unwrap_or_default()
}

pub(super) fn dx_dt(config: &Config) -> String {
    format!("Δx = {}/{}, Δt = {}", fmt_f64(config.length), config.elements, fmt_f64(config.dt))
}

/// A panel's y-range: the data's, clamped to the exact curve's range widened by its length on
/// both sides (so that a wild numerical curve does not flatten the others), then padded by 5 %.
/// Curves that leave it are named in the panel title ([`off_scale`]).
pub(super) fn clamped_range(data: (f64, f64), exact: (f64, f64)) -> (f64, f64) {
    let span = exact.1 - exact.0;
    let (lo, hi) = (data.0.max(exact.0 - span), data.1.min(exact.1 + span));
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

/// "standard: min −24.9" if some values lie outside `range`, else None. For a round-off
/// sensitive run (`sensitive`: its extremes change with a 1e-13 perturbation of the initial state)
/// only which side it leaves, with no digits: "standard: above (round-off sensitive)".
pub(super) fn off_scale(label: &str, values: &[f64], range: (f64, f64), sensitive: bool) -> Option<String> {
    let (lo, hi) = values
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
    let mut notes = Vec::new();
    if lo < range.0 {
        notes.push(if sensitive { "below".to_string() } else { format!("min {}", sig(lo, 3)) });
    }
    if hi > range.1 {
        notes.push(if sensitive { "above".to_string() } else { format!("max {}", sig(hi, 3)) });
    }
    let tail = if sensitive { " (round-off sensitive)" } else { "" };
    (!notes.is_empty()).then(|| format!("{label} {}{tail}", notes.join(", ")))
}

/// Colour index of a mass, the same in every figure.
pub(super) fn mass_style(mass: &MassKind) -> Style {
    Style::Numeric(match mass {
        MassKind::Standard => 0,
        MassKind::Mod1 => 1,
        MassKind::Mod2 => 2,
        MassKind::Mod3 => 3,
        MassKind::Custom(_) => 4,
    })
}

/// The odd paper figure: u_0(t) and λ(t) of every mass against the exact solution.
fn solution_figure(config: &Config, group: &[&CaseResult]) -> FigureFile {
    let c0 = &group[0].case;
    let (fig, _) = c0.experiment.paper_figures();
    let exact = config.exact();
    let end = c0.end;
    let times = longest_times(group);
    let mut panels = Vec::new();
    let mut columns =
        vec![times.iter().map(|&t| exact.u0(t)).collect::<Vec<_>>(), times.iter().map(|&t| exact.lambda(t)).collect()];
    let mut header = vec!["t".to_string(), "exact_u0".into(), "exact_lambda".into()];
    for r in group {
        header.push(format!("u0_{}", r.case.mass.name()));
        header.push(format!("lambda_{}", r.case.mass.name()));
        columns.push(r.col(Column::U0));
        columns.push(r.col(Column::Lambda));
    }
    for (col, exact_pts, what, ylabel) in [
        (Column::U0, exact_u0_polyline(&exact, end), "contact-node displacement u_0(t)", "u_0"),
        (Column::Lambda, exact_lambda_polyline(&exact, end), "contact force λ(t)", "λ"),
    ] {
        let exact_range = plot::data_range(exact_pts.iter().map(|p| p.1), 0.0);
        let all = group.iter().flat_map(|r| r.col(col)).chain(exact_pts.iter().map(|p| p.1));
        let y_range = clamped_range(plot::data_range(all, 0.0), exact_range);
        let mut notes = Vec::new();
        let mut curves: Vec<Curve> = group
            .iter()
            .map(|r| {
                let v = r.col(col);
                notes.extend(off_scale(r.case.mass.name(), &v, y_range, r.sensitive()));
                Curve {
                    label: r.case.mass.name().into(),
                    points: points(&r.series.times(), &v),
                    style: mass_style(&r.case.mass),
                }
            })
            .collect();
        curves.push(Curve { label: "exact".into(), points: exact_pts, style: Style::Exact });
        let title =
            if notes.is_empty() { what.to_string() } else { format!("{what}; off-scale: {}", notes.join("; ")) };
        panels.push(Panel {
            title,
            x_label: "t".into(),
            y_label: ylabel.into(),
            curves,
            x_range: Some((0.0, end)),
            y_range: Some(y_range),
        });
    }
    let title = format!("Fig. {fig} analogue: {}, {}, T = {}", c0.experiment.title(), dx_dt(config), fmt_f64(end));
    FigureFile::two_panels(solution_stem(c0.experiment, end), title, panels, (header, grid_rows(&times, &columns)))
}

/// A mass's energy curve.
fn energy_curve(r: &CaseResult) -> Curve {
    Curve {
        label: r.case.mass.name().into(),
        points: points(&r.series.times(), &r.col(Column::Energy)),
        style: mass_style(&r.case.mass),
    }
}

/// The exact energy L/8, constant on [0, end].
fn exact_energy_curve(exact: &ImpactingBar, end: f64) -> Curve {
    Curve {
        label: format!("exact (L/8 = {})", fmt_f64(exact.energy())),
        points: vec![(0.0, exact.energy()), (end, exact.energy())],
        style: Style::Exact,
    }
}

/// An energy figure (two panels side by side) and the CSV behind it: t, the exact energy L/8 and
/// each mass's energy on the time grid of the longest run.
fn energy_file(
    config: &Config,
    group: &[&CaseResult],
    title: String,
    panels: Vec<Panel>,
    periods: Option<(Vec<String>, Vec<Vec<String>>)>,
) -> FigureFile {
    let c0 = &group[0].case;
    let exact = config.exact();
    let times = longest_times(group);
    let mut header = vec!["t".to_string(), "exact_energy".into()];
    let mut columns = vec![vec![exact.energy(); times.len()]];
    for r in group {
        header.push(format!("energy_{}", r.case.mass.name()));
        columns.push(r.col(Column::Energy));
    }
    let csv = (header, grid_rows(&times, &columns));
    FigureFile { periods, ..FigureFile::two_panels(energy_stem(c0.experiment, c0.end), title, panels, csv) }
}

/// A panel of energy against t on [0, end].
fn energy_panel(title: String, curves: Vec<Curve>, end: f64, y_range: Option<(f64, f64)>) -> Panel {
    Panel { title, x_label: "t".into(), y_label: "energy".into(), curves, x_range: Some((0.0, end)), y_range }
}

/// The even paper figure: the energy of every mass (left) and a zoom on the w_0 = 0 masses after
/// the first step (right; their first step loses ≈ h/8 at once, see the report).
fn energy_figure(config: &Config, group: &[&CaseResult]) -> FigureFile {
    let c0 = &group[0].case;
    let (_, fig) = c0.experiment.paper_figures();
    let end = c0.end;
    let mut full: Vec<Curve> = group.iter().map(|r| energy_curve(r)).collect();
    full.push(exact_energy_curve(&config.exact(), end));
    let title =
        format!("Fig. {fig} analogue: energy, {}, {}, T = {}", c0.experiment.title(), dx_dt(config), fmt_f64(end));
    let panels =
        vec![energy_panel("energy ½VᵀMV + ½UᵀSU".into(), full, end, None), energy_zoom_panel(config, group, end)];
    energy_file(config, group, title, panels, None)
}

/// The right panel of [`energy_figure`]: the w_0 = 0 masses from t = Δt on, on their own range
/// (the exact energy is drawn only if it falls in it; otherwise the title says where it is).
fn energy_zoom_panel(config: &Config, group: &[&CaseResult], end: f64) -> Panel {
    let exact = config.exact();
    let zoomed: Vec<&&CaseResult> = group.iter().filter(|r| massless_contact(&r.case.mass)).collect();
    let zoom_range = plot::data_range(
        zoomed.iter().flat_map(|r| {
            let e = r.col(Column::Energy);
            r.series
                .times()
                .into_iter()
                .zip(e)
                .filter(|(t, _)| *t > 0.5 * config.dt)
                .map(|(_, v)| v)
                .collect::<Vec<_>>()
        }),
        0.08,
    );
    let mut zoom: Vec<Curve> = zoomed.iter().map(|r| energy_curve(r)).collect();
    let exact_visible = exact.energy() >= zoom_range.0 && exact.energy() <= zoom_range.1;
    let zoom_title = if exact_visible {
        "zoom: w_0 = 0 masses, t ≥ Δt".to_string()
    } else {
        zoom.push(exact_energy_curve(&exact, end));
        format!("zoom: w_0 = 0 masses, t ≥ Δt (exact {} off-scale)", fmt_f64(exact.energy()))
    };
    energy_panel(zoom_title, zoom, end, Some(zoom_range))
}

/// The long-run energy figure: the raw energy (left, every [`Config::long_every`] steps, clamped
/// to [0, 3 L/8] so that one diverging mass does not hide the others) and log10 of each period's
/// maximum energy (right: exponential growth is a straight line). CSVs: `<stem>.csv` (left) and
/// `<stem>-periods.csv` (right, with the per-period minimum too).
fn long_energy_figure(config: &Config, group: &[&CaseResult]) -> FigureFile {
    let c0 = &group[0].case;
    let (_, fig) = c0.experiment.paper_figures();
    let exact = config.exact();
    let end = c0.end;
    let title = format!(
        "Fig. {fig} analogue, long run: energy, {}, {}, T = {} ({} periods)",
        c0.experiment.title(),
        dx_dt(config),
        fmt_f64(end),
        fmt_f64(end / exact.period())
    );
    let panels = vec![long_energy_panel(config, group, end), period_max_panel(&exact, group, end)];
    energy_file(config, group, title, panels, Some(period_table(group, end)))
}

/// The left panel of [`long_energy_figure`]: the raw energy, clamped to [0, 3 L/8]; the masses
/// that leave that range are named in the title.
fn long_energy_panel(config: &Config, group: &[&CaseResult], end: f64) -> Panel {
    let exact = config.exact();
    let every = config.long_every(config.steps("long_ends", end).unwrap_or(1));
    let data = plot::data_range(group.iter().flat_map(|r| r.col(Column::Energy)), 0.0);
    let y_range = plot::data_range([data.0.max(0.0), data.1.min(3.0 * exact.energy())].into_iter(), 0.05);
    let mut notes = Vec::new();
    let mut raw: Vec<Curve> = group
        .iter()
        .map(|r| {
            notes.extend(off_scale(r.case.mass.name(), &r.col(Column::Energy), y_range, r.sensitive()));
            energy_curve(r)
        })
        .collect();
    raw.push(exact_energy_curve(&exact, end));
    let raw_title = if notes.is_empty() {
        format!("energy, every {every} steps")
    } else {
        format!("energy, every {every} steps; off-scale: {}", notes.join("; "))
    };
    energy_panel(raw_title, raw, end, Some(y_range))
}

/// The right panel of [`long_energy_figure`]: log10 of the maximum energy of each full period.
fn period_max_panel(exact: &ImpactingBar, group: &[&CaseResult], end: f64) -> Panel {
    let mut per: Vec<Curve> = group
        .iter()
        .map(|r| Curve {
            label: r.case.mass.name().into(),
            points: r
                .periods
                .max
                .iter()
                .enumerate()
                .filter(|(j, _)| r.periods.end_of(*j) <= end * (1.0 + 1e-9))
                .map(|(j, &m)| (r.periods.end_of(j), m.log10()))
                .collect(),
            style: mass_style(&r.case.mass),
        })
        .collect();
    per.push(Curve {
        label: format!("exact (L/8 = {})", fmt_f64(exact.energy())),
        points: vec![(0.0, exact.energy().log10()), (end, exact.energy().log10())],
        style: Style::Exact,
    });
    Panel {
        title: "log10 of the maximum energy of each period 3L (t ≥ Δt)".into(),
        x_label: "t (end of the period)".into(),
        y_label: "log10 max energy".into(),
        curves: per,
        x_range: Some((0.0, end)),
        y_range: None,
    }
}

/// `<stem>-periods.csv` of a long run: per period, its end time and each mass's energy extremes.
fn period_table(group: &[&CaseResult], end: f64) -> (Vec<String>, Vec<Vec<String>>) {
    let n_periods = group.iter().map(|r| r.periods.max.len()).max().unwrap_or(0);
    let mut p_header = vec!["period".to_string(), "t_end".into()];
    for r in group {
        p_header.push(format!("max_energy_{}", r.case.mass.name()));
        p_header.push(format!("min_energy_{}", r.case.mass.name()));
    }
    let p_rows = (0..n_periods)
        .map(|j| {
            let mut row = vec![j.to_string(), fmt_f64(group[0].periods.end_of(j).min(end))];
            for r in group {
                let get = |v: &Vec<f64>| v.get(j).map_or(String::new(), |&x| fmt_f64(x));
                row.push(get(&r.periods.max));
                row.push(get(&r.periods.min));
            }
            row
        })
        .collect();
    (p_header, p_rows)
}

/// Every figure of `results`: solution and energy per (horizon, scheme), and the long runs' energy.
pub(super) fn figure_files(config: &Config, results: &[CaseResult]) -> Vec<FigureFile> {
    let mut out = Vec::new();
    for g in groups(results) {
        match g[0].case.purpose {
            Purpose::Figures => {
                out.push(solution_figure(config, &g));
                out.push(energy_figure(config, &g));
            }
            Purpose::LongEnergy => out.push(long_energy_figure(config, &g)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_polylines_hit_the_kinks() {
        let b = ImpactingBar { length: 1.0 };
        let u = exact_u0_polyline(&b, 3.0);
        assert_eq!(u, vec![(0.0, 0.5), (1.0, 0.0), (2.0, 0.0), (3.0, 0.5)]);
        let l = exact_lambda_polyline(&b, 3.0);
        assert_eq!(l, vec![(0.0, 0.0), (1.0, 0.0), (1.0, -0.5), (2.0, -0.5), (2.0, 0.0), (3.0, 0.0)]);
    }
}
