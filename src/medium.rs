//! The medium of a bar or a plate: its material, far end, gap and body force ([`Medium`],
//! [`Force`]), the data that do not depend on its shape, shared by the two specifications
//! (`bar/spec.rs`, `plate/spec.rs`). ("Body" names the elastic solid against an obstacle,
//! `crate::solid::body`.)

use crate::expr::Expr;
use crate::material::{FarEnd, Material};

/// The body force: a constant, an expression in x (and y for plates; L, H, pi), or an
/// expression in x (y) and t.
#[derive(Debug, Clone, PartialEq)]
pub enum Force {
    Constant(f64),
    /// f(x) (plates: f(x, y)), constant in time.
    Field(Expr),
    /// f(x, t) (plates: f(x, y, t)): the variables of `Field` followed by t.
    Transient(Expr),
}

impl Force {
    /// The constant value, if the force does not depend on x.
    pub fn constant(&self) -> Option<f64> {
        match self {
            Force::Constant(f) => Some(*f),
            Force::Field(e) => e.is_constant(),
            Force::Transient(_) => None,
        }
    }

    /// Refuses an expression that is not finite at some node, naming the key and the node.
    pub(crate) fn check_at_nodes<const D: usize>(
        &self,
        nodes: impl Iterator<Item = [f64; D]>,
    ) -> Result<(), crate::expr::ExprError> {
        match self {
            Force::Constant(_) => Ok(()),
            Force::Field(f) => f.eval_at_nodes(nodes).map(|_| ()),
            // At t = 0 (later times: a non-finite load makes a non-finite state, which the run
            // reports as diverged).
            Force::Transient(f) => f.eval_at_nodes(nodes.map(at_time_zero)).map(|_| ()),
        }
    }
}

/// The material, far end, gap and force of a bar or a plate.
#[derive(Debug, Clone, PartialEq)]
pub struct Medium {
    pub material: Material,
    pub far_end: FarEnd,
    /// The obstacle at x = 0: u ≥ −gap on the contact boundary.
    pub gap: f64,
    pub force: Force,
}

impl Default for Medium {
    /// The paper's medium: ρ = E = 1, clamped at x = L, no gap, no force.
    fn default() -> Self {
        Medium { material: Material::UNIT, far_end: FarEnd::Clamped, gap: 0.0, force: Force::Constant(0.0) }
    }
}

/// A point of the space variables extended by t = 0.
fn at_time_zero<const D: usize>(p: [f64; D]) -> Vec<f64> {
    let mut v = p.to_vec();
    v.push(0.0);
    v
}
