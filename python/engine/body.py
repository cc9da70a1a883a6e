"""A body against a rigid plane ``n · x ≥ n · p`` with ``n = s e_k`` (issue 19 item 6): the mesh,
cell weights, contact nodes with their gaps g_i and areas a_i, clamped nodes, nodal initial
fields and nodal force computed by massredist (src/engine/body.rs, ``body.json``), and the
matrices assembled here by dolfinx:

    M = ρ Σ_c w_c ∫_c u·v,   S = ∫ λ div u div v + 2μ ε(u):ε(v),   F = (∫ u·v) I_h f,

all components of the clamped nodes held (u = 0), the Signorini dof of contact node i its
component k with ``s u_k ≥ −g_i``. A normal −e_k is run in the mesh reflected through x_k = 0
(x_k, u_k, v_k, f_k multiplied by s = −1): the bound is then the lower bound ``u_k ≥ −g_i`` of
SNES VI, and the reports' world components k are multiplied back by s (src/solid/body_system.rs
does the same with its rotation R). Collective: every rank builds it.
"""
import json

import numpy as np
import ufl
from dolfinx import fem, mesh
from dolfinx.fem import petsc as fpetsc
from mpi4py import MPI
from petsc4py import PETSc

from . import layers
from .problem import _TO_DOLFINX, Problem, _assembled, _stiffness_form


# Our P2 node order (vertices, then the edges (0,1), (1,2), (0,2)[, (0,3), (1,3), (2,3)], VTK's)
# to dolfinx's (vertices, then edge k opposite … : its edges sorted by their reference numbering).
_P2_TO_DOLFINX = {"triangle": [0, 1, 2, 4, 5, 3], "tetrahedron": [0, 1, 2, 3, 9, 8, 5, 7, 6, 4]}


class BodyProblem:
    """What the schemes (engine.schemes) and :class:`BodySampler` need, on this rank."""

    def __init__(self, scene, path, comm=MPI.COMM_WORLD):
        with open(path) as f:
            data = json.load(f)
        self.scene, self.comm = scene, comm
        d, k, s = data["dim"], data["axis"], data["sign"]
        self.bs, self.axis, self.sign = d, k, s
        points = np.array(data["points"], dtype=float)[:, :d]
        points[:, k] *= s
        self.degree = deg = int(data["degree"])
        order = _TO_DOLFINX[data["cell"]] if deg == 1 else _P2_TO_DOLFINX[data["cell"]]
        nv = len(order)
        cells = np.array(data["cells"], dtype=np.int64).reshape(-1, nv)[:, order]
        domain = ufl.Mesh(ufl.VectorElement("Lagrange", data["cell"], deg))
        if comm.rank == 0:
            arr_c, arr_x = cells, points
        else:
            arr_c, arr_x = np.empty((0, nv), np.int64), np.empty((0, d))
        self.msh = msh = mesh.create_mesh(comm, arr_c, arr_x, domain)
        self.V = V = fem.VectorFunctionSpace(msh, ("Lagrange", deg))
        W = fem.FunctionSpace(msh, ("DG", 0))
        w = fem.Function(W)
        tdim = msh.topology.dim
        ncells = msh.topology.index_map(tdim).size_local + msh.topology.index_map(tdim).num_ghosts
        weights = layers.perturbed(np.array(data["weights"], dtype=float))
        w.x.array[W.dofmap.list.array.reshape(ncells)] = weights[np.asarray(msh.topology.original_cell_index)]
        imap = V.dofmap.index_map
        self.n_owned = imap.size_local * d
        # The input node of every local block (a dof and a geometry node share their place: the field's element is the coordinate element).
        geo = msh.geometry.dofmap.array.reshape(-1, nv)
        dofs = V.dofmap.list.array.reshape(len(geo), -1)
        node = np.empty(imap.size_local + imap.num_ghosts, np.int64)
        node[dofs.ravel()] = np.asarray(msh.geometry.input_global_indices)[geo.ravel()]
        self.node = node
        owned = node[: imap.size_local]
        # Held: every component of the clamped nodes (local blocks, ghosts included).
        clamped = np.zeros(comm.bcast(len(points) if comm.rank == 0 else 0, root=0), bool)
        clamped[np.array(data["clamped"], dtype=np.int64)] = True
        self.load_energy = float(data["load_energy"])
        held_blocks = np.flatnonzero(clamped[node]).astype(np.int32)
        self.bcs = [fem.dirichletbc(np.zeros(d, PETSc.ScalarType), held_blocks, V)] if len(held_blocks) else []
        hb = held_blocks[held_blocks < imap.size_local]
        self.dirichlet = np.sort((hb[:, None] * d + np.arange(d)).ravel()).astype(np.int32)
        # Contact: component k of the owned contact nodes, with −g_i and a_i.
        slot = {int(v): i for i, v in enumerate(data["contact_nodes"])}
        blocks = np.array([b for b, v in enumerate(owned) if int(v) in slot], dtype=np.int64)
        idx = np.array([slot[int(owned[b])] for b in blocks], dtype=np.int64)
        self.contact = (blocks * d + k).astype(np.int32)
        gaps = np.array(data["gaps"], dtype=float)
        self.lb = 0.0 - gaps[idx] if len(idx) else np.empty(0)
        self.contact_lengths = np.array(data["areas"], dtype=float)[idx] if len(idx) else np.empty(0)
        self.contact_measure = float(np.sum(data["areas"]))
        self.n_contact = len(data["contact_nodes"])
        self.n_free = imap.size_global * d - comm.allreduce(len(self.dirichlet))
        self.h = float("nan")   # massredist reads the mesh size of its own mesh (src/engine/body.rs)
        self._assemble(data, w)

    def _assemble(self, data, w):
        scene, V, d = self.scene, self.V, self.bs
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        # Exact for the mass (degree 2p) and stiffness (2p − 2) on straight cells, as the Rust
        # assembly (src/fem/quadrature.rs: degree 5 for P2); curved P2 cells differ by the rules.
        dx = ufl.dx(metadata={"quadrature_degree": 2 * self.degree})
        rho = float(data["density"])
        scene.lame_lambda, scene.lame_mu = float(data["lame_lambda"]), float(data["lame_mu"])
        mass_w = rho * w * ufl.inner(u, v) * dx
        stiff = _stiffness_form(u, v, scene) * dx
        mat = lambda form: _assembled(fpetsc.assemble_matrix(fem.form(form), self.bcs, 0.0))
        self.M, self.S = mat(mass_w), mat(stiff)
        self.form_k = lambda sigma: fem.form(mass_w + sigma * stiff)
        unit = _assembled(fpetsc.assemble_matrix(fem.form(ufl.inner(u, v) * dx)))
        self._template = unit
        self.F = unit.createVecLeft()
        unit.mult(self.nodal(data["force"]), self.F)
        self.F.getArray()[self.dirichlet] = 0.0
        self.total_mass = self.comm.allreduce(float(fem.assemble_scalar(fem.form(rho * w * dx))))
        ones = ufl.as_vector([1.0] * d)
        lump = lambda form: fpetsc.assemble_vector(fem.form(form))
        self.lumped, self.lumped_unit = lump(rho * w * ufl.inner(ones, v) * dx), lump(ufl.inner(ones, v) * dx)
        for vec in (self.lumped, self.lumped_unit):
            vec.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        self.volume = self.comm.allreduce(float(self.lumped_unit.getArray()[::d].sum()))
        self.massless = self.M.getDiagonal().getArray() == 0.0
        self.massless[self.dirichlet] = False
        self.u0, self.v0 = self.nodal(data["u0"]), self.nodal(data["v0"])
        for vec in (self.u0, self.v0):
            vec.getArray()[self.dirichlet] = 0.0

    def nodal(self, values):
        """A PETSc vector of nodal world values (interleaved node · d + component) on the owned
        blocks, component k multiplied by s (module docs)."""
        d = self.bs
        vals = np.array(values, dtype=float).reshape(-1, d)
        vec = self._template.createVecLeft()
        a = vec.getArray().reshape(-1, d)
        a[:] = vals[self.node[: len(a)]]
        a[:, self.axis] *= self.sign
        return vec

    # The step QP's bounds and the discrete energy, as for the box (the same attributes M, S, F,
    # contact): one definition, in problem.py.
    lower = Problem.lower
    energy = Problem.energy


class BodySampler:
    """The per-state quantities of src/driver.rs and a body's reports (src/solid/geometry.rs
    body_stats), reduced over the ranks."""

    def __init__(self, p):
        self.p = p

    def sample(self, s):
        p, comm, d = self.p, self.p.comm, self.p.bs
        u, lam = s.u, s.lam
        uc = u.getArray()[p.contact]
        gap = uc - s.lb
        force = comm.allreduce(float(lam.sum()))
        n_c = p.n_contact
        sum_c = comm.allreduce(float(uc.sum()))
        mean = comm.allreduce(float(np.dot(p.contact_lengths, uc))) / p.contact_measure
        mom = (p.lumped.getArray()[: p.n_owned] * s.v.getArray()).reshape(-1, d).sum(axis=0)
        mu = (p.lumped_unit.getArray()[: p.n_owned] * u.getArray()).reshape(-1, d).sum(axis=0)
        mom = np.array([comm.allreduce(float(x)) for x in mom])
        mu = np.array([comm.allreduce(float(x)) for x in mu]) / p.volume
        mom[p.axis] *= p.sign
        mu[p.axis] *= p.sign
        pad = lambda a: [float(x) for x in a] + [0.0] * (3 - d)
        body = {"contact_force": -force, "active": comm.allreduce(int((lam < 0.0).sum())),
                "min_distance": comm.allreduce(float(gap.min(initial=np.inf)), op=MPI.MIN),
                "momentum": pad(mom), "mean_u": pad(mu)}
        return {"n": int(s.n), "t": s.n * p.scene.dt, "energy": p.energy(u, s.v), "u0": sum_c / n_c,
                "u_mean": mean, "contact_force": force, "pressure": force / p.contact_measure,
                "y_variation": 0.0, "l2_error": float("nan"), "exact_interp_norm": float("nan"),
                "iterations": int(s.iterations),
                "min_u": comm.allreduce(float(uc.min(initial=np.inf)), op=MPI.MIN),
                "max_lambda": comm.allreduce(float(lam.max(initial=-np.inf)), op=MPI.MAX),
                "max_product": comm.allreduce(float(np.abs(gap * lam).max(initial=0.0)), op=MPI.MAX),
                "touching": comm.allreduce(bool((lam < 0.0).any()), op=MPI.LOR), "body": body}
