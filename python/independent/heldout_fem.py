"""Finite elements for the held-out body scenes (issue 19), written from the definitions only:
P1 and P2 (isoparametric) triangles and tetrahedra, Q1 quadrangles and hexahedra (on
parallelograms and parallelepipeds), three quadrature rules, the element mass and
plane-strain / 3D stiffness, boundary facets with their outward normals, contact sets, the
shares of the contact area, and the layer weights (standard, mod1, mod2, mod3).

Nothing of massredist is imported or read; numpy only.

Reference simplex {xi_k >= 0, sum xi_k <= 1}, barycentric lambda_0 = 1 - sum xi, lambda_k = xi_k.
Node order: gmsh's (reference manual, "Node ordering"): vertices first, then the edge nodes of
the edges (0,1), (1,2), (2,0) [triangle6]; (0,1), (1,2), (2,0), (3,0), (3,2), (3,1) [tetra10].

P2 shape functions: vertex i: lambda_i (2 lambda_i - 1); edge (i, j): 4 lambda_i lambda_j.
Isoparametric map x(xi) = sum_a X_a phi_a(xi), J = dx/dxi, grad_x phi = J^-T grad_xi phi.

Quadrature:
- `gauss`: a collapsed (Duffy) tensor Gauss-Legendre rule with 6 points per direction, exact
  for polynomials of degree <= 9 on the simplex: on straight-sided cells it integrates the P2
  mass (degree 4) and stiffness (degree 2) exactly, so it checks the other side's claim of
  exactness with a rule that has nothing in common with it;
- `gm5`: the Grundmann-Moller rule of degree 5 (A. Grundmann, H. M. Moller, SIAM J. Numer.
  Anal. 15 (1978), Theorem 4), computed here from its closed formula. On curved P2 cells the
  integrands are not polynomials (det J and J^-1 vary), the integrals depend on the rule, and
  the issue/README fix the rule as degree-5 Grundmann-Moller: the held-out curved scenes use it;
- `tensor`: Gauss-Legendre with 4 points per direction on [0, 1]^n for Q1 cells, exact on
  parallelograms and parallelepipeds (the only Q1 cells the held-out scenes have).
"""
import math
import itertools

import numpy as np

EDGES = {2: [(0, 1), (1, 2), (2, 0)], 3: [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)]}


def compositions(total, parts):
    """All beta in N^parts with |beta| = total."""
    if parts == 1:
        return [(total,)]
    return [(first,) + rest for first in range(total, -1, -1) for rest in compositions(total - first, parts - 1)]


def grundmann_moller(n, s=2):
    """Points xi (m x n) and weights of the degree 2s+1 Grundmann-Moller rule (module docs):
    sum_i (-1)^i 2^-2s (d+n-2i)^d / (i! (d+n-i)!) sum_{|beta|=s-i} f((2 beta + 1)/(d+n-2i))."""
    d = 2 * s + 1
    pts, wts = [], []
    for i in range(s + 1):
        denom = d + n - 2 * i
        w = (-1) ** i * 2.0 ** (-2 * s) * denom ** d / (math.factorial(i) * math.factorial(d + n - i))
        for beta in compositions(s - i, n + 1):
            lam = [(2 * b + 1) / denom for b in beta]
            pts.append(lam[1:])
            wts.append(w)
    return np.array(pts), np.array(wts)


def collapsed_gauss(n, m=6):
    """Duffy-collapsed Gauss-Legendre on the reference simplex (module docs)."""
    x, w = np.polynomial.legendre.leggauss(m)
    x, w = (x + 1) / 2, w / 2
    pts, wts = [], []
    for idx in itertools.product(range(m), repeat=n):
        u = [x[k] for k in idx]
        wu = np.prod([w[k] for k in idx])
        if n == 2:
            pts.append((u[0], (1 - u[0]) * u[1]))
            wts.append(wu * (1 - u[0]))
        else:
            pts.append((u[0], (1 - u[0]) * u[1], (1 - u[0]) * (1 - u[1]) * u[2]))
            wts.append(wu * (1 - u[0]) ** 2 * (1 - u[1]))
    return np.array(pts), np.array(wts)


def check_rules():
    """Both rules integrate every monomial of degree <= 5 exactly (the Dirichlet integral
    a! b! c! / (a + b + c + n)!) and sum to 1/n!: a self-check run before every comparison."""
    for n in (2, 3):
        for rule in (grundmann_moller(n), collapsed_gauss(n)):
            p, w = rule
            for e in itertools.product(range(6), repeat=n):
                if sum(e) > 5:
                    continue
                exact = np.prod([math.factorial(k) for k in e]) / math.factorial(sum(e) + n)
                got = w @ np.prod(p ** np.array(e), axis=1)
                assert abs(got - exact) < 1e-15, (n, e, got, exact)


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


def tensor_gauss(n, m=4):
    """Gauss-Legendre, m points per direction on [0, 1]^n: exact on parallelogram and
    parallelepiped Q1 cells for the mass (degree 2 per variable) and the stiffness."""
    x, w = np.polynomial.legendre.leggauss(m)
    x, w = (x + 1) / 2, w / 2
    grid = np.array(np.meshgrid(*[x] * n, indexing="ij")).reshape(n, -1).T
    wts = np.prod(np.array(np.meshgrid(*[w] * n, indexing="ij")).reshape(n, -1), axis=0)
    return grid, wts


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


def layer_weights(cells, contact, volumes, kind):
    """Layer 0: cells holding a contact node; layer 1: other cells sharing a node with layer 0;
    weights standard 1 | mod1 (0, 1, 1) | mod2 (0, W, W), W = |Omega|/(|Omega| - A0) |
    mod3 (0, 1 + A0/A1, 1)."""
    layer = np.full(len(cells), 2)
    layer[[contact[c].any() for c in cells]] = 0
    near = np.zeros(len(contact), bool)
    for c in cells[layer == 0]:
        near[c] = True
    for k, c in enumerate(cells):
        if layer[k] != 0 and near[c].any():
            layer[k] = 1
    a0, a1, tot = volumes[layer == 0].sum(), volumes[layer == 1].sum(), volumes.sum()
    table = {"standard": [1, 1, 1], "mod1": [0, 1, 1], "mod2": [0, tot / (tot - a0), tot / (tot - a0)],
             "mod3": [0, 1 + a0 / a1, 1]}[kind]
    return np.array(table, float)[layer], layer
