//! `massredist reproduce`: every numerical experiment of the paper, from scratch, in seconds.
//!
//! The paper's §4.2 and §5 run the impacting-bar benchmark (§4.1: L = 1, u⁰ = (1−x)/2, v⁰ = 0,
//! f = 0, exact solution 3-periodic with energy 1/8) with Δx = 1/6, Δt = 1/100, T = 3, for four
//! time schemes and several mass redistributions:
//!
//! | paper figures | scheme                                  | masses                      |
//! |---------------|-----------------------------------------|-----------------------------|
//! | 11, 12        | Crank–Nicolson (Newmark β = ¼, γ = ½)   | standard, mod1, mod2, mod3  |
//! | 21, 22        | backward Euler                          | standard, mod1, mod2, mod3  |
//! | 31, 32        | Paoli–Schatzman, β = ¼, e = 1 (eq. 4.6) | standard, mod1, mod2, mod3  |
//! | 34, 35        | hybrid (P^hyb) (§5)                     | mod1, mod2, mod3 (w_0 = 0)  |
//!
//! Odd figures show u_0(t) and λ(t) against the exact solution, even ones the energy. We run each
//! at the paper's horizon and over several periods ([`Config::horizons`]), plus Paoli–Schatzman
//! over 100 and 1000 periods ([`Config::long_ends`]), where energy drift shows. The paper's
//! Table 1 (2D) has its own section, [`table_2d`], to be filled in by the plate code. Beyond
//! the paper, `rebound` runs every scheme × mass on the classic rebounding bar (a free bar
//! arriving at the obstacle with velocity −1) against its exact solution by characteristics.
//!
//! Layout: `experiments` is the registry ([`Experiment`], [`Case`], [`cases`]); `runs` holds one
//! pure run ([`run_case`], only the observers the figures and tables need), all of them in
//! parallel ([`compute`], rayon) and what is derived from them; `figures`, `tables`, `claims`,
//! `report` and `table2d` turn results into figure data, tables and text (pure); [`reproduce`]
//! writes figures (PNG and SVG), the CSV behind each, tables and `report.md` into a directory
//! that appears complete or not at all. Every number in the report is computed here, none is
//! typed in.

pub mod band;
pub mod bodies;
mod bodies_report;
pub mod cd_growth;
mod claims;
mod config;
pub mod elastic_fixture;
pub mod elastic_reference;
pub mod elastic_report;
pub mod elastic_setup;
pub mod elastic_table;
mod experiments;
mod figures;
pub mod friction_disc;
pub mod friction_sphere;
pub mod hertz;
mod hertz_report;
pub mod mesh_scope;
pub mod methods;
pub mod methods_disc;
pub mod methods_report;
pub mod obstacles;
mod periods;
pub mod plate_table;
pub mod ps_growth;
mod rebound;
mod rebound_report;
pub mod replicate;
mod report;
mod runs;
mod table2d;
pub mod table2d_lead;
mod tables;
pub mod two_bodies;
pub mod two_discs;

pub use bodies_report::{BODIES_COLUMNS, BODIES_DROP, BODIES_ENERGY, BODIES_IMPACT, BODIES_SPHERE, BODIES_TABLE};
pub use config::Config;
pub use experiments::{Case, Experiment, Purpose, cases, masses};
pub use figures::{exact_lambda_polyline, exact_u0_polyline};
pub use hertz_report::{HERTZ_COLUMNS, HERTZ_PRESSURE, HERTZ_TABLE};
pub use periods::{DRIFT_FACTOR, PeriodEnergy};
pub use rebound::{
    BarMotion, ExactRebound, REBOUND_BAR, REBOUND_DV, REBOUND_END, REBOUND_WINDOW, Rebound, ReboundCopy, ReboundResult,
    compute_rebound, exact_rebound, rebound_cases, rebound_scene_text, rebound_sensitive, run_rebound,
};
pub use rebound_report::{REBOUND_COLUMNS, REBOUND_FIGURE, REBOUND_TABLE};
pub use report::{report_markdown, results_tables};
pub use runs::{CaseResult, EnergyVariation, PeriodEvents, compute, energy_variation, events, period_events, run_case};
pub use table2d::{PAPER_TABLE_2D, Table2d, plate_2d_errors, table_2d};
pub use tables::{EVENT_COLUMNS, TABLE_COLUMNS, horizon_tag, sig};

use figures::{FigureFile, figure_files};
use indicatif::ProgressBar;
use massredist::observe::Summary;
use massredist::output::OutputDir;
use massredist::run::RunError;
use massredist::scene::SceneError;
use rayon::prelude::*;
use serde::Serialize;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum ReproduceError {
    #[error("{what} = {value}: must be a positive whole multiple of dt = {dt} (within 1e-9 relative)")]
    Horizon { what: &'static str, value: f64, dt: f64 },
    #[error("{case}: {source}")]
    Run { case: String, source: RunError },
    #[error("{case}: {source}")]
    Scene { case: String, source: SceneError },
    #[error("{case}: no exact solution by characteristics")]
    NoExact { case: String },
    #[error("{case}: the explicit scheme reported no stable limit Δt_c")]
    NoStableLimit { case: String },
    #[error("writing {dir}: {source}")]
    Io { dir: String, source: std::io::Error },
}

/// What [`reproduce`] wrote.
#[derive(Debug)]
pub struct Outcome {
    pub results: Vec<CaseResult>,
    /// The rebounding bar's runs (beyond the paper).
    pub rebound: Rebound,
    /// The bodies section's runs (beyond the paper, [`bodies`]).
    pub bodies: Vec<bodies::BodyResult>,
    /// File names written into the output directory, report.md last.
    pub files: Vec<String>,
    pub report: String,
}

/// Runs every experiment of `config` and writes into `out` (a folder prepared before computing,
/// [`OutputDir::prepare`]; atomically: complete or absent):
/// per figure `<stem>.png`, `<stem>.svg`, `<stem>.csv`; `table-T*.csv`, `table-long-T*.csv`,
/// `table-2d.csv`, `table-2d-elastic.csv` (the elastic candidates, [`elastic_table`]),
/// `summaries.json`, `report.md`; for the rebounding bar `rebound-u0.png`,
/// `.svg`, `.csv` and `rebound.csv`; the scope of "mod3 is best" `mesh-scope.png`, `.svg`, `.csv`
/// ([`mesh_scope`]); the Table 1 lead's sensitivity `table-2d-lead.png`, `.svg`, `.csv`
/// ([`table2d_lead`]). `progress` is advanced once per case and per figure (pass
/// `ProgressBar::hidden()` for none).
pub fn reproduce(out: OutputDir, config: &Config, progress: &ProgressBar) -> Result<Outcome, ReproduceError> {
    for &t in &config.horizons {
        config.steps("horizon", t)?;
    }
    for &t in &config.long_ends {
        config.steps("long_ends", t)?;
    }
    config.steps("rebound end", REBOUND_END)?;
    let quick = !config.full_2d_sweep;
    let methods_config = methods::MethodsConfig::reproduce();
    let n_cases = (cases(config).len()
        + rebound_cases().len()
        + bodies::body_cases(quick).len()
        + methods::cases(&methods_config).len()
        + hertz::MESHES.len()) as u64;
    let n_figures = 2 * config.horizons.len() * Experiment::ALL.len() + config.long_ends.len() + 3;
    progress.set_length(n_cases + n_figures as u64);
    progress.set_message("running");
    let (
        Sections {
            results,
            rebound,
            scope,
            ps,
            cd,
            lead,
            bodies,
            methods,
            hertz,
            disc_md,
            friction,
            sphere,
            obstacles,
            two_bodies,
            two_discs,
        },
        (table2d, elastic),
    ) = compute_sections(config, &methods_config, progress)?;
    progress.set_message("drawing");
    let figures = figure_files(config, &results);
    let rebound_figure = rebound_report::rebound_figure(config, &rebound);
    let scope_figure = mesh_scope::scope_figure(config, &scope);
    let lead_figure = table2d_lead::lead_figure(&lead.curves[0]);
    let cd_figure = cd_growth::cd_growth_figure(&cd);
    let mut body_figures = bodies_report::bodies_figures(&bodies);
    body_figures.push(hertz_report::hertz_figure(&hertz));
    body_figures.push(friction_sphere::friction_sphere_figure(&sphere));
    body_figures.push(obstacles::obstacles_figure(&obstacles));
    body_figures.push(two_bodies::two_bodies_figure(&two_bodies));
    body_figures.push(two_discs::two_discs_figure(&two_discs));
    let tables = tables::result_tables(config, &results);
    let mut files = file_names(
        config,
        &figures,
        &tables,
        &[&rebound_figure, &scope_figure, &lead_figure, &cd_figure],
        table2d.is_some(),
    );
    // The bodies section's files go before summaries.json (always written, so always found).
    let at = files.iter().position(|f| f == "summaries.json").unwrap_or(files.len());
    let body_files =
        body_figures.iter().flat_map(FigureFile::file_names).chain([BODIES_TABLE.to_string(), HERTZ_TABLE.to_string()]);
    files.splice(at..at, body_files);
    let at = files.iter().position(|f| f == "summaries.json").unwrap_or(files.len());
    files.splice(at..at, methods_report::METHODS_FILES.map(String::from));
    let at = files.iter().position(|f| f == "summaries.json").unwrap_or(files.len());
    files.insert(at, friction_disc::FRICTION_TABLE.to_string());
    files.insert(at + 1, obstacles::OBSTACLES_TABLE.to_string());
    files.insert(at + 2, two_bodies::TWO_BARS_TABLE.to_string());
    let bodies_md = bodies_report::bodies_section(&bodies) + &hertz_report::hertz_section(&hertz);
    let report = report_markdown(
        config,
        &results,
        &rebound,
        (&scope, &ps, &cd_growth::cd_growth_section(&cd, quick), &table2d_lead::lead_section(&lead)),
        &files,
        table2d.as_ref(),
        &elastic,
        &bodies_md,
    ) + &methods_report::methods_section(&methods_config, &methods)
        + "\n"
        + &disc_md
        + "\n"
        + &friction.0
        + &friction_sphere::friction_sphere_markdown(&sphere)
        + &obstacles::obstacles_markdown(&obstacles)
        + &two_bodies::two_bodies_markdown(&two_bodies)
        + &two_discs::two_discs_markdown(&two_discs);
    let dir = out.path().display().to_string();
    out.commit(|tmp| {
        figures
            .par_iter()
            .chain([&rebound_figure, &scope_figure, &lead_figure, &cd_figure])
            .chain(&body_figures)
            .try_for_each(|f| -> std::io::Result<()> {
                f.write(tmp)?;
                progress.inc(1);
                Ok(())
            })?;
        tables::write_tables(tmp, config, &results, &tables)?;
        let header = REBOUND_COLUMNS.map(String::from);
        tables::write_csv(&tmp.join(REBOUND_TABLE), &header, &rebound_report::rebound_csv_rows(&rebound))?;
        table2d::write_csvs(tmp, table2d.as_ref())?;
        elastic_report::write_elastic_csv(tmp, &elastic)?;
        let header = BODIES_COLUMNS.map(String::from);
        tables::write_csv(&tmp.join(BODIES_TABLE), &header, &bodies_report::bodies_csv_rows(&bodies))?;
        methods_report::write_methods_files(tmp, &methods)?;
        let header = HERTZ_COLUMNS.map(String::from);
        tables::write_csv(&tmp.join(HERTZ_TABLE), &header, &hertz_report::hertz_csv_rows(&hertz))?;
        std::fs::write(tmp.join(friction_disc::FRICTION_TABLE), &friction.1)?;
        std::fs::write(tmp.join(obstacles::OBSTACLES_TABLE), obstacles::obstacles_csv(&obstacles))?;
        std::fs::write(tmp.join(two_bodies::TWO_BARS_TABLE), two_bodies::two_bodies_csv(&two_bodies))?;
        std::fs::write(tmp.join("summaries.json"), summaries_json(config, &results)?)?;
        std::fs::write(tmp.join("report.md"), &report)
    })
    .map_err(|e| ReproduceError::Io { dir, source: std::io::Error::other(e) })?;
    progress.set_message("done");
    Ok(Outcome { results, rebound, bodies, files, report })
}

/// Every run of [`reproduce`] but the 2D tables, in the order the report reads them.
struct Sections {
    results: Vec<CaseResult>,
    rebound: Rebound,
    scope: Vec<mesh_scope::ScopeEntry>,
    ps: ps_growth::PsGrowth,
    /// Central differences' energy growth against Δt/Δt_c (issue 32, item 5).
    cd: Vec<cd_growth::CdGrowth>,
    lead: table2d_lead::LeadRuns,
    bodies: Vec<bodies::BodyResult>,
    methods: Vec<methods::MethodResult>,
    hertz: Vec<hertz::HertzResult>,
    /// Problem (e) of the method comparison, the dropped disc (a table in the report only).
    disc_md: String,
    /// GetFEM's frictional disc (issue 29): the report's section and its CSV.
    friction: (String, String),
    /// The sphere landing with friction (issue 29, check 7).
    sphere: Vec<friction_sphere::SchemeRuns>,
    /// Curved rigid obstacles (issue 30).
    obstacles: Vec<obstacles::CaseRuns>,
    /// Two bodies: the two-bar impacts (issue 30).
    two_bodies: Vec<two_bodies::CaseRuns>,
    /// Two discs colliding, against Hertz (issue 30).
    two_discs: Vec<two_discs::DiscRun>,
}

/// Runs [`Sections`] and, beside them, the 2D tables (scalar and elastic): the elastic table's
/// fine-mesh reference is one long sequential run, and the other sections keep the remaining
/// cores busy meanwhile. Every run is independent of the others, so the schedule changes no
/// number. `progress` is advanced once per case.
#[allow(clippy::type_complexity)]
fn compute_sections(
    config: &Config,
    methods_config: &methods::MethodsConfig,
    progress: &ProgressBar,
) -> Result<(Sections, (Option<Table2d>, Vec<elastic_table::ElasticRow>)), ReproduceError> {
    let quick = !config.full_2d_sweep;
    let (sections, tables_2d) = rayon::join(
        || -> Result<Sections, ReproduceError> {
            Ok(Sections {
                results: timed("figure 11", || compute(config, &|| progress.inc(1)))?,
                rebound: timed("rebound", || compute_rebound(config, &|| progress.inc(1)))?,
                scope: timed("mesh scope", || mesh_scope::mesh_scope(config))?,
                ps: timed("Paoli–Schatzman growth", || ps_growth::ps_growth(config))?,
                cd: timed("central-difference growth", || cd_growth::cd_growth(quick))?,
                lead: timed("Table 1 lead", table2d_lead::lead_runs),
                bodies: timed("bodies", || bodies::compute_bodies(quick, &|| progress.inc(1)))?,
                methods: timed("method classes", || methods::compute(methods_config, &|| progress.inc(1))),
                hertz: timed("Hertz", || hertz::compute_hertz(&|| progress.inc(1)))?,
                disc_md: timed("disc (methods)", || {
                    methods_disc::compute_disc(replicate::Copies::All).map(|d| methods_disc::disc_markdown(&d))
                })?,
                friction: timed("frictional disc", || {
                    friction_disc::compute_friction_disc()
                        .map(|d| (friction_disc::friction_disc_markdown(&d), friction_disc::friction_disc_csv(&d)))
                })?,
                sphere: timed("frictional sphere", friction_sphere::compute_friction_sphere)?,
                obstacles: timed("curved obstacles", obstacles::compute_obstacles)?,
                two_bodies: timed("two bodies", two_bodies::compute_two_bodies)?,
                two_discs: timed("two discs", two_discs::compute_two_discs)?,
            })
        },
        // The scalar plates run one after another; the elastic candidates in parallel beside them.
        || {
            rayon::join(
                || timed("Table 1 (2D scalar)", || plate_2d_errors(config)),
                || timed("Table 1 (2D elastic)", || elastic_rows(quick)),
            )
        },
    );
    Ok((sections?, tables_2d))
}

/// `f()`, its wall time printed on stderr (sections overlap: their times do not add up).
fn timed<T>(section: &str, f: impl FnOnce() -> T) -> T {
    let start = std::time::Instant::now();
    let out = f();
    eprintln!("reproduce: {section}: {:.1} s wall", start.elapsed().as_secs_f64());
    out
}

/// The elastic table: quick against its 80² reference computed now, full with the 160²
/// reference's fixture ([`elastic_fixture`]).
fn elastic_rows(quick: bool) -> Vec<elastic_table::ElasticRow> {
    if quick {
        return elastic_table::elastic_table(true);
    }
    let stored = elastic_fixture::load();
    elastic_table::elastic_table_stored(
        stored.as_ref().map(|f| &f.full as &dyn elastic_table::StoredFine).map_err(Clone::clone),
    )
}

/// The files [`reproduce`] writes, in the order of [`Outcome::files`]: figures, tables, events,
/// the rebounding bar's figure, the mesh-scope figure ([`mesh_scope`]), the Table 1 lead's figure
/// ([`table2d_lead`]), central differences' growth figure ([`cd_growth`]), the rebounding bar's table, `table-2d.csv`, `table-2d-elastic.csv`, `summaries.json`, `report.md`, and
/// `table-2d-sweep.csv` if the 2D runs gave one.
fn file_names(
    config: &Config,
    figures: &[FigureFile],
    tables: &[(String, Vec<&CaseResult>)],
    extra_figures: &[&FigureFile],
    with_2d_sweep: bool,
) -> Vec<String> {
    let mut files: Vec<String> = figures.iter().flat_map(FigureFile::file_names).collect();
    files.extend(tables.iter().map(|(n, _)| n.clone()));
    files.extend(config.horizons.iter().map(|&end| tables::events_file(end)));
    files.extend(extra_figures.iter().flat_map(|f| f.file_names()));
    files.push(REBOUND_TABLE.into());
    files.extend([
        "table-2d.csv".to_string(),
        elastic_table::ELASTIC_TABLE.into(),
        "summaries.json".into(),
        "report.md".into(),
    ]);
    if with_2d_sweep {
        files.push("table-2d-sweep.csv".into());
    }
    files
}

/// `summaries.json`: the configuration and, per run, its case, failure and [`Summary`].
fn summaries_json(config: &Config, results: &[CaseResult]) -> std::io::Result<String> {
    #[derive(Serialize)]
    struct Entry<'a> {
        case: &'a Case,
        failure: Option<String>,
        #[serde(flatten)]
        summary: &'a Summary,
    }
    let entries: Vec<Entry> = results
        .iter()
        .map(|r| Entry { case: &r.case, failure: r.failure.as_ref().map(|e| e.to_string()), summary: &r.summary })
        .collect();
    let json = serde_json::json!({ "config": config, "runs": entries });
    Ok(serde_json::to_string_pretty(&json).map_err(std::io::Error::other)? + "\n")
}
