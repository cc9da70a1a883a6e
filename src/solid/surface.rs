//! The rigid obstacle's surface as a level set (issue 30): φ > 0 on the body's side, φ = 0 on
//! the obstacle, and what a contact node needs of it, linearised at the reference
//! configuration (small deformation):
//!
//! ```text
//! n_i = ∇φ(X_i)/|∇φ(X_i)|,   g_i = φ(X_i)/|∇φ(X_i)|,   d_i = g_i + n_i · u_i ≥ 0,  R_i ≥ 0,  d_i R_i = 0.
//! plane      φ = n · (x − p)                              (n the unit normal: g_i, n_i as today),
//! sphere     φ = ±(|x − c| − r)                           (a circle in 2D; + outside, − inside),
//! cylinder   φ = ±(|w| − r),  w = (x − c) − ((x − c)·a) a  (3D, a the unit axis),
//! level set  φ the scene's expression in x, y[, z]        (∇φ its exact derivative, [`crate::expr::Derivative`]).
//! ```
//!
//! For the plane, the sphere and the cylinder g_i is the exact distance to the surface; for a
//! level set it is the first-order distance φ/|∇φ|. A point where ∇φ = 0 (the centre of a
//! sphere, the axis of a cylinder, a critical point of a level set) has no normal: a contact
//! node there is refused, named.

use crate::expr::{Derivative, Expr};

/// Which side of a sphere or cylinder the body is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// The body is outside (a roller, a ball to land on).
    Outside,
    /// The body is in the cavity (a casing, a seat).
    Inside,
}

impl Side {
    pub fn name(self) -> &'static str {
        match self {
            Side::Outside => "outside",
            Side::Inside => "inside",
        }
    }

    fn sign(self) -> f64 {
        match self {
            Side::Outside => 1.0,
            Side::Inside => -1.0,
        }
    }
}

/// A rigid obstacle's surface (module docs). Vectors have 3 entries, those beyond the body's
/// dimension 0.
#[derive(Debug, Clone, PartialEq)]
pub enum Surface {
    /// `{x : normal · (x − point) = 0}`, the unit normal pointing into the body.
    Plane { normal: [f64; 3], point: [f64; 3] },
    /// `{x : |x − center| = radius}` (a circle in 2D).
    Sphere { center: [f64; 3], radius: f64, side: Side },
    /// `{x : |w| = radius}`, w the part of x − center normal to the unit `axis` (3D).
    Cylinder { center: [f64; 3], axis: [f64; 3], radius: f64, side: Side },
    /// `{x : φ(x) = 0}`, φ an expression in x, y[, z], positive on the body's side.
    LevelSet(Expr),
}

impl Surface {
    /// The `obstacle.shape` key's value.
    pub fn name(&self) -> &'static str {
        match self {
            Surface::Plane { .. } => "plane",
            Surface::Sphere { .. } => "sphere",
            Surface::Cylinder { .. } => "cylinder",
            Surface::LevelSet(_) => "level-set",
        }
    }

    /// The signed distance as the scene defines it, for messages.
    pub fn formula(&self) -> &'static str {
        match self {
            Surface::Plane { .. } => "obstacle.normal · (X − obstacle.point)",
            Surface::Sphere { side: Side::Outside, .. } => "|X − obstacle.center| − obstacle.radius",
            Surface::Sphere { side: Side::Inside, .. } => "obstacle.radius − |X − obstacle.center|",
            Surface::Cylinder { side: Side::Outside, .. } => "(distance of X to the axis) − obstacle.radius",
            Surface::Cylinder { side: Side::Inside, .. } => "obstacle.radius − (distance of X to the axis)",
            Surface::LevelSet(_) => "φ(X)/|∇φ(X)| of obstacle.distance",
        }
    }

    /// Ready to evaluate φ and ∇φ at points ([`Level::at`]).
    pub fn level(&self, dim: usize) -> Level<'_> {
        let derivative = match self {
            Surface::LevelSet(e) => Some(e.derivative()),
            _ => None,
        };
        Level { surface: self, derivative, dim }
    }
}

/// φ and ∇φ of a surface at points (module docs).
pub struct Level<'s> {
    surface: &'s Surface,
    derivative: Option<Derivative>,
    dim: usize,
}

impl Level<'_> {
    /// `(φ(x), ∇φ(x))` (entries beyond the dimension 0).
    pub fn at(&self, x: [f64; 3]) -> (f64, [f64; 3]) {
        let sub = |c: [f64; 3]| [x[0] - c[0], x[1] - c[1], x[2] - c[2]];
        let radial = |w: [f64; 3], radius: f64, side: Side| {
            let r = w.iter().map(|a| a * a).sum::<f64>().sqrt();
            let s = side.sign();
            let grad = if r > 0.0 { w.map(|a| s * a / r) } else { [0.0; 3] };
            (s * (r - radius), grad)
        };
        match self.surface {
            Surface::Plane { normal, point } => {
                let w = sub(*point);
                ((0..3).map(|a| normal[a] * w[a]).sum(), *normal)
            }
            Surface::Sphere { center, radius, side } => radial(sub(*center), *radius, *side),
            Surface::Cylinder { center, axis, radius, side } => {
                let w = sub(*center);
                let along: f64 = (0..3).map(|a| w[a] * axis[a]).sum();
                radial([0, 1, 2].map(|a| w[a] - along * axis[a]), *radius, *side)
            }
            Surface::LevelSet(_) => {
                let derivative = self.derivative.as_ref().expect("a level set has its derivative");
                let (v, g) = derivative.at(&x[..self.dim]);
                let mut grad = [0.0; 3];
                grad[..self.dim].copy_from_slice(&g[..self.dim]);
                (v, grad)
            }
        }
    }

    /// `(g, n)` at x: the plane's `(φ, normal)` exactly as written; else `(φ/|∇φ|, ∇φ/|∇φ|)`,
    /// None where ∇φ is zero or not finite.
    pub fn gap_normal(&self, x: [f64; 3]) -> Option<(f64, [f64; 3])> {
        let (phi, grad) = self.at(x);
        if let Surface::Plane { .. } = self.surface {
            return Some((phi, grad));
        }
        let size = grad.iter().map(|a| a * a).sum::<f64>().sqrt();
        (size > 0.0 && size.is_finite()).then(|| (phi / size, grad.map(|a| a / size)))
    }
}
