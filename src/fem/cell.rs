//! The cell kinds of a [`super::Mesh`], as data: each kind is one row of [`Cell::data`] (its
//! names, dimension, vertex count, reference element and facets), so a new kind (P2 triangle6,
//! tetra10) is one variant, one row, and its reference element in [`super::element`].
//!
//! Local vertex order (the reference corners of [`super::element`]):
//! - triangle `[p0, p1, p2]`, counter-clockwise after [`super::Mesh::from_arrays`];
//! - quadrilateral `(0,0), (1,0), (1,1), (0,1)` (counter-clockwise);
//! - tetrahedron `[p0, p1, p2, p3]`, either orientation;
//! - hexahedron in VTK order: the face ζ = 0 as the quadrilateral, then the face ζ = 1 likewise;
//! - triangle6 (P2) the triangle's vertices, then the midside nodes of the edges (0,1), (1,2),
//!   (2,0): the order of VTK (22) and of gmsh (9), meshio's "triangle6";
//! - tetra10 (P2) the tetrahedron's vertices, then the edges (0,1), (1,2), (0,2), (0,3), (1,3),
//!   (2,3): VTK's order (24), meshio's "tetra10". gmsh (11) lists the last two swapped ((2,3)
//!   then (1,3)); its reader ([`Cell::from_gmsh_order`]) swaps them back. dolfinx numbers the
//!   edges opposite the vertices ((2,3), (1,3), (1,2), (0,3), (0,2), (0,1)): its bridge permutes.
//!
//! The facets list each facet's vertices first ([`CellData::facet_vertices`] of them), then its
//! edge nodes (P2).

/// The reference element of a cell kind ([`super::element`] integrates each).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Reference {
    /// P1 on a simplex: affine map, barycentric basis.
    P1Simplex,
    /// Q1 on [0, 1]^d: multilinear basis, 2^d-point Gauss rule.
    Q1Tensor,
    /// P2 on a simplex: isoparametric quadratic map and basis, a degree-5 rule.
    P2Simplex,
}

/// What a mesh and its readers and writers need to know about one cell kind.
#[derive(Debug)]
pub struct CellData {
    /// The scene name (`plate.cells`, `solid.cells`).
    pub name: &'static str,
    /// meshio's cell type name.
    pub meshio: &'static str,
    /// The noun of messages ("hexahedron 3 …").
    pub noun: &'static str,
    /// The VTK cell type code.
    pub vtk: u8,
    /// Dimension of the cell (and of its mesh).
    pub dim: usize,
    /// Vertices per cell.
    pub verts: usize,
    pub reference: Reference,
    /// The facets (edges in 2D, faces in 3D) as local node lists: the facet's vertices first,
    /// then (P2) its edge nodes.
    pub facets: &'static [&'static [usize]],
    /// The corners of the cell (its first `corners` nodes): `verts` for P1 and Q1, the
    /// simplex's d + 1 for P2.
    pub corners: usize,
    /// gmsh's element type number.
    pub gmsh: u32,
}

/// The cell kind of a mesh (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Cell {
    /// P1 triangles (2D).
    Triangle,
    /// Q1 quadrilaterals (2D).
    Quad,
    /// P1 tetrahedra (3D).
    Tet,
    /// Q1 hexahedra (3D).
    Hex,
    /// P2 triangles (2D, 6 nodes).
    Triangle6,
    /// P2 tetrahedra (3D, 10 nodes).
    Tet10,
}

const TRIANGLE: CellData = CellData {
    name: "triangle",
    meshio: "triangle",
    noun: "triangle",
    vtk: 5,
    dim: 2,
    verts: 3,
    reference: Reference::P1Simplex,
    facets: &[&[0, 1], &[1, 2], &[2, 0]],
    corners: 3,
    gmsh: 2,
};

const QUAD: CellData = CellData {
    name: "quad",
    meshio: "quad",
    noun: "quadrilateral",
    vtk: 9,
    dim: 2,
    verts: 4,
    reference: Reference::Q1Tensor,
    facets: &[&[0, 1], &[1, 2], &[2, 3], &[3, 0]],
    corners: 4,
    gmsh: 3,
};

const TET: CellData = CellData {
    name: "tet",
    meshio: "tetra",
    noun: "tetrahedron",
    vtk: 10,
    dim: 3,
    verts: 4,
    reference: Reference::P1Simplex,
    facets: &[&[1, 2, 3], &[0, 2, 3], &[0, 1, 3], &[0, 1, 2]],
    corners: 4,
    gmsh: 4,
};

const HEX: CellData = CellData {
    name: "hex",
    meshio: "hexahedron",
    noun: "hexahedron",
    vtk: 12,
    dim: 3,
    verts: 8,
    reference: Reference::Q1Tensor,
    facets: &[&[0, 1, 2, 3], &[4, 5, 6, 7], &[0, 1, 5, 4], &[1, 2, 6, 5], &[2, 3, 7, 6], &[3, 0, 4, 7]],
    corners: 8,
    gmsh: 5,
};

const TRIANGLE6: CellData = CellData {
    name: "triangle6",
    meshio: "triangle6",
    noun: "triangle6",
    vtk: 22,
    dim: 2,
    verts: 6,
    reference: Reference::P2Simplex,
    facets: &[&[0, 1, 3], &[1, 2, 4], &[2, 0, 5]],
    corners: 3,
    gmsh: 9,
};

const TET10: CellData = CellData {
    name: "tetra10",
    meshio: "tetra10",
    noun: "tetra10",
    vtk: 24,
    dim: 3,
    verts: 10,
    reference: Reference::P2Simplex,
    // The faces opposite vertices 0, 1, 2, 3, each with its edges (module docs' edge numbers).
    facets: &[&[1, 2, 3, 5, 9, 8], &[0, 2, 3, 6, 9, 7], &[0, 1, 3, 4, 8, 7], &[0, 1, 2, 4, 5, 6]],
    corners: 4,
    gmsh: 11,
};

impl CellData {
    /// How many of each facet's nodes are vertices (the first ones): d for simplices, 2^(d−1)
    /// for Q1.
    pub fn facet_vertices(&self) -> usize {
        if self.reference == Reference::Q1Tensor { 1 << (self.dim - 1) } else { self.dim }
    }
}

impl Cell {
    /// Every kind, in the order meshes of a file are looked for (highest dimension first).
    pub const ALL: [Cell; 6] = [Cell::Tet, Cell::Hex, Cell::Tet10, Cell::Triangle, Cell::Quad, Cell::Triangle6];

    /// This kind's row of data.
    pub fn data(self) -> &'static CellData {
        match self {
            Cell::Triangle => &TRIANGLE,
            Cell::Quad => &QUAD,
            Cell::Tet => &TET,
            Cell::Hex => &HEX,
            Cell::Triangle6 => &TRIANGLE6,
            Cell::Tet10 => &TET10,
        }
    }

    /// The kind of a gmsh element type number, if supported.
    pub fn from_gmsh(code: u32) -> Option<Cell> {
        Cell::ALL.into_iter().find(|c| c.data().gmsh == code)
    }

    /// The position in gmsh's node list of each node of ours (module docs): the identity but
    /// for tetra10, whose last two edge nodes gmsh swaps.
    pub fn gmsh_order(self) -> &'static [usize] {
        const ID: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9];
        match self {
            Cell::Tet10 => &[0, 1, 2, 3, 4, 5, 6, 7, 9, 8],
            _ => &ID[..self.verts()],
        }
    }

    /// Whether the cell is a second-order (P2) cell.
    pub fn is_quadratic(self) -> bool {
        self.data().reference == Reference::P2Simplex
    }

    /// The corners of a cell (its first nodes): [`CellData::corners`].
    pub fn corners(self) -> usize {
        self.data().corners
    }

    /// The kind of a meshio cell type name, if supported.
    pub fn from_meshio(name: &str) -> Option<Cell> {
        Cell::ALL.into_iter().find(|c| c.data().meshio == name)
    }

    pub fn verts(self) -> usize {
        self.data().verts
    }

    pub fn dim(self) -> usize {
        self.data().dim
    }

    /// Whether the cell is a tensor-product (Q1) cell.
    pub fn is_tensor(self) -> bool {
        self.data().reference == Reference::Q1Tensor
    }

    /// The scene name: quad | triangle | hex | tet | triangle6 | tetra10.
    pub fn name(self) -> &'static str {
        self.data().name
    }

    /// The noun of messages: triangle | quadrilateral | tetrahedron | hexahedron | triangle6 |
    /// tetra10.
    pub fn noun(self) -> &'static str {
        self.data().noun
    }

    /// The VTK cell type code.
    pub fn vtk(self) -> u8 {
        self.data().vtk
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_facet_is_a_facet_of_the_reference_cell() {
        // Each vertex lies on exactly `dim` facets (a simplex or a box corner), and the facets
        // of a simplex have `dim` vertices, of a box 2^(dim−1): the rows are consistent. A P2
        // edge node lies on the facets holding both ends of its edge (2 in 3D, 1 in 2D), which
        // list it after their vertices.
        for kind in Cell::ALL {
            let d = kind.data();
            for v in 0..d.corners {
                let on = d.facets.iter().filter(|f| f[..d.facet_vertices()].contains(&v)).count();
                assert_eq!(on, d.dim, "{kind:?} vertex {v}");
            }
            let per_facet = if kind.is_tensor() { 1 << (d.dim - 1) } else { d.dim };
            assert_eq!(d.facet_vertices(), per_facet);
            let nodes = if kind.is_quadratic() { per_facet * (per_facet + 1) / 2 } else { per_facet };
            assert!(d.facets.iter().all(|f| f.len() == nodes), "{kind:?}");
            for e in d.corners..d.verts {
                let on = d.facets.iter().filter(|f| f[d.facet_vertices()..].contains(&e)).count();
                assert_eq!(on, d.dim - 1, "{kind:?} edge node {e}");
            }
            assert_eq!(Cell::from_meshio(d.meshio), Some(kind));
            assert_eq!(Cell::from_gmsh(d.gmsh), Some(kind));
        }
    }
}
