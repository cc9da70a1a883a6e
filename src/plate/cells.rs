//! The Q1 cell table of the plate's exact L² pass ([`crate::plate::norms`]), built once per
//! plate from its mesh (it depends on nothing else, so the plate can cache it).

use crate::fem::Mesh;

/// What the exact L² pass needs of each Q1 cell, computed once per plate
/// ([`super::PlateSystem::quad_cells`]): its box, its corner unknowns and the positions of its x-ends
/// among the distinct vertex abscissae, so that a pass reads no mesh point and evaluates the
/// exact solution once per abscissa, not twice per cell.
#[derive(Debug, Clone)]
pub struct QuadCells {
    /// The distinct vertex abscissae, increasing.
    pub(crate) xs: Vec<f64>,
    pub(crate) cells: Vec<QuadCell>,
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct QuadCell {
    /// [x0, x1, y0, y1].
    pub(crate) bbox: [f64; 4],
    /// Positions of x0 and x1 in `xs`.
    pub(crate) ix: [usize; 2],
    /// Free unknown at (x0,y0), (x1,y0), (x1,y1), (x0,y1); `usize::MAX` on Γ_D (value 0).
    pub(crate) dof: [usize; 4],
}

impl QuadCells {
    /// The table of `mesh`'s Q1 cells, `node_dof` the free unknown of each node (None on Γ_D).
    pub fn new(mesh: &Mesh, node_dof: &[Option<usize>]) -> Self {
        let mut xs: Vec<f64> = mesh.points.iter().map(|p| p[0]).collect();
        xs.sort_by(f64::total_cmp);
        xs.dedup();
        let at = |x: f64| xs.partition_point(|&v| v < x);
        let cells = (0..mesh.n_cells())
            .map(|c| {
                let bbox = mesh.cell_box(c);
                let [x0, x1, y0, y1] = bbox;
                let mut dof = [usize::MAX; 4];
                for &v in mesh.cell(c) {
                    let q = mesh.points[v];
                    let (i, j) = (
                        usize::from((q[0] - x0).abs() > (q[0] - x1).abs()),
                        usize::from((q[1] - y0).abs() > (q[1] - y1).abs()),
                    );
                    dof[[[0, 3], [1, 2]][i][j]] = node_dof[v].unwrap_or(usize::MAX);
                }
                QuadCell { bbox, ix: [at(x0), at(x1)], dof }
            })
            .collect();
        Self { xs, cells }
    }
}
