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

    /// A mesh from flat arrays (`points`: `dim` coordinates per vertex; `cells`:
    /// `verts_per_cell` vertex indices per cell), e.g. a mesh file read by meshio.
    ///
    /// - dim 2: triangles (3) or quadrilaterals (4), checked and reoriented counter-clockwise by
    ///   [`Mesh2d::from_arrays`] (quadrilaterals must be axis-aligned rectangles).
    /// - dim 3: tetrahedra (4) of non-zero volume, either orientation (the P1 element uses
    ///   |det J|; the structured Kuhn split has both), or hexahedra (8) that are axis-aligned boxes with the vertices in VTK order (vertex a at the
    ///   corner of [`super::element`]'s reference cube, each axis possibly mirrored): the Q1
    ///   element and the contact face areas assume boxes, as plates assume rectangles.
    ///
    /// The smallest x must be 0 (the contact face); L is the largest x, H and D the extents in
    /// y and z. No `grid` (so [`Mesh::h`] is NaN). Errors name the cell or vertex.
    pub fn from_arrays(points: &[f64], cells: &[usize], verts_per_cell: usize, dim: usize) -> Result<Self, MeshError> {
        match dim {
            2 => return Ok(Self::from_2d(&Mesh2d::from_arrays(points, cells, verts_per_cell)?)),
            3 => {}
            _ => return Err(MeshError::Arrays(format!("dimension {dim}: allowed are 2 and 3"))),
        }
        let kind = match verts_per_cell {
            4 => Cell::Tet,
            8 => Cell::Hex,
            k => {
                return Err(MeshError::Arrays(format!(
                    "{k} vertices per cell in 3D: allowed are 4 (tetrahedra) and 8 (hexahedra)"
                )));
            }
        };
        let pts = checked_points(points, cells, verts_per_cell, 3)?;
        let lo = |k: usize| pts.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
        let hi = |k: usize| pts.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max);
        let extent = [hi(0), hi(1) - lo(1), hi(2) - lo(2)];
        if lo(0).abs() > 1e-12 * (hi(0) - lo(0)).abs().max(f64::MIN_POSITIVE) {
            return Err(MeshError::NotAtOrigin { xmin: lo(0) });
        }
        if extent[0] <= 0.0 {
            return Err(MeshError::Length(extent[0]));
        }
        let mesh = Self { dim: 3, points: pts, cells: cells.to_vec(), kind, extent, grid: None };
        let tol = 1e-12 * extent.iter().sum::<f64>();
        for c in 0..mesh.n_cells() {
            let p = mesh.cell_points(c);
            if kind == Cell::Tet {
                let e = |a: usize| [p[a][0] - p[0][0], p[a][1] - p[0][1], p[a][2] - p[0][2]];
                let (a, b, d) = (e(1), e(2), e(3));
                // Signed volume: (a × b)·d / 6.
                let vol = ((a[1] * b[2] - a[2] * b[1]) * d[0]
                    + (a[2] * b[0] - a[0] * b[2]) * d[1]
                    + (a[0] * b[1] - a[1] * b[0]) * d[2])
                    / 6.0;
                if vol.abs() <= tol * tol * tol {
                    return Err(MeshError::Arrays(format!("tetrahedron {c} has volume {vol:e} (degenerate)")));
                }
            } else if !is_vtk_box(&p, tol) {
                return Err(MeshError::Arrays(format!(
                    "hexahedron {c} is not an axis-aligned box with its vertices in VTK order \
                     (only such boxes are supported for Q1)"
                )));
            }
        }
        Ok(mesh)
    }

    /// A 2D (triangles, quadrilaterals) or 3D (tetrahedra, hexahedra) mesh file read by meshio
    /// through the Python bridge ([`crate::bridge::read_cells`]: gmsh `.msh`, `.vtu`, …), then
    /// checked and oriented by [`Mesh::from_arrays`]. The file's vertex and cell order is kept.
    #[cfg(feature = "python")]
    pub fn read_file(path: &std::path::Path) -> Result<Self, MeshError> {
        let m = crate::bridge::read_cells(path).map_err(|e| MeshError::Arrays(format!("{}: {e}", path.display())))?;
        Self::from_arrays(&m.points, &m.cells, m.verts_per_cell, m.dim)
    }

    /// The mesh as the bridge's flat arrays (`dim` coordinates per vertex).
    #[cfg(feature = "python")]
    pub fn arrays(&self) -> crate::bridge::MeshArrays {
        crate::bridge::MeshArrays {
            points: self.points.iter().flat_map(|p| p[..self.dim].to_vec()).collect(),
            dim: self.dim,
            cells: self.cells.clone(),
            verts_per_cell: self.kind.verts(),
        }
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

/// `dim` coordinates per vertex as points in ℝ³, after checking the array lengths, finiteness,
/// the cells' vertex range and that every vertex belongs to a cell.
fn checked_points(points: &[f64], cells: &[usize], k: usize, dim: usize) -> Result<Vec<[f64; 3]>, MeshError> {
    if !points.len().is_multiple_of(dim) || !cells.len().is_multiple_of(k) || cells.is_empty() {
        return Err(MeshError::Arrays(format!(
            "{} coordinates (need {dim} per vertex), {} cell entries (need a positive multiple of {k})",
            points.len(),
            cells.len()
        )));
    }
    if let Some(x) = points.iter().find(|x| !x.is_finite()) {
        return Err(MeshError::Arrays(format!("coordinate {x} is not finite")));
    }
    let pts: Vec<[f64; 3]> = points.chunks(dim).map(|p| [p[0], p[1], if dim == 3 { p[2] } else { 0.0 }]).collect();
    let mut used = vec![false; pts.len()];
    for &v in cells {
        if v >= pts.len() {
            return Err(MeshError::Arrays(format!("cell vertex {v} out of range 0..{}", pts.len())));
        }
        used[v] = true;
    }
    match used.iter().position(|u| !u) {
        Some(vertex) => Err(MeshError::Orphan { vertex }),
        None => Ok(pts),
    }
}

/// Whether the 8 points are an axis-aligned box of positive size with vertex a at the VTK corner
/// (x bit `[0, 1, 1, 0][a % 4]`, y bit `[0, 0, 1, 1][a % 4]`, z bit `a / 4`), each axis possibly
/// mirrored: coordinate k of vertex a equals that of vertex 0 when bit k of a is 0, and that of
/// vertex 1, 3 or 4 (the neighbours of vertex 0 along x, y, z) when it is 1.
fn is_vtk_box(p: &[[f64; 3]; 8], tol: f64) -> bool {
    const NEIGHBOUR: [usize; 3] = [1, 3, 4];
    (0..3).all(|k| {
        let (lo, hi) = (p[0][k], p[NEIGHBOUR[k]][k]);
        (hi - lo).abs() > tol
            && (0..8).all(|a| {
                let bit = [[0, 1, 1, 0][a % 4], [0, 0, 1, 1][a % 4], a / 4][k];
                (p[a][k] - if bit == 1 { hi } else { lo }).abs() <= tol
            })
    })
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
    fn from_arrays_rebuilds_structured_meshes() {
        // The arrays of a structured mesh give back the same points, cells and extent (2D through
        // Mesh2d::from_arrays, 3D here); only `grid` is lost. A flat tetrahedron and a
        // hexahedron with two vertices swapped are refused.
        let flat = |m: &Mesh| m.points.iter().flat_map(|p| p[..m.dim].to_vec()).collect::<Vec<f64>>();
        let meshes = [
            Mesh::structured_2d(2.0, 0.5, 4, 3, CellKind::Triangle).unwrap(),
            Mesh::structured_2d(2.0, 0.5, 4, 3, CellKind::Quad).unwrap(),
            Mesh::structured_3d([2.0, 0.5, 0.75], [3, 2, 2], Cell::Tet).unwrap(),
            Mesh::structured_3d([2.0, 0.5, 0.75], [3, 2, 2], Cell::Hex).unwrap(),
        ];
        for m in meshes {
            let back = Mesh::from_arrays(&flat(&m), &m.cells, m.kind.verts(), m.dim).unwrap();
            assert_eq!(back, Mesh { grid: None, ..m.clone() }, "{:?}", m.kind);
        }
        let tet = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let mut flat_tet = tet;
        flat_tet[11] = 0.0;
        // mutation: `vol.abs() <= tol * tol * tol` -> `false` -> this assertion fails.
        let err = Mesh::from_arrays(&flat_tet, &[0, 1, 2, 3], 4, 3).unwrap_err();
        assert!(err.to_string().contains("tetrahedron 0 has volume 0e0"), "{err}");
        let hex = Mesh::structured_3d([1.0, 1.0, 1.0], [2, 1, 1], Cell::Hex).unwrap();
        let mut cells = hex.cells.clone();
        cells.swap(2, 3);
        // mutation: `is_vtk_box` returning true -> this assertion fails.
        let err = Mesh::from_arrays(&flat(&hex), &cells, 8, 3).unwrap_err();
        assert!(err.to_string().contains("hexahedron 0"), "{err}");
        let shifted: Vec<f64> = tet.iter().enumerate().map(|(i, x)| if i % 3 == 0 { x + 1.0 } else { *x }).collect();
        assert!(matches!(Mesh::from_arrays(&shifted, &[0, 1, 2, 3], 4, 3), Err(MeshError::NotAtOrigin { .. })));
        assert!(matches!(Mesh::from_arrays(&tet, &[0, 1, 2, 3], 5, 3), Err(MeshError::Arrays(_))));
        assert!(matches!(Mesh::from_arrays(&tet, &[0, 1, 2, 2], 4, 3), Err(MeshError::Orphan { vertex: 3 })));
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
