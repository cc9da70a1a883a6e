//! 2D meshes of a plate (0, L) × (0, H): structured Q1 quadrilaterals or P1 triangles, or any
//! triangle mesh given as arrays (e.g. read from a file by the Python bridge).
//!
//! The boundary conditions follow from the coordinates: the contact boundary is Γ_C = {x = 0},
//! the Dirichlet boundary is Γ_D = {x = L} with L the largest x of the mesh, and the rest of the
//! boundary is free (homogeneous Neumann).
//!
//! Structured meshes number the nodes x-fastest, `node(i, j) = j (nx + 1) + i`, with
//! `x_i = L i/nx`, `y_j = H j/ny` (the last ones set to L and H exactly). Quadrilateral
//! `(i, j)` is `[node(i,j), node(i+1,j), node(i+1,j+1), node(i,j+1)]` (counter-clockwise);
//! triangles split it along the diagonal from `(x_i, y_j)` to `(x_{i+1}, y_{j+1})`:
//! `[n00, n10, n11]` and `[n00, n11, n01]` — the numbering and diagonal of dolfinx's
//! `create_rectangle` ("right" diagonal), so matrices compare entry by entry.

use thiserror::Error;

/// The cell type of a mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CellKind {
    /// Q1 quadrilaterals (bilinear elements).
    Quad,
    /// P1 triangles (linear elements).
    Triangle,
}

impl CellKind {
    pub fn verts(self) -> usize {
        match self {
            CellKind::Quad => 4,
            CellKind::Triangle => 3,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            CellKind::Quad => "quad",
            CellKind::Triangle => "triangle",
        }
    }
}

#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshError {
    #[error("plate.length = {0}: must be finite and > 0")]
    Length(f64),
    #[error("plate.height = {0}: must be finite and > 0")]
    Height(f64),
    #[error("plate.nx = {nx}, plate.ny = {ny}: need nx >= 2 and ny >= 1")]
    Cells { nx: usize, ny: usize },
    #[error("a mesh with {0} vertices per cell: allowed are 3 (triangles) and 4 (quadrilaterals)")]
    VertsPerCell(usize),
    #[error("the mesh arrays are inconsistent: {0}")]
    Arrays(String),
    #[error("cell {cell} has area {area:e} (degenerate)")]
    Degenerate { cell: usize, area: f64 },
    #[error("quadrilateral {cell} is not an axis-aligned rectangle (only rectangles are supported for Q1)")]
    NotRectangle { cell: usize },
    #[error("the mesh has its smallest x at {xmin}: the contact boundary is x = 0, so the mesh must start there")]
    NotAtOrigin { xmin: f64 },
    #[error("vertex {vertex} belongs to no cell")]
    Orphan { vertex: usize },
}

/// A 2D mesh: vertex coordinates and cells (counter-clockwise vertex lists).
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh2d {
    pub points: Vec<[f64; 2]>,
    /// `kind.verts()` vertex indices per cell.
    pub cells: Vec<usize>,
    pub kind: CellKind,
    /// Largest x (the Dirichlet boundary is x = length).
    pub length: f64,
    /// Extent in y (max y − min y).
    pub height: f64,
    /// `(nx, ny)` for a structured mesh.
    pub grid: Option<(usize, usize)>,
}

impl Mesh2d {
    /// The structured mesh of (0, L) × (0, H) with nx × ny squares (split in two triangles each
    /// for `CellKind::Triangle`).
    pub fn structured(length: f64, height: f64, nx: usize, ny: usize, kind: CellKind) -> Result<Self, MeshError> {
        if !(length.is_finite() && length > 0.0) {
            return Err(MeshError::Length(length));
        }
        if !(height.is_finite() && height > 0.0) {
            return Err(MeshError::Height(height));
        }
        if nx < 2 || ny < 1 {
            return Err(MeshError::Cells { nx, ny });
        }
        let coord = |k: usize, n: usize, ext: f64| if k == n { ext } else { ext * k as f64 / n as f64 };
        let mut points = Vec::with_capacity((nx + 1) * (ny + 1));
        for j in 0..=ny {
            for i in 0..=nx {
                points.push([coord(i, nx, length), coord(j, ny, height)]);
            }
        }
        let node = |i: usize, j: usize| j * (nx + 1) + i;
        let mut cells = Vec::with_capacity(nx * ny * 6);
        for j in 0..ny {
            for i in 0..nx {
                let (n00, n10, n11, n01) = (node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1));
                match kind {
                    CellKind::Quad => cells.extend_from_slice(&[n00, n10, n11, n01]),
                    CellKind::Triangle => cells.extend_from_slice(&[n00, n10, n11, n00, n11, n01]),
                }
            }
        }
        Ok(Self { points, cells, kind, length, height, grid: Some((nx, ny)) })
    }

    /// A mesh from flat arrays (`points`: x, y per vertex; `cells`: `verts_per_cell` indices per
    /// cell), as returned by the Python bridge's `read_mesh`. Cells are reoriented
    /// counter-clockwise; quadrilaterals must be axis-aligned rectangles. The mesh must have
    /// its smallest x at 0 (the contact boundary).
    pub fn from_arrays(points: &[f64], cells: &[usize], verts_per_cell: usize) -> Result<Self, MeshError> {
        let kind = match verts_per_cell {
            3 => CellKind::Triangle,
            4 => CellKind::Quad,
            k => return Err(MeshError::VertsPerCell(k)),
        };
        if !points.len().is_multiple_of(2) || !cells.len().is_multiple_of(verts_per_cell) || cells.is_empty() {
            return Err(MeshError::Arrays(format!(
                "{} coordinates (need 2 per vertex), {} cell entries (need a positive multiple of {verts_per_cell})",
                points.len(),
                cells.len()
            )));
        }
        if let Some(x) = points.iter().find(|x| !x.is_finite()) {
            return Err(MeshError::Arrays(format!("coordinate {x} is not finite")));
        }
        let pts: Vec<[f64; 2]> = points.chunks(2).map(|p| [p[0], p[1]]).collect();
        if let Some(&v) = cells.iter().find(|&&v| v >= pts.len()) {
            return Err(MeshError::Arrays(format!("cell vertex {v} out of range 0..{}", pts.len())));
        }
        let mut used = vec![false; pts.len()];
        for &v in cells {
            used[v] = true;
        }
        if let Some(vertex) = used.iter().position(|u| !u) {
            return Err(MeshError::Orphan { vertex });
        }
        let fold = |f: fn(f64, f64) -> f64, k: usize, init: f64| pts.iter().map(|p| p[k]).fold(init, f);
        let (xmin, xmax) = (fold(f64::min, 0, f64::INFINITY), fold(f64::max, 0, f64::NEG_INFINITY));
        let (ymin, ymax) = (fold(f64::min, 1, f64::INFINITY), fold(f64::max, 1, f64::NEG_INFINITY));
        if xmin.abs() > 1e-12 * (xmax - xmin).abs().max(f64::MIN_POSITIVE) {
            return Err(MeshError::NotAtOrigin { xmin });
        }
        let mut mesh = Self { points: pts, cells: cells.to_vec(), kind, length: xmax, height: ymax - ymin, grid: None };
        if !(mesh.length > 0.0) {
            return Err(MeshError::Length(mesh.length));
        }
        let k = kind.verts();
        for c in 0..mesh.n_cells() {
            let area = mesh.signed_area(c);
            if !(area.abs() > 0.0) {
                return Err(MeshError::Degenerate { cell: c, area });
            }
            if area < 0.0 {
                mesh.cells[c * k..(c + 1) * k].reverse();
            }
            if kind == CellKind::Quad && !mesh.is_rectangle(c) {
                return Err(MeshError::NotRectangle { cell: c });
            }
        }
        Ok(mesh)
    }

    /// A triangle (or rectangle) mesh file read by meshio through the Python bridge (gmsh
    /// `.msh`, `.xdmf`, …), then checked and oriented by [`Mesh2d::from_arrays`].
    #[cfg(feature = "python")]
    pub fn read_file(path: &std::path::Path) -> Result<Self, MeshError> {
        let (points, cells, k) =
            crate::bridge::read_mesh(path).map_err(|e| MeshError::Arrays(format!("{}: {e}", path.display())))?;
        Self::from_arrays(&points, &cells, k)
    }

    pub fn n_nodes(&self) -> usize {
        self.points.len()
    }

    pub fn n_cells(&self) -> usize {
        self.cells.len() / self.kind.verts()
    }

    /// The vertex indices of cell c (counter-clockwise).
    pub fn cell(&self, c: usize) -> &[usize] {
        let k = self.kind.verts();
        &self.cells[c * k..(c + 1) * k]
    }

    /// Flat coordinates (x, y per vertex), the layout of the Python bridge.
    pub fn points_flat(&self) -> Vec<f64> {
        self.points.iter().flat_map(|p| [p[0], p[1]]).collect()
    }

    /// Signed area of cell c (shoelace formula; > 0 when counter-clockwise).
    pub fn signed_area(&self, c: usize) -> f64 {
        let v = self.cell(c);
        let n = v.len();
        let mut s = 0.0;
        for a in 0..n {
            let (p, q) = (self.points[v[a]], self.points[v[(a + 1) % n]]);
            s += p[0] * q[1] - q[0] * p[1];
        }
        0.5 * s
    }

    pub fn area(&self, c: usize) -> f64 {
        self.signed_area(c).abs()
    }

    /// `|Ω|`, the sum of the cell areas.
    pub fn total_area(&self) -> f64 {
        (0..self.n_cells()).map(|c| self.area(c)).sum()
    }

    /// True if quadrilateral c has its edges parallel to the axes (in counter-clockwise order
    /// starting anywhere).
    fn is_rectangle(&self, c: usize) -> bool {
        let v = self.cell(c);
        let tol = 1e-12 * (self.length + self.height);
        (0..4).all(|a| {
            let (p, q) = (self.points[v[a]], self.points[v[(a + 1) % 4]]);
            (p[0] - q[0]).abs() <= tol || (p[1] - q[1]).abs() <= tol
        })
    }

    /// Bounding box `[xmin, xmax, ymin, ymax]` of cell c.
    pub fn cell_box(&self, c: usize) -> [f64; 4] {
        let mut b = [f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY];
        for &v in self.cell(c) {
            let p = self.points[v];
            b = [b[0].min(p[0]), b[1].max(p[0]), b[2].min(p[1]), b[3].max(p[1])];
        }
        b
    }

    /// Largest cell diameter (the mesh size h; Δx = L/nx on structured quad meshes).
    pub fn h(&self) -> f64 {
        if let Some((nx, _)) = self.grid {
            return self.length / nx as f64;
        }
        let mut h: f64 = 0.0;
        for c in 0..self.n_cells() {
            let v = self.cell(c);
            for a in 0..v.len() {
                for b in a + 1..v.len() {
                    let (p, q) = (self.points[v[a]], self.points[v[b]]);
                    h = h.max((p[0] - q[0]).hypot(p[1] - q[1]));
                }
            }
        }
        h
    }

    /// Tolerance for "x = 0" and "x = L": 10⁻¹⁰ of the plate's size (structured meshes put the
    /// boundary nodes at exactly 0 and L).
    fn boundary_tol(&self) -> f64 {
        1e-10 * (self.length + self.height)
    }

    /// Whether vertex v lies on the contact boundary x = 0.
    pub fn on_contact(&self, v: usize) -> bool {
        self.points[v][0].abs() <= self.boundary_tol()
    }

    /// Whether vertex v lies on the Dirichlet boundary x = L.
    pub fn on_dirichlet(&self, v: usize) -> bool {
        (self.points[v][0] - self.length).abs() <= self.boundary_tol()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structured_meshes_cover_the_rectangle() {
        for kind in [CellKind::Quad, CellKind::Triangle] {
            let m = Mesh2d::structured(2.0, 0.5, 4, 3, kind).unwrap();
            assert_eq!(m.n_nodes(), 20);
            // Every cell is counter-clockwise, areas add up to L·H (each area is an exact sum of
            // products of grid coordinates: a few ulps).
            assert!((0..m.n_cells()).all(|c| m.signed_area(c) > 0.0));
            assert!((m.total_area() - 1.0).abs() <= 64.0 * f64::EPSILON);
            assert_eq!(m.points[4], [2.0, 0.0]);
            assert_eq!(m.points[19], [2.0, 0.5]);
        }
    }

    #[test]
    fn file_meshes_are_reoriented_and_checked() {
        let pts = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
        let m = Mesh2d::from_arrays(&pts, &[0, 2, 1], 3).unwrap();
        assert!(m.signed_area(0) > 0.0);
        assert!(matches!(
            Mesh2d::from_arrays(&[1.0, 0.0, 2.0, 0.0, 1.0, 1.0], &[0, 1, 2], 3),
            Err(MeshError::NotAtOrigin { .. })
        ));
        let line = [0.0, 0.0, 1.0, 0.0, 2.0, 0.0, 0.0, 1.0];
        assert!(matches!(
            Mesh2d::from_arrays(&line, &[0, 1, 2, 0, 1, 3], 3),
            Err(MeshError::Degenerate { cell: 0, .. })
        ));
        assert!(matches!(Mesh2d::from_arrays(&line, &[0, 1, 3], 3), Err(MeshError::Orphan { vertex: 2 })));
    }
}

/// The plate's cells sorted into the intervals of its distinct vertex abscissae
/// `x_0 = 0 < … < x_m = L`: interval j holds the cells spanning [x_j, x_{j+1}] (one column of a
/// structured mesh). CSR layout: the cells of interval j are `cells[start[j]..start[j + 1]]`.
#[derive(Debug, Clone, Default)]
pub struct Columns {
    pub xs: Vec<f64>,
    start: Vec<usize>,
    cells: Vec<usize>,
}

impl Columns {
    pub fn new(mesh: &Mesh2d) -> Self {
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
