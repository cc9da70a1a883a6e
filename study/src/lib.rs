//! The paper study beside the solver: every numerical experiment of the paper (`paper`), the
//! benchmarks (`bench`), the cross-checks against dolfinx, scikit-fem and GetFEM (`crosscheck`,
//! `crosscheck_trajectory`, `bridge`) and the charts (`plot`). It uses `massredist` (the solver)
//! through its public API; the solver never imports it.
//!
//! The `massredist` binary compiles these modules into itself from the same files (see
//! `src/main.rs`); the modules name each other as `crate::paper`, `crate::bench`, … so the two
//! builds resolve alike.

pub mod bench;
#[cfg(feature = "python")]
pub mod bridge;
#[cfg(feature = "python")]
pub mod crosscheck;
pub mod crosscheck_trajectory;
pub mod paper;
pub mod plot;
pub mod repo;
