"""Weighted P1 / Q1 mass and stiffness matrices with scikit-fem (paper section 3)."""
import numpy as np
import skfem
from skfem.helpers import dot, grad

from fem_common import csr_triplets, normalize

# scikit-fem numbers quadrilateral vertices counter-clockwise, like our input.
_SPACES = {
    "interval": (skfem.MeshLine1, skfem.ElementLineP1),
    "triangle": (skfem.MeshTri1, skfem.ElementTriP1),
    "quadrilateral": (skfem.MeshQuad1, skfem.ElementQuad1),
}


@skfem.BilinearForm
def _mass(u, v, w):
    return w.weight * u * v


@skfem.BilinearForm
def _stiffness(u, v, _):
    return dot(grad(u), grad(v))


def assemble(points, cells, weights):
    """Mass ``∫ w u v dx`` and stiffness ``∫ ∇u·∇v dx`` as CSR triplets in input vertex order.

    Returns ``{"mass": (indptr, indices, data), "stiffness": (...), "n": n}``. P1 dofs of a
    scikit-fem mesh are its vertices in the given order, so no renumbering is needed. The default
    quadrature (order 2 × element degree) integrates both forms exactly on affine cells.
    """
    points, cells, weights, cell_type = normalize(points, cells, weights)
    mesh_type, element = _SPACES[cell_type]
    mesh = mesh_type(np.ascontiguousarray(points.T), np.ascontiguousarray(cells.T))
    basis = skfem.Basis(mesh, element())
    # w is constant on each cell: one value per (cell, quadrature point).
    w = np.repeat(weights[:, None], basis.X.shape[-1], axis=1)
    return {
        "mass": csr_triplets(_mass.assemble(basis, weight=w)),
        "stiffness": csr_triplets(_stiffness.assemble(basis)),
        "n": len(points),
    }
