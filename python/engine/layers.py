"""Structured plate meshes and the cell weights of mass redistribution, as plain numpy arrays.

Pure functions mirroring the Rust crate (src/plate/mesh.rs, src/plate/layers.rs), so that the
engine's mesh and weights are the solver's, cell for cell:

- nodes x-fastest, ``node(i, j) = j (nx + 1) + i``, ``x_i = L i/nx`` (the last one L exactly);
- quadrilateral (i, j) = ``[n00, n10, n11, n01]`` (counter-clockwise); triangles split it along
  the diagonal (x_i, y_j)–(x_{i+1}, y_{j+1}): ``[n00, n10, n11]`` and ``[n00, n11, n01]``;
- layer 0 = cells with a vertex on x = 0, layer 1 = the other cells sharing a vertex with layer 0;
  mod1: weights (0, 1, 1); mod2: (0, w, w) with w = |Ω|/(|Ω| − A_0); mod3: (0, 1 + A_0/A_1, 1);
  standard: 1; custom: the given list.
"""
import os

import numpy as np


def structured(length, height, nx, ny, kind):
    """``(points (N, 2), cells (k, nv))`` of the structured plate mesh, in Rust's order."""
    def coords(n, ext):
        c = ext * np.arange(n + 1) / n
        c[n] = ext
        return c
    xs, ys = coords(nx, length), coords(ny, height)
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


def areas(points, cells):
    """Cell areas (shoelace formula over the counter-clockwise vertex lists)."""
    p = points[cells]
    q = np.roll(p, -1, axis=1)
    return 0.5 * np.abs(np.sum(p[..., 0] * q[..., 1] - q[..., 0] * p[..., 1], axis=1))


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


def cell_weights(points, cells, kind, custom=None, tol=None):
    """One weight per cell for mass.kind ``kind`` (module docs)."""
    if tol is None:
        tol = 1e-10 * (np.ptp(points[:, 0]) + np.ptp(points[:, 1]))
    n = len(cells)
    if kind == "standard":
        return np.ones(n)
    if kind == "custom":
        w = np.asarray(custom, dtype=float)
        if w.shape != (n,):
            raise ValueError(f"mass.weights has {w.size} entries but the mesh has {n} cells")
        return w
    layer = cell_layers(points, cells, tol)
    a = areas(points, cells)
    a0, a1, total = a[layer == 0].sum(), a[layer == 1].sum(), a.sum()
    if not a1 > 0.0:
        raise ValueError(f'mass.kind = "{kind}" needs cells beyond the layer touching x = 0')
    by_layer = {"mod1": (0.0, 1.0, 1.0), "mod2": (0.0, total / (total - a0), total / (total - a0)),
                "mod3": (0.0, 1.0 + a0 / a1, 1.0)}
    if kind not in by_layer:
        raise ValueError(f'mass.kind = "{kind}": allowed standard, mod1, mod2, mod3, custom')
    return np.asarray(by_layer[kind])[layer]


# A deliberate defect for the trajectory cross-check's mutation test: "CELL:FACTOR" multiplies
# the weight of input cell CELL by FACTOR (tests/engine_live.rs sets it and expects a mismatch).
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
