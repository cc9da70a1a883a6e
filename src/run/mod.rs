//! Scenes run: the problem a scene poses, built for its geometry, stepped by the one driver
//! ([`crate::driver`]) with the one set of observers ([`crate::observe`]). One file per geometry
//! (as the schemes have one file per method); nothing here does I/O but the plate's run folder
//! (`plate::write_plate_run`, through [`crate::output`]).

pub mod bar;
pub mod plate;

pub use bar::*;
