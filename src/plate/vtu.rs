//! The plate's VTU frames for ParaView: the point data `u` and `v` (0 on Γ_D) and
//! `warp` = (0, 0, u) (for "Warp By Vector"), and the cell data `weight` (the mass
//! redistribution), written by the shared writer [`crate::fem::vtu`] (which also reads them
//! back).

use super::mesh::{CellKind, Mesh2d};
use crate::fem::vtu::{Array, Grid, grid_string, write_series};
pub use crate::fem::vtu::{DataArray, VtuData, VtuError, pvd_string, read_pvd, read_vtu};

/// VTK cell type codes.
pub fn vtk_type(kind: CellKind) -> u8 {
    crate::fem::vtu::vtk_type(kind.into())
}

/// The `.vtu` text of one frame: `u`, `v` at every mesh node, `weights` per cell.
pub fn vtu_string(mesh: &Mesh2d, u: &[f64], v: &[f64], weights: &[f64]) -> String {
    assert!(u.len() == mesh.n_nodes() && v.len() == mesh.n_nodes() && weights.len() == mesh.n_cells());
    let points: Vec<[f64; 3]> = mesh.points.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let warp: Vec<f64> = u.iter().flat_map(|&x| [0.0, 0.0, x]).collect();
    let grid = Grid { points: &points, cells: &mesh.cells, verts: mesh.kind.verts(), kind: vtk_type(mesh.kind) };
    let point_data = [
        Array { name: "u", components: 1, values: u },
        Array { name: "v", components: 1, values: v },
        Array { name: "warp", components: 3, values: &warp },
    ];
    grid_string(&grid, &point_data, "warp", &[Array { name: "weight", components: 1, values: weights }])
}

/// Writes `frames` as `vtu/frame_NNNNN.vtu` and the collection `plate.pvd` into `dir`.
pub fn write_frames(
    dir: &std::path::Path,
    plate: &super::PlateSystem,
    frames: &[crate::observe::Frame],
) -> std::io::Result<()> {
    let times: Vec<f64> = frames.iter().map(|f| f.t).collect();
    write_series(dir, "plate", &times, |k| vtu_string(&plate.mesh, &frames[k].u, &frames[k].v, &plate.weights))
}
