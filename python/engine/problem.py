"""The distributed plate or solid problem: dolfinx mesh, weighted mass, stiffness, load, contact
data.

``M = ρ ∫ w_h u·v``; ``S = E ∫ ∇u · ∇v`` for a plate (the scalar wave equation), and for a
solid (a vector field, src/solid/assembly.rs) the elastic ``S = ∫ λ div u div v + 2μ ε(u):ε(v)``
(plane strain in 2D); ``F_i = ∫ f w_h φ_i`` with f interpolated at the nodes
(``F = M_w I_h f``, src/plate/assembly.rs). Held dofs (rows and columns zero, so ``u = 0``
there): x = L when clamped (every component of a solid), and with ``lateral = "roller"`` the
normal component on the lateral faces (u_y on y = 0, H; u_z on z = 0, D). The Signorini dofs are
those on Γ_C = {x = 0} (a solid's x-component). Quadrature degree 2: exact for these forms on
triangles, rectangles, tetrahedra and boxes (Gauss, 2 points per direction on tensor cells).
The mesh is built on rank 0 from the same arrays as the Rust mesh (layers.structured[_3d]) and
distributed by dolfinx.
"""
import numpy as np
import ufl
from dolfinx import fem, mesh
from dolfinx.fem import petsc as fpetsc
from mpi4py import MPI
from petsc4py import PETSc

from . import layers
from .scene import force_field, initial_fields

# dolfinx orders quadrilateral and hexahedron vertices as a tensor product; ours are
# counter-clockwise (VTK order for hexahedra).
_TO_DOLFINX = {"triangle": [0, 1, 2], "quadrilateral": [0, 1, 3, 2], "tetrahedron": [0, 1, 2, 3],
               "hexahedron": [0, 1, 3, 2, 4, 5, 7, 6]}
_UFL_CELL = {"quad": "quadrilateral", "triangle": "triangle", "hex": "hexahedron", "tet": "tetrahedron"}


def _space(msh, scene):
    if scene.field == "vector":
        return fem.VectorFunctionSpace(msh, ("Lagrange", 1))
    return fem.FunctionSpace(msh, ("Lagrange", 1))


def _stiffness_form(u, v, scene):
    if scene.field == "vector":
        eps = lambda w: ufl.sym(ufl.grad(w))
        return (scene.lame_lambda * ufl.div(u) * ufl.div(v)
                + 2.0 * scene.lame_mu * ufl.inner(eps(u), eps(v)))
    return scene.modulus * ufl.inner(ufl.grad(u), ufl.grad(v))


def _mesh_arrays(scene):
    """The Rust mesh as arrays, its tolerance for "on a face" (src/fem/mesh.rs) and cell kind."""
    if scene.solid and scene.dim == 3:
        points, cells = layers.structured_3d(scene.extent, (scene.nx, scene.ny, scene.nz), scene.cells)
    else:
        points, cells = layers.structured(scene.length, scene.height, scene.nx, scene.ny, scene.cells)
    return points, cells, 1e-10 * sum(scene.extent) if scene.solid else 1e-10 * (scene.length + scene.height)


class Problem:
    """Everything the schemes and observers need, on this rank (owned dofs first)."""

    def __init__(self, scene, comm=MPI.COMM_WORLD):
        self.scene, self.comm = scene, comm
        kind = _UFL_CELL[scene.cells]
        points, cells, tol = _mesh_arrays(scene)
        measures = layers.measures(points, cells, scene.cells)
        weights = layers.perturbed(layers.cell_weights(points, cells, scene.mass, scene.weights, tol,
                                                       cell_kind=scene.cells))
        self.total_mass = float(np.dot(weights, measures)) * (scene.density if scene.solid else 1.0)
        self.bs = scene.dim if scene.solid else 1
        domain = ufl.Mesh(ufl.VectorElement("Lagrange", kind, 1))
        if comm.rank == 0:
            arr_c, arr_x = cells[:, _TO_DOLFINX[kind]], points
        else:
            arr_c, arr_x = np.empty((0, cells.shape[1]), np.int64), np.empty((0, points.shape[1]))
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
        self.x = _dof_coordinates(msh, V)[: imap.size_local]   # owned node (block) coordinates
        self._boundary(tol)
        self._assemble(points, cells)

    def _held(self, tol):
        """The dolfinx conditions ``u = 0`` and the owned dofs they hold (module docs)."""
        scene, V, msh, bs = self.scene, self.V, self.msh, self.bs
        if scene.far_end == "free":  # a plate's free end (a solid is clamped on x = L)
            return [], np.empty(0, np.int32)
        at_l = fem.locate_dofs_geometrical(V, lambda x: np.abs(x[0] - scene.length) <= tol)
        held = [(at_l[:, None] * bs + np.arange(bs)).ravel()]
        bcs = [fem.dirichletbc(np.zeros(bs, PETSc.ScalarType) if bs > 1 else PETSc.ScalarType(0.0), at_l, V)]
        if scene.solid and scene.lateral == "roller":
            ext = scene.extent
            for axis in range(1, scene.dim):
                on = lambda x, a=axis: (np.abs(x[a]) <= tol) | (np.abs(x[a] - ext[a]) <= tol)
                blocks = fem.locate_dofs_geometrical(V, on)
                facets = mesh.locate_entities_boundary(msh, msh.topology.dim - 1, on)
                dofs = fem.locate_dofs_topological(V.sub(axis), msh.topology.dim - 1, facets)
                bcs.append(fem.dirichletbc(PETSc.ScalarType(0.0), dofs, V.sub(axis)))
                held.append(blocks * bs + axis)
        return bcs, np.unique(np.concatenate(held))

    def _boundary(self, tol):
        scene, V, msh, bs = self.scene, self.V, self.msh, self.bs
        at_0 = lambda x: np.abs(x[0]) <= tol
        self.bcs, dirichlet = self._held(tol)
        owned = lambda d: np.sort(d[d < self.n_owned]).astype(np.int32)
        self.dirichlet = owned(dirichlet)
        # The Signorini dofs: the dof itself (plates), the x-component of the node (solids).
        self.contact = owned(fem.locate_dofs_geometrical(V, at_0) * bs)
        self.contact_nodes = self.contact // bs
        facets = mesh.locate_entities_boundary(self.msh, msh.topology.dim - 1, at_0)
        tags = mesh.meshtags(msh, msh.topology.dim - 1, facets, np.full(len(facets), 1, np.int32))
        self.ds_c = ufl.Measure("ds", domain=msh, subdomain_data=tags, subdomain_id=1)
        # The reference contact node: lowest y on Γ_C (src/plate/assembly.rs orders by y).
        y = self.x[self.contact_nodes, 1] if len(self.contact) else np.array([np.inf])
        ymin = self.comm.allreduce(float(y.min()), op=MPI.MIN)
        self.ref = self.contact[y == ymin][0] if len(self.contact) and y.min() == ymin else None
        self.n_contact = self.comm.allreduce(len(self.contact))
        # Free unknowns (not held), as the Rust run counts them.
        self.n_free = V.dofmap.index_map.size_global * self.bs - self.comm.allreduce(len(self.dirichlet))

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
        # ℓ_c = ∫_{Γ_C} φ_c (a solid: of the x-component's basis function); Σ ℓ_c = |Γ_C|.
        test = ufl.TestFunction(V)
        lengths = fpetsc.assemble_vector(fem.form((test[0] if scene.solid else test) * self.ds_c))
        lengths.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        self.contact_lengths = lengths.getArray()[: self.n_owned][self.contact].copy()
        self.contact_measure = self.face_area = self.comm.allreduce(float(self.contact_lengths.sum()))
        u0f, v0f = initial_fields(scene)
        self.u0, self.v0 = self.interpolate(u0f), self.interpolate(v0f)
        for vec in (self.u0, self.v0):
            vec.getArray()[self.dirichlet] = 0.0

    def interpolate(self, f):
        """Nodal values of f(x, y) (a solid: of f(i, x, y, z), component i) on the owned dofs,
        as a PETSc vector."""
        vec = self.M.createVecLeft()
        x, y, z = self.x[:, 0], self.x[:, 1], self.x[:, 2]
        if self.scene.solid:
            a = vec.getArray().reshape(-1, self.bs)
            for i in range(self.bs):
                a[:, i] = f(i, x, y, z)
        else:
            vec.getArray()[:] = f(x, y)
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
        """``Σ_c ℓ_c u_c / |Γ_C|`` with ``ℓ_c = ∫_{Γ_C} φ_c`` (u_mean)."""
        s = float(np.dot(self.contact_lengths, u.getArray()[self.contact]))
        return self.comm.allreduce(s) / self.contact_measure

    def contact_node_mean(self, u):
        """The plain mean of the contact values over the face nodes (a solid's u0)."""
        return self.comm.allreduce(float(u.getArray()[self.contact].sum())) / self.n_contact

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
