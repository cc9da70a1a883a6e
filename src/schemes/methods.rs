//! The one builder of the method classes of issue 20 on any geometry: central differences
//! ([`super::CentralDifference`]), Moreau–Jean ([`super::MoreauJean`]), and the contact laws other than exact. What a geometry or a
//! law cannot do is refused here, with the reason.

use super::{CentralDifference, MoreauJean, Scheme, SchemeError, SchemeSpec};
use crate::contact::law::ContactLaw;
use crate::problem::Geometry;

/// Builds `spec` with `law` on `geometry`, from the data (u, v).
pub fn build<G: Geometry>(
    geometry: &G,
    spec: &SchemeSpec,
    law: &ContactLaw,
    dt: f64,
    u: Vec<f64>,
    v: Vec<f64>,
) -> Result<Box<dyn Scheme>, SchemeError> {
    let system = geometry.system();
    match *spec {
        SchemeSpec::CentralDifference => {
            let Some(lumped) = geometry.lumped_mass() else {
                return Err(SchemeError::Unsupported {
                    key: "scheme.kind = \"central-difference\"",
                    geometry: geometry.name(),
                    reason: "the lumped mass (row sums over all nodes before Dirichlet removal) is not built for this geometry yet",
                });
            };
            Ok(Box::new(CentralDifference::new(system, lumped, law, dt, u, v)?))
        }
        SchemeSpec::MoreauJean { theta, restitution } => {
            if *law != ContactLaw::Exact {
                return Err(SchemeError::Unsupported {
                    key: "contact.method",
                    geometry: geometry.name(),
                    reason: "Moreau–Jean has its own impact law: use contact.method = \"exact\"",
                });
            }
            Ok(Box::new(MoreauJean::new(system, theta, restitution, dt, u, v)?))
        }
        _ => Err(SchemeError::Unsupported {
            key: if spec.method_class() { "scheme.kind" } else { "contact.method" },
            geometry: geometry.name(),
            reason: "not built yet (issue 20): central differences with exact contact are",
        }),
    }
}
