//! `massredist bench --methods`: the comparison of every method class of issue 20
//! ([`crate::paper::methods`]) on the bench's meshes ([`MethodsConfig::bench`]), written as
//! `methods.csv`, `methods.md` (tables and prose), the work–precision figure
//! (`methods-work-precision.png`, `.svg`), `environment.json` and `report.md`; problem (e), the
//! dropped disc ([`crate::paper::methods_disc`]), as a table in the report and `methods-disc.csv`.
//! An edge: it times, runs and writes; the numbers come from the library.

use crate::paper::methods::{MethodResult, MethodsConfig, cases, compute};
use crate::paper::methods_disc::{DiscResult, compute_disc, disc_csv, disc_markdown};
use crate::paper::methods_report::{METHODS_FILES, methods_markdown, write_methods_files};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::Serialize;

/// Everything `bench --methods` measured.
#[derive(Debug, Clone, Serialize)]
pub struct MethodsReport {
    pub environment: super::env::Environment,
    pub config: MethodsConfig,
    pub results: Vec<MethodResult>,
    /// Problem (e), the dropped disc (its error, if a run failed, as text).
    pub disc: Result<Vec<DiscResult>, String>,
    pub seconds: f64,
}

/// Runs the comparison (Rayon across runs).
pub fn run() -> MethodsReport {
    let started = std::time::Instant::now();
    let environment = super::env::Environment::detect();
    let config = MethodsConfig::bench();
    let bar = ProgressBar::with_draw_target(Some(cases(&config).len() as u64), ProgressDrawTarget::stderr());
    bar.set_style(ProgressStyle::with_template("{bar:40} {pos}/{len} runs {elapsed_precise}").expect("valid template"));
    let results = compute(&config, &|| bar.inc(1));
    bar.finish_and_clear();
    let disc = compute_disc(crate::paper::replicate::Copies::All).map_err(|e| e.to_string());
    MethodsReport { environment, config, results, disc, seconds: started.elapsed().as_secs_f64() }
}

/// Writes the files into `out` (prepared before computing; atomically).
pub fn write(out: massredist::output::OutputDir, r: &MethodsReport) -> Result<(), massredist::output::OutputError> {
    let e = &r.environment;
    let disc = match &r.disc {
        Ok(d) => disc_markdown(d),
        Err(e) => format!("### (e) the dropped disc\n\nnot run: {e}\n"),
    };
    let body = methods_markdown(&r.config, &r.results, METHODS_FILES[1]) + "\n" + &disc;
    let report = format!(
        "# massredist bench --methods\n\nEnvironment: {} ({} logical CPUs), {}, {} build, massredist {} at {}{}, {} Rayon \
         threads. Total time {:.1} s; {} runs (the runs of a case in parallel with others: CPU times are of one \
         thread on a shared machine).\n\n{body}",
        e.cpu,
        e.logical_cpus,
        e.rustc,
        e.profile,
        e.crate_version,
        &e.git_commit[..e.git_commit.len().min(12)],
        if e.git_dirty { " (uncommitted changes)" } else { "" },
        e.rayon_threads,
        r.seconds,
        r.results.len()
    );
    out.commit(|tmp| {
        write_methods_files(tmp, &r.results)?;
        if let Ok(d) = &r.disc {
            std::fs::write(tmp.join("methods-disc.csv"), disc_csv(d))?;
        }
        std::fs::write(tmp.join("methods.md"), &report)?;
        std::fs::write(tmp.join("report.md"), &report)?;
        let json = serde_json::to_string_pretty(&r.environment).expect("plain data serialises") + "\n";
        std::fs::write(tmp.join("environment.json"), json)?;
        Ok(())
    })
}
