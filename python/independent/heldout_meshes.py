"""Meshes of the held-out body scenes (issue 19), made here (no gmsh) and written as gmsh MSH 2.2
ASCII files for the binary: a disc and a half disc of rings (P1, or P2 with the boundary edge
nodes on the circle: curved cells), a straight-sided P2 rectangle, and a box of Kuhn tetrahedra
(P1, or P2 mapped by a smooth map: every cell curved).

Each generator returns (points (N x d), cells (C x k) in gmsh node order, order). The groups are
node predicates; the file gets the boundary facets of each group (all their nodes satisfying the
predicate) as lower-dimensional elements, and one node no cell uses (the binary drops it).
"""
import math

import numpy as np

from heldout_fem import EDGES, boundary_facets


def _orient(pts, tri):
    a, b, c = pts[tri[0]], pts[tri[1]], pts[tri[2]]
    det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
    return tri if det > 0 else [tri[0], tri[2], tri[1]]


def _zip(inner, outer, closed):
    """Triangles between two rings of node indices ordered by angle (inner may be one node)."""
    tris = []
    if len(inner) == 1:
        m = len(outer)
        for j in range(m if closed else m - 1):
            tris.append([inner[0], outer[j], outer[(j + 1) % m]])
        return tris
    p, q = len(inner), len(outer)
    steps_i, steps_o = (p, q) if closed else (p - 1, q - 1)
    i = j = 0
    while i < steps_i or j < steps_o:
        if j >= steps_o or (i < steps_i and (i + 1) / steps_i < (j + 1) / steps_o):
            tris.append([inner[i % p], outer[j % q], inner[(i + 1) % p]])
            i += 1
        else:
            tris.append([inner[i % p], outer[j % q], outer[(j + 1) % q]])
            j += 1
    return tris


def disc(radius, centre, rings, half=False):
    """P1 disc (or its lower half, flat side on top) of `rings` rings; ring k has 6k nodes
    (3k + 1 for the half), the first at the bottom (angle -pi/2) so a node touches the floor."""
    pts = [np.array(centre, float)]
    ring_nodes = [[0]]
    for k in range(1, rings + 1):
        r = radius * k / rings
        if half:
            angles = [math.pi + math.pi * j / (3 * k) for j in range(3 * k + 1)]
        else:
            angles = [-math.pi / 2 + 2 * math.pi * j / (6 * k) for j in range(6 * k)]
        ids = []
        for a in angles:
            ids.append(len(pts))
            pts.append(np.array(centre) + r * np.array([math.cos(a), math.sin(a)]))
        ring_nodes.append(ids)
    pts = np.array(pts)
    tris = []
    for k in range(1, rings + 1):
        tris += _zip(ring_nodes[k - 1], ring_nodes[k], closed=not half)
    return pts, np.array([_orient(pts, t) for t in tris])


def rectangle(length, height, nx, ny):
    """P1 rectangle (0, L) x (0, H), each square split along (i, j)-(i+1, j+1)."""
    pts = np.array([[length * i / nx, height * j / ny] for j in range(ny + 1) for i in range(nx + 1)])
    node = lambda i, j: j * (nx + 1) + i
    tris = []
    for j in range(ny):
        for i in range(nx):
            tris += [[node(i, j), node(i + 1, j), node(i + 1, j + 1)], [node(i, j), node(i + 1, j + 1), node(i, j + 1)]]
    return pts, np.array(tris)


def parallelograms(length, height, nx, ny, shear):
    """Q1 cells of the rectangle (0, L) x (0, H) sheared by x -> x + shear y (parallelograms)."""
    pts = np.array([[length * i / nx + shear * height * j / ny, height * j / ny] for j in range(ny + 1) for i in range(nx + 1)])
    node = lambda i, j: j * (nx + 1) + i
    return pts, np.array([[node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)] for j in range(ny) for i in range(nx)])


def parallelepipeds(extent, n, shear):
    """Q1 hexahedra of the box of n^3 cells sheared by x -> x + shear z (gmsh order)."""
    a = [np.linspace(0, e, n + 1) for e in extent]
    pts = np.array([[a[0][i] + shear * a[2][k], a[1][j], a[2][k]] for k in range(n + 1) for j in range(n + 1) for i in range(n + 1)])
    node = lambda i, j, k: (k * (n + 1) + j) * (n + 1) + i
    hexes = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                face = lambda kk: [node(i, j, kk), node(i + 1, j, kk), node(i + 1, j + 1, kk), node(i, j + 1, kk)]
                hexes.append(face(k) + face(k + 1))
    return pts, np.array(hexes)


def box_tets(extent, n):
    """P1 box (0, a) x (0, b) x (0, c) of n^3 cubes, 6 Kuhn tetrahedra each (conforming)."""
    a = [np.linspace(0, e, n + 1) for e in extent]
    pts = np.array([[a[0][i], a[1][j], a[2][k]] for k in range(n + 1) for j in range(n + 1) for i in range(n + 1)])
    node = lambda i, j, k: (k * (n + 1) + j) * (n + 1) + i
    tets = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                for perm in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
                    v = [0, 0, 0]
                    path = [node(i, j, k)]
                    for axis in perm:
                        v[axis] += 1
                        path.append(node(i + v[0], j + v[1], k + v[2]))
                    tets.append(path)
    tets = np.array(tets)
    for t in tets:
        p = pts[t]
        if np.linalg.det((p[1:] - p[0]).T) < 0:
            t[[2, 3]] = t[[3, 2]]
    return pts, tets


def to_p2(pts, cells, curve=None):
    """P2 cells: one node per edge, at the midpoint, then moved by curve(midpoint, a, b) if given
    (e.g. onto a circle); the node order is gmsh's (heldout_fem.EDGES)."""
    n = cells.shape[1] - 1
    pts = [p for p in pts]
    index = {}
    out = []
    for cell in cells:
        extra = []
        for i, j in EDGES[n]:
            key = tuple(sorted((cell[i], cell[j])))
            if key not in index:
                mid = 0.5 * (pts[key[0]] + pts[key[1]])
                index[key] = len(pts)
                pts.append(mid)
            extra.append(index[key])
        out.append(list(cell) + extra)
    pts, out = np.array(pts), np.array(out)
    if curve is not None:
        for (a, b), e in index.items():
            pts[e] = curve(pts[e], pts[a], pts[b])
    return pts, out


def on_circle(radius, centre, boundary_edges):
    """The curve of to_p2 for a disc: boundary edges with both ends on the circle get their
    edge node on the circle (radial projection of the midpoint), the rest stay straight."""
    c = np.array(centre)

    def curve(mid, a, b):
        ra, rb = np.linalg.norm(a - c), np.linalg.norm(b - c)
        key = (tuple(np.round(a, 12)), tuple(np.round(b, 12)))
        if abs(ra - radius) < 1e-12 and abs(rb - radius) < 1e-12 and key in boundary_edges:
            return c + radius * (mid - c) / np.linalg.norm(mid - c)
        return mid
    return curve


def boundary_edge_keys(pts, cells):
    keys = set()
    for _, verts, _, _ in boundary_facets(cells, 2, 1):
        a, b = pts[verts[0]], pts[verts[1]]
        keys.add((tuple(np.round(a, 12)), tuple(np.round(b, 12))))
        keys.add((tuple(np.round(b, 12)), tuple(np.round(a, 12))))
    return keys


def mirrored(cell, n, order):
    """The same cell with its vertices 1 and 2 swapped (negative orientation), its edge nodes
    re-listed in gmsh order for the new vertex order."""
    if order == "q1":
        return [cell[p] for p in ([0, 3, 2, 1] if n == 2 else [4, 5, 6, 7, 0, 1, 2, 3])]
    perm = [0, 2, 1] + ([3] if n == 3 else [])
    out = [cell[p] for p in perm]
    if order == 2:
        edge_node = {frozenset(e): cell[n + 1 + k] for k, e in enumerate(EDGES[n])}
        out += [edge_node[frozenset((perm[i], perm[j]))] for i, j in EDGES[n]]
    return out


def write_msh(path, pts, cells, order, groups):
    """MSH 2.2 ASCII: the cells (physical group "body"; every other one mirrored: the binary
    re-orders such cells), each group's boundary facets, and one unused node at the end.
    `groups`: name -> predicate on a point."""
    d = pts.shape[1]
    cell_type = {(2, 1): 2, (2, 2): 9, (3, 1): 4, (3, 2): 11, (2, "q1"): 3, (3, "q1"): 5}[(d, order)]
    facet_type = {(2, 1): 1, (2, 2): 8, (3, 1): 2, (3, 2): 9, (2, "q1"): 1, (3, "q1"): 3}[(d, order)]
    names = ["body"] + list(groups)
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names)), f'{d} 1 "body"']
    lines += [f'{d - 1} {k + 2} "{g}"' for k, g in enumerate(groups)]
    lines += ["$EndPhysicalNames", "$Nodes", str(len(pts) + 1)]
    lines += [f"{i + 1} {p[0]!r} {p[1]!r} {p[2] if d == 3 else 0.0!r}" for i, p in enumerate(pts)]
    lines.append(f"{len(pts) + 1} 1e3 1e3 {1e3 if d == 3 else 0.0!r}")
    lines.append("$EndNodes")
    elems = [(cell_type, 1, mirrored(c, d, order) if k % 2 else c) for k, c in enumerate(cells)]
    facets = boundary_facets(cells, d, order)
    for k, (name, pred) in enumerate(groups.items()):
        for _, _, nodes, _ in facets:
            if all(pred(pts[v]) for v in nodes):
                elems.append((facet_type, k + 2, nodes))
    lines += ["$Elements", str(len(elems))]
    lines += [f"{i + 1} {t} 2 {g} {g} " + " ".join(str(v + 1) for v in nodes) for i, (t, g, nodes) in enumerate(elems)]
    lines.append("$EndElements")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
