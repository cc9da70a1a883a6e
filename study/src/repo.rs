//! Where the repository is: its scenes, `python/`, `fixtures/` and git history.

use std::path::PathBuf;

/// The repository's root folder. These sources are compiled twice: as the crate
/// `massredist-study` (whose manifest is `study/Cargo.toml`) and into the root package's
/// `massredist` binary (manifest at the root); `CARGO_PKG_NAME` tells which.
pub fn root() -> PathBuf {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    if env!("CARGO_PKG_NAME") == "massredist-study" {
        manifest.parent().map_or(manifest.clone(), PathBuf::from)
    } else {
        manifest
    }
}
