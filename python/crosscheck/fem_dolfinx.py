"""Weighted P1 / Q1 mass and stiffness matrices with FEniCSx (dolfinx 0.5, paper section 3),
scalar (``assemble``) and for elastic solids (``assemble_elastic``, see ``fem_common``).

Import this module only after ``OMPI_MCA_ess_singleton_isolated=1`` is in the environment, or
Open MPI starts an ``orted`` daemon (the Rust bridge and gen_fixtures.py both set it).
"""
import logging
import threading

import numpy as np
import scipy.sparse as sp
import ufl
import dolfinx.fem.petsc
from dolfinx import fem, mesh
from mpi4py import MPI
from petsc4py import PETSc

from fem_common import P2_BASE, csr_triplets, grundmann_moller, interleaved_rows, normalize, permuted_csr

# dolfinx 0.5's JIT (ffcx + cffi) compiles a new form with gcc into a shared cache folder; two
# threads compiling the same form at once race on its object file ("ld: cannot find
# ./libffcx_forms_<hash>.o", seen with a cold cache when the live tests run in parallel threads,
# which release the GIL while gcc runs; function spaces compile elements the same way). One
# assembly at a time removes the race; with a warm cache it costs nothing noticeable.
_JIT_LOCK = threading.Lock()

# dolfinx orders quadrilateral and hexahedron vertices as a tensor product, x fastest: (0,0),
# (1,0), (0,1), (1,1) [then the same at z = 1]; our input is counter-clockwise (0,0), (1,0),
# (1,1), (0,1) [VTK hexahedra: that face at z = 0, then at z = 1]. Mutation: hexahedron map
# [0, 1, 2, 3, 4, 5, 6, 7] -> `massredist crosscheck` fails elastic_hex_3x2x2_custom (dolfinx)
# with |ΔM| 1.99e-2, |ΔS| 2.61e-1 (dolfinx assembles the twisted cells without complaint).
_INPUT_TO_DOLFINX = {
    "interval": [0, 1],
    "triangle": [0, 1, 2],
    "quadrilateral": [0, 1, 3, 2],
    "tetrahedron": [0, 1, 2, 3],
    "hexahedron": [0, 1, 3, 2, 4, 5, 7, 6],
    # P2: dolfinx lists the edge nodes by the edges opposite the vertices, (1,2), (0,2), (0,1)
    # [tetrahedron: (2,3), (1,3), (1,2), (0,3), (0,2), (0,1)]; ours are VTK's (``fem_common``):
    # dolfinx's node k is our node map[k] (dolfinx's own ``perm_vtk`` for these cells).
    "triangle6": [0, 1, 2, 4, 5, 3],
    "tetra10": [0, 1, 2, 3, 9, 8, 5, 7, 6, 4],
}


def _dof_to_input_vertex(msh, space):
    """Input vertex index of every P1/Q1 dof of ``space``.

    dolfinx renumbers both the geometry nodes and the dofs. A P1 dof and a geometry node sit at
    the same local position of each cell, and ``input_global_indices`` maps geometry nodes back.
    """
    ncells = msh.topology.index_map(msh.topology.dim).size_local
    nodes = msh.geometry.dofmap.array.reshape(ncells, -1)
    dofs = space.dofmap.list.array.reshape(ncells, -1)
    original = np.asarray(msh.geometry.input_global_indices, dtype=np.int64)
    vertex_of_dof = np.empty(space.dofmap.index_map.size_local, dtype=np.int64)
    vertex_of_dof[dofs.ravel()] = original[nodes.ravel()]
    return vertex_of_dof


def _to_input_order(matrix, vertex_of_dof):
    """A dolfinx ``MatrixCSR`` in dof order, as a scipy CSR matrix in input vertex order."""
    n = len(vertex_of_dof)
    coo = sp.csr_matrix((matrix.data, matrix.indices, matrix.indptr), shape=(n, n)).tocoo()
    return sp.csr_matrix((coo.data, (vertex_of_dof[coo.row], vertex_of_dof[coo.col])),
                         shape=(n, n))


def assemble(points, cells, weights):
    """[`_assemble`], one call at a time (see `_JIT_LOCK`)."""
    with _JIT_LOCK:
        return _assemble(points, cells, weights)


def _mesh_and_weight(points, cells, weights):
    """The dolfinx mesh of the normalised input and the DG0 weight function on it (P2 cells: a
    quadratic, isoparametric geometry)."""
    points, cells, weights, cell_type = normalize(points, cells, weights)
    degree = 2 if cell_type in P2_BASE else 1
    domain = ufl.Mesh(ufl.VectorElement("Lagrange", P2_BASE.get(cell_type, cell_type), degree))
    msh = mesh.create_mesh(MPI.COMM_SELF, cells[:, _INPUT_TO_DOLFINX[cell_type]], points, domain)
    W = fem.FunctionSpace(msh, ("DG", 0))
    w = fem.Function(W)
    ncells = msh.topology.index_map(msh.topology.dim).size_local
    cell_dof = W.dofmap.list.array.reshape(ncells)
    w.x.array[cell_dof] = weights[np.asarray(msh.topology.original_cell_index)]
    return msh, w, len(points)


# Quadrature degree 2: exact for both forms on affine cells and boxes (a tensor Gauss rule with
# 2 points per direction on quadrilaterals and hexahedra).
_DX = ufl.dx(metadata={"quadrature_degree": 2})


# UFL's form signature applies str() to the custom rule's arrays and warns each time; the
# signature only keys the JIT cache, and the full-precision arrays go to ffcx (its
# ``QuadratureRule``), so the warning is silenced.
logging.getLogger("UFL").setLevel(logging.ERROR)


def _dx_p2(d):
    """P2: the degree-5 Grundmann–Möller rule (``fem_common.grundmann_moller``), the rule of the
    Rust element, so that curved (isoparametric) cells, where no rule is exact for the
    stiffness, compare to round-off too; on straight-sided cells it is exact for both forms."""
    points, weights = grundmann_moller(d, 2)
    return ufl.dx(metadata={"quadrature_rule": "custom", "quadrature_degree": 5,
                            "quadrature_points": points, "quadrature_weights": weights})


def _assemble(points, cells, weights):
    """Mass ``∫ w u v dx`` and stiffness ``∫ ∇u·∇v dx`` as CSR triplets in input vertex order.

    Returns ``{"mass": (indptr, indices, data), "stiffness": (...), "n": n}``. The weight is a
    DG0 function.
    """
    msh, w, n = _mesh_and_weight(points, cells, weights)
    V = fem.FunctionSpace(msh, ("Lagrange", 1))  # Q1 on quadrilaterals
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    vertex_of_dof = _dof_to_input_vertex(msh, V)
    if len(vertex_of_dof) != n:
        raise ValueError(f"dolfinx kept {len(vertex_of_dof)} of {n} vertices")

    out = {"n": n}
    for name, form in (("mass", w * u * v * _DX), ("stiffness", ufl.inner(ufl.grad(u), ufl.grad(v)) * _DX)):
        matrix = fem.assemble_matrix(fem.form(form))
        matrix.finalize()
        out[name] = csr_triplets(_to_input_order(matrix, vertex_of_dof))
    return out


def assemble_elastic(points, cells, weights, lam, mu, rho):
    """[`_assemble_elastic`], one call at a time (see `_JIT_LOCK`)."""
    with _JIT_LOCK:
        return _assemble_elastic(points, cells, weights, lam, mu, rho)


def _assemble_elastic(points, cells, weights, lam, mu, rho):
    """Vector mass ``∫ ρ w u·v dx`` and elasticity ``∫ σ(u):ε(v) dx`` (``fem_common``) as CSR
    triplets over the rows ``vertex·d + component`` (input vertex order, no boundary condition).

    ``VectorFunctionSpace`` dofs are blocked (one block of d per vertex, renumbered by dolfinx);
    dolfinx 0.5's own ``MatrixCSR`` refuses block sizes, so the PETSc matrix (unblocked rows
    ``block·d + component``) is read instead. λ, μ, ρ are ``Constant``s: one JIT form per cell type.
    """
    msh, w, n = _mesh_and_weight(points, cells, weights)
    d = msh.geometry.dim
    degree = msh.geometry.cmap.degree
    dx = _dx_p2(d) if degree == 2 else _DX
    # P2: the dofs sit at the geometry's nodes, at the same local positions (both P2 Lagrange).
    V = fem.VectorFunctionSpace(msh, ("Lagrange", degree))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    lam_, mu_, rho_ = (fem.Constant(msh, PETSc.ScalarType(c)) for c in (lam, mu, rho))

    def eps(f):
        return ufl.sym(ufl.grad(f))

    def sigma(f):
        # Mutation: drop `lam_ * ufl.tr(eps(f)) * ufl.Identity(d) +` -> `massredist crosscheck`
        # fails all 6 elastic dolfinx cases (|ΔS| from 5.3e-1 to 2.1e0), mass unaffected.
        return lam_ * ufl.tr(eps(f)) * ufl.Identity(d) + 2 * mu_ * eps(f)

    vertex_of_block = _dof_to_input_vertex(msh, V)
    if len(vertex_of_block) != n:
        raise ValueError(f"dolfinx kept {len(vertex_of_block)} of {n} vertices")
    row_of = interleaved_rows(vertex_of_block, d)
    out = {"n": n * d}
    forms = (("mass", rho_ * w * ufl.inner(u, v) * dx), ("stiffness", ufl.inner(sigma(u), eps(v)) * dx))
    for name, form in forms:
        matrix = dolfinx.fem.petsc.assemble_matrix(fem.form(form))
        matrix.assemble()
        indptr, indices, data = matrix.getValuesCSR()
        matrix.destroy()
        out[name] = permuted_csr(sp.csr_matrix((data, indices, indptr), shape=(n * d, n * d)), row_of, n * d)
    return out
