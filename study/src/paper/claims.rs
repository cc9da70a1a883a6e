//! The paper's qualitative claims, each checked on the computed values: one function per claim,
//! each returning its rows of the claims table in `report.md`.

use super::band::Verdict;
use super::band::stable_digits;
use super::experiments::massless_contact;
use super::runs::{
    CaseResult, EnergyVariation, PeriodEvents, energy_jumps, events, period_over_runs, variation_after_impact,
};
use super::tables::{agreed_values, shift, sig, time, variation_cells, verdict_note};
use super::{Config, Experiment, Purpose};
use massredist::mass::MassKind;
use massredist::output::fmt_f64;
use massredist::scene::Column;
use std::fmt::Write as _;

/// The claims section of `report.md`: a table with one row per claim, scheme and horizon, then
/// the thresholds the verdicts use.
pub(super) fn claims(config: &Config, results: &[CaseResult]) -> String {
    let mut s = String::from(
        "## The paper's claims against these runs\n\n| claim | horizon | measured | holds? |\n|---|---|---|---|\n",
    );
    s.push_str(&smallest_error(config, results));
    s.push_str(&phase(config, results));
    s.push_str(&energy_direction(config, results));
    s.push_str(&dissipation(config, results));
    s.push_str(&long_run_stability(config, results));
    s.push_str(
        "\nThresholds: \"within one Δt\" because events are read on the time grid; an energy step counts as up or down above the round-off floor 1e3·ε·L/8; \"very light\" is a loss under 1 %, \"a lot\" over 10 % of E(Δt) at the longest horizon; \"drift\" is a per-period maximum energy up by more than 5 % from the first to the last (up to 10) periods, \"unstable\" an energy above 10 E(0) or a diverged run (a non-finite state, or an energy above 10⁶ E(0), where the run stops).\n",
    );
    s
}

fn yes(b: bool) -> &'static str {
    if b { "yes" } else { "**no**" }
}

/// The figure run of scheme `e` with mass `m` at horizon `end`.
fn find<'a>(results: &'a [CaseResult], e: Experiment, m: &MassKind, end: f64) -> Option<&'a CaseResult> {
    results.iter().find(|r| {
        r.case.purpose == Purpose::Figures && r.case.experiment == e && &r.case.mass == m && r.case.end == end
    })
}

/// Mod3 has the smallest L∞(0,T;L²) error, per scheme and horizon.
fn smallest_error(config: &Config, results: &[CaseResult]) -> String {
    let mut s = String::new();
    for &end in &config.horizons {
        for e in Experiment::ALL {
            let rows: Vec<&CaseResult> = e.masses().iter().filter_map(|m| find(results, e, m, end)).collect();
            let best = rows.iter().min_by(|a, b| {
                a.summary
                    .linf_l2_error
                    .unwrap_or(f64::INFINITY)
                    .total_cmp(&b.summary.linf_l2_error.unwrap_or(f64::INFINITY))
            });
            if let Some(best) = best {
                let _ = writeln!(
                    s,
                    "| mod3 has the smallest L∞(0,T;L²) error ({}) | T = {} | smallest: {} {} | {} |",
                    e.title(),
                    fmt_f64(end),
                    best.case.mass.name(),
                    best.stable(|s| s.linf_l2_error, 4),
                    yes(best.case.mass == MassKind::Mod3)
                );
            }
        }
    }
    s
}

/// The larger of a period's |impact shift| and |release shift| (infinite if an event is missing).
fn worst(ev: &PeriodEvents) -> f64 {
    [ev.impact_shift, ev.release_shift].iter().map(|x| x.map_or(f64::INFINITY, f64::abs)).fold(0.0, f64::max)
}

/// Phase: mod3's impact and release on time (within one Δt: events are read on the grid) in the
/// first period, and the smallest drift of all masses in the last one. Every event is read off
/// every run of the case (the perturbed copies too): a shift is shown as the one value all runs
/// give, else their range, and a verdict holds if it holds for every run.
fn phase(config: &Config, results: &[CaseResult]) -> String {
    let mut s = String::new();
    for &end in &config.horizons {
        for e in Experiment::ALL {
            let rows: Vec<&CaseResult> = e.masses().iter().filter_map(|m| find(results, e, m, end)).collect();
            let Some(mod3) = rows.iter().find(|r| r.case.mass == MassKind::Mod3) else { continue };
            let periods = events(config, mod3).len();
            if periods == 0 {
                continue;
            }
            if end == config.horizons[0] {
                let first = period_over_runs(config, mod3, 0);
                let _ = writeln!(
                    s,
                    "| no phase shift for mod3 ({}): first impact and release within one Δt of the exact times | T = {} | {} | {} |",
                    e.title(),
                    fmt_f64(end),
                    event_shifts(config, &first),
                    yes(first.iter().all(|p| worst(p) <= config.dt * (1.0 + 1e-9)))
                );
            }
            if periods > 1 {
                s.push_str(&last_period_phase(config, e, end, &rows, periods));
            }
        }
    }
    s
}

/// "impact X, release Y" of one period over the runs ([`agreed_values`]).
fn event_shifts(config: &Config, runs: &[PeriodEvents]) -> String {
    let show = |x: Option<f64>| shift(x, config.dt);
    format!(
        "impact {}, release {}",
        agreed_values(&runs.iter().map(|p| p.impact_shift).collect::<Vec<_>>(), show),
        agreed_values(&runs.iter().map(|p| p.release_shift).collect::<Vec<_>>(), show)
    )
}

/// The last-period rows of [`phase`]: mod3 has the smallest shift of all masses in period
/// `periods` (in every run), and is still within one Δt of the exact times.
fn last_period_phase(config: &Config, e: Experiment, end: f64, rows: &[&CaseResult], periods: usize) -> String {
    let mut s = String::new();
    let last_of = |r: &CaseResult| period_over_runs(config, r, periods - 1);
    let Some(mod3) = rows.iter().find(|r| r.case.mass == MassKind::Mod3) else { return s };
    let last = last_of(mod3);
    let mod3_worst = last.iter().map(worst).fold(0.0, f64::max);
    let others: Vec<String> = rows
        .iter()
        .map(|r| {
            let w: Vec<Option<f64>> = last_of(r).iter().map(|p| Some(worst(p))).collect();
            format!("{} {}", r.case.mass.name(), if w.is_empty() { "—".into() } else { stable_digits(&w, 2) })
        })
        .collect();
    let best = rows.iter().all(|r| last_of(r).iter().all(|p| worst(p) >= mod3_worst));
    let _ = writeln!(
        s,
        "| mod3 has the smallest phase shift ({}) in period {} | T = {} | max \\|impact/release shift\\| in the last period: {} | {} |",
        e.title(),
        periods,
        fmt_f64(end),
        others.join(", "),
        yes(best)
    );
    let _ = writeln!(
        s,
        "| no phase shift for mod3 ({}) after {} periods: within one Δt | T = {} | {} | {} |",
        e.title(),
        periods,
        fmt_f64(end),
        event_shifts(config, &last),
        yes(mod3_worst <= config.dt * (1.0 + 1e-9))
    );
    s
}

/// Energy after impact, w_0 = 0 masses at the paper's horizon: Crank–Nicolson conserves it
/// between contact switches (so it is piecewise constant, jumping where contact starts or ends),
/// Paoli–Schatzman moves it up and down (the paper's "small oscillations"), the dissipative
/// schemes only down. Read on every run of each case; a verdict holds if it holds for all.
fn energy_direction(config: &Config, results: &[CaseResult]) -> String {
    let mut s = String::new();
    let end = config.horizons[0];
    for e in Experiment::ALL {
        let runs: Vec<&CaseResult> =
            e.masses().iter().filter(|m| massless_contact(m)).filter_map(|m| find(results, e, m, end)).collect();
        if e == Experiment::CrankNicolson {
            s.push_str(&piecewise_constant(config, &runs, end));
            continue;
        }
        let vars: Vec<(String, Vec<EnergyVariation>)> = runs
            .iter()
            .filter_map(|r| {
                let v: Option<Vec<EnergyVariation>> = variation_after_impact(config, r).into_iter().collect();
                Some((r.case.mass.name().to_string(), v?))
            })
            .collect();
        let measured = vars
            .iter()
            .filter_map(|(m, v)| {
                let [up, down, n_up, n_down] = variation_cells(&v.iter().copied().map(Some).collect::<Vec<_>>())?;
                Some(format!("{m} {up}/{down} ({n_up}↑ {n_down}↓ steps)"))
            })
            .collect::<Vec<_>>()
            .join(", ");
        let all = |f: &dyn Fn(&EnergyVariation) -> bool| vars.iter().all(|(_, v)| v.iter().all(f));
        let (claim, holds) = if e.second_order() {
            (
                format!(
                    "energy goes up and down after impact ({}, second order; read on the central-velocity energy, which moves before impact too: the half-step energy is in the section \"Paoli–Schatzman: energy growth against Δt/h\")",
                    e.title()
                ),
                all(&|v| v.up_steps > 0 && v.down_steps > 0),
            )
        } else {
            (format!("energy never goes up after impact ({})", e.title()), all(&|v| v.up_steps == 0))
        };
        let _ = writeln!(
            s,
            "| {claim} | T = {} | Σ(ΔE)⁺/Σ(ΔE)⁻ from the impact step on (round-off: no step above the floor): {measured} | {} |",
            fmt_f64(end),
            yes(holds)
        );
    }
    s
}

/// Crank–Nicolson with w_0 = 0 (the row of [`energy_direction`]): after the first step the
/// energy changes only in steps where the contact state switches (in every run of the case).
fn piecewise_constant(config: &Config, runs: &[&CaseResult], end: f64) -> String {
    let jumps: Vec<(String, Vec<Vec<(f64, bool)>>)> = runs
        .iter()
        .map(|r| (r.case.mass.name().to_string(), r.over_series(|_, series| energy_jumps(config, series))))
        .collect();
    let measured = jumps
        .iter()
        .map(|(m, j)| {
            let text = |j: &Vec<(f64, bool)>| {
                let at: Vec<String> = j.iter().map(|(t, _)| time(*t, config.dt)).collect();
                let switching = j.iter().filter(|(_, sw)| *sw).count();
                format!("{} jumps ({switching} at a contact switch), t = {}", j.len(), at.join(", "))
            };
            let texts: Vec<String> = j.iter().map(text).collect();
            if texts.iter().all(|t| *t == texts[0]) {
                format!("{m}: {}", texts[0])
            } else {
                let n: Vec<Option<f64>> = j.iter().map(|j| Some(j.len() as f64)).collect();
                format!("{m}: {} jumps, at times that differ between the runs", stable_digits(&n, 3))
            }
        })
        .collect::<Vec<_>>()
        .join("; ");
    let holds = jumps.iter().all(|(_, j)| j.iter().all(|j| !j.is_empty() && j.iter().all(|(_, sw)| *sw)));
    format!(
        "| Crank–Nicolson's energy after the first step is piecewise constant (w_0 = 0): it changes only in steps where contact starts or ends | T = {} | steps moving E by more than the round-off floor: {measured} | {} |\n",
        fmt_f64(end),
        yes(holds)
    )
}

/// Dissipation: hybrid slight, backward Euler strong (mod3, longest horizon, relative to E(Δt)),
/// over every run of the case (shared digits).
fn dissipation(config: &Config, results: &[CaseResult]) -> String {
    let mut s = String::new();
    let end = *config.horizons.last().unwrap_or(&3.0);
    // Per run: (loss, E(Δt), E(T)).
    let loss = |e: Experiment| {
        find(results, e, &MassKind::Mod3, end).map(|r| {
            r.over_series(|summary, series| {
                let e1 = series.column(Column::Energy).and_then(|e| e.get(1).copied()).unwrap_or(f64::NAN);
                (1.0 - summary.energy_final / e1, e1, summary.energy_final)
            })
        })
    };
    let col = |v: &[(f64, f64, f64)], k: usize, d: usize| {
        stable_digits(&v.iter().map(|x| Some([x.0, x.1, x.2][k])).collect::<Vec<_>>(), d)
    };
    if let (Some(h), Some(b)) = (loss(Experiment::Hybrid), loss(Experiment::BackwardEuler)) {
        let pcts =
            |v: &[(f64, f64, f64)]| stable_digits(&v.iter().map(|x| Some(100.0 * x.0)).collect::<Vec<_>>(), 3) + " %";
        let _ = writeln!(
            s,
            "| the hybrid scheme dissipates very lightly (mod3) | T = {} | E(Δt) {} → E(T) {}: loss {} of E(Δt) | {} |",
            fmt_f64(end),
            col(&h, 1, 6),
            col(&h, 2, 6),
            pcts(&h),
            yes(h.iter().all(|x| (0.0..0.01).contains(&x.0)))
        );
        let ratio: Vec<Option<f64>> = h.iter().zip(&b).map(|(h, b)| Some(b.0 / h.0)).collect();
        let _ = writeln!(
            s,
            "| backward Euler dissipates a lot (mod3) | T = {} | E(Δt) {} → E(T) {}: loss {} of E(Δt), {}× the hybrid's | {} |",
            fmt_f64(end),
            col(&b, 1, 6),
            col(&b, 2, 6),
            pcts(&b),
            stable_digits(&ratio, 3),
            yes(b.iter().all(|x| x.0 > 0.1))
        );
    }
    s
}

/// Long runs: the paper states Paoli–Schatzman is stable (§4.2.3, citing [DuP06VBCD]). These
/// runs amplify round-off, so the measured column gives each run's verdict and the band of its
/// per-period growth over the perturbed copies, not the digits of one run.
fn long_run_stability(config: &Config, results: &[CaseResult]) -> String {
    let mut s = String::new();
    for &end in &config.long_ends {
        let rows: Vec<&CaseResult> = results
            .iter()
            .filter(|r| r.case.purpose == Purpose::LongEnergy && r.case.end == end && massless_contact(&r.case.mass))
            .collect();
        let measured: Vec<String> = rows.iter().map(|r| format!("{} {}", r.case.mass.name(), growth_band(r))).collect();
        let bounded = rows.iter().all(|r| r.verdicts().iter().all(|(v, _)| *v == Verdict::Bounded));
        let _ = writeln!(
            s,
            "| Paoli–Schatzman (β=1/4, e=1) with w_0 = 0 keeps a bounded energy with no drift (the paper cites [DuP06] for its stability; here Δt/h = {}; the growth depends on Δt/h, see the section \"Paoli–Schatzman: energy growth against Δt/h\") | T = {} | {}; growth = last/first per-period max (central-velocity) energy | {} |",
            sig(config.dt / config.h(), 2),
            fmt_f64(end),
            measured.join(", "),
            yes(bounded)
        );
    }
    s
}

/// "growth ×a–×b; 5 runs from U⁰ perturbed by ≤ 1e-13: …" for a long run (the band over its
/// runs; the growth of a diverged run is up to where it stopped).
pub(super) fn growth_band(r: &CaseResult) -> String {
    let g: Vec<Option<f64>> = r.verdicts().iter().map(|(_, g)| *g).collect();
    let stopped = r.over_runs(|s| s.divergence.map(|d| d.time));
    // The stop time only where every run stopped: whether one more run crosses the divergence
    // threshold before T is itself round-off (the verdict range says so).
    let when = if stopped.iter().all(Option::is_some) {
        format!(", stopped at t = {}", super::band::stable_digits(&stopped, 4))
    } else {
        String::new()
    };
    format!("growth ×{}{when}{}", super::band::stable_digits(&g, 3), verdict_note(r))
}
