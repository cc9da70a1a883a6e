//! `massredist reproduce` on the reduced configuration: every file is there and well formed, and
//! the numbers in the tables, the figure CSVs and report.md are those of an independent run of
//! the same case through `run::run_scene` / `run::integrate` (nothing is compared with a stored
//! number).

use indicatif::ProgressBar;
use massredist::mass::MassKind;
use massredist::paper::{self, Config, EVENT_COLUMNS, Experiment, Outcome, TABLE_COLUMNS, horizon_tag};
use massredist::run::{Problem, SeriesRecorder, SummaryObserver, integrate, run_scene};
use massredist::scene::{Column, Scene};
use std::collections::BTreeSet;
use std::path::Path;

fn quick(dir: &Path) -> Outcome {
    paper::reproduce(dir, &Config::quick(), &ProgressBar::hidden()).expect("quick reproduce runs")
}

fn csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r.records().map(|rec| rec.unwrap().iter().map(String::from).collect()).collect();
    (header, rows)
}

/// The file names the reduced configuration must produce (the documented naming contract).
fn expected_files(config: &Config) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for &end in &config.horizons {
        let t = horizon_tag(end);
        for e in Experiment::ALL {
            let (a, b) = e.paper_figures();
            for stem in [format!("fig{a}-{}-{t}", e.slug()), format!("fig{b}-{}-energy-{t}", e.slug())] {
                for ext in ["png", "svg", "csv"] {
                    out.insert(format!("{stem}.{ext}"));
                }
            }
        }
        out.insert(format!("table-{t}.csv"));
        out.insert(format!("events-{t}.csv"));
    }
    for &end in &config.long_ends {
        let stem = format!("fig32-paoli-schatzman-energy-{}", horizon_tag(end));
        for ext in ["png", "svg", "csv"] {
            out.insert(format!("{stem}.{ext}"));
        }
        out.insert(format!("{stem}-periods.csv"));
        out.insert(format!("table-long-{}.csv", horizon_tag(end)));
    }
    for f in ["table-2d.csv", "table-2d-sweep.csv", "summaries.json", "report.md"] {
        out.insert(f.into());
    }
    out
}

#[test]
fn quick_reproduce_writes_every_file_well_formed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("rep");
    let config = Config::quick();
    let outcome = quick(&dir);
    let expected = expected_files(&config);
    let listed: BTreeSet<String> = outcome.files.iter().cloned().collect();
    assert_eq!(listed, expected);
    // The directory holds exactly these files (no temporary leftovers), none of them empty.
    let on_disk: BTreeSet<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    let marked: BTreeSet<String> = expected.iter().cloned().chain([massredist::output::MARKER.to_string()]).collect();
    assert_eq!(on_disk, marked, "the files and the output marker");
    for f in &expected {
        let bytes = std::fs::read(dir.join(f)).unwrap();
        assert!(!bytes.is_empty(), "{f} is empty");
        if f.ends_with(".png") {
            assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{f} is not a PNG");
        }
        if f.ends_with(".svg") {
            assert!(bytes.starts_with(b"<svg"), "{f} is not an SVG");
        }
    }
    // Nothing was left next to the output directory either.
    assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), 1);

    // Table CSVs: the documented header, one row per scheme × mass, numbers that parse.
    for &end in &config.horizons {
        let (header, rows) = csv(&dir.join(format!("table-{}.csv", horizon_tag(end))));
        assert_eq!(header, TABLE_COLUMNS);
        let pairs: Vec<(String, String)> = rows.iter().map(|r| (r[0].clone(), r[1].clone())).collect();
        let want: Vec<(String, String)> = Experiment::ALL
            .iter()
            .flat_map(|e| e.masses().into_iter().map(|m| (e.slug().to_string(), m.name().to_string())))
            .collect();
        assert_eq!(pairs, want);
        for r in &rows {
            assert_eq!(r[3], "ok");
            for cell in &r[4..] {
                cell.parse::<f64>().unwrap_or_else(|e| panic!("{cell}: {e}"));
            }
        }
        let (header, rows) = csv(&dir.join(format!("events-{}.csv", horizon_tag(end))));
        assert_eq!(header, EVENT_COLUMNS);
        // One row per case and full period of the exact solution (period 3L = 3).
        assert_eq!(rows.len(), want.len() * (end / 3.0).floor() as usize);
    }
    for &end in &config.long_ends {
        let (header, rows) = csv(&dir.join(format!("table-long-{}.csv", horizon_tag(end))));
        assert_eq!(header, TABLE_COLUMNS);
        assert_eq!(rows.len(), Experiment::PaoliSchatzman.masses().len());
    }

    // Figure CSVs: header names the exact curves and every mass; every cell is a number; one row
    // per time step t_0 … t_N.
    for &end in &config.horizons {
        let steps = (end / config.dt).round() as usize;
        for e in Experiment::ALL {
            let (a, b) = e.paper_figures();
            let t = horizon_tag(end);
            let masses: Vec<&str> = e.masses().iter().map(|m| m.name()).collect();
            let (header, rows) = csv(&dir.join(format!("fig{a}-{}-{t}.csv", e.slug())));
            let mut want = vec!["t".to_string(), "exact_u0".into(), "exact_lambda".into()];
            for m in &masses {
                want.push(format!("u0_{m}"));
                want.push(format!("lambda_{m}"));
            }
            assert_eq!(header, want);
            assert_eq!(rows.len(), steps + 1);
            let (header, erows) = csv(&dir.join(format!("fig{b}-{}-energy-{t}.csv", e.slug())));
            let mut want = vec!["t".to_string(), "exact_energy".into()];
            want.extend(masses.iter().map(|m| format!("energy_{m}")));
            assert_eq!(header, want);
            assert_eq!(erows.len(), steps + 1);
            for r in rows.iter().chain(&erows) {
                for cell in r {
                    cell.parse::<f64>().unwrap_or_else(|e| panic!("{cell}: {e}"));
                }
            }
        }
    }
    let long = horizon_tag(config.long_ends[0]);
    let (header, _) = csv(&dir.join(format!("fig32-paoli-schatzman-energy-{long}-periods.csv")));
    assert_eq!(&header[..4], ["period", "t_end", "max_energy_standard", "min_energy_standard"]);

    // report.md: a table row for each scheme × mass in each horizon's table, the claims, the 2D
    // section with its pending row, and a link to every figure.
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert_eq!(report, outcome.report);
    for e in Experiment::ALL {
        for m in e.masses() {
            let row = format!("| {} | {} |", e.title(), m.name());
            let n = report.lines().filter(|l| l.starts_with(&row)).count();
            let tables =
                config.horizons.len() + if e == Experiment::PaoliSchatzman { config.long_ends.len() } else { 0 };
            assert_eq!(n, tables, "rows {row}");
        }
    }
    assert!(report.contains("## The paper's claims against these runs"));
    assert!(report.contains("## Table 1 of the paper (2D)"));
    assert!(report.contains("| paper | 0.0104 | 0.0046 | 0.0038 |"));
    assert!(report.lines().any(|l| l.starts_with("| this project | 0.0")), "the 2D row holds numbers");
    for f in expected.iter().filter(|f| f.ends_with(".png")) {
        assert!(report.contains(&format!("]({f})")), "report.md does not show {f}");
    }
}

/// The value printed in report.md for (scheme, mass) in the table of horizon T, column `col`
/// (0-based after the leading `|`).
fn report_cell(report: &str, section: &str, e: Experiment, m: &MassKind, col: usize) -> String {
    let start = report.find(section).unwrap_or_else(|| panic!("no section {section}"));
    let row = format!("| {} | {} |", e.title(), m.name());
    let line = report[start..].lines().find(|l| l.starts_with(&row)).unwrap();
    line.split('|').nth(col + 1).unwrap().trim().to_string()
}

/// `printed` is `exact` rounded to 4 significant digits: within half a unit of the last digit.
fn printed_matches(printed: &str, exact: f64) {
    let v: f64 = printed.parse().unwrap();
    let half_ulp = 0.5 * 10f64.powi(exact.abs().log10().floor() as i32 - 3);
    // + 4 ε|x|: the decimal printing itself rounds once.
    assert!((v - exact).abs() <= half_ulp + 4.0 * f64::EPSILON * exact.abs(), "printed {printed}, computed {exact}");
}

/// Same arithmetic on the same inputs: equal up to a different evaluation order at most, which
/// moves a result by a few ulps, far below 1e-12 relative.
fn same(a: f64, b: f64, what: &str) {
    assert!((a - b).abs() <= 1e-12 * a.abs().max(b.abs()), "{what}: {a} vs {b}");
}

#[test]
fn report_values_agree_with_an_independent_run() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("rep");
    let config = Config::quick();
    let outcome = quick(&dir);
    let report = &outcome.report;

    // Crank–Nicolson, mod3, T = 3 as a scene file, through run_scene.
    let scene = Scene::from_toml(
        "[bar]\nlength = 1.0\nelements = 6\n[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"crank-nicolson\"\n\
         [time]\ndt = 0.01\nend = 3.0\n[output]\nseries = [\"u0\", \"lambda\", \"energy\"]\n",
    )
    .unwrap();
    let (summary, series) = run_scene(&scene, &mut []).unwrap();
    let (_, rows) = csv(&dir.join("table-T3.csv"));
    let row = rows.iter().find(|r| r[0] == "crank-nicolson" && r[1] == "mod3").unwrap();
    let col = |name: &str| row[TABLE_COLUMNS.iter().position(|c| *c == name).unwrap()].parse::<f64>().unwrap();
    same(col("linf_l2_error"), summary.linf_l2_error.unwrap(), "L∞(L²) error");
    same(col("max_contact_error"), summary.max_contact_error.unwrap(), "contact error");
    same(col("l2_lambda_error"), summary.l2_lambda_error.unwrap(), "λ error");
    same(col("energy_final"), summary.energy_final, "final energy");
    same(col("impact_time_shift"), summary.impact_time_shift.unwrap(), "impact shift");
    let section = "## Results, T = 3";
    let (e, m) = (Experiment::CrankNicolson, MassKind::Mod3);
    printed_matches(&report_cell(report, section, e, &m, 2), summary.linf_l2_error.unwrap());
    printed_matches(&report_cell(report, section, e, &m, 4), summary.max_contact_error.unwrap());
    printed_matches(&report_cell(report, section, e, &m, 5), summary.l2_lambda_error.unwrap());
    // The figure's CSV holds the run's series (shortest round-trip decimals: exact).
    let (header, frows) = csv(&dir.join("fig11-crank-nicolson-T3.csv"));
    let k = header.iter().position(|h| h == "u0_mod3").unwrap();
    let u0 = series.column(Column::U0).unwrap();
    assert_eq!(frows.len(), u0.len());
    for (r, v) in frows.iter().zip(&u0) {
        same(r[k].parse().unwrap(), *v, "u0 series");
    }

    // Paoli–Schatzman, mod2, long run T = 30, directly through integrate.
    let end = config.long_ends[0];
    let steps = (end / config.dt).round() as usize;
    let problem = Problem::benchmark(config.length, config.elements, &MassKind::Mod2).unwrap();
    let mut scheme = problem.scheme(&Experiment::PaoliSchatzman.spec(), config.dt).unwrap();
    let mut obs = SummaryObserver::new(&problem, steps, config.dt, true);
    let mut energy = SeriesRecorder::new(vec![Column::Energy], 1, steps + 1);
    integrate(&problem, scheme.as_mut(), steps, &mut [&mut obs, &mut energy]).unwrap();
    let s = obs.finish();
    let (_, rows) = csv(&dir.join(format!("table-long-{}.csv", horizon_tag(end))));
    let row = rows.iter().find(|r| r[0] == "paoli-schatzman" && r[1] == "mod2").unwrap();
    let col = |name: &str| row[TABLE_COLUMNS.iter().position(|c| *c == name).unwrap()].parse::<f64>().unwrap();
    same(col("linf_l2_error"), s.linf_l2_error.unwrap(), "long L∞(L²) error");
    same(col("energy_max"), s.energy_max, "long max energy");
    same(col("energy_min"), s.energy_min, "long min energy");
    printed_matches(
        &report_cell(report, &format!("over T = {}", end), Experiment::PaoliSchatzman, &MassKind::Mod2, 2),
        s.linf_l2_error.unwrap(),
    );
    // The per-period maxima: period 0 (t in [Δt, 3)) from the independent energy series.
    let (header, prows) = csv(&dir.join(format!("fig32-paoli-schatzman-energy-{}-periods.csv", horizon_tag(end))));
    let k = header.iter().position(|h| h == "max_energy_mod2").unwrap();
    let e = energy.column(Column::Energy).unwrap();
    let t = energy.times();
    let max0 = t
        .iter()
        .zip(&e)
        .filter(|(t, _)| **t > 0.5 * config.dt && **t < 3.0 - 0.5 * config.dt)
        .map(|(_, v)| *v)
        .fold(f64::MIN, f64::max);
    same(prows[0][k].parse().unwrap(), max0, "period-0 max energy");
}

#[test]
fn the_2d_table_row_is_the_plate_code_s_error() {
    use massredist::mass::MassKind;
    use massredist::plate::CellKind;
    use massredist::scene::{Formulation, SchemeSpec};
    let t = massredist::paper::plate_2d_errors(&Config::quick()).expect("judged runs succeed");
    let cn = SchemeSpec::CrankNicolson { formulation: Formulation::Full };
    for (mass, value) in [(MassKind::Mod1, t.mod1), (MassKind::Mod2, t.mod2), (MassKind::Mod3, t.mod3)] {
        let direct = massredist::plate::table::linf_l2_error(CellKind::Quad, 20, &mass, &cn, 0.01, 3.0).unwrap();
        assert_eq!(value, direct, "{}", mass.name());
    }
    let section = massredist::paper::table_2d(Some(&t));
    assert!(section.contains("| paper | 0.0104 | 0.0046 | 0.0038 |"));
    // The section shows the judged values (3 significant digits) next to the paper's.
    let row = section.lines().find(|l| l.starts_with("| this project |")).expect("project row");
    let cells: Vec<f64> = row.split('|').filter_map(|c| c.trim().parse().ok()).collect();
    for (shown, value) in cells.iter().zip([t.mod1, t.mod2, t.mod3]) {
        assert!((shown - value).abs() <= 5e-3 * value, "{row}");
    }
}
