//! massredist: the weighted finite element mass redistribution method for dynamic contact
//! (Dabaghi, Krejčí, Petrov, Pousin, Renard), with exact solutions and cross-checks.

pub mod bar;
pub mod characteristics;
pub mod column;
pub mod contact;
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
pub mod mesh_file;
pub mod models;
pub mod numfmt;
pub mod observe;
pub mod output;
pub mod plate;
pub mod problem;
#[cfg(feature = "python")]
pub mod python;
pub mod run;
pub mod scene;
pub mod schemes;
pub mod solid;
pub mod spec;
pub mod system;
