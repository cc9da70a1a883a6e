"""Weighted P1 / Q1 mass and stiffness matrices with scikit-fem (paper section 3), scalar
(``assemble``) and for elastic solids (``assemble_elastic``, see ``fem_common``)."""
import numpy as np
import skfem
from skfem.helpers import dot, grad
from skfem.models.elasticity import linear_elasticity

from fem_common import csr_triplets, interleaved_rows, normalize, permuted_csr

# scikit-fem numbers quadrilateral vertices counter-clockwise, like our input.
_SPACES = {
    "interval": (skfem.MeshLine1, skfem.ElementLineP1),
    "triangle": (skfem.MeshTri1, skfem.ElementTriP1),
    "quadrilateral": (skfem.MeshQuad1, skfem.ElementQuad1),
    "tetrahedron": (skfem.MeshTet1, skfem.ElementTetP1),
    "hexahedron": (skfem.MeshHex1, skfem.ElementHex1),
}

# scikit-fem's hexahedron vertex s sits at the reference corner (0,0,0), (0,0,1), (0,1,0),
# (1,0,0), (0,1,1), (1,0,1), (1,1,0), (1,1,1) (``MeshHex1.doflocs``): it is our (VTK) vertex
# _VTK_OF_SKFEM_HEX[s] (skfem.io.meshio's INV_HEX_MAPPING[:8]). Other cells keep the input order.
# Mutation: [0, 4, 3, 1, 7, 5, 2, 6] -> [0, 4, 3, 1, 7, 5, 6, 2] (two vertices swapped) ->
# `massredist crosscheck` fails elastic_hex_3x2x2_custom (skfem) with |ΔM| 1.69e-2, |ΔS| 5.61e-1.
_VTK_OF_SKFEM_HEX = [0, 4, 3, 1, 7, 5, 2, 6]


@skfem.BilinearForm
def _mass(u, v, w):
    return w.weight * u * v


@skfem.BilinearForm
def _stiffness(u, v, _):
    return dot(grad(u), grad(v))


@skfem.BilinearForm
def _vector_mass(u, v, w):
    return w.weight * dot(u, v)


def _basis(points, cells, weights, element=None):
    """The scikit-fem basis of the normalised input (``element`` wraps the P1/Q1 element, e.g.
    ``skfem.ElementVector``), the weight per (cell, quadrature point) and the vertex count."""
    points, cells, weights, cell_type = normalize(points, cells, weights)
    mesh_type, scalar = _SPACES[cell_type]
    if cell_type == "hexahedron":
        cells = cells[:, _VTK_OF_SKFEM_HEX]
    mesh = mesh_type(np.ascontiguousarray(points.T), np.ascontiguousarray(cells.T))
    basis = skfem.Basis(mesh, element(scalar()) if element else scalar())
    # w is constant on each cell: one value per (cell, quadrature point).
    return basis, np.repeat(weights[:, None], basis.X.shape[-1], axis=1), len(points)


def assemble(points, cells, weights):
    """Mass ``∫ w u v dx`` and stiffness ``∫ ∇u·∇v dx`` as CSR triplets in input vertex order.

    Returns ``{"mass": (indptr, indices, data), "stiffness": (...), "n": n}``. P1 dofs of a
    scikit-fem mesh are its vertices in the given order, so no renumbering is needed. The default
    quadrature (order 2 × element degree) integrates both forms exactly on affine cells.
    """
    basis, w, n = _basis(points, cells, weights)
    return {
        "mass": csr_triplets(_mass.assemble(basis, weight=w)),
        "stiffness": csr_triplets(_stiffness.assemble(basis)),
        "n": n,
    }


def assemble_elastic(points, cells, weights, lam, mu, rho):
    """Vector mass ``∫ ρ w u·v dx`` and elasticity ``∫ σ(u):ε(v) dx`` (``fem_common``) as CSR
    triplets over the rows ``vertex·d + component`` (input vertex order, no boundary condition).

    ``skfem.models.elasticity.linear_elasticity(λ, μ)`` is ``C(ε(u)):ε(v)`` with
    ``C(ε) = 2μ ε + λ tr ε I``; in 2D that is plane strain. The ``ElementVector`` dof of
    component c at vertex a is ``basis.nodal_dofs[c, a]``, mapped explicitly to ``a·d + c``.
    """
    basis, w, n = _basis(points, cells, weights, skfem.ElementVector)
    d = basis.mesh.dim()
    row_of = np.empty(n * d, dtype=np.int64)
    row_of[basis.nodal_dofs.T.reshape(-1)] = interleaved_rows(np.arange(n), d)
    mass = _vector_mass.assemble(basis, weight=rho * w)
    stiffness = linear_elasticity(lam, mu).assemble(basis)
    return {
        "mass": permuted_csr(mass, row_of, n * d),
        "stiffness": permuted_csr(stiffness, row_of, n * d),
        "n": n * d,
    }
