//! What the builders of the method classes ([`super::methods`], [`super::nitsche`]) need of a
//! geometry, passed as data so that `schemes` does not depend on `problem` (which calls them).

use crate::system::ContactSystem;

/// What the builder needs of a geometry: its name (for messages) and its lumped mass (row sums
/// over all nodes before Dirichlet removal), computed only for central differences. Passed as
/// data so that `schemes` does not depend on `problem` (which calls [`super::methods::build`]).
pub struct GeometryParts<'a, A, L: FnOnce() -> Option<Vec<f64>>> {
    pub system: &'a ContactSystem<A>,
    pub name: &'static str,
    pub lumped_mass: L,
}
