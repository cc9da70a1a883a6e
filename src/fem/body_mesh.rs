//! Meshes of bodies of any shape from arrays ([`Mesh::body_from_arrays`]), e.g. a gmsh file
//! read at the scene's edge: no box is assumed (the box scenes keep [`Mesh::from_arrays`]).
//! Every error names the cell or node.
//!
//! Orientation: each cell's det J ([`super::element::det_range`], at its quadrature points and
//! nodes) must have one sign. A cell whose det J is negative throughout is the mirror image of
//! a valid one and is **re-ordered** (triangles and P2 cells: vertices 1 and 2 swapped with
//! their edges; quadrilaterals reversed; hexahedra: the faces ζ = 0 and ζ = 1 swapped;
//! tetrahedra: vertices 1 and 2); a cell whose det J changes sign (tangled: a P2 edge node
//! pushed across the cell, a non-convex quadrilateral) is **refused**; so is a cell whose
//! det J vanishes (degenerate).

use super::element::{MAX_VERTS, det_range};
use super::mesh::{Cell, Mesh, MeshError};
use std::collections::BTreeMap;

/// The node permutation that mirrors a cell of `kind` (module docs).
fn mirror(kind: Cell) -> &'static [usize] {
    match kind {
        Cell::Triangle => &[0, 2, 1],
        Cell::Quad => &[0, 3, 2, 1],
        Cell::Tet => &[0, 2, 1, 3],
        Cell::Hex => &[4, 5, 6, 7, 0, 1, 2, 3],
        // Edges (0,1), (1,2), (2,0) become (0,2), (2,1), (1,0): old 5, 4, 3.
        Cell::Triangle6 => &[0, 2, 1, 5, 4, 3],
        // Edges (0,1), (1,2), (0,2), (0,3), (1,3), (2,3) become (0,2), (2,1), (0,1), (0,3),
        // (2,3), (1,3): old 6, 5, 4, 7, 9, 8.
        Cell::Tet10 => &[0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
    }
}

impl Mesh {
    /// The mesh of a body of any shape: `points` (`kind.dim()` coordinates per node), `cells`
    /// (`kind.verts()` node indices per cell, [`super::cell`]'s local order), `groups` (name →
    /// node indices, e.g. a mesh file's physical groups). Checked, naming the cell or node:
    /// the array lengths, finite coordinates, indices in range; each cell's orientation (module
    /// docs: mirrored cells re-ordered, tangled or degenerate ones refused, det J relative to
    /// (10⁻¹² × the bounding box's size)^d); no cell repeated (the same corners); each facet in
    /// at most 2 cells; P2: an edge's node the same in every cell that has the edge. Nodes that
    /// no cell uses are dropped (the others renumbered in order, groups too: sorted, each once,
    /// dropped nodes left out). `extent` is the bounding box's size; no `grid`.
    pub fn body_from_arrays(
        kind: Cell,
        points: &[f64],
        cells: &[usize],
        groups: BTreeMap<String, Vec<usize>>,
    ) -> Result<Self, MeshError> {
        let (dim, k) = (kind.dim(), kind.verts());
        if !points.len().is_multiple_of(dim) || !cells.len().is_multiple_of(k) || cells.is_empty() {
            return Err(MeshError::Arrays(format!(
                "{} coordinates (need {dim} per node), {} cell entries (need a positive multiple of {k})",
                points.len(),
                cells.len()
            )));
        }
        let n = points.len() / dim;
        if let Some(i) = points.iter().position(|x| !x.is_finite()) {
            return Err(MeshError::Arrays(format!(
                "node {} has coordinate {} = {}: not finite",
                i / dim,
                i % dim,
                points[i]
            )));
        }
        // New index of each used node, in the input's order.
        let mut new = vec![usize::MAX; n];
        for (i, &v) in cells.iter().enumerate() {
            if v >= n {
                return Err(MeshError::Arrays(format!("cell {} has node {v}, out of range 0..{n}", i / k)));
            }
            new[v] = 0;
        }
        let mut pts = Vec::new();
        for (v, slot) in new.iter_mut().enumerate() {
            if *slot == 0 {
                *slot = pts.len();
                let p = &points[v * dim..(v + 1) * dim];
                pts.push([p[0], p[1], if dim == 3 { p[2] } else { 0.0 }]);
            }
        }
        let mut renumbered = BTreeMap::new();
        for (name, nodes) in groups {
            let mut kept = Vec::with_capacity(nodes.len());
            for v in nodes {
                match new.get(v) {
                    Some(&i) if i != usize::MAX => kept.push(i),
                    Some(_) => {}
                    None => {
                        return Err(MeshError::Arrays(format!("group \"{name}\" has node {v}, out of range 0..{n}")));
                    }
                }
            }
            kept.sort_unstable();
            kept.dedup();
            renumbered.insert(name, kept);
        }
        let lo = |a: usize| pts.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min);
        let hi = |a: usize| pts.iter().map(|p| p[a]).fold(f64::NEG_INFINITY, f64::max);
        let extent = [hi(0) - lo(0), hi(1) - lo(1), hi(2) - lo(2)];
        let cells = cells.iter().map(|&v| new[v]).collect();
        let mut mesh = Self { dim, points: pts, cells, kind, extent, grid: None, groups: renumbered };
        mesh.orient()?;
        mesh.check_conforming()?;
        Ok(mesh)
    }

    /// Re-orders mirrored cells, refuses degenerate and tangled ones (module docs).
    fn orient(&mut self) -> Result<(), MeshError> {
        let (k, d, kind) = (self.kind.verts(), self.dim, self.kind);
        let tol = (1e-12 * self.extent.iter().sum::<f64>()).powi(d as i32);
        let corners = kind.corners();
        for c in 0..self.n_cells() {
            let cell = self.cell(c);
            let repeated = (0..corners).any(|a| (a + 1..k).any(|b| cell[a] == cell[b]))
                || (corners..k).any(|a| (a + 1..k).any(|b| cell[a] == cell[b]));
            let [lo, hi] = det_range(kind, &self.cell_points(c));
            if repeated || hi.abs().max(lo.abs()) <= tol || (lo.abs().min(hi.abs()) <= tol && lo * hi >= 0.0) {
                return Err(MeshError::Degenerate { noun: kind.noun(), cell: c, measure: self.measure(c) });
            }
            if lo < 0.0 && hi > 0.0 {
                return Err(MeshError::Tangled { noun: kind.noun(), cell: c, min: lo, max: hi });
            }
            if hi < 0.0 {
                let old: [usize; MAX_VERTS] = std::array::from_fn(|a| if a < k { cell[a] } else { 0 });
                for (slot, &from) in self.cells[c * k..(c + 1) * k].iter_mut().zip(mirror(kind)) {
                    *slot = old[from];
                }
            }
        }
        Ok(())
    }

    /// No cell repeated, each facet in at most 2 cells, and (P2) one node per edge; by sorting
    /// (keys, cell) pairs (no hash map: linear memory, fast on 10⁶ cells).
    fn check_conforming(&self) -> Result<(), MeshError> {
        let data = self.kind.data();
        let corners = self.kind.corners();
        let mut keys: Vec<([usize; MAX_VERTS], usize)> = (0..self.n_cells())
            .map(|c| {
                let mut key = [usize::MAX; MAX_VERTS];
                key[..corners].copy_from_slice(&self.cell(c)[..corners]);
                key[..corners].sort_unstable();
                (key, c)
            })
            .collect();
        keys.sort_unstable();
        if let Some(w) = keys.windows(2).find(|w| w[0].0 == w[1].0) {
            return Err(MeshError::Duplicate { noun: data.noun, cell: w[1].1.max(w[0].1), first: w[0].1.min(w[1].1) });
        }
        drop(keys);
        let fv = data.facet_vertices();
        let mut facets: Vec<([usize; 4], usize)> = Vec::with_capacity(self.n_cells() * data.facets.len());
        for c in 0..self.n_cells() {
            let v = self.cell(c);
            for f in data.facets {
                let mut key = [usize::MAX; 4];
                for (slot, &a) in key.iter_mut().zip(&f[..fv]) {
                    *slot = v[a];
                }
                key.sort_unstable();
                facets.push((key, c));
            }
        }
        facets.sort_unstable();
        if let Some(w) = facets.windows(3).find(|w| w[0].0 == w[2].0) {
            let count = facets.iter().filter(|f| f.0 == w[0].0).count();
            let last = facets.iter().filter(|f| f.0 == w[0].0).map(|f| f.1).max().unwrap_or(w[2].1);
            let vertices = w[0].0.iter().copied().filter(|&x| x != usize::MAX).collect();
            return Err(MeshError::Facet { vertices, count, first: w[0].1, cell: last });
        }
        drop(facets);
        if self.kind.is_quadratic() { self.check_edge_nodes() } else { Ok(()) }
    }

    /// The straight-sided P2 mesh of a triangle or tetrahedron mesh: a node at the midpoint of
    /// every edge (numbered after the vertices, in order of first appearance), cells
    /// triangle6 / tetra10 with [`super::cell`]'s edge order; the groups kept (vertices only).
    /// Other kinds: `MeshError::Kind`.
    pub fn quadratic(&self) -> Result<Mesh, MeshError> {
        let (kind, edges): (Cell, &[[usize; 2]]) = match self.kind {
            Cell::Triangle => (Cell::Triangle6, &[[0, 1], [1, 2], [2, 0]]),
            Cell::Tet => (Cell::Tet10, &[[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]]),
            other => return Err(MeshError::Kind { kind: other.name(), dim: self.dim, allowed: "triangle, tet" }),
        };
        let mut points = self.points.clone();
        let mut node_of: std::collections::HashMap<[usize; 2], usize> = std::collections::HashMap::new();
        let mut cells = Vec::with_capacity(self.n_cells() * kind.verts());
        for c in 0..self.n_cells() {
            let v = self.cell(c);
            cells.extend_from_slice(v);
            for &[a, b] in edges {
                let key = [v[a].min(v[b]), v[a].max(v[b])];
                let node = *node_of.entry(key).or_insert_with(|| {
                    let (p, q) = (self.points[v[a]], self.points[v[b]]);
                    points.push(std::array::from_fn(|k| 0.5 * (p[k] + q[k])));
                    points.len() - 1
                });
                cells.push(node);
            }
        }
        Ok(Mesh { kind, points, cells, grid: None, ..self.clone() })
    }

    /// P2: every cell with the edge (a, b) has the same node on it.
    fn check_edge_nodes(&self) -> Result<(), MeshError> {
        let edges: &[[usize; 2]] =
            if self.dim == 2 { &[[0, 1], [1, 2], [2, 0]] } else { &[[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]] };
        let corners = self.kind.corners();
        let mut all: Vec<([usize; 2], usize, usize)> = Vec::with_capacity(self.n_cells() * edges.len());
        for c in 0..self.n_cells() {
            let v = self.cell(c);
            for (e, &[a, b]) in edges.iter().enumerate() {
                all.push(([v[a].min(v[b]), v[a].max(v[b])], v[corners + e], c));
            }
        }
        all.sort_unstable();
        match all.windows(2).find(|w| w[0].0 == w[1].0 && w[0].1 != w[1].1) {
            Some(w) => {
                Err(MeshError::EdgeNode { vertices: w[0].0, cell: w[1].2, node: w[1].1, first: w[0].2, other: w[0].1 })
            }
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangle6 on the unit square (diagonal 0–2), node 9 at (7, 7) unused; one cell given
    /// clockwise.
    fn square6() -> (Vec<f64>, Vec<usize>) {
        #[rustfmt::skip]
        let p = vec![0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.5, 0.0, 1.0, 0.5, 0.5, 0.5, 0.5, 1.0, 0.0, 0.5, 7.0, 7.0];
        // Cell 0 counter-clockwise [0, 1, 2 | 01, 12, 20]; cell 1 clockwise [0, 2, 3 reversed].
        let cells = vec![0, 1, 2, 4, 5, 6, 0, 3, 2, 8, 7, 6];
        (p, cells)
    }

    #[test]
    fn a_body_mesh_is_oriented_renumbered_and_its_groups_follow() {
        // The clockwise cell is re-ordered (mirror: [0,2,1,5,4,3] of its nodes); the unused node 9
        // is dropped and the group's entry for it too; the area is 1 (straight sides).
        let (p, cells) = square6();
        let groups = BTreeMap::from([("left".to_string(), vec![3, 0, 8, 9, 0])]);
        let m = Mesh::body_from_arrays(Cell::Triangle6, &p, &cells, groups).unwrap();
        assert_eq!(m.n_nodes(), 9);
        assert_eq!(m.cell(1), [0, 2, 3, 6, 7, 8]);
        assert_eq!(m.groups["left"], vec![0, 3, 8]);
        assert!((m.total_measure() - 1.0).abs() <= 4.0 * f64::EPSILON);
        assert!((0..2).all(|c| det_range(m.kind, &m.cell_points(c))[0] > 0.0));
        assert_eq!(m.extent, [1.0, 1.0, 0.0]);
    }

    /// mutations, as run: the `lo < 0.0 && hi > 0.0` test removed -> the tangled cell is
    /// mirrored or kept and the first assertion fails; `check_edge_nodes` skipped -> the
    /// EdgeNode assertion fails; the facet window `windows(3)` -> `windows(4)` -> the
    /// three-triangles assertion fails.
    #[test]
    fn tangled_degenerate_nonconforming_and_bad_arrays_are_refused_by_name() {
        let (mut p, cells) = square6();
        // The edge node of (1, 2) pushed across the cell, beyond vertex 0.
        (p[10], p[11]) = (-0.8, 0.5);
        let err = Mesh::body_from_arrays(Cell::Triangle6, &p, &cells, BTreeMap::new()).unwrap_err();
        assert!(matches!(err, MeshError::Tangled { cell: 0, .. }), "{err}");
        let (mut p, mut cells) = square6();
        // Cell 1 with its own node on the diagonal 0–2: node 9 moved onto node 6.
        cells[11] = 9;
        (p[18], p[19]) = (0.5, 0.5);
        let err = Mesh::body_from_arrays(Cell::Triangle6, &p, &cells, BTreeMap::new()).unwrap_err();
        assert_eq!(err, MeshError::EdgeNode { vertices: [0, 2], cell: 1, node: 9, first: 0, other: 6 });
        let (p, _) = square6();
        let err = Mesh::body_from_arrays(Cell::Triangle, &p, &[0, 1, 4], BTreeMap::new()).unwrap_err();
        assert!(matches!(err, MeshError::Degenerate { cell: 0, .. }), "{err}");
        let err = Mesh::body_from_arrays(Cell::Triangle, &p, &[0, 1, 2, 0, 2, 1], BTreeMap::new()).unwrap_err();
        assert_eq!(err, MeshError::Duplicate { noun: "triangle", cell: 1, first: 0 });
        let err =
            Mesh::body_from_arrays(Cell::Triangle, &p, &[0, 1, 2, 0, 1, 3, 0, 1, 5], BTreeMap::new()).unwrap_err();
        assert!(matches!(err, MeshError::Facet { count: 3, first: 0, cell: 2, .. }), "{err}");
        let err = Mesh::body_from_arrays(Cell::Triangle, &p, &[0, 1, 10], BTreeMap::new()).unwrap_err();
        assert_eq!(err.to_string(), "the mesh arrays are inconsistent: cell 0 has node 10, out of range 0..10");
        let mut bad = p.clone();
        bad[7] = f64::NAN;
        let err = Mesh::body_from_arrays(Cell::Triangle, &bad, &[0, 1, 2], BTreeMap::new()).unwrap_err();
        assert_eq!(err.to_string(), "the mesh arrays are inconsistent: node 3 has coordinate 1 = NaN: not finite");
        let groups = BTreeMap::from([("g".to_string(), vec![12])]);
        let err = Mesh::body_from_arrays(Cell::Triangle, &p, &[0, 1, 2], groups).unwrap_err();
        assert!(err.to_string().contains("group \"g\" has node 12"), "{err}");
    }

    #[test]
    fn mirrored_cells_of_every_kind_are_reordered_and_keep_their_integrals() {
        // Each structured cell mirrored by its permutation is mirrored back: the same measure,
        // a positive det J. A P2 mirror of the straight P1 box: the structured triangles and
        // tetrahedra with edge midpoints added. Mass sums are the measure (round-off: 1e-14).
        let meshes = [
            Mesh::structured_2d(2.0, 0.5, 3, 2, Cell::Triangle).unwrap(),
            Mesh::structured_2d(2.0, 0.5, 3, 2, Cell::Quad).unwrap(),
            Mesh::structured_3d([2.0, 0.5, 0.75], [2, 2, 1], Cell::Tet).unwrap(),
            Mesh::structured_3d([2.0, 0.5, 0.75], [2, 2, 1], Cell::Hex).unwrap(),
        ];
        for m in meshes {
            let k = m.kind.verts();
            let mirrored: Vec<usize> = (0..m.n_cells())
                .flat_map(|c| mirror(m.kind).iter().map(move |&a| (c, a)))
                .map(|(c, a)| m.cell(c)[a])
                .collect();
            let back = Mesh::body_from_arrays(m.kind, &m.flat_points(), &mirrored, BTreeMap::new()).unwrap();
            for c in 0..m.n_cells() {
                assert!(det_range(m.kind, &back.cell_points(c))[0] > 0.0, "{:?} {c}", m.kind);
                let mut a = back.cell(c).to_vec();
                let mut b = m.cell(c)[..k].to_vec();
                a.sort_unstable();
                b.sort_unstable();
                assert_eq!(a, b);
            }
            assert!((back.total_measure() - m.total_measure()).abs() <= 1e-14, "{:?}", m.kind);
        }
    }
}
