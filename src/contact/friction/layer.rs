//! Central differences with friction on a contact layer massless in every component
//! (`mass.contact_directions = "all"`): the step's only solve is the layer's quasi-static
//! frictional problem ([`FrictionExplicit`]).

use super::{Friction, FrictionRecord, FrictionStep, SetupError, Tangential};
use crate::contact::StepLaw;
use crate::contact::lcp::LcpError;

/// Central differences with friction (module docs for the frictional problem): the contact layer
/// massless in every component (`mass.contact_directions = "all"` with w_0 = 0), so that the
/// contact nodes' normal and tangential unknowns are quasi-static at t_{n+1} and the step's only
/// solve is the frictional problem of the massless block M (contact nodes and any other massless
/// unknown):
///
/// ```text
/// K_MM U_M^{n+1} = F_M(t_{n+1}) − K_MI U_I^{n+1} + E_n r_n + E_t r_t,
/// ```
///
/// with the same solver as the implicit schemes ([`FrictionStep`] on `K_MM`, σ = 1; `Δu_t` the
/// step's increment `u_t^{n+1} − u_tⁿ`, the bound at t_{n+1}: the quasi-static rows have one time
/// level). The interior feels friction through `K_IM` only: with `1ᵀ K = 0` along a
/// translation, velocity Verlet gives `ΔP_t = ½ Δt (Σ r_tⁿ + Σ r_t^{n+1})`. The initial state's
/// quasi-static solve (the data at t = 0) sets `u_t⁰` and is not a step: its dissipation and
/// impulse are not counted.
#[derive(Debug)]
pub struct FrictionExplicit {
    /// The massless unknowns M (increasing), numbered 0.. in `step`.
    massless: Vec<usize>,
    /// `(row in M, j outside M, K_{M_row, j})`.
    coupling: Vec<(usize, usize, f64)>,
    rhs: Vec<f64>,
    lower: Vec<f64>,
    step: FrictionStep,
    started: bool,
}

impl FrictionExplicit {
    /// On `system` with the lumped mass `lumped`: refused unless every contact-node unknown
    /// (normal and tangential) is massless.
    pub fn new<A: crate::linalg::SymMatrix>(
        system: &crate::system::ContactSystem<A>,
        lumped: &[f64],
        friction: Friction,
        dt: f64,
    ) -> Result<Self, SetupError> {
        let tangential =
            system.tangential.as_ref().ok_or(SetupError::Shape("friction needs tangential directions (a solid)"))?;
        let massless: Vec<usize> = (0..lumped.len()).filter(|&i| lumped[i] <= 0.0).collect();
        let mut local = vec![usize::MAX; lumped.len()];
        for (k, &i) in massless.iter().enumerate() {
            local[i] = k;
        }
        let contact_nodes = system.contact.iter().chain(tangential.unknowns.iter().flatten());
        if contact_nodes.clone().any(|&i| local[i] == usize::MAX) {
            return Err(SetupError::Shape(
                "friction in central differences needs every component of the contact nodes massless (a redistributed mass with mass.contact_directions = \"all\")",
            ));
        }
        let (mut block, mut coupling) = (Vec::new(), Vec::new());
        system.stiffness.for_each_entry(&mut |i, j, v| match (local[i], local[j]) {
            (usize::MAX, _) => {}
            (a, usize::MAX) => coupling.push((a, j, v)),
            (a, b) => block.push((a, b, v)),
        });
        let nm = massless.len();
        let k_mm =
            crate::linalg::sparse::from_triplets(nm, &block, "stiffness").map_err(crate::linalg::LinalgError::from)?;
        let contact: Vec<usize> = system.contact.iter().map(|&c| local[c]).collect();
        let tangential = Tangential {
            unknowns: tangential.unknowns.iter().map(|t| t.iter().map(|&j| local[j]).collect()).collect(),
            ..tangential.clone()
        };
        let step = FrictionStep::new(&k_mm, &contact, &tangential, friction, "stiffness", 1.0, dt)?;
        Ok(Self { massless, coupling, rhs: vec![0.0; nm], lower: system.lower.clone(), step, started: false })
    }
}

impl crate::contact::ExplicitLaw for FrictionExplicit {
    fn quasi_static(
        &mut self,
        u: &mut [f64],
        load: &[f64],
        _forced: bool,
        lambda: &mut [f64],
    ) -> Result<usize, LcpError> {
        let first = !self.started;
        if first {
            // u_t⁰: the tangential targets of the initial solve.
            let u_m: Vec<f64> = self.massless.iter().map(|&i| u[i]).collect();
            self.step.start(&u_m);
            self.started = true;
        }
        for (r, &i) in self.rhs.iter_mut().zip(&self.massless) {
            *r = load[i];
        }
        for &(a, j, v) in &self.coupling {
            self.rhs[a] -= v * u[j];
        }
        let sweeps = self.step.solve(&mut self.rhs, &self.lower, lambda)?;
        for (&r, &i) in self.rhs.iter().zip(&self.massless) {
            u[i] = r;
        }
        if first {
            let record = &mut self.step.dense.record;
            (record.dissipation, record.impulse, record.max_cone_excess) = (0.0, [0.0; 3], 0.0);
        }
        Ok(sweeps)
    }

    fn friction(&self) -> Option<&FrictionRecord> {
        Some(&self.step.dense.record)
    }
}
