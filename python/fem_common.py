"""Input normalisation and CSR export shared by the two assembly backends.

Both backends take the same mesh description (see ``normalize``) and return the weighted mass
``M_ij = ∫ w φ_i φ_j dx`` and the stiffness ``S_ij = ∫ ∇φ_i·∇φ_j dx`` (paper section 3) as CSR
triplets over all input vertices, in input vertex order, with no boundary condition applied.
"""
import numpy as np
import scipy.sparse as sp

# (geometric dimension, vertices per cell) -> cell name
CELL_TYPES = {(1, 2): "interval", (2, 3): "triangle", (2, 4): "quadrilateral"}


def normalize(points, cells, weights):
    """Return ``(points (n, gdim) float64, cells (k, nv) int64, weights (k,) float64, cell_type)``.

    ``points`` has shape (n,) or (n, 1) for intervals and (n, 2) in 2D; quadrilaterals are given
    counter-clockwise (v0, v1, v2, v3); ``weights`` holds one value per cell, in cell order.
    """
    points = np.asarray(points, dtype=np.float64)
    points = points.reshape(len(points), -1)
    cells = np.asarray(cells, dtype=np.int64)
    weights = np.asarray(weights, dtype=np.float64).reshape(-1)
    key = (points.shape[1], cells.shape[1])
    if key not in CELL_TYPES:
        raise ValueError(f"unsupported mesh: gdim={key[0]} with {key[1]} vertices per cell; "
                         f"allowed (gdim, vertices per cell): {sorted(CELL_TYPES)}")
    if len(weights) != len(cells):
        raise ValueError(f"{len(weights)} weights for {len(cells)} cells (need one per cell)")
    used = np.unique(cells)
    if len(used) != len(points) or used[0] != 0 or used[-1] != len(points) - 1:
        raise ValueError("every input vertex must belong to a cell (CSR covers all vertices)")
    return points, cells, weights, CELL_TYPES[key]


def csr_triplets(matrix):
    """``(indptr int64, indices int64, data float64)`` of a scipy matrix, sorted within rows.

    The assembled sparsity pattern is kept, explicit zeros included.
    """
    csr = sp.csr_matrix(matrix)
    csr.sort_indices()
    return (np.ascontiguousarray(csr.indptr, dtype=np.int64),
            np.ascontiguousarray(csr.indices, dtype=np.int64),
            np.ascontiguousarray(csr.data, dtype=np.float64))
