//! The bar (0, L): P1 elements on a uniform mesh ([`assembly`]: weighted mass, stiffness, load,
//! material, far end) and its exact L² norms ([`norms`]); its scenes run in [`crate::run`]. The bar's
//! [`crate::problem::Geometry`] implementation is in [`crate::problem`]; everything else (the
//! contact system, schemes, driver, observers) is shared with the other geometries.

pub mod assembly;
pub mod norms;
