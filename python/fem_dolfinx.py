"""Weighted P1 / Q1 mass and stiffness matrices with FEniCSx (dolfinx 0.5, paper section 3).

Import this module only after ``OMPI_MCA_ess_singleton_isolated=1`` is in the environment, or
Open MPI starts an ``orted`` daemon (the Rust bridge and gen_fixtures.py both set it).
"""
import threading

import numpy as np
import scipy.sparse as sp
import ufl
from dolfinx import fem, mesh
from mpi4py import MPI

from fem_common import csr_triplets, normalize

# dolfinx 0.5's JIT (ffcx + cffi) compiles a new form with gcc into a shared cache folder; two
# threads compiling the same form at once race on its object file ("ld: cannot find
# ./libffcx_forms_<hash>.o", seen with a cold cache when the live tests run in parallel threads,
# which release the GIL while gcc runs; function spaces compile elements the same way). One
# assembly at a time removes the race; with a warm cache it costs nothing noticeable.
_JIT_LOCK = threading.Lock()

# dolfinx orders quadrilateral vertices as a tensor product (0,0), (1,0), (0,1), (1,1); our input
# is counter-clockwise (0,0), (1,0), (1,1), (0,1).
_INPUT_TO_DOLFINX = {"interval": [0, 1], "triangle": [0, 1, 2], "quadrilateral": [0, 1, 3, 2]}


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


def _assemble(points, cells, weights):
    """Mass ``∫ w u v dx`` and stiffness ``∫ ∇u·∇v dx`` as CSR triplets in input vertex order.

    Returns ``{"mass": (indptr, indices, data), "stiffness": (...), "n": n}``. The weight is a
    DG0 function; the quadrature degree is fixed to 2 (exact for both forms on affine cells and
    rectangles; a tensor Gauss rule with 2 points per direction on quadrilaterals).
    """
    points, cells, weights, cell_type = normalize(points, cells, weights)
    domain = ufl.Mesh(ufl.VectorElement("Lagrange", cell_type, 1))
    msh = mesh.create_mesh(MPI.COMM_SELF, cells[:, _INPUT_TO_DOLFINX[cell_type]], points, domain)

    V = fem.FunctionSpace(msh, ("Lagrange", 1))  # Q1 on quadrilaterals
    W = fem.FunctionSpace(msh, ("DG", 0))
    w = fem.Function(W)
    ncells = msh.topology.index_map(msh.topology.dim).size_local
    cell_dof = W.dofmap.list.array.reshape(ncells)
    w.x.array[cell_dof] = weights[np.asarray(msh.topology.original_cell_index)]

    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    dx = ufl.dx(metadata={"quadrature_degree": 2})
    vertex_of_dof = _dof_to_input_vertex(msh, V)
    if len(vertex_of_dof) != len(points):
        raise ValueError(f"dolfinx kept {len(vertex_of_dof)} of {len(points)} vertices")

    out = {"n": len(points)}
    for name, form in (("mass", w * u * v * dx), ("stiffness", ufl.inner(ufl.grad(u), ufl.grad(v)) * dx)):
        matrix = fem.assemble_matrix(fem.form(form))
        matrix.finalize()
        out[name] = csr_triplets(_to_input_order(matrix, vertex_of_dof))
    return out
