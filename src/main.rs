//! The `massredist` command line: run, check, reproduce, bench, crosscheck.

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use massredist::run::{Observer, Sample, run_scene};
use massredist::scene::Scene;
use std::path::PathBuf;
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
    },
    /// Validate a scene and print it with every default filled in.
    Check { scene: PathBuf },
}

/// A progress bar on stderr, drawn only when stderr is a terminal.
struct Progress(ProgressBar);

impl Observer for Progress {
    fn observe(&mut self, s: &Sample) {
        if s.state.n % 256 == 0 {
            self.0.set_position(s.state.n as u64);
        }
    }
}

fn progress(len: u64) -> Progress {
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    bar.set_style(ProgressStyle::with_template("{bar:40} {pos}/{len} steps {elapsed_precise} eta {eta}").unwrap());
    Progress(bar)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Check { scene } => match Scene::from_file(&scene) {
            Ok(s) => {
                print!("{}", s.resolved_toml());
                ExitCode::SUCCESS
            }
            Err(e) => fail(&scene, e.to_string(), 2),
        },
        Command::Run { scene, out } => {
            let s = match Scene::from_file(&scene) {
                Ok(s) => s,
                Err(e) => return fail(&scene, e.to_string(), 2),
            };
            let mut bar = progress(s.time.steps as u64);
            let result = run_scene(&s, &mut [&mut bar]);
            bar.0.finish_and_clear();
            let (summary, series) = match result {
                Ok(r) => r,
                Err(e) => return fail(&scene, e.to_string(), 1),
            };
            if let Err(e) = massredist::output::write_run(&out, &s, &summary, &series) {
                return fail(&out, e.to_string(), 1);
            }
            eprintln!(
                "{}: {} steps in {:.3} s, L∞(L²) error {}, energy {} -> {}",
                out.display(),
                summary.steps,
                summary.wall_seconds,
                summary.linf_l2_error.map_or("n/a".into(), |e| format!("{e:.4e}")),
                summary.energy_initial,
                summary.energy_final
            );
            ExitCode::SUCCESS
        }
    }
}

fn fail(path: &std::path::Path, msg: String, code: u8) -> ExitCode {
    eprintln!("error: {}: {msg}", path.display());
    ExitCode::from(code)
}
