//! Finite elements shared by the geometries of dimension 2 and 3: one mesh abstraction
//! ([`mesh::Mesh`]: points in ℝ³, a `dim` field, structured quad/triangle and hex/tet meshes),
//! one set of reference elements ([`element`]: P1 simplices in closed form, Q1 tensor cells with
//! Gauss quadrature), and the mass redistribution by cell layers ([`layers`]) for any mesh that
//! implements [`CellMesh`] (the plate's `Mesh2d` and [`mesh::Mesh`]).

pub mod element;
pub mod frames;
pub mod layers;
pub mod mesh;
pub mod mesh2d;
pub mod vtu;

pub use mesh::{Cell, Mesh};

/// What the cell-layer mass redistribution needs of a mesh (any dimension).
pub trait CellMesh {
    fn n_nodes(&self) -> usize;
    fn n_cells(&self) -> usize;
    /// The vertex indices of cell c.
    fn cell(&self, c: usize) -> &[usize];
    /// The area (2D) or volume (3D) of cell c.
    fn measure(&self, c: usize) -> f64;
    /// Whether vertex v lies on the contact boundary x = 0.
    fn on_contact(&self, v: usize) -> bool;
    /// Whether vertex v lies on the clamped boundary x = L.
    fn on_dirichlet(&self, v: usize) -> bool;
    /// Coordinates of vertex v, for messages ("(x, y)" or "(x, y, z)").
    fn describe_point(&self, v: usize) -> String;
}

impl CellMesh for mesh2d::Mesh2d {
    fn n_nodes(&self) -> usize {
        mesh2d::Mesh2d::n_nodes(self)
    }

    fn n_cells(&self) -> usize {
        mesh2d::Mesh2d::n_cells(self)
    }

    fn cell(&self, c: usize) -> &[usize] {
        mesh2d::Mesh2d::cell(self, c)
    }

    fn measure(&self, c: usize) -> f64 {
        self.area(c)
    }

    fn on_contact(&self, v: usize) -> bool {
        mesh2d::Mesh2d::on_contact(self, v)
    }

    fn on_dirichlet(&self, v: usize) -> bool {
        mesh2d::Mesh2d::on_dirichlet(self, v)
    }

    fn describe_point(&self, v: usize) -> String {
        let [x, y] = self.points[v];
        format!("({x}, {y})")
    }
}
