//! Scenes run: the problem a scene poses, built for its geometry, stepped by the one driver
//! ([`crate::driver`]) with the one set of observers ([`crate::observe`]). One file per geometry
//! (as the schemes have one file per method); nothing here does I/O but the plate's run folder
//! (`plate::write_plate_run`, through [`crate::output`]).

pub mod bar;
pub mod plate;

pub use bar::*;

/// Sets a scene up as `run` does (assembly, exact solution, factorisation) without stepping:
/// `check` calls it, so a scene `check` accepts starts its run.
pub fn check(scene: &crate::scene::AnyScene) -> Result<(), crate::scene::SceneError> {
    match scene {
        crate::scene::AnyScene::Bar(s) => bar::setup(s).map(|_| ()),
        crate::scene::AnyScene::Plate(s) => plate::setup(s).map(|_| ()),
    }
}
