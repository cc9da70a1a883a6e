//! The cells of a 2D mesh by columns of x: what an exact L² error against a plane wave
//! u(x, t) needs (the plate's [`crate::plate::norms`] and the elastic table's 2D solid).

use super::mesh::Mesh;

/// The cells of a 2D mesh sorted into the intervals of its distinct vertex abscissae
/// `x_0 = 0 < … < x_m = L`: interval j holds the cells spanning [x_j, x_{j+1}] (one column of a
/// structured mesh). CSR layout: the cells of interval j are `cells[start[j]..start[j + 1]]`.
#[derive(Debug, Clone, Default)]
pub struct Columns {
    pub xs: Vec<f64>,
    start: Vec<usize>,
    cells: Vec<usize>,
}

impl Columns {
    pub fn new(mesh: &Mesh) -> Self {
        let mut xs: Vec<f64> = mesh.points.iter().map(|p| p[0]).collect();
        xs.sort_by(f64::total_cmp);
        xs.dedup();
        let mut lists = vec![Vec::new(); xs.len().saturating_sub(1)];
        for c in 0..mesh.n_cells() {
            let [x0, x1, _, _] = mesh.cell_box(c);
            let j0 = xs.partition_point(|&x| x < x0);
            let j1 = xs.partition_point(|&x| x < x1);
            for list in &mut lists[j0..j1] {
                list.push(c);
            }
        }
        let mut start = vec![0];
        let mut cells = Vec::new();
        for list in lists {
            cells.extend(list);
            start.push(cells.len());
        }
        Columns { xs, start, cells }
    }

    pub fn of(&self, j: usize) -> &[usize] {
        &self.cells[self.start[j]..self.start[j + 1]]
    }
}
