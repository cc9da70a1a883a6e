//! One mesh abstraction for dimension 2 and 3: points in ℝ³ (z = 0 in 2D), cells as flat vertex
//! lists, and structured meshes of the box (0, L) × (0, H) [× (0, D)].
//!
//! The boundary conditions follow from the coordinates, as for plates: the contact boundary is
//! Γ_C = {x = 0}, the clamped boundary Γ_D = {x = L}, the other faces are lateral.
//!
//! - 2D structured meshes are the plate's ([`Mesh2d::structured`], converted by
//!   [`Mesh::from_2d`]): nodes x-fastest, quadrilaterals counter-clockwise, triangles split along
//!   the diagonal (x_i, y_j)–(x_{i+1}, y_{j+1}) (dolfinx's "right" diagonal).
//! - 3D structured meshes number the nodes x-fastest, then y, then z:
//!   `node(i, j, k) = (k (ny + 1) + j)(nx + 1) + i`, with `x_i = L i/nx` etc. (the last ones
//!   set to L, H, D exactly). Hexahedron (i, j, k) lists its corners in VTK order: the face
//!   z = z_k counter-clockwise `[n000, n100, n110, n010]`, then the face z = z_{k+1} likewise.
//!   Tetrahedra: the Kuhn split of each cube into 6 tetrahedra around the main diagonal
//!   n000–n111, one per order of the axes (x, y, z): `[n000, n000 + e_a, n000 + e_a + e_b, n111]`.
//!   Neighbouring cubes split their shared faces along the same diagonal (the one through the
//!   corner with the smallest indices), so the mesh is conforming.

use super::CellMesh;
use super::mesh2d::{CellKind, Mesh2d, MeshError};

pub use super::element::Cell;

impl From<CellKind> for Cell {
    fn from(k: CellKind) -> Self {
        match k {
            CellKind::Quad => Cell::Quad,
            CellKind::Triangle => Cell::Triangle,
        }
    }
}

/// A mesh of dimension 2 or 3 (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    pub dim: usize,
    /// Vertex coordinates (z = 0 in 2D).
    pub points: Vec<[f64; 3]>,
    /// `kind.verts()` vertex indices per cell.
    pub cells: Vec<usize>,
    pub kind: Cell,
    /// `[L, H, D]`: the largest x, and the extents in y and z (D = 0 in 2D).
    pub extent: [f64; 3],
    /// `[nx, ny, nz]` for a structured mesh (nz = 0 in 2D).
    pub grid: Option<[usize; 3]>,
}

impl Mesh {
    /// The structured mesh of (0, L) × (0, H) with nx × ny squares (the plate's numbering).
    pub fn structured_2d(length: f64, height: f64, nx: usize, ny: usize, kind: CellKind) -> Result<Self, MeshError> {
        Ok(Self::from_2d(&Mesh2d::structured(length, height, nx, ny, kind)?))
    }

    /// A 2D plate mesh as a [`Mesh`] (same node and cell numbering).
    pub fn from_2d(m: &Mesh2d) -> Self {
        Self {
            dim: 2,
            points: m.points.iter().map(|p| [p[0], p[1], 0.0]).collect(),
            cells: m.cells.clone(),
            kind: m.kind.into(),
            extent: [m.length, m.height, 0.0],
            grid: m.grid.map(|(nx, ny)| [nx, ny, 0]),
        }
    }

    /// The structured mesh of (0, L) × (0, H) × (0, D) with nx × ny × nz cubes: hexahedra, or
    /// 6 tetrahedra per cube (module docs). `kind` must be `Hex` or `Tet`.
    pub fn structured_3d(extent: [f64; 3], n: [usize; 3], kind: Cell) -> Result<Self, MeshError> {
        let [l, h, d] = extent;
        let [nx, ny, nz] = n;
        for (v, err) in [(l, MeshError::Length(l)), (h, MeshError::Height(h)), (d, MeshError::Height(d))] {
            if !(v.is_finite() && v > 0.0) {
                return Err(err);
            }
        }
        if nx < 2 || ny < 1 || nz < 1 {
            return Err(MeshError::Cells { nx, ny });
        }
        if kind.dim() != 3 {
            return Err(MeshError::VertsPerCell(kind.verts()));
        }
        let coord = |k: usize, n: usize, ext: f64| if k == n { ext } else { ext * k as f64 / n as f64 };
        let mut points = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
        for k in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    points.push([coord(i, nx, l), coord(j, ny, h), coord(k, nz, d)]);
                }
            }
        }
        let node = |i: usize, j: usize, k: usize| (k * (ny + 1) + j) * (nx + 1) + i;
        let per_cube = if kind == Cell::Hex { 8 } else { 24 };
        let mut cells = Vec::with_capacity(nx * ny * nz * per_cube);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let c = |a: usize, b: usize, e: usize| node(i + a, j + b, k + e);
                    if kind == Cell::Hex {
                        cells.extend_from_slice(&[
                            c(0, 0, 0),
                            c(1, 0, 0),
                            c(1, 1, 0),
                            c(0, 1, 0),
                            c(0, 0, 1),
                            c(1, 0, 1),
                            c(1, 1, 1),
                            c(0, 1, 1),
                        ]);
                        continue;
                    }
                    // Kuhn split: one tetrahedron per order (a, b, c) of the axes.
                    for order in [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]] {
                        let mut s = [0usize; 3];
                        let mut tet = [c(0, 0, 0), 0, 0, c(1, 1, 1)];
                        for (step, &axis) in order[..2].iter().enumerate() {
                            s[axis] = 1;
                            tet[step + 1] = c(s[0], s[1], s[2]);
                        }
                        cells.extend_from_slice(&tet);
                    }
                }
            }
        }
        Ok(Self { dim: 3, points, cells, kind, extent, grid: Some(n) })
    }

    pub fn n_nodes(&self) -> usize {
        self.points.len()
    }

    pub fn n_cells(&self) -> usize {
        self.cells.len() / self.kind.verts()
    }

    /// The vertex indices of cell c.
    pub fn cell(&self, c: usize) -> &[usize] {
        let k = self.kind.verts();
        &self.cells[c * k..(c + 1) * k]
    }

    /// The vertex coordinates of cell c (first `kind.verts()` entries).
    pub fn cell_points(&self, c: usize) -> [[f64; 3]; 8] {
        let mut p = [[0.0; 3]; 8];
        for (a, &v) in self.cell(c).iter().enumerate() {
            p[a] = self.points[v];
        }
        p
    }

    /// The mesh size along x: L/nx on structured meshes.
    pub fn h(&self) -> f64 {
        match self.grid {
            Some([nx, ..]) => self.extent[0] / nx as f64,
            None => f64::NAN,
        }
    }

    /// `|Γ_C|`: H in 2D, H·D in 3D (the face x = 0 of the box).
    pub fn face_area(&self) -> f64 {
        if self.dim == 2 { self.extent[1] } else { self.extent[1] * self.extent[2] }
    }

    /// Tolerance for "on a face": 10⁻¹⁰ of the box's size (structured meshes put boundary
    /// nodes exactly on it).
    fn tol(&self) -> f64 {
        1e-10 * self.extent.iter().sum::<f64>()
    }

    /// Whether vertex v lies on the lateral face of normal `axis` (1 = y, 2 = z): y ∈ {0, H}
    /// or z ∈ {0, D}.
    pub fn on_lateral(&self, v: usize, axis: usize) -> bool {
        let t = self.points[v][axis];
        axis < self.dim && (t.abs() <= self.tol() || (t - self.extent[axis]).abs() <= self.tol())
    }
}

impl CellMesh for Mesh {
    fn n_nodes(&self) -> usize {
        Mesh::n_nodes(self)
    }

    fn n_cells(&self) -> usize {
        Mesh::n_cells(self)
    }

    fn cell(&self, c: usize) -> &[usize] {
        Mesh::cell(self, c)
    }

    fn measure(&self, c: usize) -> f64 {
        super::element::CellIntegrals::new(self.kind, &self.cell_points(c)).measure()
    }

    fn on_contact(&self, v: usize) -> bool {
        self.points[v][0].abs() <= self.tol()
    }

    fn on_dirichlet(&self, v: usize) -> bool {
        (self.points[v][0] - self.extent[0]).abs() <= self.tol()
    }

    fn describe_point(&self, v: usize) -> String {
        let p = self.points[v];
        if self.dim == 2 { format!("({}, {})", p[0], p[1]) } else { format!("({}, {}, {})", p[0], p[1], p[2]) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structured_boxes_are_filled_by_their_cells() {
        // Σ |c| = L H D for hexahedra and for the Kuhn tetrahedra (each volume is a product of
        // grid spacings over 6: a few ulps), and every tetrahedron is non-degenerate.
        for kind in [Cell::Hex, Cell::Tet] {
            let m = Mesh::structured_3d([2.0, 0.5, 0.75], [4, 3, 2], kind).unwrap();
            assert_eq!(m.n_nodes(), 5 * 4 * 3);
            assert_eq!(m.n_cells(), 24 * if kind == Cell::Hex { 1 } else { 6 });
            let vol: f64 = (0..m.n_cells()).map(|c| m.measure(c)).sum();
            assert!((vol - 0.75).abs() <= 64.0 * f64::EPSILON, "{kind:?}: {vol}");
            assert!((0..m.n_cells()).all(|c| m.measure(c) > 0.0));
            assert_eq!(m.points[m.n_nodes() - 1], [2.0, 0.5, 0.75]);
        }
    }

    #[test]
    fn the_kuhn_split_is_conforming() {
        // Every interior triangular face is shared by exactly two tetrahedra, every boundary one
        // by one: count faces (sorted vertex triples).
        let m = Mesh::structured_3d([1.0, 1.0, 1.0], [3, 2, 2], Cell::Tet).unwrap();
        let mut faces = std::collections::HashMap::new();
        for c in 0..m.n_cells() {
            let t = m.cell(c);
            for skip in 0..4 {
                let mut f: Vec<usize> = (0..4).filter(|&a| a != skip).map(|a| t[a]).collect();
                f.sort_unstable();
                *faces.entry(f).or_insert(0) += 1;
            }
        }
        let boundary = faces.values().filter(|&&n| n == 1).count();
        assert!(faces.values().all(|&n| n == 1 || n == 2));
        // The box's surface: 2 triangles per boundary square, 2(3·2 + 3·2 + 2·2) squares.
        assert_eq!(boundary, 2 * 2 * (6 + 6 + 4));
    }
}
