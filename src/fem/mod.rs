//! Finite elements shared by the geometries of dimension 2 and 3: one mesh ([`mesh::Mesh`]:
//! points in ℝ³, one cell kind of [`cell::Cell`], structured boxes or checked arrays
//! ([`checks`])), one set of reference elements ([`element`]: P1 simplices in closed form, Q1
//! tensor cells with Gauss quadrature) through which plates and solids assemble, and the mass
//! redistribution by cell layers ([`layers`]). Mesh files are read at the scene's edge and arrive
//! here as arrays; nothing here calls Python. (The VTU frame format [`vtu`] and its streaming
//! observer [`frames`] are the output edge of every 2D/3D geometry.)

pub mod body_mesh;
pub mod cell;
pub mod checks;
pub mod columns;
pub mod element;
pub mod frames;
pub mod layers;
pub mod mesh;
pub mod quadrature;
pub mod vtu;

pub use cell::Cell;
pub use mesh::{Mesh, MeshError};
