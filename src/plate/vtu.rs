//! The plate's VTU frames for ParaView, written by the shared binary writer
//! [`crate::fem::vtu`] (which also reads them back): the points (z = 0), the cells (VTK_QUAD = 9
//! or VTK_TRIANGLE = 5), the point data `u` and `v` (0 on Γ_D) and `warp` = (0, 0, u) (for "Warp
//! By Vector"), and the cell data `weight` (the mass redistribution). The streaming writer of a
//! run is the one of every geometry ([`FrameWriter`]).

use crate::fem::Mesh;
use crate::fem::vtu::{Array, Grid, Layout};

/// The frame layout of a plate: its mesh and `weights` serialised once, point arrays `u`, `v`,
/// `warp`.
pub fn layout(mesh: &Mesh, weights: &[f64]) -> Layout {
    assert_eq!(weights.len(), mesh.n_cells());
    let grid = Grid { points: &mesh.points, cells: &mesh.cells, verts: mesh.kind.verts(), kind: mesh.kind.vtk() };
    Layout::new(
        &grid,
        &[("u", 1), ("v", 1), ("warp", 3)],
        "warp",
        &[Array { name: "weight", components: 1, values: weights }],
    )
}

/// `warp` = (0, 0, u) into `out`.
fn warp(u: &[f64], out: &mut Vec<f64>) {
    out.clear();
    out.extend(u.iter().flat_map(|&x| [0.0, 0.0, x]));
}

/// The `.vtu` of one frame: `u`, `v` at every mesh node, `weights` per cell.
pub fn vtu_bytes(mesh: &Mesh, u: &[f64], v: &[f64], weights: &[f64]) -> Vec<u8> {
    let mut w = Vec::new();
    warp(u, &mut w);
    layout(mesh, weights).frame(&[u, v, &w])
}

pub use crate::fem::vtu::pvd_string;
// The reader of the files written here is the one of every mesh (`crate::fem::vtu`).
pub use crate::fem::vtu::{DataArray, VtuData, VtuError, read_pvd, read_vtu};

/// The plate's frames for the streaming writer: `u`, `v`, `warp` and `weight`.
impl crate::fem::frames::VtuFrames for super::PlateSystem {
    fn collection(&self) -> &'static str {
        "plate"
    }

    fn frame_layout(&self) -> Layout {
        layout(&self.mesh, &self.weights)
    }

    fn point_arrays(
        &self,
        u: &[f64],
        v: &[f64],
        _lambda: &[f64],
        _friction: Option<&crate::contact::friction::FrictionRecord>,
        arrays: &mut Vec<Vec<f64>>,
    ) {
        arrays.resize(3, Vec::new());
        arrays[0].clear();
        arrays[0].extend_from_slice(u);
        arrays[1].clear();
        arrays[1].extend_from_slice(v);
        warp(u, &mut arrays[2]);
    }
}

/// The streaming frame writer of every geometry ([`crate::fem::frames`]).
pub use crate::fem::frames::FrameWriter;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::Cell;

    #[test]
    fn a_frame_reads_back_bit_for_bit() {
        // Values that ASCII would need all 17 digits for, and the geometry of both cell kinds.
        // mutation: `Layout::write` writing the `v` values into the `u` block -> fails on the `u`
        // comparison.
        for kind in [Cell::Quad, Cell::Triangle] {
            let mesh = Mesh::structured_2d(1.0, 0.5, 3, 2, kind).unwrap();
            let n = mesh.n_nodes();
            let u: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin() / 3.0).collect();
            let v: Vec<f64> = (0..n).map(|i| -(i as f64).sqrt() * 1e-300).collect();
            let weights: Vec<f64> = (0..mesh.n_cells()).map(|c| 1.0 / (c + 3) as f64).collect();
            let bytes = vtu_bytes(&mesh, &u, &v, &weights);
            assert_eq!(bytes.len(), layout(&mesh, &weights).frame_bytes());
            let d = read_vtu(&bytes).unwrap();
            assert_eq!((d.n_points, d.n_cells), (n, mesh.n_cells()));
            assert_eq!(d.point_array("u").unwrap().values, u);
            assert_eq!(d.point_array("v").unwrap().values, v);
            let w = &d.point_array("warp").unwrap();
            assert_eq!((w.components, w.values[3 * n - 1]), (3, u[n - 1]));
            assert_eq!(d.cell_array("weight").unwrap().values, weights);
            assert_eq!(d.connectivity, mesh.cells);
            let k = mesh.kind.verts();
            assert_eq!(d.offsets, (1..=mesh.n_cells()).map(|c| c * k).collect::<Vec<_>>());
            assert!(d.types.iter().all(|&t| t == kind.vtk()));
            let points: Vec<f64> = mesh.points.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
            assert_eq!(d.points, points);
        }
    }
}
