//! `massredist bench`: the work–precision sweep, the per-step performance against the floor of
//! a bare tridiagonal solve and against an independent Python stepper, and the environment.
//!
//! - [`sweep`]: scheme × mass × h × Δt on the exact benchmark, errors and times, fitted rates;
//! - [`perf`]: ns per node-step of each scheme next to a bare LDLᵀ / two-sided solve;
//! - [`mod@env`]: the environment record and the Python peer (subprocess, at the edge);
//! - [`report`]: CSV, Markdown tables, the work–precision figure (PNG and SVG);
//! - [`timing`]: the repeated, fastest-run clock both [`sweep`] and [`perf`] use.
//!
//! Everything is measured in the same process and the same run, so the ratios quoted in
//! `report.md` compare like with like. This module is an edge (it times, spawns and writes);
//! the schemes it drives are the library's own.

pub mod baseline;
pub mod env;
pub mod explicit_scaling;
pub mod friction;
pub mod layer;
pub mod methods;
pub mod perf;
pub mod report;
pub mod scaling;
pub mod sweep;
pub mod timing;
pub mod whole;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use massredist::mass::MassKind;
use massredist::scene::SchemeSpec;
use rayon::prelude::*;
use serde::Serialize;
use std::fmt::Write as _;

/// One Rust-vs-Python comparison at the same size, Δt = h and number of steps.
#[derive(Debug, Clone, Serialize)]
pub struct PythonRatio {
    pub scheme: String,
    pub mass: String,
    pub implementation: String,
    pub elements: usize,
    pub steps: usize,
    pub python_us_per_step: f64,
    pub rust_us_per_step: f64,
    /// python / rust.
    pub ratio: f64,
    /// max_i |u_i(rust) − u_i(python)| after the same steps (both solve the same problem).
    pub max_abs_difference: f64,
}

/// Everything `massredist bench` measured.
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    pub environment: env::Environment,
    pub config: sweep::SweepConfig,
    pub results: Vec<sweep::CaseResult>,
    pub rates: Vec<sweep::Rates>,
    pub timings: Vec<perf::SizeTimings>,
    /// 2D plate: time per step against one sparse solve pair.
    pub plate: Vec<perf::PlateTimings>,
    pub python: Vec<PythonRatio>,
    /// Why the Python comparison is missing or partial.
    pub python_note: Option<String>,
    /// Whole-process user-facing runs against the bare kernel and numpy ([`whole`]).
    pub whole: whole::WholeProcess,
    /// Plates and solids against the scipy baseline, and the 3D scaling.
    pub baseline: baseline::BaselineReport,
    pub seconds: f64,
}

/// Sizes of the per-step performance table.
pub const PERF_SIZES: [usize; 2] = [1_000, 10_000];
/// Size, steps of the Python comparison (one period at Δt = h for m = 10³).
pub const PYTHON_ELEMENTS: usize = 1_000;

fn progress(len: usize, what: &str) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(len as u64), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template(&format!("{{bar:40}} {{pos}}/{{len}} {what} {{elapsed_precise}} eta {{eta}}"))
            .expect("valid template"),
    );
    bar
}

/// Rust against the Python steppers (python/scripts/bench_stepper.py, run as a subprocess).
fn python_ratios(quick: bool) -> (Vec<PythonRatio>, Option<String>) {
    let m = PYTHON_ELEMENTS;
    let steps = 3 * m; // one period at Δt = h
    let dense_steps = if quick { 100 } else { 300 };
    let py = match env::run_python(m, steps, dense_steps, if quick { 2 } else { 3 }) {
        Ok(p) => p,
        Err(e) => return (Vec::new(), Some(format!("Python comparison skipped: {e}"))),
    };
    let mut out = Vec::new();
    for run in &py.runs {
        // The Python stepper runs the hybrid scheme on mod3 and Crank–Nicolson on the standard mass.
        let (spec, mass) = match SchemeSpec::from_name(&run.scheme) {
            Some(spec @ SchemeSpec::Hybrid) => (spec, MassKind::Mod3),
            Some(spec @ SchemeSpec::CrankNicolson { .. }) => (spec, MassKind::Standard),
            _ => continue,
        };
        // A loop time that is not positive is timer noise, not a measurement: leave it out.
        if !(run.seconds_per_step > 0.0) {
            continue;
        }
        let Some((secs, u)) = perf::time_steps(&spec, &mass, m, run.steps, 0.1) else { continue };
        let diff = u.iter().zip(&run.u_final).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        out.push(PythonRatio {
            scheme: run.scheme.clone(),
            mass: run.mass.clone(),
            implementation: run.implementation.clone(),
            elements: m,
            steps: run.steps,
            python_us_per_step: run.seconds_per_step * 1e6,
            rust_us_per_step: secs * 1e6,
            ratio: run.seconds_per_step / secs,
            max_abs_difference: diff,
        });
    }
    let note = (!py.missing.is_empty()).then(|| py.missing.join("; "));
    let note = Some(format!(
        "{} (Python {}, numpy {}, scipy {}){}",
        py.python,
        py.python_version,
        py.numpy,
        py.scipy,
        note.map_or(String::new(), |n| format!("; missing: {n}"))
    ));
    (out, note)
}

/// Runs the whole benchmark: per-step timings first (sequential, one thread busy), then the
/// Python peer, then the sweep (Rayon across independent runs).
pub fn run(quick: bool) -> BenchReport {
    let started = std::time::Instant::now();
    let environment = env::Environment::detect();
    let min_total = if quick { 0.15 } else { 0.5 };
    let bar = progress(PERF_SIZES.len() + 1, "timings");
    let mut timings = Vec::new();
    for m in PERF_SIZES {
        timings.push(perf::time_size(m, min_total));
        bar.inc(1);
    }
    let (python, python_note) = python_ratios(quick);
    let plate_sizes: &[(usize, usize)] = if quick { &[(48, 12)] } else { &[(48, 12), (96, 24)] };
    let plate = plate_sizes.iter().filter_map(|&(nx, ny)| perf::time_plate(nx, ny, min_total)).collect();
    let whole = whole::measure(quick);
    bar.finish_and_clear();
    let baseline = baseline::run(quick);

    let config = if quick { sweep::SweepConfig::quick() } else { sweep::SweepConfig::full() };
    let cases = sweep::cases(&config);
    // Largest first, for load balance; the canonical order is restored afterwards.
    let mut order: Vec<usize> = (0..cases.len()).collect();
    order.sort_by(|&a, &b| cases[b].work(config.end).total_cmp(&cases[a].work(config.end)));
    let bar = progress(cases.len(), "runs");
    let mut results: Vec<(usize, sweep::CaseResult)> = order
        .par_iter()
        .map(|&i| {
            let r = sweep::run_case(&cases[i], &config);
            bar.inc(1);
            (i, r)
        })
        .collect();
    bar.finish_and_clear();
    results.sort_by_key(|p| p.0);
    let results: Vec<sweep::CaseResult> = results.into_iter().map(|p| p.1).collect();
    let rates = sweep::rates(&results, 24);
    BenchReport {
        environment,
        config,
        results,
        rates,
        timings,
        plate,
        python,
        python_note,
        whole,
        baseline,
        seconds: started.elapsed().as_secs_f64(),
    }
}

/// Whether the sweeps run with fused multiply-add on this CPU.
fn fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    return std::arch::is_x86_feature_detected!("fma");
    #[cfg(not(target_arch = "x86_64"))]
    false
}

fn ratio(a: Option<f64>, b: f64) -> String {
    a.map_or("failed".into(), |a| format!("{:.2}", a / b))
}

/// The performance tables in Markdown. (One function of about 110 lines on purpose: it is the
/// report's template, and keeping it in one piece keeps the document's order visible.)
pub fn performance_markdown(r: &BenchReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "ns per node-step (fastest of repeated runs, Δt = h, one thread, no diagnostics) next to a bare tridiagonal \
         solve of the same size (ns per unknown): LDLᵀ (one forward + one backward chain, the naive floor of an \
         implicit 1D step) and the two-sided twisted solve the schemes use (two independent chains per sweep; \
         fused multiply-add in the chains: {}).\n",
        if fma() { "yes, detected at run time" } else { "no, not available on this CPU" }
    );
    let _ = writeln!(s, "| scheme | mass | m | ns/node-step | × LDLᵀ floor | × twisted solve |");
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|");
    for t in &r.timings {
        let _ = writeln!(
            s,
            "| *bare LDLᵀ solve* | | {} | {:.2} | 1.00 | {:.2} |",
            t.elements,
            t.ldlt_ns,
            t.ldlt_ns / t.twisted_ns
        );
        let _ = writeln!(
            s,
            "| *bare twisted solve, no FMA* | | {} | {:.2} | {:.2} | {:.2} |",
            t.elements,
            t.twisted_no_fma_ns,
            t.twisted_no_fma_ns / t.ldlt_ns,
            t.twisted_no_fma_ns / t.twisted_ns
        );
        let _ = writeln!(
            s,
            "| *bare twisted solve{}* | | {} | {:.2} | {:.2} | 1.00 |",
            if fma() { ", FMA" } else { "" },
            t.elements,
            t.twisted_ns,
            t.twisted_ns / t.ldlt_ns
        );
        for c in &t.schemes {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} |",
                c.scheme,
                c.mass,
                t.elements,
                c.ns_per_node_step.map_or("failed".into(), |v| format!("{v:.2}")),
                ratio(c.ns_per_node_step, t.ldlt_ns),
                ratio(c.ns_per_node_step, t.twisted_ns)
            );
        }
    }
    let _ = writeln!(s);
    if !r.python.is_empty() {
        let _ = writeln!(
            s,
            "Against an independent Python implementation of the same problem (m = {}, Δt = h, timed in-process by \
             python/scripts/bench_stepper.py, set-up excluded; Rust timed in this process over the same number of steps). \
             `pttrs`: numpy with LAPACK's tridiagonal dpttrs; `stepper`: python/crosscheck/stepper.py (dense Cholesky).\n",
            PYTHON_ELEMENTS
        );
        let _ = writeln!(
            s,
            "| scheme | mass | Python implementation | steps | Python µs/step | Rust µs/step | Python / Rust | max |Δu| |"
        );
        let _ = writeln!(s, "|---|---|---|---:|---:|---:|---:|---:|");
        for p in &r.python {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.2} | {:.3} | {:.1} | {:.1e} |",
                p.scheme,
                p.mass,
                p.implementation,
                p.steps,
                p.python_us_per_step,
                p.rust_us_per_step,
                p.ratio,
                p.max_abs_difference
            );
        }
    }
    if !r.plate.is_empty() {
        let _ = writeln!(
            s,
            "\n2D plate (quad mesh, Mod 3, Δt = h, one period): time per step against one sparse triangular solve pair \
             (L Lᵀ of M + Δt²/4 S, AMD ordering) of the same size.\n"
        );
        let _ = writeln!(s, "| mesh | unknowns | scheme | µs/step | × solve pair |");
        let _ = writeln!(s, "|---|---:|---|---:|---:|");
        for p in &r.plate {
            let _ = writeln!(
                s,
                "| {}×{} | {} | *bare solve pair* | {:.1} | 1.00 |",
                p.nx, p.ny, p.unknowns, p.solve_pair_us
            );
            for (label, us) in &p.schemes {
                let _ = writeln!(
                    s,
                    "| {}×{} | {} | {} | {} | {} |",
                    p.nx,
                    p.ny,
                    p.unknowns,
                    label,
                    us.map_or("failed".into(), |u| format!("{u:.1}")),
                    us.map_or("–".into(), |u| format!("{:.2}", u / p.solve_pair_us))
                );
            }
        }
    }
    s += &whole::markdown(&r.whole);
    if let Some(n) = &r.python_note {
        let _ = writeln!(s, "\nPython: {n}");
    }
    s
}

fn environment_markdown(e: &env::Environment) -> String {
    format!(
        "Environment: {} ({} logical CPUs), {}, {}, {} build, massredist {} at {}{}, {} Rayon threads.\n",
        e.cpu,
        e.logical_cpus,
        e.os,
        e.rustc,
        e.profile,
        e.crate_version,
        &e.git_commit[..e.git_commit.len().min(12)],
        if e.git_dirty { " (uncommitted changes)" } else { "" },
        e.rayon_threads
    )
}

/// Writes `report.md`, `work_precision.csv`, `rates.md`, `performance.md`, `environment.json`,
/// `bench.json` and the figure (`work_precision.png`, `.svg`) into `out` (a folder prepared before
/// computing; atomically).
pub fn write(out: massredist::output::OutputDir, r: &BenchReport) -> Result<(), massredist::output::OutputError> {
    let schemes: Vec<&str> = sweep::scheme_cases().iter().map(|c| c.label).collect();
    let masses: Vec<&str> = sweep::masses().iter().map(|m| m.name()).collect();
    let finest = r.config.elements.iter().copied().max().unwrap_or(0);
    let rates_md = report::rates_markdown(&r.rates, finest, &r.config.dt_divisors);
    let perf_md = performance_markdown(r);
    let env_md = environment_markdown(&r.environment);
    let failures: Vec<String> = r
        .results
        .iter()
        .filter_map(|c| {
            c.failure
                .as_ref()
                .map(|f| format!("- {} / {} m={} Δt=h/{}: {f}", c.scheme, c.mass, c.elements, c.dt_divisor))
        })
        .collect();
    let mut full = String::new();
    let _ =
        writeln!(full, "# massredist bench{}\n", if r.config == sweep::SweepConfig::quick() { " --quick" } else { "" });
    let _ = writeln!(full, "{env_md}");
    let _ = writeln!(full, "Total time {:.1} s; {} runs in the sweep.\n", r.seconds, r.results.len());
    let _ = writeln!(full, "## Work–precision\n\n![work–precision](work_precision.svg)\n");
    let _ = writeln!(full, "## Observed convergence rates\n\n{rates_md}");
    let _ = writeln!(full, "## Performance\n\n{perf_md}");
    let baseline_md = baseline::markdown(&r.baseline);
    let _ = writeln!(full, "## Plates and solids against scipy\n\n{baseline_md}");
    if !failures.is_empty() {
        let _ = writeln!(full, "## Diverged or failed runs\n\n{}\n", failures.join("\n"));
    }
    out.commit(|tmp| {
        std::fs::write(tmp.join("work_precision.csv"), report::results_csv(&r.results))?;
        std::fs::write(tmp.join("rates.md"), &rates_md)?;
        std::fs::write(tmp.join("performance.md"), &perf_md)?;
        std::fs::write(tmp.join("baseline.md"), &baseline_md)?;
        for ext in ["png", "svg"] {
            let path = tmp.join(format!("solid_scaling.{ext}"));
            baseline::scaling_figure(&path, &r.baseline.scaling).map_err(std::io::Error::other)?;
        }
        std::fs::write(tmp.join("report.md"), &full)?;
        std::fs::write(tmp.join("environment.json"), json(&r.environment))?;
        std::fs::write(tmp.join("bench.json"), json(r))?;
        for ext in ["png", "svg"] {
            report::work_precision_figure(
                &tmp.join(format!("work_precision.{ext}")),
                &r.results,
                &schemes,
                &masses,
                &r.config.dt_divisors,
            )
            .map_err(std::io::Error::other)?;
        }
        Ok(())
    })
}

fn json<T: Serialize>(v: &T) -> String {
    serde_json::to_string_pretty(v).expect("plain data serialises") + "\n"
}
