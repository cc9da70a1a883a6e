"""Input normalisation and CSR export shared by the two assembly backends.

Both backends take the same mesh description (see ``normalize``) and return the weighted mass
``M_ij = ∫ w φ_i φ_j dx`` and the stiffness ``S_ij = ∫ ∇φ_i·∇φ_j dx`` (paper section 3) as CSR
triplets over all input vertices, in input vertex order, with no boundary condition applied.

For elastic solids (``assemble_elastic``) the unknowns are interleaved per vertex, as in the Rust
crate (``src/solid/assembly.rs``): component i of vertex a is row ``a·d + i``, and

    M_(a,i),(b,j) = δ_ij ρ ∫ w φ_a φ_b,   S = ∫ σ(u):ε(v),  σ = λ tr ε I + 2μ ε  (plane strain in 2D).
"""
import numpy as np
import scipy.sparse as sp

# (geometric dimension, vertices per cell) -> cell name
CELL_TYPES = {
    (1, 2): "interval",
    (2, 3): "triangle",
    (2, 4): "quadrilateral",
    (3, 4): "tetrahedron",
    (3, 8): "hexahedron",
    (2, 6): "triangle6",
    (3, 10): "tetra10",
}

# Second-order cells: input node order VTK's (meshio's "triangle6", "tetra10"; the Rust crate's
# ``src/fem/cell.rs``): the vertices, then the midside nodes of the edges (0,1), (1,2), (2,0)
# [triangle6] or (0,1), (1,2), (0,2), (0,3), (1,3), (2,3) [tetra10].
P2_BASE = {"triangle6": "triangle", "tetra10": "tetrahedron"}


def grundmann_moller(n, s):
    """``(points (k, n), weights (k,))`` of the Grundmann–Möller rule of degree 2s + 1 on the
    reference n-simplex {x >= 0, sum x <= 1} (SIAM J. Numer. Anal. 15 (1978), Theorem 4):
    sum_i (-1)^i 2^(-2s) (d+n-2i)^d / (i! (d+n-i)!) sum_{|b| = s-i} f((2b + 1)/(d + n - 2i)),
    b in N^(n+1), the point's coordinates the last n barycentric ones. Written here from the
    paper, independently of the Rust rule (``src/fem/quadrature.rs``) it is compared with."""
    from itertools import product
    from math import factorial
    d = 2 * s + 1
    points, weights = [], []
    for i in range(s + 1):
        denom = d + n - 2 * i
        w = (-1) ** i * denom ** d / (factorial(i) * factorial(d + n - i) * 4 ** s)
        for b in product(range(s - i + 1), repeat=n + 1):
            if sum(b) == s - i:
                points.append([(2 * bk + 1) / denom for bk in b[1:]])
                weights.append(w)
    return np.array(points), np.array(weights)


def normalize(points, cells, weights):
    """Return ``(points (n, gdim) float64, cells (k, nv) int64, weights (k,) float64, cell_type)``.

    ``points`` has shape (n,) or (n, 1) for intervals, (n, 2) in 2D and (n, 3) in 3D;
    quadrilaterals are given counter-clockwise (v0, v1, v2, v3), hexahedra in VTK order (the face
    z = 0 counter-clockwise, then the face z = 1 likewise); ``weights`` holds one value per cell.
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


def interleaved_rows(node_of_block, bs):
    """Rust row ``node·bs + component`` of every unblocked library row ``block·bs + component``."""
    node_of_block = np.asarray(node_of_block, dtype=np.int64)
    return (node_of_block[:, None] * bs + np.arange(bs)[None, :]).reshape(-1)


def permuted_csr(matrix, row_of, n):
    """The scipy matrix ``matrix`` (n × n) with row and column k moved to ``row_of[k]``."""
    coo = sp.coo_matrix(matrix)
    return csr_triplets(sp.csr_matrix((coo.data, (row_of[coo.row], row_of[coo.col])), shape=(n, n)))
