"""Weighted P1 / Q1 mass and stiffness matrices with scikit-fem (paper section 3), scalar
(``assemble``) and for elastic solids (``assemble_elastic``, see ``fem_common``)."""
import numpy as np
import skfem
from skfem.helpers import dot, grad
from skfem.models.elasticity import linear_elasticity

from fem_common import csr_triplets, grundmann_moller, interleaved_rows, normalize, permuted_csr

# scikit-fem numbers quadrilateral vertices counter-clockwise, like our input.
_SPACES = {
    "interval": (skfem.MeshLine1, skfem.ElementLineP1),
    "triangle": (skfem.MeshTri1, skfem.ElementTriP1),
    "quadrilateral": (skfem.MeshQuad1, skfem.ElementQuad1),
    "tetrahedron": (skfem.MeshTet1, skfem.ElementTetP1),
    "hexahedron": (skfem.MeshHex1, skfem.ElementHex1),
    # Quadratic (isoparametric) meshes: scikit-fem takes the VTK node order of meshio's
    # "triangle6"/"tetra10" (its edges (0,1), (1,2), (0,2) [+ (0,3), (1,3), (2,3)]: ours) and
    # renumbers the nodes (vertices first); ``_p2_rows`` maps them back.
    "triangle6": (skfem.MeshTri2, skfem.ElementTriP2),
    "tetra10": (skfem.MeshTet2, skfem.ElementTetP2),
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
    """The scikit-fem basis of the normalised input (``element`` wraps the P1/Q1/P2 element,
    e.g. ``skfem.ElementVector``), the weight per (cell, quadrature point), the input node count
    and the input node of each scikit-fem node (``None`` if the identity)."""
    points, cells, weights, cell_type = normalize(points, cells, weights)
    mesh_type, scalar = _SPACES[cell_type]
    if cell_type == "hexahedron":
        cells = cells[:, _VTK_OF_SKFEM_HEX]
    mesh = mesh_type(np.ascontiguousarray(points.T), np.ascontiguousarray(cells.T))
    quadrature = {}
    node_of = None
    if mesh_type in (skfem.MeshTri2, skfem.MeshTet2):
        # The degree-5 Grundmann–Möller rule, the Rust element's (``fem_dolfinx._dx_p2``).
        x, w = grundmann_moller(mesh.dim(), 2)
        quadrature = {"quadrature": (np.ascontiguousarray(x.T), w)}
        node_of = _p2_nodes(mesh, cells)
    basis = skfem.Basis(mesh, element(scalar()) if element else scalar(), **quadrature)
    # w is constant on each cell: one value per (cell, quadrature point).
    return basis, np.repeat(weights[:, None], basis.X.shape[-1], axis=1), len(points), node_of


def _p2_nodes(mesh, cells):
    """The input node of each scikit-fem P2 node: vertex i is the i-th smallest input vertex
    index (``Mesh.__post_init__`` renumbers them by ``np.unique``); the node of the mesh's edge
    ``t2e[e, c]`` (2D: its facet ``t2f``) is the input edge node ``cells[c, nv + e]`` (the
    local edge orders agree)."""
    nv = mesh.t.shape[0]
    vertices = np.unique(cells[:, :nv])
    edges = mesh.t2f if mesh.dim() == 2 else mesh.t2e
    node_of = np.empty(len(vertices) + edges.max() + 1, dtype=np.int64)
    node_of[:len(vertices)] = vertices
    node_of[len(vertices) + edges.T.ravel()] = cells[:, nv:].ravel()
    return node_of


def assemble(points, cells, weights):
    """Mass ``∫ w u v dx`` and stiffness ``∫ ∇u·∇v dx`` as CSR triplets in input vertex order.

    Returns ``{"mass": (indptr, indices, data), "stiffness": (...), "n": n}``. P1 dofs of a
    scikit-fem mesh are its vertices in the given order, so no renumbering is needed. The default
    quadrature (order 2 × element degree) integrates both forms exactly on affine cells.
    """
    basis, w, n, _ = _basis(points, cells, weights)
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
    basis, w, n, node_of = _basis(points, cells, weights, skfem.ElementVector)
    d = basis.mesh.dim()
    row_of = np.empty(n * d, dtype=np.int64)
    if node_of is None:
        row_of[basis.nodal_dofs.T.reshape(-1)] = interleaved_rows(np.arange(n), d)
    else:
        # P2: vertex dofs (nodal_dofs), then edge dofs (edge_dofs), d components each.
        nverts = basis.nodal_dofs.shape[1]
        row_of[basis.nodal_dofs.T.reshape(-1)] = interleaved_rows(node_of[:nverts], d)
        edge_dofs = basis.facet_dofs if d == 2 else basis.edge_dofs
        row_of[edge_dofs.T.reshape(-1)] = interleaved_rows(node_of[nverts:], d)
    mass = _vector_mass.assemble(basis, weight=rho * w)
    stiffness = linear_elasticity(lam, mu).assemble(basis)
    return {
        "mass": permuted_csr(mass, row_of, n * d),
        "stiffness": permuted_csr(stiffness, row_of, n * d),
        "n": n * d,
    }
