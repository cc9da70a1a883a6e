//! The sections of `massredist reproduce` that answer issue 22's questions about the paper's
//! claims: the scope of "mod3 is best" over meshes and horizons (`paper::mesh_scope`) and
//! Paoli–Schatzman's energy growth against Δt/h on its half-step energy (`paper::ps_growth`);
//! the Table 1 lead at Δt = h/2, T = 2 (`paper::table2d_lead`).

use massredist_study::paper::{self, Config};

/// The mesh-scope entries at the paper's mesh and horizon (m = 6, T = 3) are the L∞(0,T;L²)
/// errors of the paper's runs (`run_case`, through `SummaryObserver`: another observer of the
/// same state), the T = 2 error is at most the T = 3 one (a max over fewer steps), and every
/// entry has five runs. Broken on purpose: reading T = 2 as `t_n ≤ 0.9·T` (so that T = 3 stops at
/// 2.7) fails the first assertion.
#[test]
fn mesh_scope_at_the_paper_s_mesh_is_the_table_s_error() {
    use paper::mesh_scope::{SCOPE_ENDS, mesh_scope};
    let config = Config::paper();
    let entries = mesh_scope(&config).unwrap();
    for x in entries.iter().filter(|x| x.elements == 6 && x.end == 3.0) {
        let case =
            paper::Case { experiment: x.experiment, mass: x.mass.clone(), end: 3.0, purpose: paper::Purpose::Figures };
        let table = paper::run_case(&config, &case).unwrap().summary.linf_l2_error.unwrap();
        // Same states, same exact L² pass: equal to the last bit.
        assert_eq!(x.value(), table, "{} {}", x.experiment.slug(), x.mass.name());
    }
    for x in &entries {
        assert_eq!(x.errors.len(), 5);
        if x.end == SCOPE_ENDS[0] {
            let later = entries
                .iter()
                .find(|y| {
                    y.end == SCOPE_ENDS[1]
                        && y.experiment == x.experiment
                        && y.mass == x.mass
                        && y.elements == x.elements
                })
                .unwrap();
            assert!(x.value() <= later.value());
        }
    }
}

/// Paoli–Schatzman with β = ¼ conserves the half-step energy without contact: before the first
/// impact it stays at E^{3/2} to round-off in every growth run (all masses, Δt = h, h/4, h/8, five
/// runs each), which is what makes it the measure of growth. And with Δt = h every run of every
/// mass is stopped by the divergence rule (the expected failure the section reports). Broken on
/// purpose: Σ = (U^{n+1} − Uⁿ)/2 instead of the sum in `HalfStep` fails the first assertion
/// (drift of order 1).
#[test]
fn the_half_step_energy_is_conserved_before_impact_and_dt_h_diverges() {
    use paper::ps_growth::{PS_DT_DIVISORS, ps_growth};
    let ps = ps_growth(&Config::paper()).unwrap();
    assert_eq!(ps.growth.len(), 4 * PS_DT_DIVISORS.len());
    for g in &ps.growth {
        assert_eq!(g.runs.len(), 5);
        for r in &g.runs {
            // A sum of O(m) = 7 products per step over at most ~50 pre-impact steps: 1e-12 of E₀
            // is ample for round-off and far below any scheme error.
            assert!(r.pre_impact_drift < 1e-12, "{} h/{}: {r:?}", g.mass.name(), g.divisor);
            assert!(r.max_ratio >= 1.0 - 1e-12, "the maximum includes E₀ itself");
        }
        if g.divisor == 1 {
            assert!(g.runs.iter().all(|r| r.diverged), "{} at Δt = h: {:?}", g.mass.name(), g.runs);
        }
    }
    // Over one period at the paper's Δt the half-step energy does not move before the impact.
    for (m, moves) in &ps.moves {
        assert_eq!(moves[1][0], (0, 0), "{}", m.name());
    }
}

/// The Table 1 lead: its (1−x)/2 row is the plate code's error for the same set-up
/// (`plate_table::linf_l2_error`, built from `PaperPlate`, not from scene text), the (1−x)/4 row is
/// exactly half of it (gap 0 and f = 0: the problem and Crank–Nicolson's contact step are
/// positively homogeneous), and the sensitivity curve at Δt = h/2, T = 2 (the 1D bar with h =
/// 0.05) gives the same errors. Broken on purpose: writing u⁰ = (1-x)/2 for both rows in
/// `lead_rows` fails the halving assertion.
#[test]
fn the_table_1_lead_is_the_plate_s_error_and_halves_with_u0() {
    use massredist::fem::Cell;
    use massredist::mass::MassKind;
    use massredist::scene::SchemeSpec;
    use paper::table2d_lead::{LEAD_DT, LEAD_END, lead_rows, sensitivity};
    let [half, quarter] = lead_rows();
    let (half, quarter) = (half.unwrap(), quarter.unwrap());
    let curve = sensitivity().into_iter().find(|(dt, _)| *dt == LEAD_DT).unwrap().1;
    let at_end = curve.iter().find(|(t, _)| (t - LEAD_END).abs() < 1e-9).unwrap().1;
    for (k, m) in [MassKind::Mod1, MassKind::Mod2, MassKind::Mod3].iter().enumerate() {
        let plate =
            paper::plate_table::linf_l2_error(Cell::Quad, 20, m, &SchemeSpec::CRANK_NICOLSON, LEAD_DT, LEAD_END)
                .unwrap();
        // Same mesh and data by two constructions (closed-form initial data vs the expression
        // (1-x)/2): equal up to the rounding of the interpolated U⁰, a few ulps amplified by
        // 80 steps.
        assert!((half[k] - plate).abs() <= 1e-12 * plate, "{}: {} vs {plate}", m.name(), half[k]);
        // Halving u⁰ halves U⁰ exactly (a power of two), and every later operation scales.
        assert!((quarter[k] - 0.5 * half[k]).abs() <= 1e-12 * half[k], "{}", m.name());
        // The 1D bar with h = 0.05 is the Q1 plate with y-independent data (tests/plate.rs).
        assert!((at_end[k] - plate).abs() <= 1e-10 * plate, "{}: 1D {} vs 2D {plate}", m.name(), at_end[k]);
    }
}

/// The significant digits of a printed number ("0.04164" → 4, "0.125000" → 6, "2.5e-6" → 2).
fn printed_digits(cell: &str) -> usize {
    let mantissa = cell.trim_start_matches(['-', '+']).split('e').next().unwrap();
    mantissa.chars().filter(char::is_ascii_digit).skip_while(|&c| c == '0').count()
}

/// The leading significant digits on which all `values` agree (written here, not the library's).
fn shared_digits(values: &[f64]) -> usize {
    (1..=16)
        .rev()
        .find(|&d| values.iter().all(|v| format!("{v:.*e}", d - 1) == format!("{:.*e}", d - 1, values[0])))
        .unwrap_or(0)
}

/// Every number in the report's result tables (T = 3, 9 and the long run of `--quick`) has at most
/// the significant digits its five runs share: this case and its four reruns from U⁰ perturbed
/// by ≤ 1e-13 (a band "a–b" where they share fewer than two). Read from the Markdown the report
/// prints, against the runs' summaries. Broken on purpose: (1) `band::is_rerun` returning
/// `is_sensitive(case)` (only the known amplifiers rerun) fails the "four reruns" assertion;
/// (2) `table_markdown` printing `sig(s.linf_l2_error, 4)` of the one run instead of
/// `r.stable(…)` failed on Crank–Nicolson's standard mass at T = 6 ("0.2177"; its runs give 0.18 to 0.24), when
/// `--quick` ran T = 3 and 6 (T = 9 gives 0.26–0.48).
#[test]
fn the_result_tables_print_only_digits_that_the_perturbed_runs_share() {
    use massredist::observe::Summary;
    let config = Config::quick();
    let results = paper::compute(&config, &|| {}).unwrap();
    let md = paper::results_tables(&config, &results);
    let columns: [fn(&Summary) -> Option<f64>; 7] = [
        |s| s.linf_l2_error,
        |s| s.linf_l2_error_relative,
        |s| s.max_contact_error,
        |s| s.l2_lambda_error,
        |s| Some(s.energy_min),
        |s| Some(s.energy_max),
        |s| Some(s.energy_final),
    ];
    let mut checked = 0;
    let mut horizon = 0.0;
    for line in md.lines() {
        if let Some(t) = line.strip_prefix("## Results, ") {
            horizon = t.split("T = ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
            continue;
        }
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let Some(r) = results.iter().find(|r| {
            cells.len() > 3
                && r.case.end == horizon
                && cells[1] == r.case.experiment.title()
                && cells[2] == r.case.mass.name()
        }) else {
            continue;
        };
        assert_eq!(r.copies.len(), 4, "{line}");
        for (f, cell) in columns.iter().zip(&cells[3..10]) {
            let runs: Vec<f64> =
                std::iter::once(&r.summary).chain(r.copies.iter().map(|c| &c.summary)).filter_map(f).collect();
            if cell.contains('–') || *cell == "—" {
                continue;
            }
            assert!(printed_digits(cell) <= shared_digits(&runs), "{cell} in {line}: runs {runs:?}");
            checked += 1;
        }
    }
    // 34 cases (15 + 15 + 4) × 7 numbers.
    assert_eq!(checked, 34 * 7 - bands(&md), "{md}");
}

/// The band cells ("a–b") of the tables' first seven value columns.
fn bands(md: &str) -> usize {
    md.lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| scheme"))
        .map(|l| l.split('|').skip(3).take(7).filter(|c| c.contains('–')).count())
        .sum()
}

/// The lead's perturbed copies (u⁰ times 1 + δ(x), |δ| ≤ 1e-13) run, and stay within 1e-9
/// relative of the unperturbed rows (Crank–Nicolson with w_0 = 0 does not amplify round-off by
/// more than a few thousand over 80 steps); the section then prints their shared digits.
#[test]
fn the_lead_s_perturbed_copies_run_and_stay_close() {
    use paper::table2d_lead::{lead_copies, lead_rows};
    let rows = lead_rows();
    let copies = lead_copies();
    assert_eq!(copies.len(), 4);
    for c in &copies {
        for (row, copy) in rows.iter().zip(c) {
            let (row, copy) = (row.unwrap(), copy.expect("the perturbed copy runs"));
            for (a, b) in row.iter().zip(&copy) {
                assert!((a - b).abs() <= 1e-9 * a, "{a} vs {b}");
            }
        }
    }
}

/// The 2D sections print shared digits only: every elastic configuration the section prints
/// (`printed_configurations`, in its order) has four perturbed reruns per mass and its printed
/// errors have at most the digits the five runs share; the scalar table's judged row likewise.
/// Broken on purpose: `elastic_table` running `0..0` perturbed copies instead of `0..PERTURBATIONS`
/// fails the "four reruns" assertion (left 0); `plate_2d_errors` doing the same fails the scalar
/// five-runs assertion (left 1).
#[test]
fn the_2d_sections_print_only_digits_that_the_perturbed_runs_share() {
    use paper::elastic_report::elastic_section;
    use paper::elastic_table::{elastic_table, printed_configurations};
    let rows = elastic_table(true);
    let section = elastic_section(&rows);
    let lines: Vec<&str> = section.lines().filter(|l| l.starts_with("| elastic")).collect();
    let printed = printed_configurations(&rows);
    assert_eq!(lines.len(), printed.len());
    for (line, group) in lines.iter().zip(&printed) {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        for (cell, r) in cells[2..5].iter().zip(group) {
            assert_eq!(r.perturbed.len(), 4, "{line}");
            let runs: Vec<f64> =
                std::iter::once(r.linf_l2_error).chain(r.perturbed.iter().copied()).flatten().collect();
            assert_eq!(runs.len(), 5, "{line}");
            assert!(cell.contains('–') || printed_digits(cell) <= shared_digits(&runs), "{cell} in {line}: {runs:?}");
        }
    }
    let t = paper::plate_2d_errors(&Config::quick()).unwrap();
    let md = paper::table_2d(Some(&t));
    let line = md.lines().find(|l| l.starts_with("| this project")).unwrap();
    let judged: Vec<usize> = (0..t.rows.len()).filter(|&i| t.rows[i].judged).collect();
    for (cell, &i) in line.split('|').map(str::trim).skip(2).zip(&judged) {
        let copies = &t.copies.iter().find(|(k, _)| *k == i).expect("the judged row is rerun").1;
        let runs: Vec<f64> = std::iter::once(t.rows[i].linf_l2_error).chain(copies.iter().copied()).flatten().collect();
        assert_eq!(runs.len(), 5);
        assert!(printed_digits(cell) <= shared_digits(&runs), "{cell}: {runs:?}");
    }
}
