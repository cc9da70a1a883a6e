//! The one mesh of dimension 2 and 3 (plates and solids): points in ℝ³ (z = 0 in 2D), cells of
//! one kind ([`Cell`]) as flat vertex lists, structured meshes of the box (0, L) × (0, H)
//! [× (0, D)], and meshes from arrays ([`Mesh::from_arrays`], e.g. a file read at the scene's
//! edge; checks in [`super::checks`]).
//!
//! The boundary conditions follow from the coordinates: the contact boundary is Γ_C = {x = 0},
//! the clamped boundary Γ_D = {x = L} with L the largest x, the other faces are lateral (free or
//! roller).
//!
//! - 2D structured meshes number the nodes x-fastest, `node(i, j) = j (nx + 1) + i`, with
//!   `x_i = L i/nx`, `y_j = H j/ny` (the last ones set to L and H exactly). Quadrilateral
//!   `(i, j)` is `[node(i,j), node(i+1,j), node(i+1,j+1), node(i,j+1)]` (counter-clockwise);
//!   triangles split it along the diagonal from `(x_i, y_j)` to `(x_{i+1}, y_{j+1})`:
//!   `[n00, n10, n11]` and `[n00, n11, n01]` — the numbering and diagonal of dolfinx's
//!   `create_rectangle` ("right" diagonal), so matrices compare entry by entry.
//! - 3D structured meshes number the nodes x-fastest, then y, then z:
//!   `node(i, j, k) = (k (ny + 1) + j)(nx + 1) + i`, likewise. Hexahedron (i, j, k) lists its
//!   corners in VTK order: the face z = z_k counter-clockwise `[n000, n100, n110, n010]`, then
//!   the face z = z_{k+1} likewise. Tetrahedra: the Kuhn split of each cube into 6 tetrahedra
//!   around the main diagonal n000–n111, one per order of the axes (x, y, z):
//!   `[n000, n000 + e_a, n000 + e_a + e_b, n111]`. Neighbouring cubes split their shared faces
//!   along the same diagonal (the one through the corner with the smallest indices), so the
//!   mesh is conforming.

use super::element::{CellIntegrals, MAX_VERTS};
use thiserror::Error;

pub use super::cell::Cell;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshError {
    #[error("the mesh's extent along {axis} is {value}: must be finite and > 0")]
    Extent { axis: &'static str, value: f64 },
    #[error("a structured mesh with {n:?} cells along x, y, z: need nx >= 2 and ny, nz >= 1")]
    Cells { n: [usize; 3] },
    #[error("{kind} cells in a structured {dim}D mesh: allowed are {allowed}")]
    Kind { kind: &'static str, dim: usize, allowed: &'static str },
    #[error(
        "{kind} cells in a box mesh: a box scene's mesh has triangle, quad, tetra or hexahedron cells (P2 cells are for bodies)"
    )]
    BoxKind { kind: &'static str },
    #[error("the mesh arrays are inconsistent: {0}")]
    Arrays(String),
    #[error("{noun} {cell} has measure {measure:e} (degenerate)")]
    Degenerate { noun: &'static str, cell: usize, measure: f64 },
    #[error(
        "{noun} {cell} is not an axis-aligned {shape} with its vertices in {order} order (only such cells are supported for Q1)"
    )]
    NotBox { noun: &'static str, cell: usize, shape: &'static str, order: &'static str },
    #[error(
        "{noun} {cell} is tangled: its det J ranges over [{min:e}, {max:e}] (changes sign: a node, e.g. a P2 edge node, lies across the cell; fix the mesh)"
    )]
    Tangled { noun: &'static str, cell: usize, min: f64, max: f64 },
    #[error(
        "cell {cell} has node {node} on the edge {vertices:?} but cell {first} has node {other} there: a conforming P2 mesh shares edge nodes"
    )]
    EdgeNode { vertices: [usize; 2], cell: usize, node: usize, first: usize, other: usize },
    #[error("the mesh has its smallest x at {xmin}: the contact boundary is x = 0, so the mesh must start there")]
    NotAtOrigin { xmin: f64 },
    #[error("vertex {vertex} belongs to no cell")]
    Orphan { vertex: usize },
    #[error("{noun} {cell} has the vertices of {noun} {first} (a duplicated cell)")]
    Duplicate { noun: &'static str, cell: usize, first: usize },
    #[error(
        "the facet with vertices {vertices:?} belongs to {count} cells (the first {first}, the last {cell}): a conforming mesh shares a facet between at most 2 cells"
    )]
    Facet { vertices: Vec<usize>, count: usize, first: usize, cell: usize },
    #[error(
        "{noun} {cell} has a boundary facet with vertices {vertices:?} inside the box (0, L) × (0, H) [× (0, D)]: the mesh has a hole or a non-conforming face there"
    )]
    Hole { noun: &'static str, cell: usize, vertices: Vec<usize> },
    #[error("the cells measure {measure} of the box's {bbox}: the mesh does not fill the box")]
    NotFilling { measure: f64, bbox: f64 },
}

/// A mesh of dimension 2 or 3 (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// `kind.dim()`.
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
    /// Named node sets (a mesh file's physical groups): name → node indices, sorted, each once.
    /// Empty for structured meshes.
    pub groups: std::collections::BTreeMap<String, Vec<usize>>,
}

/// `x_k = ext k/n`, the last one set to ext exactly.
fn coord(k: usize, n: usize, ext: f64) -> f64 {
    if k == n { ext } else { ext * k as f64 / n as f64 }
}

/// Refuses a non-finite or non-positive extent.
fn check_extent(extent: &[f64]) -> Result<(), MeshError> {
    match extent.iter().enumerate().find(|(_, v)| !(v.is_finite() && **v > 0.0)) {
        Some((k, &value)) => Err(MeshError::Extent { axis: ["x", "y", "z"][k], value }),
        None => Ok(()),
    }
}

impl Mesh {
    /// The structured mesh of (0, L) × (0, H) with nx × ny squares (module docs), quadrilaterals
    /// or two triangles per square.
    pub fn structured_2d(length: f64, height: f64, nx: usize, ny: usize, kind: Cell) -> Result<Self, MeshError> {
        check_extent(&[length, height])?;
        if nx < 2 || ny < 1 {
            return Err(MeshError::Cells { n: [nx, ny, 0] });
        }
        if kind.dim() != 2 || kind.is_quadratic() {
            return Err(MeshError::Kind { kind: kind.name(), dim: 2, allowed: "quad, triangle" });
        }
        let mut points = Vec::with_capacity((nx + 1) * (ny + 1));
        for j in 0..=ny {
            for i in 0..=nx {
                points.push([coord(i, nx, length), coord(j, ny, height), 0.0]);
            }
        }
        let node = |i: usize, j: usize| j * (nx + 1) + i;
        let mut cells = Vec::with_capacity(nx * ny * 6);
        for j in 0..ny {
            for i in 0..nx {
                let (n00, n10, n11, n01) = (node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1));
                match kind {
                    Cell::Quad => cells.extend_from_slice(&[n00, n10, n11, n01]),
                    _ => cells.extend_from_slice(&[n00, n10, n11, n00, n11, n01]),
                }
            }
        }
        let extent = [length, height, 0.0];
        Ok(Self { dim: 2, points, cells, kind, extent, grid: Some([nx, ny, 0]), groups: Default::default() })
    }

    /// The structured mesh of (0, L) × (0, H) × (0, D) with nx × ny × nz cubes: hexahedra, or
    /// 6 tetrahedra per cube (module docs).
    pub fn structured_3d(extent: [f64; 3], n: [usize; 3], kind: Cell) -> Result<Self, MeshError> {
        check_extent(&extent)?;
        let [l, h, d] = extent;
        let [nx, ny, nz] = n;
        if nx < 2 || ny < 1 || nz < 1 {
            return Err(MeshError::Cells { n });
        }
        if kind.dim() != 3 || kind.is_quadratic() {
            return Err(MeshError::Kind { kind: kind.name(), dim: 3, allowed: "hex, tet" });
        }
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
                        let corners =
                            [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]];
                        cells.extend(corners.iter().map(|&[a, b, e]| c(a, b, e)));
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
        Ok(Self { dim: 3, points, cells, kind, extent, grid: Some(n), groups: Default::default() })
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
    pub fn cell_points(&self, c: usize) -> [[f64; 3]; MAX_VERTS] {
        let mut p = [[0.0; 3]; MAX_VERTS];
        for (a, &v) in self.cell(c).iter().enumerate() {
            p[a] = self.points[v];
        }
        p
    }

    /// The element integrals of cell c ([`CellIntegrals`]).
    pub fn integrals(&self, c: usize) -> CellIntegrals {
        CellIntegrals::new(self.kind, &self.cell_points(c))
    }

    /// The area (2D) or volume (3D) of cell c.
    pub fn measure(&self, c: usize) -> f64 {
        self.integrals(c).measure()
    }

    /// `|Ω|`, the sum of the cell measures.
    pub fn total_measure(&self) -> f64 {
        (0..self.n_cells()).map(|c| self.measure(c)).sum()
    }

    /// Coordinates as the flat arrays of the Python bridge and of [`Mesh::from_arrays`]: `dim`
    /// per vertex.
    pub fn flat_points(&self) -> Vec<f64> {
        self.points.iter().flat_map(|p| p[..self.dim].to_vec()).collect()
    }

    /// Bounding box `[xmin, xmax, ymin, ymax]` of cell c (in the xy-plane).
    pub fn cell_box(&self, c: usize) -> [f64; 4] {
        let mut b = [f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY];
        for &v in self.cell(c) {
            let p = self.points[v];
            b = [b[0].min(p[0]), b[1].max(p[0]), b[2].min(p[1]), b[3].max(p[1])];
        }
        b
    }

    /// The mesh size: L/nx on structured meshes, else the largest cell diameter.
    pub fn h(&self) -> f64 {
        if let Some([nx, ..]) = self.grid {
            return self.extent[0] / nx as f64;
        }
        let mut h: f64 = 0.0;
        for c in 0..self.n_cells() {
            let v = self.cell(c);
            for a in 0..v.len() {
                for b in a + 1..v.len() {
                    let (p, q) = (self.points[v[a]], self.points[v[b]]);
                    h = h.max(((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt());
                }
            }
        }
        h
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

    /// Whether vertex v lies on the contact boundary x = 0.
    pub fn on_contact(&self, v: usize) -> bool {
        self.points[v][0].abs() <= self.tol()
    }

    /// Whether vertex v lies on the clamped boundary x = L.
    pub fn on_dirichlet(&self, v: usize) -> bool {
        (self.points[v][0] - self.extent[0]).abs() <= self.tol()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structured_boxes_are_filled_by_their_cells() {
        // Σ |c| = L H [D] for every kind (each measure is a product of grid spacings over 1, 2
        // or 6: a few ulps), every cell is positively sized, the last node is the far corner.
        for kind in [Cell::Quad, Cell::Triangle] {
            let m = Mesh::structured_2d(2.0, 0.5, 4, 3, kind).unwrap();
            assert_eq!(m.n_nodes(), 20);
            assert!((m.total_measure() - 1.0).abs() <= 64.0 * f64::EPSILON, "{kind:?}");
            assert_eq!((m.points[4], m.points[19]), ([2.0, 0.0, 0.0], [2.0, 0.5, 0.0]));
        }
        for kind in [Cell::Hex, Cell::Tet] {
            let m = Mesh::structured_3d([2.0, 0.5, 0.75], [4, 3, 2], kind).unwrap();
            assert_eq!(m.n_nodes(), 5 * 4 * 3);
            assert_eq!(m.n_cells(), 24 * if kind == Cell::Hex { 1 } else { 6 });
            let vol = m.total_measure();
            assert!((vol - 0.75).abs() <= 64.0 * f64::EPSILON, "{kind:?}: {vol}");
            assert!((0..m.n_cells()).all(|c| m.measure(c) > 0.0));
            assert_eq!(m.points[m.n_nodes() - 1], [2.0, 0.5, 0.75]);
        }
        assert!(matches!(Mesh::structured_3d([1.0; 3], [2, 1, 1], Cell::Quad), Err(MeshError::Kind { .. })));
        assert!(matches!(Mesh::structured_3d([1.0; 3], [2, 1, 1], Cell::Tet10), Err(MeshError::Kind { .. })));
        assert!(matches!(Mesh::structured_2d(1.0, 1.0, 2, 1, Cell::Triangle6), Err(MeshError::Kind { .. })));
        let err = Mesh::structured_2d(1.0, f64::NAN, 2, 1, Cell::Quad).unwrap_err();
        // NaN != NaN: compare the message, which names the axis.
        assert_eq!(err.to_string(), "the mesh's extent along y is NaN: must be finite and > 0");
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
