//! A box's matrices straight into compressed columns (issue 31: the scene's path at scale).
//!
//! The weighted mass, the unit mass and the stiffness are assembled cell by cell into their
//! compressed columns on the free unknowns, the pattern from the node graph (unknown (a, i)
//! couples to (b, j) when nodes a and b share a cell, and i = j for a mass): no element triplets
//! (about 23 kB of them per hexahedron) and no matrix over all nodes. Each entry receives its
//! cell contributions in increasing cell order, computed as [`super::assembly::assemble`]
//! computes them at the same position (the stiffness by [`stiffness_entry`], which every solid
//! assembly calls), so the matrices equal the principal submatrices of the triplet assembly bit
//! for bit, pattern included (`tests/central_solid.rs`).
//! [`super::SolidSystem::assemble`] takes them for a box (every scheme; the unit mass only when
//! an L² error is asked for: [`super::SolidSystem::mass_unit`]), and so does the explicit
//! benches' set-up ([`super::lean`]).

use super::dof_map::DofMap;
use crate::fem::Mesh;
use crate::fem::element::CellIntegrals;
use crate::linalg::sparse::{self, SpMat};
use crate::mass::ContactDirections;
use crate::material::Lame;

/// The compressed-column pattern on the unknowns `dof_of` maps to (full index → index in
/// 0..n, None where eliminated): unknown (a, i) couples to (b, j) when nodes a and b share a
/// cell, and `i == j` unless `full(a, b)` (a vector mass is `δ_ij` times a scalar, except
/// between nodes whose frames differ: [`super::curved`]). Rows increase within a column.
fn node_graph(
    mesh: &Mesh,
    dof_of: &DofMap,
    n: usize,
    full: impl Fn(usize, usize) -> bool + Copy,
    keep: Option<&[bool]>,
) -> (Vec<usize>, Vec<usize>) {
    let d = mesh.dim;
    let cells = touching_cells(mesh, dof_of, keep);
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); mesh.n_nodes()];
    for c in (0..mesh.n_cells()).filter(|&c| cells.as_ref().is_none_or(|t| t[c])) {
        let v = mesh.cell(c);
        for &a in v {
            adj[a].extend_from_slice(v);
        }
    }
    adj.iter_mut().for_each(|l| {
        l.sort_unstable();
        l.dedup();
    });
    // Column (a, i) holds rows (b, j) for b adjacent to a, j free, in increasing index (the
    // free indices increase with the full ones).
    let rows = |g: usize| {
        let (a, i) = (g / d, g % d);
        let col = dof_of.get(g);
        adj[a]
            .iter()
            .flat_map(move |&b| {
                let comps = if full(a, b) { 0..d } else { i..i + 1 };
                comps.filter_map(move |j| dof_of.get(b * d + j))
            })
            .filter(move |&row| kept(keep, row, col))
    };
    let columns = || (0..mesh.n_nodes() * d).filter(|&g| dof_of.is_free(g));
    // Counted first, then allocated once at its size (a growing vector holds up to twice its
    // entries at the peak).
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    for g in columns() {
        col_ptr.push(col_ptr[col_ptr.len() - 1] + rows(g).count());
    }
    let mut row_idx = Vec::with_capacity(col_ptr[n]);
    for g in columns() {
        row_idx.extend(rows(g));
    }
    (col_ptr, row_idx)
}

/// The matrix on the pattern of [`node_graph`] whose entry (row (a, i), column (b, j)) is the
/// sum over the cells c that hold a and b, in increasing c, of `block(c, e, a, b)[i][j]` (a, b
/// local vertex numbers of c, e its integrals): the value and the order of
/// [`super::assembly::assemble`]'s triplets, so the two are equal bit for bit (the expressions
/// are symmetric in exact arithmetic only: λ ∂_i φ_a ∂_j φ_b rounds otherwise than
/// λ ∂_j φ_b ∂_i φ_a). One block per pair of a cell's vertices, and one search of the column
/// per pair: a node's free components are consecutive rows. Only the diagonal of a block is
/// read unless `full(node a, node b)` ([`node_graph`]).
pub(super) fn assemble_on(
    mesh: &Mesh,
    dof_of: &DofMap,
    n: usize,
    full: impl Fn(usize, usize) -> bool + Copy,
    keep: Option<&[bool]>,
    block: impl Fn(usize, &crate::fem::element::CellIntegrals, usize, usize) -> [[f64; 3]; 3],
) -> SpMat {
    let d = mesh.dim;
    let (col_ptr, row_idx) = node_graph(mesh, dof_of, n, full, keep);
    let mut val = vec![0.0; row_idx.len()];
    let cells = touching_cells(mesh, dof_of, keep);
    for c in (0..mesh.n_cells()).filter(|&c| cells.as_ref().is_none_or(|t| t[c])) {
        let e = mesh.integrals(c);
        let v = mesh.cell(c);
        for a in 0..v.len() {
            for b in 0..v.len() {
                // Entry (row, col) = ((b, j), (a, i)): the triplet of that position.
                let x = block(c, &e, b, a);
                for i in 0..d {
                    let Some(col) = dof_of.get(v[a] * d + i) else { continue };
                    let rows = &row_idx[col_ptr[col]..col_ptr[col + 1]];
                    let comps = if full(v[a], v[b]) { 0..d } else { i..i + 1 };
                    // The position of (b, j): searched for the first, the next row after that.
                    let mut at: Option<usize> = None;
                    for j in comps {
                        let Some(row) = dof_of.get(v[b] * d + j) else { continue };
                        if !kept(keep, row, Some(col)) {
                            continue;
                        }
                        let k = match at {
                            Some(k) if rows.get(k + 1) == Some(&row) => k + 1,
                            _ => rows.partition_point(|&r| r < row),
                        };
                        assert_eq!(rows.get(k), Some(&row), "the pattern holds every cell pair");
                        at = Some(k);
                        val[col_ptr[col] + k] += x[j][i];
                    }
                }
            }
        }
    }
    sparse::from_csc(n, col_ptr, row_idx, val)
}

/// The stiffness on the unknowns `dof_of` maps to (full index → index in 0..n), assembled cell
/// by cell without triplets (module docs).
pub fn stiffness(mesh: &Mesh, lame: &Lame, dof_of: &DofMap, n: usize) -> SpMat {
    assemble_on(mesh, dof_of, n, |_, _| true, None, |_, e, a, b| stiffness_block(e, lame, a, b, mesh.dim))
}

/// The entries of [`stiffness`] in the rows and columns of the unknowns `keep` marks, bit for
/// bit, the others absent: what a massless layer's quasi-static rows read (`K_CC`, `K_CI`)
/// where the product is matrix-free ([`touching`]).
pub fn stiffness_touching(mesh: &Mesh, lame: &Lame, dof_of: &DofMap, n: usize, keep: &[bool]) -> SpMat {
    touching(mesh, dof_of, n, keep, |_, e, a, b| stiffness_block(e, lame, a, b, mesh.dim))
}

/// The entries of the matrix of the cells' `block`s in the rows and columns of the unknowns
/// `keep` marks (every component pair of two nodes: [`assemble_on`]), the others absent.
/// Without a marked unknown, an empty matrix (no pattern built).
pub(super) fn touching(
    mesh: &Mesh,
    dof_of: &DofMap,
    n: usize,
    keep: &[bool],
    block: impl Fn(usize, &crate::fem::element::CellIntegrals, usize, usize) -> [[f64; 3]; 3],
) -> SpMat {
    if !keep.iter().any(|&k| k) {
        return sparse::from_csc(n, vec![0; n + 1], Vec::new(), Vec::new());
    }
    assemble_on(mesh, dof_of, n, |_, _| true, Some(keep), block)
}

/// With `keep`, whether each cell holds a node with a marked unknown: a kept entry's row or
/// column is such a node's, so every cell that adds to it is one of these, and the others are
/// skipped (a massless layer's few cells instead of the mesh). None without `keep`.
fn touching_cells(mesh: &Mesh, dof_of: &DofMap, keep: Option<&[bool]>) -> Option<Vec<bool>> {
    let keep = keep?;
    let d = mesh.dim;
    let marked = |a: usize| (0..d).any(|i| dof_of.get(a * d + i).is_some_and(|k| keep[k]));
    Some((0..mesh.n_cells()).map(|c| mesh.cell(c).iter().any(|&a| marked(a))).collect())
}

/// Whether entry (row, col) is assembled: every entry without `keep`, else those whose row or
/// column is marked.
fn kept(keep: Option<&[bool]>, row: usize, col: Option<usize>) -> bool {
    keep.is_none_or(|k| k[row] || col.is_some_and(|c| k[c]))
}

/// `S_(a,i),(b,j)` of one cell ([`super::assembly`]'s module docs): `Σ_q w_q (λ ∂_i φ_a ∂_j φ_b + μ (δ_ij ∇φ_a·∇φ_b +
/// ∂_j φ_a ∂_i φ_b))` over the cell's quadrature points, a and b its local vertices. The one
/// expression of every solid assembly (triplets, compressed columns, frames), so that they agree
/// bit for bit.
pub fn stiffness_entry(e: &CellIntegrals, lame: &Lame, a: usize, b: usize, i: usize, j: usize) -> f64 {
    let mut s = 0.0;
    for q in 0..e.nq {
        let (ga, gb) = (&e.grads[q][a], &e.grads[q][b]);
        let delta = if i == j { e.grad_dot(q, a, b) } else { 0.0 };
        s += e.weights[q] * (lame.lambda * ga[i] * gb[j] + lame.mu * (delta + ga[j] * gb[i]));
    }
    s
}

/// The d × d block `S_(a,i),(b,j)` of one cell, each entry [`stiffness_entry`]'s sum in its
/// order (the same bits): one pass over the quadrature points for the block.
pub fn stiffness_block(e: &CellIntegrals, lame: &Lame, a: usize, b: usize, d: usize) -> [[f64; 3]; 3] {
    let mut s = [[0.0; 3]; 3];
    for q in 0..e.nq {
        let (ga, gb) = (&e.grads[q][a], &e.grads[q][b]);
        let dot = e.grad_dot(q, a, b);
        for (i, row) in s.iter_mut().enumerate().take(d) {
            for (j, x) in row.iter_mut().enumerate().take(d) {
                let delta = if i == j { dot } else { 0.0 };
                *x += e.weights[q] * (lame.lambda * ga[i] * gb[j] + lame.mu * (delta + ga[j] * gb[i]));
            }
        }
    }
    s
}

/// The weighted vector mass `δ_ij ρ Σ_c w_c^(i) ∫_c φ_a φ_b` on the unknowns `dof_of` maps to,
/// assembled as [`stiffness`] (the expression of [`super::assembly::assemble_directed`]).
pub fn mass(
    mesh: &Mesh,
    weights: &[f64],
    directions: ContactDirections,
    density: f64,
    dof_of: &DofMap,
    n: usize,
) -> SpMat {
    assert_eq!(weights.len(), mesh.n_cells(), "one weight per cell");
    assemble_on(
        mesh,
        dof_of,
        n,
        |_, _| false,
        None,
        |c, e, a, b| {
            let mut x = [[0.0; 3]; 3];
            for (i, row) in x.iter_mut().enumerate().take(mesh.dim) {
                row[i] = density * directions.weight(i, weights[c]) * e.mass[a][b];
            }
            x
        },
    )
}
