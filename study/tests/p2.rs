//! Second-order bodies (triangle6, tetra10) read from gmsh files: the solid's assembly on them
//! (identities of the weighted vector mass and the elasticity stiffness, curved sides
//! included), and their VTU frames (quadratic VTK cells 22 and 24, read back here and, with
//! the `python` feature, by meshio).

use massredist::fem::vtu::{Grid, Layout, read_vtu};
use massredist::fem::{Cell, Mesh};
use massredist::linalg::sparse::triplets;
use massredist::scene::mesh_file::read_body;
use massredist::solid::assembly::{Lame, assemble};
use std::path::PathBuf;

fn fixture(name: &str) -> PathBuf {
    massredist_study::repo::root().join("fixtures/meshes").join(name)
}

fn bodies() -> [Mesh; 2] {
    [
        read_body("solid.mesh", &fixture("disc_p2_22a.msh"), 2).unwrap(),
        read_body("solid.mesh", &fixture("sphere_tet10_41b.msh"), 3).unwrap(),
    ]
}

/// `y = A x` for a sparse matrix.
fn mul(a: &massredist::linalg::sparse::SpMat, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    for (i, j, v) in triplets(a) {
        y[i] += v * x[j];
    }
    y
}

/// On the curved P2 disc and sphere (isoparametric: affine fields are in the space, curved
/// sides or not): the weighted mass sums to d ρ Σ_c w_c |c| (1ᵀ M 1 per component), M and K
/// are symmetric, and K annihilates the rigid motions (translations, rotations: their strain is
/// 0) to round-off, ‖K r‖ ≤ 1e-12 ‖K‖_max ‖r‖_max n (sums of n terms of that size).
/// mutation, as run: the P2 edge basis gradient factor 4 -> 2 (element.rs) -> fails (earlier:
/// the reader's det J check finds the disc's cells tangled).
#[test]
fn p2_assembly_keeps_the_mass_and_annihilates_rigid_motions() {
    let lame = Lame { lambda: 20.0, mu: 20.0, density: 1.5 };
    for m in bodies() {
        let d = m.dim;
        let weights: Vec<f64> = (0..m.n_cells()).map(|c| 0.5 + (c % 3) as f64).collect();
        let (mass, stiff) = assemble(&m, &weights, &lame).unwrap();
        let total: f64 = triplets(&mass).map(|t| t.2).sum();
        let want: f64 = d as f64 * lame.density * (0..m.n_cells()).map(|c| weights[c] * m.measure(c)).sum::<f64>();
        assert!((total - want).abs() <= 1e-12 * want, "{:?}: {total} vs {want}", m.kind);
        for a in [&mass, &stiff] {
            let t: Vec<_> = triplets(a).collect();
            let get = |i: usize, j: usize| t.iter().filter(|x| x.0 == i && x.1 == j).map(|x| x.2).sum::<f64>();
            for &(i, j, v) in t.iter().step_by(97) {
                assert!((v - get(j, i)).abs() <= 1e-13 * v.abs().max(1.0), "{:?} ({i}, {j})", m.kind);
            }
        }
        let kmax = triplets(&stiff).map(|t| t.2.abs()).fold(0.0, f64::max);
        let n = m.n_nodes();
        let mut motions: Vec<Vec<f64>> =
            (0..d).map(|k| (0..n * d).map(|i| if i % d == k { 1.0 } else { 0.0 }).collect()).collect();
        // Rotations about each axis pair (k, l): u_k = −x_l, u_l = x_k.
        for (k, l) in if d == 2 { vec![(0, 1)] } else { vec![(0, 1), (1, 2), (0, 2)] } {
            let mut r = vec![0.0; n * d];
            for v in 0..n {
                r[v * d + k] = -m.points[v][l];
                r[v * d + l] = m.points[v][k];
            }
            motions.push(r);
        }
        for r in motions {
            let rmax = r.iter().map(|x| x.abs()).fold(0.0, f64::max);
            let worst = mul(&stiff, &r).iter().map(|x| x.abs()).fold(0.0, f64::max);
            assert!(worst <= 1e-12 * kmax * rmax * 30.0, "{:?}: K r = {worst:e} (K max {kmax:e})", m.kind);
        }
    }
}

/// A VTU frame of each P2 body has VTK_QUADRATIC_TRIANGLE (22) / VTK_QUADRATIC_TETRA (24) cells
/// with our connectivity (our node order is VTK's), and the points and a point array back bit
/// for bit.
#[test]
fn p2_frames_write_quadratic_vtk_cells() {
    for m in bodies() {
        let grid = Grid { points: &m.points, cells: &m.cells, verts: m.kind.verts(), kind: m.kind.vtk() };
        let layout = Layout::new(&grid, &[("x", 1)], "", &[]);
        let x: Vec<f64> = m.points.iter().map(|p| p[0]).collect();
        let back = read_vtu(layout.frame(&[&x])).unwrap();
        let code = if m.kind == Cell::Triangle6 { 22 } else { 24 };
        assert!(back.types.iter().all(|&t| t == code) && back.types.len() == m.n_cells());
        assert_eq!(back.connectivity, m.cells);
        assert_eq!(back.point_array("x").unwrap().values, x);
    }
}

/// meshio reads the frames back as "triangle6" / "tetra10" with our connectivity, and the
/// scene's reader (through meshio for `.vtu`) gives back the same body mesh.
#[cfg(feature = "python")]
#[test]
fn meshio_reads_p2_frames_as_quadratic_cells() {
    let dir = tempfile::tempdir().unwrap();
    for m in bodies() {
        let grid = Grid { points: &m.points, cells: &m.cells, verts: m.kind.verts(), kind: m.kind.vtk() };
        let path = dir.path().join(format!("{}.vtu", m.kind.name()));
        std::fs::write(&path, Layout::new(&grid, &[], "", &[]).frame(&[])).unwrap();
        let blocks = massredist_study::bridge::read_mesh_blocks(&path).unwrap();
        assert_eq!(blocks.blocks.len(), 1);
        let (name, cells, nv) = &blocks.blocks[0];
        assert_eq!((name.as_str(), *nv), (m.kind.data().meshio, m.kind.verts()));
        assert!(cells.iter().zip(&m.cells).all(|(a, &b)| *a as usize == b));
        let back = read_body("solid.mesh", &path, m.dim).unwrap();
        assert_eq!((&back.cells, &back.points), (&m.cells, &m.points));
    }
}
