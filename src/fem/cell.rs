//! The cell kinds of a [`super::Mesh`], as data: each kind is one row of [`Cell::data`] (its
//! names, dimension, vertex count, reference element and facets), so a new kind (P2 triangle6,
//! tetra10) is one variant, one row, and its reference element in [`super::element`].
//!
//! Local vertex order (the reference corners of [`super::element`]):
//! - triangle `[p0, p1, p2]`, counter-clockwise after [`super::Mesh::from_arrays`];
//! - quadrilateral `(0,0), (1,0), (1,1), (0,1)` (counter-clockwise);
//! - tetrahedron `[p0, p1, p2, p3]`, either orientation;
//! - hexahedron in VTK order: the face ζ = 0 as the quadrilateral, then the face ζ = 1 likewise.

/// The reference element of a cell kind ([`super::element`] integrates each).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Reference {
    /// P1 on a simplex: affine map, barycentric basis.
    P1Simplex,
    /// Q1 on [0, 1]^d: multilinear basis, 2^d-point Gauss rule.
    Q1Tensor,
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
    /// The facets (edges in 2D, faces in 3D) as local vertex lists.
    pub facets: &'static [&'static [usize]],
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
};

impl Cell {
    /// Every kind, in the order meshes of a file are looked for (highest dimension first).
    pub const ALL: [Cell; 4] = [Cell::Tet, Cell::Hex, Cell::Triangle, Cell::Quad];

    /// This kind's row of data.
    pub fn data(self) -> &'static CellData {
        match self {
            Cell::Triangle => &TRIANGLE,
            Cell::Quad => &QUAD,
            Cell::Tet => &TET,
            Cell::Hex => &HEX,
        }
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

    /// The scene name: quad | triangle | hex | tet.
    pub fn name(self) -> &'static str {
        self.data().name
    }

    /// The noun of messages: triangle | quadrilateral | tetrahedron | hexahedron.
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
        // of a simplex have `dim` vertices, of a box 2^(dim−1): the rows are consistent.
        for kind in Cell::ALL {
            let d = kind.data();
            for v in 0..d.verts {
                let on = d.facets.iter().filter(|f| f.contains(&v)).count();
                assert_eq!(on, d.dim, "{kind:?} vertex {v}");
            }
            let per_facet = if kind.is_tensor() { 1 << (d.dim - 1) } else { d.dim };
            assert!(d.facets.iter().all(|f| f.len() == per_facet), "{kind:?}");
            assert_eq!(Cell::from_meshio(d.meshio), Some(kind));
        }
    }
}
