//! massredist: the weighted finite element mass redistribution method for dynamic contact
//! (Dabaghi, Krejčí, Petrov, Pousin, Renard), with exact solutions and cross-checks.

#[cfg(feature = "python")]
pub mod bridge;
#[cfg(feature = "python")]
pub mod crosscheck;

pub mod bar;
pub mod bench;
pub mod characteristics;
pub mod column;
pub mod contact;
pub mod crosscheck_trajectory;
pub mod driver;
pub mod engine;
pub mod exact;
pub mod expr;
pub mod fem;
pub mod linalg;
pub mod machine;
pub mod mass;
pub mod material;
pub mod medium;
pub mod models;
pub mod numfmt;
pub mod observe;
pub mod output;
pub mod paper;
pub mod plate;
pub mod plot;
pub mod problem;
pub mod run;
pub mod scene;
pub mod schemes;
pub mod solid;
pub mod system;
