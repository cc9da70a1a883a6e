"""The 1D benchmark of section 4 assembled by a FEM backend and run by the independent steppers;
elastic matrices of a mesh file read through meshio."""
import importlib

import numpy as np
import scipy.sparse as sp

import mesh_io
import stepper

SCHEMES = {"crank-nicolson", "hybrid"}
BACKENDS = {"dolfinx", "skfem"}


def bar_mesh(L, m):
    """Vertices x_i = i h (i = 0..m, h = L/m) and elements [x_j, x_{j+1}] of the bar (0, L)."""
    h = L / m
    points = np.arange(m + 1) * h
    cells = np.column_stack([np.arange(m), np.arange(1, m + 1)]).astype(np.int64)
    return points, cells


def _backend(backend):
    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; allowed: {sorted(BACKENDS)}")
    return importlib.import_module("fem_" + backend)


def assemble_elastic_file(backend, path, weights, lam, mu, rho):
    """``backend``'s ``assemble_elastic`` on the mesh file ``path`` as ``mesh_io.read_cells``
    reads it (the file's vertex and cell order; ``weights`` one per cell)."""
    points, cells, _ = mesh_io.read_cells(path)
    return _backend(backend).assemble_elastic(points, cells, weights, lam, mu, rho)


def free_matrices(backend, L, m, weights):
    """M and S of the bar from ``backend`` on the m free dofs (Dirichlet vertex m dropped)."""
    points, cells = bar_mesh(L, m)
    out = _backend(backend).assemble(points, cells, weights)
    n = out["n"]
    M, S = (sp.csr_matrix((data, indices, indptr), shape=(n, n))[:m, :m]
            for indptr, indices, data in (out["mass"], out["stiffness"]))
    return M, S


def trajectory_1d(backend, L, m, weights, scheme, dt, steps):
    """``(U (steps+1, m), λ (steps+1,))`` of the section 4 benchmark.

    Initial data u0(x) = (L - x)/2, v0 = 0 interpolated at the free nodes, F = 0.
    """
    if scheme not in SCHEMES:
        raise ValueError(f"unknown scheme {scheme!r}; allowed: {sorted(SCHEMES)}")
    if len(weights) != m:
        raise ValueError(f"{len(weights)} weights for m = {m} elements")
    M, S = free_matrices(backend, L, m, weights)
    x = bar_mesh(L, m)[0][:m]
    u0, v0, F = (L - x) / 2, np.zeros(m), np.zeros(m)
    if scheme == "crank-nicolson":
        return stepper.crank_nicolson(M, S, F, u0, v0, dt, steps)
    return stepper.hybrid(M, S, F, u0, v0, dt, steps, L / m)
