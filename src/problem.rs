//! A discretised problem of any geometry: its contact system, initial data and (if known) exact
//! solution, and the one place where a scene's scheme is built on it.
//!
//! A geometry ([`Geometry`]) is a mesh with its assembled [`ContactSystem`] and what reports
//! need of it (contact means, exact L² norms, nodal values). A bar ([`BarSystem`]) is one over
//! a tridiagonal back-end, a plate (`crate::plate::PlateSystem`, its impl in `crate::plate::geometry`) and a solid
//! (`crate::solid::SolidSystem`, in `crate::solid::geometry`) ones over a sparse back-end. Schemes are
//! generic; only the bar-only schemes (Paoli–Schatzman and the reduced Newmark formulation)
//! need the bar itself, and [`Geometry::bar`] is how they get it — every other geometry rejects
//! them here, in [`Problem::scheme`].

use crate::bar::assembly::BarSystem;
use crate::contact::Backend;
use crate::exact::Exact;
use crate::schemes::{
    BackwardEuler, Beta, Formulation, Gamma, Hybrid, Newmark, NewmarkReduced, PaoliSchatzman, Scheme, SchemeError,
    SchemeSpec,
};
use crate::system::ContactSystem;

/// What the driver and the observers need of a geometry (object safe).
pub trait GeometryView: std::fmt::Debug + Send + Sync {
    /// "bar", "plate" or "solid", for messages.
    fn name(&self) -> &'static str;
    /// Space dimension of the mesh (1 for a bar, 2 for a plate, 2 or 3 for a solid).
    fn dim(&self) -> usize;
    /// The mesh size along x.
    fn h(&self) -> f64;
    /// The extent L along x (contact at x = 0, far end at x = L).
    fn length(&self) -> f64;
    /// `|Ω|/L`: 1 for a bar, the height H for a plate.
    fn section(&self) -> f64;
    /// `|Γ_C|`: 1 for a bar (a point), the length of the contact edge for a plate.
    fn contact_measure(&self) -> f64;
    /// The contact unknowns (λ order); the first is the reference node (x = 0, lowest y).
    fn contact(&self) -> &[usize];
    /// The mean of u over Γ_C, `∫_{Γ_C} u_h / |Γ_C|` (u_0 for a bar).
    fn contact_mean(&self, u: &[f64]) -> f64;
    /// The reported contact displacement `u0`: u at the reference contact node (bars, plates);
    /// solids report the plain mean over the contact-face nodes.
    fn u0(&self, u: &[f64]) -> f64 {
        u[self.contact()[0]]
    }
    /// `‖u_h − u(·, t)‖_{L²(Ω)}` against an x-only exact solution (NaN where the geometry
    /// cannot integrate it: [`GeometryView::integrates`]).
    fn l2_error(&self, u: &[f64], exact: &Exact, t: f64) -> f64;
    /// Whether [`GeometryView::l2_error`] can integrate this exact solution (bars and plates
    /// always; solids on structured tensor-product meshes).
    fn integrates(&self, _exact: &Exact) -> bool {
        true
    }
    /// `‖I_h u(·, t)‖_{L²(Ω)}`; `scratch` holds the interpolant (reused between calls).
    fn interp_norm(&self, exact: &Exact, t: f64, scratch: &mut Vec<f64>) -> f64;
    /// `max |u(x, y) − u(x, y_min)|` over the unknowns (0 for a bar).
    fn y_variation(&self, _u: &[f64]) -> f64 {
        0.0
    }
    /// Number of mesh nodes (Dirichlet nodes included).
    fn n_nodes(&self) -> usize;
    /// Values per node: 1 for scalar fields (bars, plates), d for a solid's displacement.
    fn components(&self) -> usize {
        1
    }
    /// Values at all mesh nodes (0 on the Dirichlet boundary) from values on the unknowns:
    /// `n_nodes() · components()` of them, interleaved `node · components() + component`.
    fn nodal_values(&self, u: &[f64], out: &mut [f64]);
}

/// A geometry with its contact system over a linear-algebra back-end.
pub trait Geometry: GeometryView {
    type Matrix: Backend;
    fn system(&self) -> &ContactSystem<Self::Matrix>;
    /// The bar, for the bar-only schemes (None for other geometries).
    fn bar(&self) -> Option<&BarSystem> {
        None
    }
}

/// A discretised problem: the geometry with its system, initial data and (if known) the exact
/// solution. `Problem` alone is a bar problem.
#[derive(Debug, Clone)]
pub struct Problem<G = BarSystem> {
    pub system: G,
    pub u0: Vec<f64>,
    pub v0: Vec<f64>,
    pub exact: Option<Exact>,
}

impl<G: Geometry> Problem<G> {
    /// Builds the scheme of a scene on this problem (factors its matrices once).
    pub fn scheme(&self, spec: &SchemeSpec, dt: f64) -> Result<Box<dyn Scheme>, SchemeError> {
        let (u, v) = (self.u0.clone(), self.v0.clone());
        let s = self.system.system();
        Ok(match *spec {
            SchemeSpec::CrankNicolson { formulation: Formulation::Full } => {
                Box::new(Newmark::crank_nicolson(s, dt, u, v)?)
            }
            SchemeSpec::Newmark { beta, gamma, formulation: Formulation::Full } => {
                Box::new(Newmark::new(s, beta, gamma, dt, u, v)?)
            }
            SchemeSpec::BackwardEuler => Box::new(BackwardEuler::new(s, dt, u, v)?),
            SchemeSpec::Hybrid => Box::new(Hybrid::new(s, dt, u, v)?),
            // Bar-only schemes (module docs of `schemes`).
            SchemeSpec::CrankNicolson { formulation: Formulation::Reduced }
            | SchemeSpec::Newmark { formulation: Formulation::Reduced, .. }
            | SchemeSpec::PaoliSchatzman { .. } => {
                let Some(bar) = self.system.bar() else {
                    let (key, reason) = spec.bar_only().expect("these schemes are bar-only");
                    return Err(SchemeError::Unsupported { key, geometry: self.system.name(), reason });
                };
                match *spec {
                    SchemeSpec::PaoliSchatzman { beta, restitution } => {
                        Box::new(PaoliSchatzman::new(bar, beta, restitution, dt, u, v)?)
                    }
                    SchemeSpec::Newmark { beta, gamma, .. } => {
                        Box::new(NewmarkReduced::new(bar, beta, gamma, dt, u, v)?)
                    }
                    _ => Box::new(NewmarkReduced::new(bar, Beta::DEFAULT, Gamma::DEFAULT, dt, u, v)?),
                }
            }
        })
    }

    /// The discrete energy `½VᵀMV + ½UᵀSU − UᵀF` of a state.
    pub fn energy(&self, u: &[f64], v: &[f64]) -> f64 {
        self.system.system().energy(u, v)
    }
}

impl GeometryView for BarSystem {
    fn name(&self) -> &'static str {
        "bar"
    }

    fn dim(&self) -> usize {
        1
    }

    fn h(&self) -> f64 {
        self.bar.h()
    }

    fn length(&self) -> f64 {
        self.bar.length
    }

    fn section(&self) -> f64 {
        1.0
    }

    fn contact_measure(&self) -> f64 {
        1.0
    }

    fn contact(&self) -> &[usize] {
        &self.system.contact
    }

    fn contact_mean(&self, u: &[f64]) -> f64 {
        u[0]
    }

    /// The paper's closed form is integrated split at its kinks ([`crate::bar::norms::l2_error`]);
    /// the general solution by its own exact cell rule (`Characteristics::l2_error_p1`).
    fn l2_error(&self, u: &[f64], exact: &Exact, t: f64) -> f64 {
        match exact {
            Exact::Paper(e) => crate::bar::norms::l2_error(&self.bar, u, e, t),
            Exact::General(c) => {
                let nodes: Vec<f64> = (0..=self.m()).map(|i| self.bar.x(i)).collect();
                let mut values = u.to_vec();
                values.resize(self.m() + 1, 0.0); // u_m = 0 when clamped
                c.l2_error_p1(&nodes, &values, t)
            }
        }
    }

    fn interp_norm(&self, exact: &Exact, t: f64, scratch: &mut Vec<f64>) -> f64 {
        scratch.resize(self.n(), 0.0);
        for (i, e) in scratch.iter_mut().enumerate() {
            *e = exact.u(self.bar.x(i), t);
        }
        crate::bar::norms::l2_norm_p1(&self.bar, scratch)
    }

    fn n_nodes(&self) -> usize {
        self.m() + 1
    }

    fn nodal_values(&self, u: &[f64], out: &mut [f64]) {
        out[..u.len()].copy_from_slice(u);
        out[u.len()..].fill(0.0);
    }
}

impl Geometry for BarSystem {
    type Matrix = crate::linalg::tridiag::SymTridiag;

    fn system(&self) -> &ContactSystem<Self::Matrix> {
        &self.system
    }

    fn bar(&self) -> Option<&BarSystem> {
        Some(self)
    }
}
