//! A bar's specification, [`BarSpec`]: what the `[bar]` table of a scene validates into
//! (its table parser, `super::table`), and what the bar's problem is built from (`super::problem`).

use crate::expr::Expr;
use crate::material::{FarEnd, Material};
use crate::medium::Force;

/// Initial data of the bar.
#[derive(Debug, Clone, PartialEq)]
pub enum Initial {
    /// u⁰ = (L − x)/2, v⁰ = 0: the paper's benchmark (exact solution known when f = 0).
    Paper,
    /// u⁰(x), v⁰(x) as expressions in x (and L, pi), interpolated at every node.
    Fields { displacement: Expr, velocity: Expr },
}

#[derive(Debug, Clone, PartialEq)]
pub struct BarSpec {
    pub length: f64,
    pub elements: usize,
    pub material: Material,
    pub far_end: FarEnd,
    /// The obstacle at x = 0: u(0, t) ≥ −gap.
    pub gap: f64,
    pub initial: Initial,
    pub force: Force,
}

impl BarSpec {
    /// The paper's bar: ρ = E = 1, clamped at L, no gap.
    pub fn is_paper_bar(&self) -> bool {
        self.material == Material::UNIT && self.far_end == FarEnd::Clamped && self.gap == 0.0
    }

    /// The exact solution is known without body force: the paper's closed form on its bar, the
    /// solution by characteristics otherwise ([`crate::characteristics`]).
    pub fn has_exact_solution(&self) -> bool {
        self.force.constant() == Some(0.0)
    }
}
