//! Two (or more) elastic bodies in contact (issue 30): the bodies joined into one mesh, the
//! contact of each pair of facing facet groups, and the change of variables that makes the pair
//! condition a bound on one unknown.
//!
//! ```text
//! pair (first group A of body 1, second group B of body 2), per node i of A:
//!   ν_i    the normal pointing from body 2 into body 1 (the obstacle's convention);
//!   d_i  = g_i + ν_i · (u_i − Σ_k N_k(ξ_i) u_k) ≥ 0,   R_i ≥ 0,   d_i R_i = 0,
//! ```
//!
//! the contract's `d_i = g_i + n_i · (u_i − Σ_k N_k u_k)` with n_i = ν_i; ν_i is minus the
//! first group's outward normal (the contract's "pointing from the first body to the second"
//! is that outward normal: with it the distance is g − n_out · (u_i − Σ N_k u_k)).
//!
//! - **Matching interfaces** (node to node): every node i of A has a node k of B whose
//!   position differs from X_i by a multiple of ν_i up to 1e-10 × the interface's size (the
//!   largest side of the bounding box of A ∪ B), each k taken once: N_k = 1, ν_i = −n_A(i)
//!   with n_A(i) the mean of the outward unit normals of A's boundary facets at i (weighted by
//!   their measures), g_i = ν_i · (X_i − X_k).
//! - **Non-matching interfaces** (node to segment): the closest point X_p of B's boundary
//!   facets facing i (n_B · n_A(i) < −0.01, n_B the chord's outward normal) and in front of it
//!   (g_i ≥ the touching allowance below), in the reference configuration: N_k(ξ_i) its
//!   facet's shape functions there, ν_i the facet's outward unit normal at X_p (from body 2
//!   into body 1; a second-order segment's: the curve's), g_i = ν_i · (X_i − X_p). A node of A
//!   with no such facet (the far side of a disc whose whole boundary is the group) is not a
//!   contact node of the pair; none at all is refused. First-order facets in 2D and 3D,
//!   second-order segments in 2D (P2 triangles); 3D second-order facets are refused.
//! - A gap in [−1e-12 × the interface's size, 0) counts as touching (0); below it the node is
//!   refused (it starts inside the other body).
//!
//! **The change of variables** ([`super::coupling::Coupling`]). In node i's frame R_i (first column ν_i) its normal unknown
//! u'_i,0 = ν_i · u_i is replaced by `w_i = u'_i,0 − Σ_k Σ_c N_k (R_kᵀ ν_i)_c u'_k,c = d_i − g_i`:
//! u' = T z with T = I + E, E's only rows the pair nodes' normal ones, its columns the other
//! body's nodes. T is unimodular (T⁻¹ = I − E, since no row of E is a column of E: a node is
//! refused as both a first-group and a second-group node), and the system in z is
//! `Tᵀ M T z̈ + Tᵀ S T z = Tᵀ F + Tᵀ C λ` with the bound `w_i ≥ −g_i` on the unknown w_i: every
//! scheme and the exact contact solver apply unchanged. The reaction on w_i acts on body 1
//! along ν_i and, through Eᵀ, on body 2 as −N_k R_i ν_i: equal and opposite, so that the pair's
//! momentum is conserved to round-off with no external force.

use super::body::{boundary_facets, facet_normal};
use crate::fem::Mesh;
use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum PairError {
    #[error(
        "pair \"{pair}\": node {node} at ({at}) of group \"{group}\" has no facing facet of group \"{other}\" (a boundary facet of the second group whose outward normal n has n · n_first < −0.01)"
    )]
    NoFacing { pair: String, node: usize, at: String, group: String, other: String },
    #[error(
        "pair \"{pair}\": node {node} at ({at}) starts inside the other body: its gap is {gap:e} < 0 (a gap above −1e-12 × the interface's size counts as touching)"
    )]
    Inside { pair: String, node: usize, at: String, gap: f64 },
    #[error(
        "pair \"{pair}\": group \"{group}\" has no boundary facet (pair.groups names facing facet groups of the bodies' boundaries)"
    )]
    NoFacets { pair: String, group: String },
    #[error(
        "pair \"{pair}\": the interface is not matching and group \"{group}\" has second-order facets: node-to-segment contact is offered on first-order facets (use matching meshes on the interface, or first-order cells)"
    )]
    SecondOrder { pair: String, group: String },
    #[error(
        "node {node} (body \"{body}\") is a contact node of pair \"{first}\" and of \"{second}\": a node belongs to one pair's first group, and a first-group node to no second group (swap pair.groups)"
    )]
    Shared { node: usize, body: String, first: String, second: String },
}

/// The contact of one pair on the joined mesh (module docs): per first-group node i (not
/// clamped), its gap, normal ν_i, share of A's area and the second body's nodes with N_k.
#[derive(Debug, Clone, PartialEq)]
pub struct PairContact {
    pub nodes: Vec<usize>,
    pub gaps: Vec<f64>,
    pub normals: Vec<[f64; 3]>,
    pub areas: Vec<f64>,
    pub masters: Vec<Vec<(usize, f64)>>,
    /// Whether the pair is node to node.
    pub matching: bool,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn shown(mesh: &Mesh, v: usize) -> String {
    mesh.points[v][..mesh.dim].iter().map(|x| crate::numfmt::fmt_f64(*x)).collect::<Vec<_>>().join(", ")
}

/// The boundary facets of `mesh` whose nodes are all in `set`: (cell, facet).
fn facets_in(mesh: &Mesh, set: &[bool], all: &[(usize, usize)]) -> Vec<(usize, usize)> {
    let data = mesh.kind.data();
    all.iter().copied().filter(|&(c, f)| data.facets[f].iter().all(|&a| set[mesh.cell(c)[a]])).collect()
}

/// The closest point of a first-order facet (its vertices `p`) to `x`: the shape functions
/// there (one per vertex). A segment: the clamped projection; a triangle: the closest point by
/// regions (Ericson, Real-Time Collision Detection, 5.1.5); a quadrilateral: Newton on the
/// bilinear map, clamped to [0, 1]² (exact in one step on parallelograms).
fn closest(p: &[[f64; 3]], x: [f64; 3]) -> Vec<f64> {
    match p.len() {
        2 => {
            let t = sub(p[1], p[0]);
            let s = (dot(sub(x, p[0]), t) / dot(t, t)).clamp(0.0, 1.0);
            vec![1.0 - s, s]
        }
        3 => {
            let (a, b, c) = (p[0], p[1], p[2]);
            let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(x, a));
            let (d1, d2) = (dot(ab, ap), dot(ac, ap));
            if d1 <= 0.0 && d2 <= 0.0 {
                return vec![1.0, 0.0, 0.0];
            }
            let bp = sub(x, b);
            let (d3, d4) = (dot(ab, bp), dot(ac, bp));
            if d3 >= 0.0 && d4 <= d3 {
                return vec![0.0, 1.0, 0.0];
            }
            let vc = d1 * d4 - d3 * d2;
            if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
                let v = d1 / (d1 - d3);
                return vec![1.0 - v, v, 0.0];
            }
            let cp = sub(x, c);
            let (d5, d6) = (dot(ab, cp), dot(ac, cp));
            if d6 >= 0.0 && d5 <= d6 {
                return vec![0.0, 0.0, 1.0];
            }
            let vb = d5 * d2 - d1 * d6;
            if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
                let w = d2 / (d2 - d6);
                return vec![1.0 - w, 0.0, w];
            }
            let va = d3 * d6 - d5 * d4;
            if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
                let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
                return vec![0.0, 1.0 - w, w];
            }
            let denom = 1.0 / (va + vb + vc);
            let (v, w) = (vb * denom, vc * denom);
            vec![1.0 - v - w, v, w]
        }
        _ => {
            // Q1 face, vertices counter-clockwise: X(s, t) = Σ N_k(s, t) p_k.
            let shape = |s: f64, t: f64| [(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t];
            let (mut s, mut t) = (0.5, 0.5);
            for _ in 0..20 {
                let n = shape(s, t);
                let at: [f64; 3] = std::array::from_fn(|a| (0..4).map(|k| n[k] * p[k][a]).sum());
                let ds: [f64; 3] = std::array::from_fn(|a| (1.0 - t) * (p[1][a] - p[0][a]) + t * (p[2][a] - p[3][a]));
                let dt: [f64; 3] = std::array::from_fn(|a| (1.0 - s) * (p[3][a] - p[0][a]) + s * (p[2][a] - p[1][a]));
                let r = sub(x, at);
                let (a11, a12, a22) = (dot(ds, ds), dot(ds, dt), dot(dt, dt));
                let (b1, b2) = (dot(ds, r), dot(dt, r));
                let det = a11 * a22 - a12 * a12;
                let (es, et) = ((a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det);
                let (ns, nt) = ((s + es).clamp(0.0, 1.0), (t + et).clamp(0.0, 1.0));
                let done = (ns - s).abs() <= 1e-15 && (nt - t).abs() <= 1e-15;
                (s, t) = (ns, nt);
                if done {
                    break;
                }
            }
            shape(s, t).to_vec()
        }
    }
}

/// The closest point of a facet in front of a node: its distance, the normal there, the
/// facet's nodes with N_k, the gap.
struct Closest {
    dist: f64,
    normal: [f64; 3],
    masters: Vec<(usize, f64)>,
    gap: f64,
}

/// The closest point of a second-order segment (2D; nodes: its two vertices, then its middle
/// node) to `x`: Newton on (X(s) − x) · X'(s) = 0 from the chord's projection, clamped to
/// [0, 1], with N = ((1 − s)(1 − 2s), s(2s − 1), 4s(1 − s)); and the curve's unit normal there,
/// on the side of the chord's outward normal `chord`.
fn closest_p2(p: &[[f64; 3]], x: [f64; 3], chord: [f64; 3]) -> (Vec<f64>, [f64; 3]) {
    let shape = |s: f64| [(1.0 - s) * (1.0 - 2.0 * s), s * (2.0 * s - 1.0), 4.0 * s * (1.0 - s)];
    let slope = |s: f64| [4.0 * s - 3.0, 4.0 * s - 1.0, 4.0 - 8.0 * s];
    let curve = |n: [f64; 3]| -> [f64; 3] { std::array::from_fn(|a| (0..3).map(|k| n[k] * p[k][a]).sum()) };
    let mut s = closest(&p[..2], x)[1];
    for _ in 0..30 {
        let (xs, ts) = (curve(shape(s)), curve(slope(s)));
        let tt: [f64; 3] = std::array::from_fn(|a| 4.0 * (p[0][a] + p[1][a] - 2.0 * p[2][a]));
        let r = sub(xs, x);
        let (f, df) = (dot(r, ts), dot(ts, ts) + dot(r, tt));
        let next = if df > 0.0 { (s - f / df).clamp(0.0, 1.0) } else { s };
        let done = (next - s).abs() <= 1e-15;
        s = next;
        if done {
            break;
        }
    }
    let t = curve(slope(s));
    let l = dot(t, t).sqrt();
    let mut n = [t[1] / l, -t[0] / l, 0.0];
    if dot(n, chord) < 0.0 {
        n = n.map(|a| -a);
    }
    (shape(s).to_vec(), n)
}

/// The contact of pair `name` on the joined `mesh` (module docs): `first` and `second` the
/// nodes of the two facing groups (`groups` their names, for messages), `clamped` the mask of
/// clamped nodes (they leave the pair).
pub fn pair_contact(
    mesh: &Mesh,
    name: &str,
    (first, second): (&[usize], &[usize]),
    groups: [&str; 2],
    clamped: &[bool],
) -> Result<PairContact, PairError> {
    let n = mesh.n_nodes();
    let mask = |set: &[usize]| {
        let mut m = vec![false; n];
        set.iter().for_each(|&v| m[v] = true);
        m
    };
    let (in_a, in_b) = (mask(first), mask(second));
    let all = boundary_facets(mesh);
    let (fa, fb) = (facets_in(mesh, &in_a, &all), facets_in(mesh, &in_b, &all));
    for (f, g) in [(&fa, groups[0]), (&fb, groups[1])] {
        if f.is_empty() {
            return Err(PairError::NoFacets { pair: name.into(), group: g.into() });
        }
    }
    // n_A(i): the measure-weighted mean outward normal of A's facets at i.
    let data = mesh.kind.data();
    let mut outward = vec![[0.0; 3]; n];
    for &(c, f) in &fa {
        let (nf, m) = facet_normal(mesh, c, f);
        for &a in data.facets[f] {
            let v = mesh.cell(c)[a];
            for k in 0..3 {
                outward[v][k] += m * nf[k];
            }
        }
    }
    let mut nodes: Vec<usize> = first.iter().copied().filter(|&v| !clamped[v]).collect();
    let unit = |x: [f64; 3]| {
        let l = dot(x, x).sqrt();
        x.map(|a| a / l)
    };
    let size = {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for &v in first.iter().chain(second) {
            for a in 0..3 {
                (lo[a], hi[a]) = (lo[a].min(mesh.points[v][a]), hi[a].max(mesh.points[v][a]));
            }
        }
        (0..3).map(|a| hi[a] - lo[a]).fold(0.0, f64::max).min(f64::MAX)
    };
    let nu: Vec<[f64; 3]> = nodes.iter().map(|&v| unit(outward[v]).map(|a| -a)).collect();
    // Matching: each node of A faces one node of B along ν_i, each of B used once.
    let mut used = vec![false; n];
    let mut matched = Vec::with_capacity(nodes.len());
    for (&i, &nv) in nodes.iter().zip(&nu) {
        let xi = mesh.points[i];
        let facing = second.iter().copied().find(|&k| {
            let r = sub(mesh.points[k], xi);
            let t = sub(r, nv.map(|a| a * dot(r, nv)));
            !used[k] && dot(t, t).sqrt() <= 1e-10 * size
        });
        let Some(k) = facing else { break };
        used[k] = true;
        matched.push(k);
    }
    let touching = -1e-12 * size;
    let refuse = |i: usize, gap: f64| PairError::Inside { pair: name.into(), node: i, at: shown(mesh, i), gap };
    let matching = matched.len() == nodes.len();
    let (mut gaps, mut normals, mut masters) = (Vec::new(), Vec::new(), Vec::new());
    if matching {
        for ((&i, &k), &nv) in nodes.iter().zip(&matched).zip(&nu) {
            let g = dot(nv, sub(mesh.points[i], mesh.points[k]));
            if g < touching {
                return Err(refuse(i, g));
            }
            gaps.push(g.max(0.0));
            normals.push(nv);
            masters.push(vec![(k, 1.0)]);
        }
    } else {
        let p2 = mesh.kind.is_quadratic();
        if p2 && mesh.dim == 3 {
            return Err(PairError::SecondOrder { pair: name.into(), group: groups[1].into() });
        }
        let master: Vec<([f64; 3], Vec<usize>)> = fb
            .iter()
            .map(|&(c, f)| (facet_normal(mesh, c, f).0, data.facets[f].iter().map(|&a| mesh.cell(c)[a]).collect()))
            .collect();
        // The largest facet of B: a node behind a facet closer than this starts inside body 2.
        let reach = master
            .iter()
            .map(|(_, v)| {
                let r = sub(mesh.points[v[1]], mesh.points[v[0]]);
                dot(r, r).sqrt()
            })
            .fold(0.0, f64::max);
        let (mut kept, mut first_left) = (Vec::with_capacity(nodes.len()), None);
        for (&i, &nv) in nodes.iter().zip(&nu) {
            let xi = mesh.points[i];
            let mut best: Option<Closest> = None;
            let mut behind: Option<(f64, f64)> = None;
            for (chord, verts) in &master {
                if dot(*chord, nv) < 0.01 {
                    // n_B · n_A(i) = −n_B · ν_i ≥ −0.01: not facing.
                    continue;
                }
                let p: Vec<[f64; 3]> = verts.iter().map(|&v| mesh.points[v]).collect();
                let (shape, nb) = if p2 { closest_p2(&p, xi, *chord) } else { (closest(&p, xi), *chord) };
                let xp: [f64; 3] = std::array::from_fn(|a| shape.iter().zip(&p).map(|(s, q)| s * q[a]).sum());
                let r = sub(xi, xp);
                let (dist, g) = (dot(r, r).sqrt(), dot(nb, r));
                if g < touching && behind.is_none_or(|b| dist < b.0) {
                    behind = Some((dist, g));
                }
                // Only a facet in front of the node (g ≥ the touching allowance).
                if g >= touching && best.as_ref().is_none_or(|b| dist < b.dist) {
                    let pairs = verts.iter().copied().zip(shape).filter(|(_, s)| *s != 0.0).collect();
                    best = Some(Closest { dist, normal: nb, masters: pairs, gap: g });
                }
            }
            let in_front = best.as_ref().map_or(f64::INFINITY, |b| b.dist);
            if let Some((_, g)) = behind.filter(|b| b.0 < in_front && b.0 <= reach) {
                return Err(refuse(i, g));
            }
            let Some(Closest { normal: nb, masters: pairs, gap: g, .. }) = best else {
                first_left.get_or_insert(i);
                continue;
            };
            kept.push(i);
            gaps.push(g.max(0.0));
            normals.push(nb);
            masters.push(pairs);
        }
        if let Some(i) = first_left.filter(|_| kept.is_empty()) {
            let (group, other) = (groups[0].into(), groups[1].into());
            return Err(PairError::NoFacing { pair: name.into(), node: i, at: shown(mesh, i), group, other });
        }
        nodes = kept;
    }
    // The node's share of A's area, as for a body against an obstacle.
    let mut slot = vec![usize::MAX; n];
    for (s, &v) in nodes.iter().enumerate() {
        slot[v] = s;
    }
    let mut areas = vec![0.0; nodes.len()];
    for &(c, f) in &fa {
        let on: Vec<usize> = data.facets[f].iter().map(|&a| mesh.cell(c)[a]).collect();
        let (_, m) = facet_normal(mesh, c, f);
        for (&v, s) in on.iter().zip(super::body::shares(on.len(), data.facet_vertices())) {
            if slot[v] != usize::MAX {
                areas[slot[v]] += s * m;
            }
        }
    }
    Ok(PairContact { nodes, gaps, normals, areas, masters, matching })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::{Cell, Mesh};

    /// The closest point of a segment, a triangle and a square to points off them: the shape
    /// functions there, exactly (the clamped projection, Ericson's regions, Newton on a square
    /// which is affine: one step).
    #[test]
    fn the_closest_point_of_a_facet_gives_its_shape_functions() {
        let seg = [[0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
        assert_eq!(closest(&seg, [0.25, 1.5, 0.0]), vec![0.75, 0.25]);
        assert_eq!(closest(&seg, [-2.0, 1.5, 0.0]), vec![1.0, 0.0]);
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert_eq!(closest(&tri, [0.25, 0.5, 3.0]), vec![0.25, 0.25, 0.5]);
        assert_eq!(closest(&tri, [2.0, -1.0, 3.0]), vec![0.0, 1.0, 0.0]);
        let quad = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        let n = closest(&quad, [0.25, 0.5, -1.0]);
        for (a, b) in n.iter().zip([0.375, 0.125, 0.125, 0.375]) {
            assert!((a - b).abs() <= 1e-15, "{n:?}");
        }
    }

    /// Two unit squares of 2 × 2 and 3 × 3 quads, the second above the first with a gap 0.1:
    /// node to segment, each of the first's top nodes against the segment above it, ν = −e_y
    /// (from the upper body into the lower), g = 0.1, N_k the linear interpolation; with the gap
    /// −0.1 instead, the node starts inside and is refused, named.
    #[test]
    fn a_non_matching_pair_takes_the_segment_above_each_node() {
        let lower = Mesh::structured_2d(1.0, 1.0, 2, 2, Cell::Quad).unwrap();
        let mut upper = Mesh::structured_2d(1.0, 1.0, 3, 3, Cell::Quad).unwrap();
        let join = |upper: &Mesh| {
            let mut points = lower.points.clone();
            points.extend_from_slice(&upper.points);
            let mut cells = lower.cells.clone();
            cells.extend(upper.cells.iter().map(|v| v + lower.n_nodes()));
            Mesh { points, cells, grid: None, ..lower.clone() }
        };
        for p in upper.points.iter_mut() {
            p[1] += 1.1;
        }
        let mesh = join(&upper);
        let top: Vec<usize> = (0..lower.n_nodes()).filter(|&v| lower.points[v][1] == 1.0).collect();
        let bottom: Vec<usize> =
            (0..upper.n_nodes()).filter(|&v| upper.points[v][1] == 1.1).map(|v| v + lower.n_nodes()).collect();
        let clamped = vec![false; mesh.n_nodes()];
        let p = pair_contact(&mesh, "p", (&top, &bottom), ["top", "bottom"], &clamped).unwrap();
        assert!(!p.matching);
        for (k, &i) in p.nodes.iter().enumerate() {
            assert!((p.gaps[k] - 0.1).abs() <= 1e-15 && p.normals[k] == [-0.0, -1.0, -0.0], "{p:?}");
            let x: f64 = p.masters[k].iter().map(|&(m, n)| n * mesh.points[m][0]).sum();
            assert!((x - mesh.points[i][0]).abs() <= 1e-15, "node {i}: {:?}", p.masters[k]);
        }
        for pt in upper.points.iter_mut() {
            pt[1] -= 0.2;
        }
        let e = pair_contact(&join(&upper), "p", (&top, &bottom), ["top", "bottom"], &clamped).unwrap_err();
        assert!(matches!(e, PairError::Inside { .. }), "{e}");
    }
}
