//! The problem a solid scene poses ([`SolidSpec`] → [`SolidProblem`]: the assembled
//! [`SolidSystem`], the interpolated initial data and the plane-wave exact solution where it
//! applies), and the solid's place in the one run path ([`GeometrySpec`]).

use super::assembly::{SolidAssemblyError, SolidSystem};
use super::spec::{Built, SolidInitial, SolidSpec, Support};
use crate::characteristics::{CharacteristicsError, InitialData};
use crate::contact::law::ContactLaw;
use crate::exact::{Exact, ImpactingBar, by_characteristics, paper_data};
use crate::expr::Expr;
use crate::fem::MeshError;
use crate::fem::frames::VtuFrames;
use crate::mass::{ContactDirections, MassKind};
use crate::material::{FarEnd, Material};
use crate::problem::Problem;
use crate::schemes::{SchemeSpec, StiffnessOperator};
use crate::spec::Scene;
use crate::spec::{GeometrySpec, Totals};
use serde::Serialize;
use std::sync::Arc;
use thiserror::Error;

/// A solid problem.
pub type SolidProblem = Problem<SolidSystem>;

impl SolidSpec {
    /// The problem of this spec with a mass redistribution: the assembled solid, the nodal
    /// interpolants of the initial data, and the plane wave up to `t_end` where it applies
    /// (the paper's closed form for λ + 2μ = ρ = 1 without gap, else the solution by
    /// characteristics of the bar with density ρ and modulus λ + 2μ).
    pub fn problem(&self, mass: &MassKind, t_end: f64) -> Result<Problem<SolidSystem>, SolidError> {
        self.problem_directed(mass, ContactDirections::All, t_end)
    }

    /// [`SolidSpec::problem`] with the mass's `contact_directions` ([`ContactDirections`]).
    pub fn problem_directed(
        &self,
        mass: &MassKind,
        directions: ContactDirections,
        t_end: f64,
    ) -> Result<Problem<SolidSystem>, SolidError> {
        self.problem_for(mass, directions, t_end, None)
    }

    /// [`SolidSpec::problem_directed`] for central differences with `scheme.operator =
    /// operator` where `explicit` is Some: a box's or a body's against a plane system is then
    /// the lean one ([`SolidSystem::assemble_explicit`]: no consistent mass, no whole stiffness
    /// matrix).
    pub fn problem_for(
        &self,
        mass: &MassKind,
        directions: ContactDirections,
        t_end: f64,
        explicit: Option<StiffnessOperator>,
    ) -> Result<Problem<SolidSystem>, SolidError> {
        let built = self.built()?;
        let weights = self.weights(&built, mass)?;
        if let Some((bodies, joined)) = &built.joined {
            // Each body its own data (`super::bodies`).
            let solid = SolidSystem::assemble_bodies(weights, self.lame, bodies, joined)?;
            let data = |f: fn(&super::bodies::NamedBody) -> &Vec<Expr>| {
                solid.interpolate_nodes(|v, i, p| f(&bodies.bodies[joined.body_of(v)])[i].eval(&p[..self.dim]))
            };
            let (u0, v0) = (data(|b| &b.displacement), data(|b| &b.velocity));
            return Ok(Problem { system: solid, u0, v0, exact: None });
        }
        let mesh = Arc::clone(&built.mesh);
        let solid = match explicit {
            Some(choice) => SolidSystem::assemble_explicit(
                (mesh, &built.contact),
                (weights, directions),
                self.lame,
                &self.support,
                choice,
            )?,
            None => SolidSystem::assemble(mesh, weights, directions, self.lame, &self.support, &built.contact)?,
        };
        let l = self.extent[0];
        let (u0, v0) = match &self.initial {
            SolidInitial::Paper => {
                (solid.interpolate(|i, p| if i == 0 { (l - p[0]) / 2.0 } else { 0.0 }), vec![0.0; solid.dofs.len()])
            }
            SolidInitial::Fields { displacement, velocity } => {
                let eval = |f: &[Expr]| solid.interpolate(|i, p| f[i].eval(&p[..self.dim]));
                (eval(displacement), eval(velocity))
            }
        };
        Ok(Problem { system: solid, u0, v0, exact: self.exact(t_end)? })
    }

    /// The cell weights of a mass redistribution on the built mesh ([`Built::weights`]).
    pub fn weights(&self, built: &Built, mass: &MassKind) -> Result<Vec<f64>, SolidError> {
        Ok(built.weights(mass).map_err(SolidAssemblyError::from)?)
    }

    /// The plane wave up to `t_end` where it applies (module docs of [`crate::solid`]): the
    /// paper's closed form for λ + 2μ = ρ = 1 without gap, else the solution by characteristics
    /// of the bar with density ρ and modulus λ + 2μ; None for other data.
    pub fn exact(&self, t_end: f64) -> Result<Option<Exact>, SolidError> {
        let l = self.extent[0];
        Ok(if !self.is_plane_wave() {
            None
        } else if self.initial == SolidInitial::Paper
            && self.lame.p_modulus() == 1.0
            && self.lame.density == 1.0
            && self.support.gap() == 0.0
        {
            Some(Exact::Paper(ImpactingBar { length: l }))
        } else {
            let material = Material { density: self.lame.density, modulus: self.lame.p_modulus() };
            let exact = |data| by_characteristics(l, material, FarEnd::Clamped, self.support.gap(), data, t_end);
            let c = match &self.initial {
                SolidInitial::Paper => {
                    let (x, u, v) = paper_data(l);
                    exact(InitialData::PiecewiseLinear { x: &x, u: &u, v: &v })
                }
                SolidInitial::Fields { displacement, velocity } => {
                    let at = |x: f64| [x, 0.0, 0.0];
                    let u = |x: f64| displacement[0].eval(&at(x)[..self.dim]);
                    let v = |x: f64| velocity[0].eval(&at(x)[..self.dim]);
                    exact(InitialData::Smooth { u: &u, v: &v })
                }
            }
            .map_err(SolidError::Exact)?;
            Some(Exact::General(std::sync::Arc::new(c)))
        })
    }
}

impl From<super::spec::BuildError> for SolidError {
    fn from(e: super::spec::BuildError) -> Self {
        match e {
            super::spec::BuildError::Mesh(m) => SolidError::Mesh(m),
            super::spec::BuildError::Body(b) => SolidError::Body(b),
            super::spec::BuildError::Bodies(b) => SolidError::Assembly(b.into()),
        }
    }
}

#[derive(Debug, Error)]
pub enum SolidError {
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Assembly(#[from] SolidAssemblyError),
    #[error("the plane-wave exact solution of this solid: {0}")]
    Exact(CharacteristicsError),
    #[error(transparent)]
    Body(#[from] super::body::BodyError),
    /// The lean system of central differences is the box's (`super::lean`).
    #[error("a body with an [obstacle] has no lean explicit system (the box's, without [obstacle])")]
    NotABox,
}

/// The solid keys of `summary.json`.
#[derive(Serialize)]
pub struct SolidHead {
    dim: usize,
    height: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    depth: Option<f64>,
    nx: usize,
    ny: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    nz: Option<usize>,
    cells: &'static str,
    /// The box's lateral faces and gap (absent for a body: its plane is `[obstacle]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    lateral: Option<&'static str>,
    lame_lambda: f64,
    lame_mu: f64,
    density: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    gap: Option<f64>,
    initial: &'static str,
    /// `∫ ρ w_h` (per component).
    total_mass: f64,
    /// Unknowns (free components).
    unknowns: usize,
}

impl GeometrySpec for SolidSpec {
    type System = SolidSystem;
    type Error = SolidError;
    type Head = SolidHead;
    const SETUP_KEYS: &'static str = "solid.*, mass.*, scheme.*, time.dt";

    fn elements(&self) -> usize {
        self.cells_per_axis[0]
    }

    /// Central differences take the lean system (`super::lean`; boxes and bodies against a
    /// plane), but with Nitsche's law, whose term reads a contact row that the lean stiffness
    /// does not hold.
    fn problem(scene: &Scene<Self>) -> Result<SolidProblem, SolidError> {
        let explicit = match scene.scheme {
            SchemeSpec::CentralDifference { operator } if !matches!(scene.contact, ContactLaw::Nitsche { .. }) => {
                Some(operator)
            }
            _ => None,
        };
        scene.geometry.problem_for(&scene.mass, scene.contact_directions, scene.time.exact_end(), explicit)
    }

    fn summary_head(scene: &Scene<Self>, totals: &Totals) -> SolidHead {
        let s = &scene.geometry;
        let three = s.dim == 3;
        // The box's lateral faces and gap (a body's plane is its `[obstacle]`).
        let face = match s.support {
            Support::Face { gap, lateral, .. } => Some((gap, lateral.name())),
            Support::Plane(_) | Support::Bodies(_) => None,
        };
        SolidHead {
            dim: s.dim,
            height: s.extent[1],
            depth: three.then_some(s.extent[2]),
            nx: s.cells_per_axis[0],
            ny: s.cells_per_axis[1],
            nz: three.then_some(s.cells_per_axis[2]),
            cells: s.cells.name(),
            lateral: face.map(|f| f.1),
            lame_lambda: s.lame.lambda,
            lame_mu: s.lame.mu,
            density: s.lame.density,
            gap: face.map(|f| f.0),
            initial: s.initial.name(),
            total_mass: totals.total_mass,
            unknowns: totals.unknowns,
        }
    }

    fn totals(system: &SolidSystem) -> Totals {
        Totals { total_mass: system.total_mass(), unknowns: system.dofs.len() }
    }

    fn frames(system: &SolidSystem) -> Option<&dyn VtuFrames> {
        Some(system)
    }
}
