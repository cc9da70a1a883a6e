//! 2D plates (0, L) × (0, H) in unilateral contact with a rigid obstacle on Γ_C = {x = 0},
//! clamped on Γ_D = {x = L}, free elsewhere: the paper's weighted mass redistribution in 2D
//! (its conclusion's Table, Δx₁ = Δx₂ = 0.05), for the scalar wave equation
//!
//! ```text
//! u_tt − Δu = f in Ω,   u = 0 on Γ_D,   ∂_y u = 0 on y = 0, H,
//! 0 ≤ u ⊥ ∂_x u ≤ 0 on Γ_C   (Signorini; the contact pressure is λ = ∂_x u, as in 1D).
//! ```
//!
//! What is plate-specific lives here: the sparse weighted mass and stiffness with the material,
//! far end, gap and load ([`assembly`], through the element integrals of every mesh), the plate as a [`crate::problem::Geometry`] ([`geometry`]: contact means, exact
//! L² norms against x-only solutions ([`norms`]), nodal values), its specification ([`spec`],
//! parsed from the `[plate]` table by [`table`]), the problem a scene poses ([`problem`])
//! and VTU/PVD output ([`vtu`]). The mesh (Q1 quadrilaterals or P1 triangles) and the mass weights by
//! layers of cells touching Γ_C are the ones of solids ([`crate::fem::mesh`],
//! [`crate::fem::layers`]). Everything else is the one core shared with bars: the contact system
//! ([`crate::system`]) over the sparse back-end ([`crate::linalg::sparse`]) with the exact
//! many-node contact solver ([`crate::contact::Schur`]), the schemes ([`crate::schemes`]), the
//! driver and observers, and the run path ([`crate::run`]).
//!
//! With Q1 on a structured mesh, x-only weights and y-independent data, every matrix is a
//! tensor product with the 1D one and the discrete solution is the 1D solution extended in y
//! (tests/plate.rs checks this to round-off). P1 triangles on one-diagonal meshes are not
//! tensor products, so their solutions vary in y. The hybrid scheme keeps the paper's Lemma 5.1
//! on any mesh and with any contact states along Γ_C (proof in [`crate::schemes::hybrid`],
//! checked per step in tests/plate.rs). Paoli–Schatzman and the reduced Newmark formulation need
//! a bar's one-node system ([`crate::schemes::SchemeSpec::needs`]).

pub mod assembly;
pub mod cells;
pub mod geometry;
pub mod norms;
pub mod problem;
pub mod spec;
pub mod table;
pub mod vtu;

pub use assembly::{PlateSystem, assemble};
pub use problem::{PlateError, PlateProblem};
pub use spec::{PlateInitial, PlateSpec};
