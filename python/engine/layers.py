"""Structured meshes (plates and solids) and the cell weights of mass redistribution, as plain
numpy arrays.

Pure functions mirroring the Rust crate (src/fem/mesh2d.rs, src/fem/mesh.rs, src/fem/layers.rs),
so that the engine's mesh and weights are the solver's, cell for cell:

- nodes x-fastest, ``node(i, j) = j (nx + 1) + i``, ``x_i = L i/nx`` (the last one L exactly);
- quadrilateral (i, j) = ``[n00, n10, n11, n01]`` (counter-clockwise); triangles split it along
  the diagonal (x_i, y_j)–(x_{i+1}, y_{j+1}): ``[n00, n10, n11]`` and ``[n00, n11, n01]``;
- layer 0 = cells with a vertex on x = 0, layer 1 = the other cells sharing a vertex with layer 0;
  mod1: weights (0, 1, 1); mod2: (0, w, w) with w = |Ω|/(|Ω| − A_0); mod3: (0, 1 + A_0/A_1, 1);
  standard: 1; custom: the given list.
"""
import os

import numpy as np


def _coords(n, ext):
    """``ext i/n`` for i = 0..n, the last one ``ext`` exactly (src/fem/mesh.rs)."""
    c = ext * np.arange(n + 1) / n
    c[n] = ext
    return c


def structured(length, height, nx, ny, kind):
    """``(points (N, 2), cells (k, nv))`` of the structured plate mesh, in Rust's order."""
    xs, ys = _coords(nx, length), _coords(ny, height)
    points = np.column_stack([np.tile(xs, ny + 1), np.repeat(ys, nx + 1)])
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    i, j = i.ravel(), j.ravel()          # j-major, i fastest: Rust's loop order
    n00 = j * (nx + 1) + i
    n10, n11, n01 = n00 + 1, n00 + nx + 2, n00 + nx + 1
    if kind == "quad":
        cells = np.column_stack([n00, n10, n11, n01])
    else:
        cells = np.column_stack([n00, n10, n11, n00, n11, n01]).reshape(-1, 3)
    return points, cells.astype(np.int64)


# The Kuhn split: one tetrahedron per order of the axes (src/fem/mesh.rs).
_KUHN = ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0))


def structured_3d(extent, n, kind):
    """``(points (N, 3), cells (k, nv))`` of the structured box mesh (hex | tet), in Rust's order."""
    (l, h, d), (nx, ny, nz) = extent, n
    xs, ys, zs = _coords(nx, l), _coords(ny, h), _coords(nz, d)
    points = np.column_stack([np.tile(xs, (ny + 1) * (nz + 1)), np.tile(np.repeat(ys, nx + 1), nz + 1),
                              np.repeat(zs, (nx + 1) * (ny + 1))])
    k, j, i = (a.ravel() for a in np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij"))
    node = lambda a, b, c: ((k + c) * (ny + 1) + j + b) * (nx + 1) + i + a
    if kind == "hex":
        corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
        return points, np.column_stack([node(*c) for c in corners]).astype(np.int64)
    tets = []
    for order in _KUHN:
        s, tet = [0, 0, 0], [node(0, 0, 0)]
        for axis in order[:2]:
            s[axis] = 1
            tet.append(node(*s))
        tets.append(np.column_stack(tet + [node(1, 1, 1)]))
    return points, np.stack(tets, axis=1).reshape(-1, 4).astype(np.int64)


def areas(points, cells):
    """Cell areas (shoelace formula over the counter-clockwise vertex lists)."""
    p = points[cells]
    q = np.roll(p, -1, axis=1)
    return 0.5 * np.abs(np.sum(p[..., 0] * q[..., 1] - q[..., 0] * p[..., 1], axis=1))


def measures(points, cells, kind):
    """Cell areas (quad, triangle) or volumes: a hexahedron of the structured box is the product
    of its spans, a tetrahedron |det(p1 − p0, p2 − p0, p3 − p0)|/6."""
    if kind in ("quad", "triangle"):
        return areas(points[:, :2], cells)
    p = points[cells]
    if kind == "hex":
        return np.prod(p.max(axis=1) - p.min(axis=1), axis=1)
    return np.abs(np.linalg.det(p[:, 1:] - p[:, :1])) / 6.0


def cell_layers(points, cells, tol):
    """Layer of every cell: 0 touches x = 0, 1 shares a vertex with layer 0, 2 the rest."""
    on_contact = np.abs(points[:, 0]) <= tol
    layer = np.full(len(cells), 2, dtype=np.int8)
    l0 = on_contact[cells].any(axis=1)
    near = np.zeros(len(points), dtype=bool)
    near[cells[l0].ravel()] = True
    layer[near[cells].any(axis=1)] = 1
    layer[l0] = 0
    return layer


def cell_weights(points, cells, kind, custom=None, tol=None, cell_kind=None):
    """One weight per cell for mass.kind ``kind`` (module docs); ``cell_kind`` names the cells
    (quad | triangle | hex | tet; default: 2D cells)."""
    if tol is None:
        tol = 1e-10 * np.ptp(points, axis=0).sum()
    n = len(cells)
    if kind == "standard":
        return np.ones(n)
    if kind == "custom":
        w = np.asarray(custom, dtype=float)
        if w.shape != (n,):
            raise ValueError(f"mass.weights has {w.size} entries but the mesh has {n} cells")
        return w
    layer = cell_layers(points, cells, tol)
    a = areas(points, cells) if cell_kind is None else measures(points, cells, cell_kind)
    a0, a1, total = a[layer == 0].sum(), a[layer == 1].sum(), a.sum()
    if not a1 > 0.0:
        raise ValueError(f'mass.kind = "{kind}" needs cells beyond the layer touching x = 0')
    by_layer = {"mod1": (0.0, 1.0, 1.0), "mod2": (0.0, total / (total - a0), total / (total - a0)),
                "mod3": (0.0, 1.0 + a0 / a1, 1.0)}
    if kind not in by_layer:
        raise ValueError(f'mass.kind = "{kind}": allowed standard, mod1, mod2, mod3, custom')
    return np.asarray(by_layer[kind])[layer]


# A deliberate defect for the trajectory cross-check's mutation test: "CELL:FACTOR" multiplies
# the weight of input cell CELL by FACTOR (study/tests/engine_live.rs sets it and expects a mismatch).
PERTURB_ENV = "MASSREDIST_ENGINE_PERTURB_WEIGHT"


def perturbed(weights, spec=None):
    """``weights`` with the perturbation of ``$MASSREDIST_ENGINE_PERTURB_WEIGHT`` applied."""
    spec = os.environ.get(PERTURB_ENV, "") if spec is None else spec
    if not spec:
        return weights
    cell, factor = spec.split(":")
    w = weights.copy()
    w[int(cell)] *= float(factor)
    return w
