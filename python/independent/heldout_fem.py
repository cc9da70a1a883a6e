"""Finite elements for the held-out body scenes (issue 19), written from the definitions only:
P1 and P2 (isoparametric) triangles and tetrahedra, Q1 quadrangles and hexahedra (on
parallelograms and parallelepipeds), the element mass and plane-strain / 3D stiffness on one of
the quadrature rules of `shared`, boundary facets with their outward normals, contact sets and
the shares of the contact area (the layer weights: `shared.layer_weights`).

Nothing of massredist is imported or read; numpy only.

Reference simplex {xi_k >= 0, sum xi_k <= 1}, barycentric lambda_0 = 1 - sum xi, lambda_k = xi_k.
Node order: gmsh's (reference manual, "Node ordering"): vertices first, then the edge nodes of
the edges (0,1), (1,2), (2,0) [triangle6]; (0,1), (1,2), (2,0), (3,0), (3,2), (3,1) [tetra10].

P2 shape functions: vertex i: lambda_i (2 lambda_i - 1); edge (i, j): 4 lambda_i lambda_j.
Isoparametric map x(xi) = sum_a X_a phi_a(xi), J = dx/dxi, grad_x phi = J^-T grad_xi phi.

Quadrature: `shared` (`gauss`, `gm5`, `tensor`).
"""
import numpy as np

EDGES = {2: [(0, 1), (1, 2), (2, 0)], 3: [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)]}


def shape(n, order, xi):
    """Values (k,) and reference gradients (k, n) of the P1, P2 or Q1 shape functions at xi."""
    if order == "q1":
        return tensor_shape(n, xi)
    lam = np.concatenate([[1 - xi.sum()], xi])
    dlam = np.vstack([-np.ones(n), np.eye(n)])
    if order == 1:
        return lam, dlam
    phi = [lam[i] * (2 * lam[i] - 1) for i in range(n + 1)]
    grad = [(4 * lam[i] - 1) * dlam[i] for i in range(n + 1)]
    for i, j in EDGES[n]:
        phi.append(4 * lam[i] * lam[j])
        grad.append(4 * (lam[j] * dlam[i] + lam[i] * dlam[j]))
    return np.array(phi), np.array(grad)


QUAD_CORNERS = {2: [(0, 0), (1, 0), (1, 1), (0, 1)],
                3: [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]}
QUAD_FACETS = {2: [[0, 1], [1, 2], [2, 3], [3, 0]],
               3: [[0, 1, 2, 3], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]}


def tensor_shape(n, xi):
    """Q1 on [0, 1]^n, corners in gmsh order (quadrangle counter-clockwise; hexahedron: the face
    zeta = 0 counter-clockwise, then zeta = 1): phi_a = prod_k (c_k xi_k + (1 - c_k)(1 - xi_k))."""
    phi, grad = [], []
    for c in QUAD_CORNERS[n]:
        f = [xi[k] if c[k] else 1 - xi[k] for k in range(n)]
        df = [1.0 if c[k] else -1.0 for k in range(n)]
        phi.append(np.prod(f))
        grad.append([df[k] * np.prod([f[j] for j in range(n) if j != k]) for k in range(n)])
    return np.array(phi), np.array(grad)


def element(X, order, lam, mu, rule):
    """Mass (k x k, rho = 1, unweighted), stiffness (k d x k d, dofs (a, i) -> a d + i) and
    measure of one cell with nodes X (k x d), isoparametric:
    S_(a,i),(b,j) = int lam d_i phi_a d_j phi_b + mu (delta_ij grad phi_a . grad phi_b + d_j phi_a d_i phi_b)."""
    k, d = X.shape
    m = np.zeros((k, k))
    s = np.zeros((k, d, k, d))
    vol = 0.0
    for xi, w in zip(*rule):
        phi, gref = shape(d, order, np.asarray(xi))
        J = X.T @ gref
        det = np.linalg.det(J)
        assert det > 0, "cells are generated positively oriented"
        g = gref @ np.linalg.inv(J)
        wd = w * det
        vol += wd
        m += wd * np.outer(phi, phi)
        gg = g @ g.T
        s += wd * (lam * np.einsum("ai,bj->aibj", g, g)
                   + mu * (np.einsum("ab,ij->aibj", gg, np.eye(d)) + np.einsum("aj,bi->aibj", g, g)))
    return m, s.reshape(k * d, k * d), vol


def facets_of(n, order):
    """Local facets: (vertex indices, all node indices, the cell's vertices whose mean lies
    inside the cell, off the facet) of each facet of the reference cell."""
    if order == "q1":
        return [(f, f, list(range(len(QUAD_CORNERS[n])))) for f in QUAD_FACETS[n]]
    out = []
    for opposite in range(n + 1):
        verts = [v for v in range(n + 1) if v != opposite]
        nodes = list(verts)
        if order == 2:
            nodes += [n + 1 + e for e, (i, j) in enumerate(EDGES[n]) if i in verts and j in verts]
        out.append((verts, nodes, [opposite]))
    return out


def boundary_facets(cells, n, order):
    """(cell index, vertex nodes, all nodes, interior nodes) of each facet of one cell."""
    seen = {}
    for c, cell in enumerate(cells):
        for verts, nodes, opp in facets_of(n, order):
            key = tuple(sorted(cell[verts]))
            seen.setdefault(key, []).append((c, cell[verts], cell[nodes], cell[opp]))
    return [v[0] for v in seen.values() if len(v) == 1]


def facet_normal(pts, verts, inside):
    """Outward unit normal and measure of a straight (planar) facet through its vertices
    (triangle or parallelogram faces; the normal points away from the mean of `inside`)."""
    p = pts[verts]
    if len(verts) == 2:
        t = p[1] - p[0]
        a = np.array([t[1], -t[0]])
    else:
        a = (0.5 if len(verts) == 3 else 1.0) * np.cross(p[1] - p[0], p[-1] - p[0])
    meas = np.linalg.norm(a)
    nrm = a / meas
    if nrm @ (p[0] - pts[inside].mean(axis=0)) < 0:
        nrm = -nrm
    return nrm, meas


def area_shares(n_nodes_facet, dim):
    """int_f phi_a / |f| on a straight facet: P1 1/k each; P2 segment 1/6, 1/6, 2/3 (Simpson);
    P2 triangle: 0 at the vertices, 1/3 at the edge nodes."""
    if dim == 2 and n_nodes_facet == 3:
        return [1 / 6, 1 / 6, 2 / 3]
    if dim == 3 and n_nodes_facet == 6:
        return [0, 0, 0, 1 / 3, 1 / 3, 1 / 3]
    return [1 / n_nodes_facet] * n_nodes_facet
