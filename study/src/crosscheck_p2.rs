//! The second-order (P2, isoparametric) cases of `massredist crosscheck`: the weighted vector
//! mass and the elasticity stiffness on triangle6 and tetra10 meshes, straight-sided (jittered
//! structured meshes with edge midpoints, [`Mesh::quadratic`]) and curved (the gmsh disc and
//! sphere of `fixtures/meshes/`, read by the pure-Rust reader), against dolfinx (a quadratic
//! geometry, `VectorFunctionSpace` P2) and scikit-fem (`MeshTri2`/`MeshTet2`, `ElementTriP2`/
//! `ElementTetP2`).
//!
//! Quadrature: both backends are given the degree-5 Grundmann–Möller rule of the Rust element,
//! written independently in `python/crosscheck/fem_common.py::grundmann_moller`: exact for both forms on
//! straight-sided cells, and on curved cells (where the stiffness is rational and no rule is
//! exact) the same sum, so every case compares to round-off. Tolerance: the elastic cases' `8 ε
//! max|entry| r` (`super::tolerances`). Weights: seeded per cell (layer masses on P2 bodies
//! belong to the body scenes).

use super::{MatrixCase, Physics, SOLID_LAME, seeded_weights};
use crate::bridge::MeshArrays;
use massredist::fem::{Cell, Mesh};
use massredist::linalg::sparse::to_dense;
use std::collections::BTreeMap;

/// The P2 matrix cases (module docs). Panics only on a bug in these fixed, valid cases (the
/// fixtures are committed).
pub fn p2_cases() -> Vec<MatrixCase> {
    let fixture = |name: &str| crate::repo::root().join("fixtures/meshes").join(name);
    let straight = |m: Mesh| {
        let q = super::jittered(m).quadratic().expect("a simplex mesh");
        Mesh::body_from_arrays(q.kind, &q.flat_points(), &q.cells, BTreeMap::new()).expect("a valid P2 mesh")
    };
    let read = |name: &str, dim: usize| {
        massredist::scene::mesh_file::read_body("solid.mesh", &fixture(name), dim).expect("the committed fixture")
    };
    let meshes = [
        ("elastic_p2_tri6_4x3_custom", straight(Mesh::structured_2d(1.0, 0.75, 4, 3, Cell::Triangle).expect("valid"))),
        (
            "elastic_p2_tet10_2x2x2_custom",
            straight(Mesh::structured_3d([1.0, 0.75, 0.5], [2, 2, 2], Cell::Tet).expect("valid")),
        ),
        ("elastic_p2_disc_curved_custom", read("disc_p2_22a.msh", 2)),
        ("elastic_p2_sphere_curved_custom", read("sphere_tet10_22a.msh", 3)),
    ];
    meshes
        .into_iter()
        .enumerate()
        .map(|(k, (name, mesh))| {
            let weights: Vec<f64> =
                seeded_weights(mesh.n_cells(), 0x9_2e1 + k as u64).iter().map(|w| w + 0.5).collect();
            let (m, s) =
                massredist::solid::assembly::assemble(&mesh, &weights, &SOLID_LAME).expect("assembly succeeds");
            let flat = |a: Vec<Vec<f64>>| a.into_iter().flatten().collect::<Vec<f64>>();
            MatrixCase {
                name: name.into(),
                mesh: MeshArrays::of(&mesh),
                weights,
                physics: Physics::Elastic(SOLID_LAME),
                file: None,
                mass: flat(to_dense(&m)),
                stiffness: flat(to_dense(&s)),
            }
        })
        .collect()
}
