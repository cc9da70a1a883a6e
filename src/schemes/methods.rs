//! The one builder of the method classes of issue 20 on any geometry: central differences
//! ([`super::CentralDifference`]), Moreau–Jean ([`super::MoreauJean`]), and the contact laws other than exact. What a geometry or a
//! law cannot do is refused here, with the reason.

use super::penalty_implicit::{Implicit, PenaltyImplicit};
use super::{Beta, CentralDifference, Formulation, Gamma, MoreauJean, Scheme, SchemeError, SchemeSpec};
use crate::contact::Backend;
use crate::contact::law::ContactLaw;

pub use super::parts::GeometryParts;

/// Builds `spec` with `law` on a geometry, from the data (u, v).
pub fn build<A: Backend, L: FnOnce() -> Option<Vec<f64>>>(
    geometry: GeometryParts<'_, A, L>,
    spec: &SchemeSpec,
    law: &ContactLaw,
    dt: f64,
    u: Vec<f64>,
    v: Vec<f64>,
) -> Result<Box<dyn Scheme>, SchemeError> {
    let system = geometry.system;
    match *spec {
        _ if matches!(law, ContactLaw::Nitsche { .. }) => super::nitsche::build(geometry, spec, law, dt, u, v),
        SchemeSpec::CentralDifference => {
            let Some(lumped) = (geometry.lumped_mass)() else {
                return Err(SchemeError::Unsupported {
                    key: "scheme.kind = \"central-difference\"",
                    geometry: geometry.name,
                    reason: "its lumped mass (row sums over all nodes before Dirichlet removal) is not built yet (bars, plates and solids have one)",
                });
            };
            Ok(Box::new(CentralDifference::new(system, lumped, law, dt, u, v)?))
        }
        SchemeSpec::MoreauJean { theta, restitution } => {
            if *law != ContactLaw::Exact {
                return Err(SchemeError::Unsupported {
                    key: "contact.method",
                    geometry: geometry.name,
                    reason: "Moreau–Jean has its own impact law: use contact.method = \"exact\"",
                });
            }
            Ok(Box::new(MoreauJean::new(system, theta, restitution, dt, u, v)?))
        }
        SchemeSpec::CrankNicolson { formulation: Formulation::Full } => {
            let kind = Implicit::Newmark { beta: Beta::DEFAULT.get(), gamma: Gamma::DEFAULT.get() };
            Ok(Box::new(PenaltyImplicit::new(system, kind, law, dt, u, v)?))
        }
        SchemeSpec::Newmark { beta, gamma, formulation: Formulation::Full } => {
            let kind = Implicit::Newmark { beta: beta.get(), gamma: gamma.get() };
            Ok(Box::new(PenaltyImplicit::new(system, kind, law, dt, u, v)?))
        }
        SchemeSpec::BackwardEuler => {
            Ok(Box::new(PenaltyImplicit::new(system, Implicit::BackwardEuler, law, dt, u, v)?))
        }
        _ => Err(SchemeError::Unsupported {
            key: "contact.method = \"penalty\"",
            geometry: geometry.name,
            reason: "the penalty law is built for crank-nicolson, newmark and backward-euler (full formulation) and central-difference; this scheme's contact treatment is its own",
        }),
    }
}
