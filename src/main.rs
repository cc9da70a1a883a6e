//! The `massredist` command line: run, check, reproduce, bench, crosscheck.

mod exit;

// The study (study/src: the paper's experiments, the benchmarks, the cross-checks, the charts),
// compiled into this binary from its own files. It is also the library `massredist_study`, but
// this binary cannot depend on it: that crate depends on this package's library, and Cargo
// refuses the package cycle. The modules name each other `crate::paper`, `crate::bench`, … so
// both builds resolve alike; what only the study's tests use is dead code here.
// Without the default feature `study` the binary is the solver's alone (run, check): the
// solver's tests build and pass so (`cargo test -p massredist --no-default-features`).
#[cfg(feature = "study")]
#[allow(dead_code, unused_imports)]
#[path = "../study/src/bench/mod.rs"]
mod bench;
#[cfg(all(feature = "python", feature = "study"))]
#[allow(dead_code, unused_imports)]
#[path = "../study/src/bridge.rs"]
mod bridge;
#[cfg(all(feature = "python", feature = "study"))]
#[allow(dead_code, unused_imports)]
#[path = "../study/src/crosscheck.rs"]
mod crosscheck;
#[cfg(feature = "study")]
#[allow(dead_code, unused_imports)]
#[path = "../study/src/crosscheck_trajectory.rs"]
mod crosscheck_trajectory;
#[cfg(feature = "study")]
#[allow(dead_code, unused_imports)]
#[path = "../study/src/paper/mod.rs"]
mod paper;
#[cfg(feature = "study")]
#[allow(dead_code, unused_imports)]
#[path = "../study/src/plot.rs"]
mod plot;
#[cfg(feature = "study")]
#[path = "../study/src/repo.rs"]
mod repo;

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use massredist::driver::{Observer, Sample};
use massredist::observe::Summary;
use massredist::output::OutputDir;
use massredist::run::{GeometrySpec, RunError, run_scene_into};
use massredist::scene::AnyScene;
use massredist::scene::{Registered, Scene};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "massredist", version, about = "Weighted finite element mass redistribution for dynamic contact")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene and write series.csv, summary.json and scene.resolved.toml into DIR.
    Run {
        scene: PathBuf,
        #[arg(long)]
        out: PathBuf,
        #[command(flatten)]
        force: Force,
        /// `fenicsx`: step the (plate) scene with dolfinx and PETSc under MPI (src/engine.rs).
        #[arg(long, value_enum, default_value = "rust")]
        engine: Engine,
        /// MPI ranks of the fenicsx engine.
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..))]
        ranks: u16,
    },
    /// Validate a scene and print it with every default filled in.
    Check { scene: PathBuf },
    /// Compare the Rust matrices and trajectories with dolfinx and scikit-fem (feature `python`).
    #[cfg(all(feature = "python", feature = "study"))]
    Crosscheck {
        /// Also write the report as JSON to this file.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Run every numerical experiment of the paper and write figures, CSVs and report.md into DIR
    /// (by default docs/reproduce, the folder the documentation links to; run from the repository
    /// root it is replaced in place, which the folder's marker allows: it lists what reproduce wrote).
    #[cfg(feature = "study")]
    Reproduce {
        #[arg(long, default_value = "docs/reproduce")]
        out: PathBuf,
        /// Shorter runs (long run T = 30, a small 2D sweep): every output, in less time.
        #[arg(long)]
        quick: bool,
        #[command(flatten)]
        force: Force,
        /// Start every run from initial data perturbed by ≤ 1e-13 (a check that the report prints
        /// only digits round-off leaves alone; see tests/roundoff_audit.rs).
        #[arg(long, hide = true)]
        roundoff_audit: bool,
    },
    /// Work–precision sweep, per-step performance against a bare solve and a Python stepper;
    /// writes CSV, tables, figure and report.md into DIR.
    #[cfg(feature = "study")]
    Bench {
        /// m up to 1536 and Δt = h, h/2, h/4 (under two minutes on 2 cores).
        #[arg(long)]
        quick: bool,
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
        #[command(flatten)]
        force: Force,
        /// Only draw the engine-scaling figure (PNG and SVG next to this table, as written by
        /// python/scripts/bench_engine.py), then exit.
        #[arg(long, value_name = "CSV")]
        scaling_figure: Option<PathBuf>,
        /// Only the comparison of the method classes (issue 20: src/paper/methods.rs) into DIR.
        #[arg(long)]
        methods: bool,
        /// Only measure implicit against explicit 3D solids (time per step, peak memory; up to
        /// 10⁶ unknowns; with --quick small sizes) into this table (and .md, .png, .svg beside it),
        /// then exit.
        #[arg(long, value_name = "CSV")]
        explicit_scaling: Option<PathBuf>,
        /// Only measure the cost of a frictional step against the frictionless one (the disc and
        /// sphere scenes, Crank–Nicolson and central differences) into this table (and .md
        /// beside it), then exit.
        #[arg(long, value_name = "CSV")]
        friction: Option<PathBuf>,
        /// Only measure central differences' massless contact layer against the number of
        /// contact nodes (10² … 10⁴; with --quick the two smallest) into this table (and .md
        /// beside it), then exit.
        #[arg(long, value_name = "CSV")]
        layer: Option<PathBuf>,
    },
}

/// Which engine steps a `run`.
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Engine {
    Rust,
    Fenicsx,
}

/// `--force` of the commands that write an output folder.
#[derive(clap::Args, Clone, Copy)]
struct Force {
    /// Replace DIR even if massredist did not write it (deleting what it holds); never a file, a
    /// folder holding the scene, the current folder or the home folder.
    #[arg(long)]
    force: bool,
}

/// A progress bar on stderr, drawn only when stderr is a terminal.
struct Progress(ProgressBar);

impl Observer for Progress {
    fn observe(&mut self, s: &Sample) {
        if s.state.n.is_multiple_of(256) {
            self.0.set_position(s.state.n as u64);
        }
    }
}

fn progress(len: u64) -> Progress {
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    bar.set_style(ProgressStyle::with_template("{bar:40} {pos}/{len} steps {elapsed_precise} eta {eta}").unwrap());
    Progress(bar)
}

/// The command line: one match arm per command, each preparing its output folder and calling
/// the library (about 90 lines: the arms are short, and one place lists every command's edge).
fn main() -> ExitCode {
    let cli = Cli::parse();
    // What cannot fit in memory is refused before it is allocated (machine.rs).
    let _ = massredist::machine::install_memory_limit();
    // SIGTERM, SIGINT, SIGHUP: the staging folder is removed, exit 128 + signal (src/output/staging.rs).
    if let Err(e) = massredist::output::install_signal_cleanup() {
        eprintln!("warning: no signal handler ({e}); an interrupted run leaves its temporary folder");
    }
    match cli.command {
        #[cfg(feature = "study")]
        Command::Bench { scaling_figure: Some(csv), .. } => match bench::scaling::scaling_figure(&csv) {
            Ok(paths) => {
                paths.iter().for_each(|p| eprintln!("wrote {}", p.display()));
                ExitCode::SUCCESS
            }
            Err(m) => fail(&csv, m, exit::FAILURE),
        },
        #[cfg(feature = "study")]
        Command::Bench { methods: true, out, force, .. } => {
            let dir = match prepare(&out, force, &[]) {
                Ok(d) => d,
                Err(code) => return code,
            };
            let report = bench::methods::run();
            if let Err(e) = bench::methods::write(dir, &report) {
                return fail(&out, e.to_string(), exit::FAILURE);
            }
            eprintln!("{}: {} runs in {:.1} s; see report.md", out.display(), report.results.len(), report.seconds);
            ExitCode::SUCCESS
        }
        #[cfg(feature = "study")]
        Command::Bench { explicit_scaling: Some(csv), quick, .. } => {
            match bench::explicit_scaling::run(&csv, quick, 21) {
                Ok(paths) => {
                    paths.iter().for_each(|p| eprintln!("wrote {}", p.display()));
                    ExitCode::SUCCESS
                }
                Err(m) => fail(&csv, m, exit::FAILURE),
            }
        }
        #[cfg(feature = "study")]
        Command::Bench { layer: Some(csv), quick, .. } => match bench::layer::run(&csv, quick) {
            Ok(paths) => {
                paths.iter().for_each(|p| eprintln!("wrote {}", p.display()));
                ExitCode::SUCCESS
            }
            Err(m) => fail(&csv, m, exit::FAILURE),
        },
        #[cfg(feature = "study")]
        Command::Bench { friction: Some(csv), .. } => match bench::friction::run(&csv) {
            Ok(paths) => {
                paths.iter().for_each(|p| eprintln!("wrote {}", p.display()));
                ExitCode::SUCCESS
            }
            Err(m) => fail(&csv, m, exit::FAILURE),
        },
        #[cfg(feature = "study")]
        Command::Bench { quick, out, force, .. } => {
            let dir = match prepare(&out, force, &[]) {
                Ok(d) => d,
                Err(code) => return code,
            };
            let report = bench::run(quick);
            if let Err(e) = bench::write(dir, &report) {
                return fail(&out, e.to_string(), exit::FAILURE);
            }
            eprintln!("{}: {} runs in {:.1} s; see report.md", out.display(), report.results.len(), report.seconds);
            ExitCode::SUCCESS
        }
        #[cfg(all(feature = "python", feature = "study"))]
        Command::Crosscheck { json } => crosscheck(json),
        Command::Check { scene } => match AnyScene::from_file(&scene).and_then(|s| {
            let estimate = massredist::run::check(&s)?;
            Ok((s, estimate))
        }) {
            Ok((s, estimate)) => {
                let note = estimate.note.as_ref().map_or(String::new(), |n| format!("# {n}\n"));
                if let Err(e) = print_out(&(note + &s.resolved_toml())) {
                    return e;
                }
                eprintln!("{}: {}", scene.display(), describe(&estimate));
                ExitCode::SUCCESS
            }
            Err(e) => fail(&scene, e.to_string(), exit::INVALID),
        },
        #[cfg(feature = "study")]
        Command::Reproduce { out, quick, force, roundoff_audit } => match prepare(&out, force, &[]) {
            Ok(dir) => {
                massredist::problem::set_roundoff_audit(roundoff_audit);
                reproduce(dir, quick)
            }
            Err(code) => code,
        },
        Command::Run { scene, out, force, engine, ranks } => match prepare(&out, force, &inputs(&scene)) {
            Ok(dir) => match (AnyScene::from_file(&scene), engine) {
                (Ok(AnyScene::Plate(s)), Engine::Fenicsx) => run_engine(&scene, s, dir, ranks.into()),
                (Ok(AnyScene::Solid(s)), Engine::Fenicsx) => run_engine(&scene, s, dir, ranks.into()),
                (Ok(_), Engine::Fenicsx) => fail(
                    &scene,
                    "--engine fenicsx runs plate and solid scenes ([plate], [solid]); bars run in Rust".into(),
                    exit::INVALID,
                ),
                (Ok(any), Engine::Rust) => massredist::with_scene!(&any, s => run_with(&scene, s, dir)),
                (Err(e), _) => fail(&scene, e.to_string(), exit::INVALID),
            },
            Err(code) => code,
        },
    }
}

/// The scene file and every file it names: the inputs a run never deletes (issue 32, E12).
fn inputs(scene: &Path) -> Vec<PathBuf> {
    std::iter::once(scene.to_path_buf()).chain(AnyScene::named_files(scene)).collect()
}

/// The output folder `out` checked and its temporary sibling created before anything is
/// computed ([`OutputDir::prepare`]); the command streams into it and commits it at the end.
/// A refusal is exit code 2.
fn prepare(out: &Path, force: Force, inputs: &[PathBuf]) -> Result<OutputDir, ExitCode> {
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    match OutputDir::prepare(out, force.force, &inputs) {
        Ok(dir) => {
            for p in dir.removed_left_overs() {
                eprintln!("removed {}, the partial output of an interrupted run", p.display());
            }
            Ok(dir)
        }
        Err(e) => {
            eprintln!("error: {e}");
            Err(ExitCode::from(exit::INVALID))
        }
    }
}

/// `reproduce`: every experiment of the paper and the rebounding bar into `out`.
#[cfg(feature = "study")]
fn reproduce(out: OutputDir, quick: bool) -> ExitCode {
    let config = if quick { paper::Config::quick() } else { paper::Config::paper() };
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    bar.set_style(ProgressStyle::with_template("{bar:40} {pos}/{len} {msg} {elapsed_precise}").unwrap());
    let started = std::time::Instant::now();
    let path = out.path().to_path_buf();
    let result = paper::reproduce(out, &config, &bar);
    bar.finish_and_clear();
    match result {
        Ok(o) => {
            let stopped = o.results.iter().filter(|r| r.failure.is_some()).count();
            eprintln!(
                "{}: {} runs of the paper ({} diverged) and {} of the rebounding bar, {} files in {:.2} s; see {}",
                path.display(),
                o.results.len(),
                stopped,
                o.rebound.runs.len(),
                o.files.len(),
                started.elapsed().as_secs_f64(),
                path.join("report.md").display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => fail(&path, e.to_string(), exit::FAILURE),
    }
}

/// A run's error: computing (named by the scene) or writing (the message names the folder);
/// exit code 2 for a scene that cannot be set up, 1 otherwise, the temporary folder removed.
fn run_failed(scene: &Path, e: RunError) -> ExitCode {
    match e {
        RunError::Output(e) => {
            eprintln!("error: {e}");
            ExitCode::from(exit::FAILURE)
        }
        // A scene that cannot be set up is invalid input (as `check` says).
        e if e.invalid_input() => fail(scene, e.to_string(), exit::INVALID),
        e => fail(scene, e.to_string(), exit::FAILURE),
    }
}

/// `run` in Rust for any geometry: the progress bar, the run streamed into `dir`, the report
/// line and the exit code.
fn run_with<G: GeometrySpec + Registered>(scene: &Path, s: &Scene<G>, dir: OutputDir) -> ExitCode {
    if matches!(s.scheme, massredist::schemes::SchemeSpec::CentralDifference { .. }) {
        // An explicit run's large arrays mapped on their own, returned when freed (machine.rs:
        // its peak memory; the implicit schemes keep glibc's default, which they run faster on).
        let _ = massredist::machine::map_large_arrays();
    }
    let out = dir.path().to_path_buf();
    let mut bar = progress(s.time.steps as u64);
    let result = run_scene_into(s, dir, &mut [&mut bar]);
    bar.0.finish_and_clear();
    let summary = match result {
        Ok(r) => r,
        Err(e) => return run_failed(scene, e),
    };
    eprintln!(
        "{}: {} steps in {:.3} s, L∞(L²) error {}, energy {} -> {}, largest step increase {:e}",
        out.display(),
        summary.steps,
        summary.wall_seconds,
        summary.linf_l2_error.map_or("n/a".into(), |e| format!("{e:.4e}")),
        summary.energy_initial,
        summary.energy_final,
        summary.energy_max_increase
    );
    status(&out, &summary)
}

/// `run --engine fenicsx`: the scene stepped by dolfinx/PETSc in `ranks` MPI processes.
fn run_engine<G: massredist::engine::EngineGeometry>(
    scene: &Path,
    s: massredist::scene::Scene<G>,
    dir: OutputDir,
    ranks: usize,
) -> ExitCode {
    let out = dir.path().to_path_buf();
    let outcome = massredist::engine::run(&s, dir, ranks);
    if outcome.is_ok() {
        eprintln!("{}", massredist::engine::report(&out));
    }
    match outcome {
        Ok(massredist::engine::EngineOutcome::Completed) => ExitCode::SUCCESS,
        Ok(massredist::engine::EngineOutcome::Diverged) => ExitCode::from(exit::DIVERGED),
        Err(e) => fail(scene, e.to_string(), if e.is_invalid() { exit::INVALID } else { exit::FAILURE }),
    }
}

/// The exit code of a written run: 0, or [`exit::DIVERGED`] with a word on stderr.
fn status(out: &Path, summary: &Summary) -> ExitCode {
    match &summary.divergence {
        None => ExitCode::SUCCESS,
        Some(d) => {
            eprintln!(
                "{}: {d}; the run stopped there (status \"diverged\" in summary.json, which describes the last finite state; series.csv ends at it)",
                out.display()
            );
            ExitCode::from(exit::DIVERGED)
        }
    }
}

#[cfg(all(feature = "python", feature = "study"))]
fn crosscheck(json: Option<PathBuf>) -> ExitCode {
    let report = match crosscheck::matrix_cases().and_then(|c| crosscheck::run(None, &c)) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: crosscheck: {e}");
            return ExitCode::from(exit::FAILURE);
        }
    };
    if let Err(code) = print_out(&crosscheck::table(&report)) {
        return code;
    }
    // Trajectory cases: plate and solid scenes stepped by this binary and by the FEniCSx engine.
    let tmp = std::env::temp_dir().join(format!("massredist-crosscheck-{}", std::process::id()));
    let exe = std::env::current_exe().unwrap_or_else(|_| PathBuf::from("massredist"));
    let traj = std::fs::create_dir_all(&tmp).map_or_else(
        |e| vec![crosscheck_trajectory::failed_setup(&tmp, &e)],
        |()| crosscheck_trajectory::run_all(&exe, &tmp),
    );
    let _ = std::fs::remove_dir_all(&tmp);
    if let Err(code) = print_out(&crosscheck_trajectory::table(&traj)) {
        return code;
    }
    let failed = report.cases.iter().filter(|c| !c.pass).count() + traj.iter().filter(|c| !c.pass).count();
    if let Some(path) = json {
        let mut value = serde_json::to_value(&report).expect("report serialises");
        value["trajectories"] = serde_json::to_value(&traj).expect("trajectories serialise");
        let text = serde_json::to_string_pretty(&value).expect("report serialises") + "\n";
        if let Err(e) = massredist::output::write_file_atomically(&path, text.as_bytes()) {
            return fail(&path, e.to_string(), exit::FAILURE);
        }
    }
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        eprintln!("crosscheck: {failed} case(s) outside tolerance");
        ExitCode::from(exit::FAILURE)
    }
}

/// Writes `text` to stdout. A closed stdout (`check X | head -c0`: EPIPE) is a clean exit, 0
/// with nothing more said (the reader wanted no more); another write error is exit 1.
fn print_out(text: &str) -> Result<(), ExitCode> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Err(ExitCode::SUCCESS),
        Err(e) => {
            eprintln!("error: writing to stdout: {e}");
            Err(ExitCode::from(exit::FAILURE))
        }
    }
}

fn fail(path: &std::path::Path, msg: String, code: u8) -> ExitCode {
    // A failure caused by a stopping signal (a child it stopped) is not reported: the signal
    // thread exits with 128 + the signal.
    massredist::output::wait_if_signalled();
    eprintln!("error: {}: {msg}", path.display());
    ExitCode::from(code)
}

/// `check`'s estimate of a run ([`massredist::run::Estimate`]) in one line.
fn describe(e: &massredist::run::Estimate) -> String {
    let head = format!("{} unknowns, set up in {:.3} s", e.unknowns, e.setup_seconds);
    match (e.step_seconds, e.run_seconds()) {
        (Some(step), Some(run)) => format!(
            "{head}; {:.3e} s per step (mean of the first {}, with the summary{}), so about {:.3e} s for the {} steps (without output{})",
            step,
            e.probe_steps,
            if e.exact_error { " and its exact L² error" } else { "" },
            run,
            e.steps,
            if e.touched { "" } else { "; no contact in those steps: steps in contact cost more" }
        ),
        _ => format!("{head}; its first step did not complete, no time estimate"),
    }
}
