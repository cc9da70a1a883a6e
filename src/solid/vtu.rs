//! The solid's VTU frames for ParaView, written by the shared writer [`crate::fem::vtu`] (which
//! also reads them back): the point data `displacement` and `velocity` (3-component vectors, z
//! = 0 in 2D; 0 where eliminated) and `contact_pressure` (λ_c / ∫_{Γ_C} φ_c on the contact
//! nodes, 0 elsewhere), and the cell data `weight` (the mass redistribution). "Warp By Vector"
//! with `displacement` shows the deformed solid.

use super::assembly::SolidSystem;
use crate::fem::vtu::{Array, Grid, grid_string, vtk_type, write_series};

/// Pads interleaved d-component nodal values to 3 components.
fn to_3d(values: &[f64], d: usize) -> Vec<f64> {
    values.chunks(d).flat_map(|c| [c[0], c[1], if d == 3 { c[2] } else { 0.0 }]).collect()
}

/// The `.vtu` text of one frame: `u`, `v` nodal values interleaved `node·d + component` (as
/// [`crate::problem::GeometryView::nodal_values`] gives them), λ in contact order.
pub fn vtu_string(solid: &SolidSystem, u: &[f64], v: &[f64], lambda: &[f64]) -> String {
    let mesh = &solid.mesh;
    let d = mesh.dim;
    assert!(u.len() == mesh.n_nodes() * d && v.len() == u.len() && lambda.len() == solid.contact_nodes.len());
    let mut pressure = vec![0.0; mesh.n_nodes()];
    for ((&node, &l), &a) in solid.contact_nodes.iter().zip(lambda).zip(&solid.contact_areas) {
        pressure[node] = l / a;
    }
    let (u3, v3) = (to_3d(u, d), to_3d(v, d));
    let grid = Grid { points: &mesh.points, cells: &mesh.cells, verts: mesh.kind.verts(), kind: vtk_type(mesh.kind) };
    let point_data = [
        Array { name: "contact_pressure", components: 1, values: &pressure },
        Array { name: "displacement", components: 3, values: &u3 },
        Array { name: "velocity", components: 3, values: &v3 },
    ];
    grid_string(&grid, &point_data, "displacement", &[Array { name: "weight", components: 1, values: &solid.weights }])
}

/// Writes `frames` as `vtu/frame_NNNNN.vtu` and the collection `solid.pvd` into `dir`.
pub fn write_frames(
    dir: &std::path::Path,
    solid: &SolidSystem,
    frames: &[crate::observe::Frame],
) -> std::io::Result<()> {
    let times: Vec<f64> = frames.iter().map(|f| f.t).collect();
    write_series(dir, "solid", &times, |k| vtu_string(solid, &frames[k].u, &frames[k].v, &frames[k].lambda))
}

/// The solid's frames for the streaming writer ([`crate::fem::frames::FrameWriter`]).
impl crate::fem::frames::VtuFrames for SolidSystem {
    const COLLECTION: &'static str = "solid";

    fn write_vtu(&self, out: &mut dyn std::io::Write, u: &[f64], v: &[f64], lambda: &[f64]) -> std::io::Result<()> {
        out.write_all(vtu_string(self, u, v, lambda).as_bytes())
    }
}
