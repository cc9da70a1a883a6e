//! Regenerates `fixtures/elastic-reference.json`, the elastic table's fine-mesh reference as the
//! table reads it (`massredist_study::paper::elastic_fixture`): the 160² reference up to T = 10
//! with every free-face run of the full grid against it, and the coarse set that CI recomputes.
//! A deliberate command (several minutes on 2 cores):
//! `cargo run --release -p massredist-study --bin elastic-fixture`.

use massredist_study::bench::env::Environment;
use massredist_study::paper::elastic_fixture::{self, Provenance};
use std::process::ExitCode;

fn main() -> ExitCode {
    let env = Environment::detect();
    let provenance = Provenance {
        command: "cargo run --release -p massredist-study --bin elastic-fixture".into(),
        commit: env.git_commit,
        dirty: env.git_dirty,
        rustc: env.rustc,
        what: "the free-face (λ = 3/7, μ = 2/7) runs of the elastic table against the fine-mesh reference \
               (Q1, Crank–Nicolson, mod2, Δt = h/5; full: 160² cells to T = 10 with its 80² check, the full \
               grid; coarse: 40² to T = 3, the quick grid): the running maximum of the L² error at each T, \
               unperturbed and in the 4 perturbed copies"
            .into(),
    };
    let started = std::time::Instant::now();
    let fixture = match elastic_fixture::compute(provenance) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let path = elastic_fixture::path();
    let text = serde_json::to_string_pretty(&fixture).expect("the fixture serialises") + "\n";
    if let Err(e) = std::fs::write(&path, text) {
        eprintln!("error: {}: {e}", path.display());
        return ExitCode::FAILURE;
    }
    eprintln!("wrote {} in {:.1} s", path.display(), started.elapsed().as_secs_f64());
    ExitCode::SUCCESS
}
