//! 2D plates (0, L) × (0, H) in unilateral contact with a rigid obstacle on Γ_C = {x = 0},
//! clamped on Γ_D = {x = L}, free elsewhere: the paper's weighted mass redistribution in 2D
//! (its conclusion's Table, Δx₁ = Δx₂ = 0.05), for the scalar wave equation
//!
//! ```text
//! u_tt − Δu = f in Ω,   u = 0 on Γ_D,   ∂_y u = 0 on y = 0, H,
//! 0 ≤ u ⊥ ∂_x u ≤ 0 on Γ_C   (Signorini; the contact pressure is λ = ∂_x u, as in 1D).
//! ```
//!
//! Discretisation: Q1 quadrilaterals or P1 triangles ([`mesh`]), one mass weight per cell
//! ([`mass`]: standard, mod1, mod2, mod3, custom — layers of cells touching Γ_C), sparse weighted
//! mass and stiffness ([`assembly`], faer sparse matrices), node-wise Signorini conditions on
//! all nodes of Γ_C solved exactly at each step as an LCP on the contact nodes ([`contact`],
//! [`lcp`]), Newmark/Crank–Nicolson, backward Euler and the hybrid scheme ([`schemes`]),
//! exact L² errors against the y-independent benchmark ([`norms`]), a driver with observers
//! ([`run`]), scenes with a `[plate]` table ([`scene`]), VTU/PVD output ([`vtu`]) and the
//! paper's 2D table with a sensitivity sweep ([`table`]).
//!
//! With Q1 on a structured mesh, x-only weights and y-independent data, every matrix is a
//! tensor product with the 1D one and the discrete solution is the 1D solution extended in y
//! (tests/plate.rs checks this to round-off). P1 triangles on one-diagonal meshes are not
//! tensor products, so their solutions vary in y.
//!
//! The hybrid scheme's 2D form ([`schemes::hybrid`]) keeps the paper's Lemma 5.1: its energy
//! never increases, on any mesh and with any contact states along Γ_C (proof in its docs,
//! checked numerically in tests/plate.rs). Backward Euler is dissipative as in 1D;
//! Crank–Nicolson is not (its energy oscillates after impacts, as in the paper's Figure 12).
//!
//! Not ported: Paoli–Schatzman (its projection of S on (ker M)^⊥ and its one-step-ahead state
//! carry over in principle, but nothing here needs it) and the reduced Newmark formulation
//! (equal to the full one step by step in 1D). File meshes (gmsh, xdmf through the Python
//! bridge) can be turned into a [`mesh::Mesh2d`] with `Mesh2d::from_arrays`; scenes do not read
//! them yet.
//!
//! **Shared with 1D.** The schemes run on a mesh-free [`assembly::ContactSystem`], of which the
//! 1D bar is an instance (`ContactSystem::from_bar`); tests run them on the bar and compare with
//! [`crate::schemes`]. Reused as is: [`crate::mass::MassKind`], [`crate::exact::ImpactingBar`],
//! [`crate::run::Summary`] and `Needs`, [`crate::scene::SchemeSpec`] and the scene parsers of
//! `[mass]`, `[scheme]` and `[time]`, `crate::schemes::check_range` and `SchemeError`,
//! [`crate::output`]'s atomic writers.

pub mod assembly;
pub mod geometry;
pub mod layers;
pub mod mesh;
pub mod norms;
pub mod scene;
pub mod vtu;

pub use assembly::{PlateSystem, assemble};
pub use mesh::{CellKind, Mesh2d};
