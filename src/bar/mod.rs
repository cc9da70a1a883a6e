//! The bar (0, L): its specification ([`spec`]) read from the `[bar]` table ([`table`]), P1 elements on a uniform mesh ([`assembly`]:
//! weighted mass, stiffness, load, material, far end), the problem a scene poses ([`problem`]),
//! its exact L² norms ([`norms`]) and its place in the one driver ([`geometry`]: reports, fast
//! diagnostics, the one-node system of Paoli–Schatzman and the reduced formulation). Everything else (the contact system, schemes, driver,
//! observers, run path) is shared with the other geometries.

pub mod assembly;
pub mod geometry;
pub mod norms;
pub mod problem;
pub mod spec;
pub mod table;

pub use assembly::BarSystem;
pub use problem::{BarError, BarProblem};
pub use spec::{BarSpec, Initial};
