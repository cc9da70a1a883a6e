//! Elastic solids in 2D (plane strain) and 3D: linear elastodynamics in unilateral frictionless
//! contact with a rigid obstacle on Γ_C = {x = 0}, clamped on Γ_D = {x = L},
//!
//! ```text
//! ρ u_tt − div σ(u) = f,   σ = λ tr ε(u) I + 2μ ε(u)   in Ω = (0, L) × (0, H) [× (0, D)],
//! u = 0 on x = L,   σn = 0 (free) or u·n = 0, (σn)_t = 0 (roller) on the lateral faces,
//! u_x ≥ −gap,  σ_xx ≤ 0,  (u_x + gap) σ_xx = 0,  σ_xy = σ_xz = 0   on x = 0,
//! ```
//!
//! a new geometry and a vector field on the one core: the mesh and reference elements are
//! [`crate::fem`]'s (shared with dimension 2 and 3), the mass redistribution by cell layers is
//! [`crate::fem::layers`] (shared with plates), the contact system, the sparse back-end with
//! its exact many-node contact solver, the schemes, the driver and the observers are the same
//! as for bars and plates.
//!
//! One elastic body: its mesh comes from a [`MeshSource`] (the box generator, a mesh file, or
//! arrays passed with the scene), its [`Support`] says where it meets the rigid obstacle and
//! where it is held — the box's face x = 0 against the plane x = −gap, clamped on x = L
//! ([`Support::Face`]), or any body against the plane of `[obstacle]` ([`Support::Plane`],
//! [`body`]) — and its mesh and contact set are built once ([`SolidSpec::built`]). What is
//! solid-specific: the vector assembly ([`assembly`], a body's frame and load in
//! [`body_system`]), the solid as a [`crate::problem::Geometry`] ([`geometry`]) with a body's
//! own reports ([`report`]), its specification ([`spec`], parsed from the `[solid]` table and a body's
//! `[obstacle]` by [`table`]), the problem it poses ([`problem`]), and VTU frames with the displacement and
//! velocity vectors and the contact pressure ([`vtu`]).
//!
//! With Q1 cells on a structured mesh, x-only weights and data u = (u¹ᴰ(x), 0[, 0]), and either
//! λ = 0 or roller lateral faces, the discrete solution is the 1D solution with modulus λ + 2μ
//! extended in y (and z): the x-rows are the tensor products of the bar's matrices, and the
//! transverse rows vanish on such fields (tests/solid.rs checks this to round-off).

pub mod assembly;
pub mod bodies;
pub mod bodies_system;
pub mod body;
pub mod body_system;
pub mod columns;
pub mod coupling;
pub mod curved;
pub mod dof_map;
pub mod geometry;
pub mod kernel;
pub mod lean;
pub mod lumped;
pub mod pair;
pub mod problem;
pub mod report;
pub mod spec;
pub mod stencil;
pub mod surface;
pub mod table;
pub mod vtu;

pub use assembly::{Lame, Lateral, SolidSystem};
pub use body::{BodyContact, BodyError, Frames};
pub use problem::{SolidError, SolidProblem};
pub use spec::{BodySpec, Built, ContactSet, MeshSource, Obstacle, SolidInitial, SolidSpec, Support};
pub use surface::{Side, Surface};
pub use table::bodies::RawPair;
pub use table::obstacle::RawObstacle;
