//! `massredist reproduce` on the reduced configuration: every file is there and well formed, and
//! the numbers in the tables, the figure CSVs and report.md are those of a second run of the
//! same case through `run::run_scene` / `run::integrate` (nothing is compared with a stored
//! number). That second run is the same code: those tests check the plumbing (that each case's
//! numbers reach the right cell), not the numbers; the numbers are checked against exact
//! solutions and identities in `tests/schemes.rs`, `tests/exact_solution.rs` and the claims.

use indicatif::ProgressBar;
use massredist::bar::BarProblem;
use massredist::driver::integrate;
use massredist::mass::MassKind;
use massredist::models::PaperBar;
use massredist::observe::{SeriesRecorder, SummaryObserver};
use massredist::run::run_scene;
use massredist::scene::{BarScene, Column};
use massredist_study::paper::{
    self, Config, EVENT_COLUMNS, Experiment, Outcome, REBOUND_COLUMNS, REBOUND_FIGURE, REBOUND_TABLE, TABLE_COLUMNS,
    horizon_tag,
};
use std::collections::BTreeSet;
use std::path::Path;

fn quick(dir: &Path) -> Outcome {
    let out = massredist::output::OutputDir::prepare(dir, false, &[]).expect("a fresh folder");
    paper::reproduce(out, &Config::quick(), &ProgressBar::hidden()).expect("quick reproduce runs")
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
    for f in ["table-2d.csv", "table-2d-sweep.csv", paper::elastic_table::ELASTIC_TABLE, "summaries.json", "report.md"]
    {
        out.insert(f.into());
    }
    for ext in ["png", "svg", "csv"] {
        out.insert(format!("{REBOUND_FIGURE}.{ext}"));
    }
    out.insert(REBOUND_TABLE.into());
    for ext in ["png", "svg", "csv"] {
        out.insert(format!("{}.{ext}", paper::cd_growth::CD_GROWTH_FIGURE));
    }
    for ext in ["png", "svg", "csv"] {
        out.insert(format!("{}.{ext}", paper::mesh_scope::SCOPE_FIGURE));
        out.insert(format!("{}.{ext}", paper::table2d_lead::LEAD_FIGURE));
    }
    // The bodies section (tests/bodies_reproduce.rs and tests/hertz.rs check its numbers).
    for stem in
        [paper::BODIES_ENERGY, paper::BODIES_DROP, paper::BODIES_SPHERE, paper::BODIES_IMPACT, paper::HERTZ_PRESSURE]
    {
        for ext in ["png", "svg", "csv"] {
            out.insert(format!("{stem}.{ext}"));
        }
    }
    out.insert(paper::BODIES_TABLE.into());
    // The method classes (tests/methods_bench.rs checks their numbers).
    out.extend(paper::methods_report::METHODS_FILES.map(String::from));
    out.insert(paper::HERTZ_TABLE.into());
    // Friction (tests/friction_disc.rs checks their numbers): the disc's table, the sphere's
    // figure.
    out.insert(paper::friction_disc::FRICTION_TABLE.into());
    for ext in ["png", "svg", "csv"] {
        out.insert(format!("{}.{ext}", paper::friction_sphere::FRICTION_SPHERE));
    }
    // Curved obstacles (tests/obstacles.rs checks their numbers): the table and the figure.
    out.insert(paper::obstacles::OBSTACLES_TABLE.into());
    for ext in ["png", "svg", "csv"] {
        out.insert(format!("{}.{ext}", paper::obstacles::OBSTACLES_FIGURE));
    }
    // Two bodies (tests/two_bodies.rs checks their numbers): the table and the figure.
    out.insert(paper::two_bodies::TWO_BARS_TABLE.into());
    for ext in ["png", "svg", "csv"] {
        out.insert(format!("{}.{ext}", paper::two_bodies::TWO_BARS_FIGURE));
        // Two discs colliding (tests/two_discs.rs checks their numbers): the figure.
        out.insert(format!("{}.{ext}", paper::two_discs::TWO_DISCS_FIGURE));
    }
    out
}

/// (About 110 lines: one `reproduce --quick` run, checked file by file; split, each part would
/// run `reproduce` again.)
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
            for cell in &r[4..13] {
                cell.parse::<f64>().unwrap_or_else(|e| panic!("{cell}: {e}"));
            }
            // Every case is rerun from perturbed U⁰ (issue 22): five runs and the digits they share;
            // Crank–Nicolson's standard mass chatters, so its rows share fewer than 16.
            let chaotic = r[0] == "crank-nicolson" && r[1] == "standard";
            assert_eq!(r[13], "5", "{r:?}");
            assert!(!chaotic || r[14].parse::<usize>().unwrap() < 16, "{r:?}");
        }
        let (header, rows) = csv(&dir.join(format!("events-{}.csv", horizon_tag(end))));
        assert_eq!(header, EVENT_COLUMNS);
        // One row per case and full period of the exact solution (period 3L = 3).
        assert_eq!(rows.len(), want.len() * (end / 3.0).floor() as usize);
        for r in &rows {
            // The last contact of period j follows its impact at (3j + 1)L + impact_shift.
            let cell = |k: usize| r[k].parse::<f64>().unwrap();
            let impact = 3.0 * cell(2) + 1.0 + cell(3);
            assert!(cell(5) >= impact - 1e-9, "{r:?}: last contact before the impact");
        }
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
            // One row per horizon, per long run (Paoli–Schatzman), and in the rebounding bar's table.
            let tables =
                config.horizons.len() + if e == Experiment::PaoliSchatzman { config.long_ends.len() } else { 0 } + 1;
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

/// Plumbing only: the second run is the same code as the report's (see the module docs).
///
/// mutation: the table writer prints `energy_min` in the `energy_final` column -> fails with
/// "final energy: … vs …"; a wrong scheme (the numbers themselves) would not fail here.
#[test]
fn report_cells_carry_the_numbers_of_a_second_run_of_the_same_case() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("rep");
    let config = Config::quick();
    let outcome = quick(&dir);
    let report = &outcome.report;

    // Crank–Nicolson, mod3, T = 3 as a scene file, through run_scene.
    let scene = BarScene::from_toml(
        "[bar]\nlength = 1.0\nelements = 6\n[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"crank-nicolson\"\n\
         [time]\ndt = 0.01\nend = 3.0\n[output]\nseries = [\"u0\", \"lambda\", \"energy\"]\n",
    )
    .unwrap();
    let massredist::run::SceneRun { summary, series, .. } = run_scene(&scene, &mut []).unwrap();
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
    let problem = PaperBar { length: config.length, elements: config.elements }.problem(&MassKind::Mod2).unwrap();
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
    use massredist::fem::Cell;
    use massredist::mass::MassKind;
    use massredist::scene::{Formulation, SchemeSpec};
    let t = massredist_study::paper::plate_2d_errors(&Config::quick()).expect("judged runs succeed");
    let cn = SchemeSpec::CrankNicolson { formulation: Formulation::Full };
    for (mass, value) in [(MassKind::Mod1, t.mod1), (MassKind::Mod2, t.mod2), (MassKind::Mod3, t.mod3)] {
        let direct =
            massredist_study::paper::plate_table::linf_l2_error(Cell::Quad, 20, &mass, &cn, 0.01, 3.0).unwrap();
        assert_eq!(value, direct, "{}", mass.name());
    }
    let section = massredist_study::paper::table_2d(Some(&t));
    assert!(section.contains("| paper | 0.0104 | 0.0046 | 0.0038 |"));
    // The section shows the judged values (3 significant digits) next to the paper's.
    let row = section.lines().find(|l| l.starts_with("| this project |")).expect("project row");
    let cells: Vec<f64> = row.split('|').filter_map(|c| c.trim().parse().ok()).collect();
    for (shown, value) in cells.iter().zip([t.mod1, t.mod2, t.mod3]) {
        assert!((shown - value).abs() <= 5e-3 * value, "{row}");
    }
}

#[test]
fn the_elastic_section_states_the_closest_configuration_and_the_10_percent_verdict() {
    use massredist_study::paper::elastic_report::elastic_section;
    use massredist_study::paper::elastic_table::elastic_table;
    use std::collections::BTreeMap;
    // The paper's Table 1, quoted from the paper (conclusion), and its "within 10 %".
    let paper = [("mod1", 0.0104), ("mod2", 0.0046), ("mod3", 0.0038)];
    let within = 1.1;
    let rows = elastic_table(true);
    // quick: {quad, triangle} × {λ = 0 free, λ > 0 free, λ > 0 roller} × CN, Δt = 0.01, T = 3 × 3 masses.
    assert_eq!(rows.len(), 2 * 3 * 3);
    // The worst factor of each configuration, grouped here independently of the library.
    let mut groups: BTreeMap<(String, u64, String, String, u64, u64), Vec<f64>> = BTreeMap::new();
    for r in &rows {
        let e = r.linf_l2_error.unwrap_or_else(|| panic!("{r:?}"));
        let p = paper.iter().find(|(m, _)| *m == r.mass).unwrap().1;
        let key =
            (r.cells.into(), r.lambda.to_bits(), r.lateral.into(), r.scheme.into(), r.dt.to_bits(), r.end.to_bits());
        groups.entry(key).or_default().push((e / p).max(p / e));
    }
    assert_eq!(groups.len(), 6);
    let best = groups
        .values()
        .map(|f| {
            assert_eq!(f.len(), 3);
            f.iter().copied().fold(1.0, f64::max)
        })
        .fold(f64::INFINITY, f64::min);
    let section = elastic_section(&rows);
    assert!(section.contains(&format!("(worst factor {best:.2} from the paper)")), "{section}");
    let matching = groups.values().filter(|f| f.iter().all(|&x| x <= within)).count();
    if matching == 0 {
        assert!(
            section.contains("None of the 6 elastic configurations matches all three values within 10 %"),
            "{section}"
        );
    } else {
        assert!(section.contains(&format!("{matching} of the 6 configurations match all three")), "{section}");
    }
    // mutation: MATCH_FACTOR = 6.0 -> fails: the section claims "4 of the 6 configurations match
    // all three values within 10 %" (best factor 5.01).
}

// ---------------------------------------------------------------------------------------------
// Beyond the paper: the rebounding bar.

/// The mass with the smallest L∞(L²) error per scheme, from `rebound.csv` rows.
fn best_per_scheme(rows: &[Vec<String>]) -> Vec<(String, String)> {
    let k = REBOUND_COLUMNS.iter().position(|c| *c == "linf_l2_error").unwrap();
    let mut best: Vec<(String, String, f64)> = Vec::new();
    for r in rows {
        let e: f64 = r[k].parse().unwrap();
        match best.iter_mut().find(|b| b.0 == r[0]) {
            Some(b) if e < b.2 => *b = (r[0].clone(), r[1].clone(), e),
            Some(_) => {}
            None => best.push((r[0].clone(), r[1].clone(), e)),
        }
    }
    best.into_iter().map(|(s, m, _)| (s, m)).collect()
}

#[test]
fn quick_reproduce_writes_the_rebound_section_and_its_verdict_follows_the_table() {
    // Mutation check: writing "Yes, mod3 still wins" when mod3 is *not* the best of any
    // scheme (flipping `best.mass == MassKind::Mod3` in the verdict) fails the last assertion;
    // not writing rebound.csv fails the first read.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("rep");
    let config = Config::quick();
    let outcome = quick(&dir);
    let (header, rows) = csv(&dir.join(REBOUND_TABLE));
    assert_eq!(header, REBOUND_COLUMNS);
    let pairs: Vec<(String, String)> = rows.iter().map(|r| (r[0].clone(), r[1].clone())).collect();
    let want: Vec<(String, String)> =
        paper::rebound_cases().iter().map(|(e, m)| (e.slug().to_string(), m.name().to_string())).collect();
    assert_eq!(pairs, want, "one row per scheme × mass, hybrid without the standard mass");
    for r in &rows {
        assert_eq!(r[3], "ok", "{r:?}");
        for cell in r[4..].iter().chain([&r[2]]) {
            cell.parse::<f64>().unwrap_or_else(|e| panic!("{cell}: {e} in {r:?}"));
        }
    }
    // The figure's CSV: t, the exact curves and each mass with Crank–Nicolson, every step.
    let (header, frows) = csv(&dir.join(format!("{REBOUND_FIGURE}.csv")));
    let mut want = vec!["t".to_string(), "exact_u0".into(), "exact_lambda".into()];
    for m in Experiment::CrankNicolson.masses() {
        want.extend([format!("u0_{}", m.name()), format!("lambda_{}", m.name())]);
    }
    assert_eq!(header, want);
    assert_eq!(frows.len(), (paper::REBOUND_END / config.dt).round() as usize + 1);
    for r in &frows {
        for cell in r {
            assert!(cell.parse::<f64>().unwrap().is_finite(), "{cell} in {r:?}");
        }
    }
    // report.md: the section, its table rows, the figure, and a verdict that says what the
    // numbers say.
    let report = &outcome.report;
    let section = &report[report.find("## Beyond the paper: the rebounding bar").expect("the section")..];
    assert!(section.contains(&format!("]({REBOUND_FIGURE}.png)")));
    for (e, m) in paper::rebound_cases() {
        assert!(section.contains(&format!("| {} | {} |", e.title(), m.name())), "{e:?} {m:?}");
    }
    let best = best_per_scheme(&rows);
    let mod3_everywhere = best.iter().all(|(_, m)| m == "mod3");
    let mod3_nowhere = best.iter().all(|(_, m)| m != "mod3");
    assert_eq!(section.contains("**Yes, mod3 still wins**"), mod3_everywhere, "{best:?}");
    assert_eq!(section.contains("**No, mod3 does not win here**"), mod3_nowhere, "{best:?}");
    for (scheme, mass) in &best {
        let title = Experiment::ALL.iter().find(|e| e.slug() == scheme).unwrap().title();
        let line = section.lines().find(|l| l.starts_with(&format!("- {title}:"))).unwrap();
        assert!(line.contains(&format!("smallest first: {mass} ")), "{line}");
    }
}

/// The rebounding bar of `scenes/rebound-free-bar.toml` with the paper's mesh and step, written
/// out by hand (not through `paper::rebound_scene_text`).
const REBOUND_CN_MOD3: &str = "[bar]\nlength = 1.0\nelements = 6\ndensity = 1.0\nmodulus = 1.0\nfar_end = \"free\"\n\
    gap = 0.1\ninitial = { displacement = \"0\", velocity = \"-1\" }\n[mass]\nkind = \"mod3\"\n\
    [scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = 0.01\nend = 3.0\n[output]\nseries = [\"u0\", \"lambda\"]\n";

/// Keeps U at every step (for the centre of mass).
#[derive(Default)]
struct States {
    u: Vec<Vec<f64>>,
}

impl massredist::driver::Observer for States {
    fn observe(&mut self, s: &massredist::driver::Sample) {
        self.u.push(s.state.u.to_vec());
    }
}

#[test]
fn rebound_row_plumbing_matches_an_independent_run_scene() {
    // A plumbing check: the row of rebound.csv for Crank–Nicolson with mod3 holds the numbers of
    // an independent run_scene of the same scene, and its derived columns (last contact, rebound
    // velocity) are recomputed here from the states. Mutation check: weighting the centre of mass
    // by the nodes (all weights 1) instead of M·1 in `BarMotion` moves the rebound velocity
    // (0.9826 → 1.0041) and fails `same(.., "rebound velocity")`.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("rep");
    let config = Config::quick();
    quick(&dir);
    // The section's bar is the shipped scene's (but the mesh and the time).
    let shipped =
        BarScene::from_file(massredist_study::repo::root().join("scenes/rebound-free-bar.toml").as_path()).unwrap();
    let scene = BarScene::from_toml(REBOUND_CN_MOD3).unwrap();
    let ours =
        BarScene::from_toml(&paper::rebound_scene_text(&config, Experiment::CrankNicolson, &MassKind::Mod3)).unwrap();
    assert_eq!(ours.geometry, scene.geometry);
    assert_eq!(
        (ours.mass.clone(), ours.scheme.clone(), ours.time),
        (scene.mass.clone(), scene.scheme.clone(), scene.time)
    );
    let mut bar = shipped.geometry.clone();
    bar.elements = scene.geometry.elements;
    assert_eq!(bar, scene.geometry);

    let mut states = States::default();
    let massredist::run::SceneRun { summary, series, .. } = run_scene(&scene, &mut [&mut states]).unwrap();
    let (_, rows) = csv(&dir.join(REBOUND_TABLE));
    let row = rows.iter().find(|r| r[0] == "crank-nicolson" && r[1] == "mod3").unwrap();
    let col = |name: &str| row[REBOUND_COLUMNS.iter().position(|c| *c == name).unwrap()].parse::<f64>().unwrap();
    let s = &summary;
    for (name, value) in [
        ("linf_l2_error", s.linf_l2_error.unwrap()),
        ("linf_l2_error_relative", s.linf_l2_error_relative.unwrap()),
        ("max_contact_error", s.max_contact_error.unwrap()),
        ("l2_lambda_error", s.l2_lambda_error.unwrap()),
        ("energy_initial", s.energy_initial),
        ("energy_min", s.energy_min),
        ("energy_max", s.energy_max),
        ("energy_final", s.energy_final),
        ("first_impact_time", s.first_impact_time.unwrap()),
        ("impact_time_shift", s.impact_time_shift.unwrap()),
        ("first_release_time", s.first_release_time.unwrap()),
        ("release_time_shift", s.release_time_shift.unwrap()),
    ] {
        same(col(name), value, name);
    }
    // Last contact: the last t_n with contact force, λ < 0 (the bar leaves after it); episodes:
    // runs of steps with force (contact read off the force, issue 32 item 1).
    let (t, lambda) = (series.times(), series.column(Column::Lambda).unwrap());
    let last = lambda.iter().rposition(|&l| l < 0.0).unwrap();
    assert!(last + 1 < lambda.len());
    same(col("last_contact_time"), t[last], "last contact");
    let episodes = (0..lambda.len()).filter(|&n| lambda[n] < 0.0 && (n == 0 || !(lambda[n - 1] < 0.0))).count();
    assert_eq!(col("contact_episodes"), episodes as f64);
    // Rebound velocity: the centre of mass 1ᵀMU / 1ᵀM1 over [T − 0.5, T], M·1 from the problem.
    let problem = BarProblem::from_scene(&scene).unwrap();
    let m = &problem.system.system.mass;
    let mut w = vec![0.0; problem.u0.len()];
    m.mul_into(&vec![1.0; w.len()], &mut w);
    let centre = |u: &[f64]| w.iter().zip(u).map(|(a, b)| a * b).sum::<f64>() / w.iter().sum::<f64>();
    let (n, k) = (states.u.len() - 1, (0.5 / config.dt).round() as usize);
    let v = (centre(&states.u[n]) - centre(&states.u[n - k])) / (t[n] - t[n - k]);
    same(col("rebound_velocity"), v, "rebound velocity");
}

/// The report's statements that issue 10 found stated more firmly than the runs allow.
///
/// Mutations not run yet (a rebuild of the crate took 20 min on the shared machine at the end):
/// the hybrid scheme reporting the interpolant at n = 0 (E(0) = 1/8) would exceed the bound by
/// h/8; `energy_jumps` counting from n = 0 would add the first-step loss, which is no contact
/// switch, and turn the claim to "**no**". What was seen failing: the bound without its
/// round-off term (2.3e-14 over L/8 − h/8).
#[test]
fn report_statements_follow_the_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("rep");
    let config = Config::quick();
    let outcome = quick(&dir);
    // The hybrid scheme starts from u_0⁰ = u_1⁰: the interpolant of (L − x)/2 without element
    // 0's strain energy ½ (h/2)²/h = h/8, so its energy never exceeds L/8 − h/8 (its E(0)).
    let h = config.length / config.elements as f64;
    let bound = config.length / 8.0 - h / 8.0;
    let (_, rows) = csv(&dir.join("table-T3.csv"));
    let k = TABLE_COLUMNS.iter().position(|c| *c == "energy_max").unwrap();
    let hybrid: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == "hybrid").collect();
    assert_eq!(hybrid.len(), 3);
    for r in hybrid {
        let e: f64 = r[k].parse().unwrap();
        // ½UᵀSU sums m terms of size ≤ |S|·|U|² ≤ (4/h)(1/2)² = m that cancel down to O(E):
        // rounding of a few m·m·ε.
        let m = config.elements as f64;
        assert!(
            e <= bound + 4.0 * m * m * f64::EPSILON,
            "hybrid {}: E max {e} above its own initial energy {bound}",
            r[1]
        );
    }
    // Crank–Nicolson with w_0 = 0: piecewise constant energy, jumps only where contact switches.
    let row = outcome
        .report
        .lines()
        .find(|l| l.contains("Crank–Nicolson's energy after the first step is piecewise constant"));
    assert!(row.is_some_and(|l| l.ends_with("| yes |")), "{row:?}");
    // The standard mass with Crank–Nicolson is shown over perturbed runs, not as one run's digits.
    let section = outcome.report.split("## Results, T = 9").nth(1).unwrap();
    let std_row = section.lines().find(|l| l.starts_with("| Crank–Nicolson | standard |")).unwrap();
    assert!(std_row.contains("runs from U⁰ perturbed"), "{std_row}");
    // The release is documented as "first u_0 > 0", with the last contact next to it.
    assert!(outcome.report.contains("a chatter (u_0 leaving the obstacle and coming back) counts as a release"));
}
