//! The exit codes of the `massredist` command, in one place (`docs/scenes.md`, "Exit codes").

/// Success (`main` returns `ExitCode::SUCCESS`, the same value).
#[allow(dead_code)]
pub const SUCCESS: u8 = 0;

/// A failure while computing or writing, after the checks passed: the run failed, a write
/// failed, a cross-check was outside its tolerance.
pub const FAILURE: u8 = 1;

/// The command cannot start: invalid arguments (clap also exits with 2) or scene, or an output
/// folder that is refused or cannot be created. Nothing was computed and nothing written.
pub const INVALID: u8 = 2;

/// `run`: the run diverged (a non-finite state, or an energy above `output.divergence_factor`
/// times its reference; `massredist::driver::DivergenceCriterion`). It stopped there and its
/// folder is written, a result: `summary.json` has `status = "diverged"` and `divergence`
/// (step, time, reason) and describes the last finite state, `series.csv` ends at it. `reproduce`
/// and `bench` report diverged runs in their tables and exit 0.
pub const DIVERGED: u8 = 3;

/// `run`, `reproduce`, `bench` stopped by SIGTERM, SIGINT or SIGHUP: 128 + the signal number
/// (143, 130, 129), as a shell reports a process killed by that signal, after the temporary
/// output folder was removed (`massredist::output::install_signal_cleanup`). SIGXFSZ (a file
/// size limit) is not an exit of its own: the write fails and the run exits with [`FAILURE`].
#[allow(dead_code)]
pub const SIGNALLED_BASE: u8 = 128;
