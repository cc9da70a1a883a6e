"""The distributed plate problem: dolfinx mesh, weighted mass, stiffness, load, contact data.

``M = ρ ∫ w_h u·v``, ``S = E ∫ ∇u : ∇v`` (a scalar field: the plate's wave equation; a vector
field would use the elastic stress here, issue 11), ``F_i = ∫ f w_h φ_i`` with f interpolated
at the nodes (``F = M_w I_h f``, src/plate/assembly.rs), the Dirichlet dofs x = L removed
(rows and columns zero, so ``u = 0`` there) when clamped, and the Signorini dofs on
Γ_C = {x = 0} (the normal component for a vector field). Quadrature degree 2: exact for these
forms on triangles and rectangles (fem_dolfinx.py). The mesh is built on rank 0 from the same
arrays as the Rust mesh (layers.structured) and distributed by dolfinx.
"""
import numpy as np
import ufl
from dolfinx import fem, mesh
from dolfinx.fem import petsc as fpetsc
from mpi4py import MPI
from petsc4py import PETSc

from . import layers
from .scene import force_field, initial_fields

# dolfinx orders quadrilateral vertices as a tensor product; ours are counter-clockwise.
_TO_DOLFINX = {"triangle": [0, 1, 2], "quadrilateral": [0, 1, 3, 2]}


def _space(msh, scene):
    if scene.field == "vector":
        return fem.VectorFunctionSpace(msh, ("Lagrange", 1))
    return fem.FunctionSpace(msh, ("Lagrange", 1))


def _stiffness_form(u, v, scene):
    if scene.field == "vector":
        raise NotImplementedError("elastic solids: the stress form comes with issue 11")
    return scene.modulus * ufl.inner(ufl.grad(u), ufl.grad(v))


class Problem:
    """Everything the schemes and observers need, on this rank (owned dofs first)."""

    def __init__(self, scene, comm=MPI.COMM_WORLD):
        self.scene, self.comm = scene, comm
        kind = "quadrilateral" if scene.cells == "quad" else "triangle"
        points, cells = layers.structured(scene.length, scene.height, scene.nx, scene.ny, scene.cells)
        tol = 1e-10 * (scene.length + scene.height)
        weights = layers.perturbed(layers.cell_weights(points, cells, scene.mass, scene.weights, tol))
        self.total_mass = float(np.dot(weights, layers.areas(points, cells)))
        domain = ufl.Mesh(ufl.VectorElement("Lagrange", kind, 1))
        if comm.rank == 0:
            arr_c, arr_x = cells[:, _TO_DOLFINX[kind]], points
        else:
            arr_c, arr_x = np.empty((0, cells.shape[1]), np.int64), np.empty((0, 2))
        self.msh = msh = mesh.create_mesh(comm, arr_c, arr_x, domain)
        self.V = V = _space(msh, scene)
        self.W = fem.FunctionSpace(msh, ("DG", 0))
        self.w = fem.Function(self.W)
        tdim = msh.topology.dim
        ncells = msh.topology.index_map(tdim).size_local + msh.topology.index_map(tdim).num_ghosts
        cell_dof = self.W.dofmap.list.array.reshape(ncells)
        self.w.x.array[cell_dof] = weights[np.asarray(msh.topology.original_cell_index)]
        imap = V.dofmap.index_map
        self.n_owned = imap.size_local * V.dofmap.index_map_bs
        self.h = scene.length / scene.nx
        self.x = _dof_coordinates(msh, V)[: imap.size_local]   # owned dof coordinates
        self._boundary(tol)
        self._assemble(points, cells)

    def _boundary(self, tol):
        scene, V, msh = self.scene, self.V, self.msh
        at_l = lambda x: np.abs(x[0] - scene.length) <= tol
        at_0 = lambda x: np.abs(x[0]) <= tol
        self.bcs = []
        dirichlet = np.empty(0, np.int32)
        if scene.far_end == "clamped":
            dirichlet = fem.locate_dofs_geometrical(V, at_l)
            self.bcs = [fem.dirichletbc(PETSc.ScalarType(0.0), dirichlet, V)]
        owned = lambda d: np.sort(d[d < self.n_owned]).astype(np.int32)
        self.dirichlet = owned(dirichlet)
        self.contact = owned(fem.locate_dofs_geometrical(V, at_0))   # scalar: the dof itself
        facets = mesh.locate_entities_boundary(self.msh, msh.topology.dim - 1, at_0)
        tags = mesh.meshtags(msh, msh.topology.dim - 1, facets, np.full(len(facets), 1, np.int32))
        self.ds_c = ufl.Measure("ds", domain=msh, subdomain_data=tags, subdomain_id=1)
        # The reference contact node: lowest y on Γ_C (src/plate/assembly.rs orders by y).
        y = self.x[self.contact, 1] if len(self.contact) else np.array([np.inf])
        ymin = self.comm.allreduce(float(y.min()), op=MPI.MIN)
        self.ref = self.contact[y == ymin][0] if len(self.contact) and y.min() == ymin else None
        self.n_contact = self.comm.allreduce(len(self.contact))

    def _assemble(self, points, cells):
        scene, V = self.scene, self.V
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        dx = ufl.dx(metadata={"quadrature_degree": 2})
        mass_w = self.w * ufl.inner(u, v) * dx
        mat = lambda form, diag: _assembled(fpetsc.assemble_matrix(fem.form(form), self.bcs, diag))
        self.M = mat(scene.density * mass_w, 0.0)
        self.S = mat(_stiffness_form(u, v, scene) * dx, 0.0)
        self.M1 = mat(ufl.inner(u, v) * dx, 0.0)                      # unweighted (L² norms)
        self.form_k = lambda sigma: fem.form(scene.density * mass_w + sigma * _stiffness_form(u, v, scene) * dx)
        # Load: F = M_w I_h f over all nodes (Dirichlet columns included), then 0 on x = L.
        mw_all = _assembled(fpetsc.assemble_matrix(fem.form(mass_w)))
        fh = self.interpolate(force_field(scene))
        self.F = mw_all.createVecLeft()
        mw_all.mult(fh, self.F)
        self.F.setValues(self.dirichlet + self.F.getOwnershipRange()[0], np.zeros(len(self.dirichlet)))
        self.F.assemble()
        diag = self.M.getDiagonal().getArray()
        self.massless = diag == 0.0
        self.massless[self.dirichlet] = False
        lengths = fpetsc.assemble_vector(fem.form(ufl.TestFunction(V) * self.ds_c))
        lengths.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        self.contact_lengths = lengths.getArray()[: self.n_owned][self.contact].copy()
        self.contact_measure = self.comm.allreduce(float(self.contact_lengths.sum()))
        u0f, v0f = initial_fields(scene)
        self.u0, self.v0 = self.interpolate(u0f), self.interpolate(v0f)
        for vec in (self.u0, self.v0):
            vec.getArray()[self.dirichlet] = 0.0

    def interpolate(self, f):
        """Nodal values of f(x, y) on the owned dofs, as a PETSc vector."""
        vec = self.M.createVecLeft()
        vec.getArray()[:] = f(self.x[:, 0], self.x[:, 1])
        return vec

    def lower(self, values):
        """Bounds for the step QP: ``values`` on the contact dofs, −∞ elsewhere."""
        xl = self.M.createVecLeft()
        xl.set(PETSc.NINFINITY)
        xl.getArray()[self.contact] = values
        return xl

    def energy(self, u, v):
        """``½ VᵀMV + ½ UᵀSU − UᵀF`` (src/system.rs)."""
        return 0.5 * _quad(self.M, v) + 0.5 * _quad(self.S, u) - u.dot(self.F)

    def contact_mean(self, u):
        """``Σ_c ℓ_c u_c / |Γ_C|`` with ``ℓ_c = ∫_{Γ_C} φ_c``."""
        s = float(np.dot(self.contact_lengths, u.getArray()[self.contact]))
        return self.comm.allreduce(s) / self.contact_measure

    def at_ref(self, u):
        """u at the reference contact node (x = 0, lowest y), on every rank."""
        return self.comm.allreduce(float(u.getArray()[self.ref]) if self.ref is not None else 0.0)


def _dof_coordinates(msh, V):
    """The input coordinates of every local P1/Q1 dof, bit for bit (a P1 dof and a geometry
    node share their place in each cell; ``tabulate_dof_coordinates`` maps through the
    reference cell and rounds)."""
    geo = msh.geometry.dofmap.array.reshape(-1, len(msh.geometry.dofmap.links(0)))
    dofs = V.dofmap.list.array.reshape(len(geo), -1)
    x = np.empty((V.dofmap.index_map.size_local + V.dofmap.index_map.num_ghosts, 3))
    x[dofs.ravel()] = msh.geometry.x[geo.ravel()]
    return x


def _assembled(mat):
    mat.assemble()
    return mat


def _quad(mat, x):
    y = mat.createVecLeft()
    mat.mult(x, y)
    return x.dot(y)
