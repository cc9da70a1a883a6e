//! A body against a rigid plane run by the engine (issue 19 item 6): the data the Rust side
//! computed — nodes, cells, cell weights, contact nodes with their gaps g_i and areas a_i, the
//! clamped nodes, the nodal initial fields and the nodal force — written as `body.json` next to
//! the resolved scene, so that the engine assembles its own matrices (dolfinx) with exactly the
//! same mass weights and contact set. The plane's normal must be a coordinate axis ±e_k: the
//! contact unknown of node i is then the world component k of its displacement, bounded below by
//! −g_i (+e_k) or above by g_i (−e_k), a SNES VI bound (python/engine/body.py).

use crate::fem::Cell;
use crate::mass::MassKind;
use crate::solid::{SolidInitial, SolidSpec};
use serde::Serialize;

/// What `body.json` holds (python/engine/body.py reads it).
#[derive(Serialize)]
struct BodyData {
    dim: usize,
    /// "triangle" | "tetrahedron" | "quadrilateral" | "hexahedron" (our node order).
    cell: &'static str,
    /// 1 (P1, Q1) or 2 (triangle6, tetra10: the coordinate element and the field are P2).
    degree: usize,
    points: Vec<[f64; 3]>,
    cells: Vec<usize>,
    weights: Vec<f64>,
    density: f64,
    lame_lambda: f64,
    lame_mu: f64,
    /// The normal's axis k and its sign s (n = s e_k).
    axis: usize,
    sign: f64,
    contact_nodes: Vec<usize>,
    gaps: Vec<f64>,
    areas: Vec<f64>,
    clamped: Vec<usize>,
    /// Nodal world values, interleaved `node · dim + component`.
    u0: Vec<f64>,
    v0: Vec<f64>,
    force: Vec<f64>,
    /// The reference load energy of the Rust run's divergence rule
    /// (`driver::reference_load_energy`: `E_F`, or for a free body, whose S_rr is singular, the
    /// free-flight scale over the run); the engine's rule uses this one.
    load_energy: f64,
}

/// The axis k and sign s of a normal `n = s e_k` (None for any other normal).
pub fn axis_of(normal: [f64; 3], dim: usize) -> Option<(usize, f64)> {
    let k = (0..dim).find(|&k| normal[k] != 0.0)?;
    let on_axis = (0..3).all(|j| j == k || normal[j] == 0.0) && normal[k].abs() == 1.0;
    on_axis.then_some((k, normal[k]))
}

/// Why the engine cannot run this body (None if it can).
pub fn refusal(spec: &SolidSpec) -> Option<String> {
    let b = spec.support.body()?;
    let Some(n) = b.obstacle.plane_normal() else {
        return Some(format!(
            "obstacle.shape = \"{}\": the fenicsx engine runs plane obstacles only (curved obstacles run on the native engine)",
            b.obstacle.surface.name()
        ));
    };
    if axis_of(n, spec.dim).is_none() {
        return Some(format!(
            "obstacle.normal = {:?}: the fenicsx engine runs planes whose normal is a coordinate axis (±e_x, ±e_y{}) only",
            &n[..spec.dim],
            if spec.dim == 3 { ", ±e_z" } else { "" }
        ));
    }
    if b.force.iter().any(|e| e.depends_on("t")) {
        return Some("solid.force: the fenicsx engine runs forces that do not depend on t only".into());
    }
    match spec.built() {
        Ok(_) => None,
        Err(e) => Some(e.to_string()),
    }
}

/// `body.json` of a body scene (None for the box), with `|Γ_C|`, `L` and h for the observers.
pub fn data(spec: &SolidSpec, mass: &MassKind, t_end: f64) -> Result<Option<(String, [f64; 3])>, String> {
    let Some(b) = spec.support.body() else { return Ok(None) };
    let problem = spec.problem(mass, t_end).map_err(|e| e.to_string())?;
    let load_energy = crate::driver::reference_load_energy(crate::problem::Geometry::system(&problem.system), t_end)
        .map_err(|e| e.to_string())?;
    let (axis, sign) = b.obstacle.plane_normal().and_then(|n| axis_of(n, spec.dim)).ok_or("obstacle.normal")?;
    // The mesh, contact set and weights the problem was assembled with.
    let (mesh, weights) = (&problem.system.mesh, problem.system.weights.clone());
    let contact = spec.built().map_err(|e| e.to_string())?.contact.clone();
    let d = spec.dim;
    let nodal = |f: &dyn Fn(usize, &[f64]) -> f64| -> Vec<f64> {
        mesh.points.iter().flat_map(|p| (0..d).map(move |i| f(i, &p[..d]))).collect()
    };
    let (u0, v0) = match &spec.initial {
        SolidInitial::Paper => {
            let l = spec.extent[0];
            (nodal(&|i, p| if i == 0 { (l - p[0]) / 2.0 } else { 0.0 }), vec![0.0; mesh.n_nodes() * d])
        }
        SolidInitial::Fields { displacement, velocity } => {
            (nodal(&|i, p| displacement[i].eval(p)), nodal(&|i, p| velocity[i].eval(p)))
        }
    };
    let force = nodal(&|i, p| {
        let mut args = [0.0; 4];
        args[..d].copy_from_slice(p);
        b.force[i].eval(&args[..d + 1])
    });
    let section: f64 = contact.areas.iter().sum();
    let clamped = (0..mesh.n_nodes()).filter(|&v| contact.clamped[v]).collect();
    let out = [section, mesh.extent[0], mesh.h()];
    let data = BodyData {
        dim: d,
        cell: match mesh.kind {
            Cell::Quad => "quadrilateral",
            Cell::Hex => "hexahedron",
            _ if d == 2 => "triangle",
            _ => "tetrahedron",
        },
        cells: mesh.cells.clone(),
        points: mesh.points.clone(),
        weights,
        density: spec.lame.density,
        lame_lambda: spec.lame.lambda,
        lame_mu: spec.lame.mu,
        degree: if mesh.kind.is_quadratic() { 2 } else { 1 },
        axis,
        sign,
        contact_nodes: contact.nodes,
        gaps: contact.gaps,
        areas: contact.areas,
        clamped,
        u0,
        v0,
        force,
        load_energy,
    };
    serde_json::to_string(&data).map(|j| Some((j, out))).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::axis_of;

    /// ±e_k gives (k, ±1); anything else, including a normal with a component beyond `dim` or
    /// a unit vector off the axes, none.
    // mutation: `&& normal[k].abs() == 1.0` dropped -> [0.5, 0.0] is taken as +e_x, fails.
    #[test]
    fn only_coordinate_axes_are_bounds() {
        assert_eq!(axis_of([0.0, 1.0, 0.0], 2), Some((1, 1.0)));
        assert_eq!(axis_of([-1.0, 0.0, 0.0], 2), Some((0, -1.0)));
        assert_eq!(axis_of([0.0, 0.0, -1.0], 3), Some((2, -1.0)));
        assert_eq!(axis_of([0.6, 0.8, 0.0], 2), None);
        assert_eq!(axis_of([0.5, 0.0, 0.0], 2), None);
        assert_eq!(axis_of([0.0, 0.0, 1.0], 2), None);
    }
}
