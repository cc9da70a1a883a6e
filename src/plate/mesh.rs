//! The plate's 2D meshes: [`crate::fem::mesh2d`] (the 2D mesh every geometry builds on).

pub use crate::fem::mesh2d::*;
