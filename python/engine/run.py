"""One engine run: the problem, the scheme, and the loop over the steps, each state's diagnostics
(its own: energy, u0, u_mean, contact force and pressure, L² error, y-variation, contact extremes,
solver iterations; reduced over the ranks) streamed to massredist, whose observers and divergence
rule decide the rest (python/engine/stream.py, src/engine/stream.rs). The engine's own files:
engine.json and the fields (XDMF). Collective: every rank calls it."""
import json
import math
import time

import numpy as np
from dolfinx import fem, io
from mpi4py import MPI
from petsc4py import PETSc

from . import exact as exact_mod
from . import qp, schemes
from .problem import Problem, _quad


class Sampler:
    """The per-state quantities of src/driver.rs, reduced over the ranks."""

    def __init__(self, p, bar, with_l2):
        self.p, self.bar, self.with_l2 = p, bar, with_l2
        comm, bs = p.comm, p.bs
        # The base line: the nodes at the lowest y (and z), matched to every node by its x.
        lo = [comm.allreduce(float(p.x[:, a].min(initial=np.inf)), op=MPI.MIN) for a in (1, 2)]
        bottom = np.flatnonzero((p.x[:, 1] == lo[0]) & (p.x[:, 2] == lo[1]))
        self.bottom_x = np.concatenate(comm.allgather(p.x[bottom, 0]))
        self.bottom_idx = bottom * bs             # u (u_x of a solid) at the base nodes
        order = np.argsort(self.bottom_x)
        self.bottom_x, self.order = self.bottom_x[order], order
        pos = np.clip(np.searchsorted(self.bottom_x, p.x[:, 0]), 0, len(self.bottom_x) - 1)
        self.has_base = self.bottom_x[pos] == p.x[:, 0]
        self.base_pos = pos
        self.fn = fem.Function(p.V)
        msh = p.msh
        tdim = msh.topology.dim
        nloc = msh.topology.index_map(tdim).size_local
        geo = msh.geometry.dofmap.array.reshape(-1, len(msh.geometry.dofmap.links(0)))[:nloc]
        self.cell_points = msh.geometry.x[geo]
        self.cell_dofs = p.V.dofmap.list.array.reshape(-1, p.V.dofmap.dof_layout.num_dofs)[:nloc]

    def y_variation(self, u):
        """``max |u_x(x, y, z) − u_x(x, y_0, z_0)|`` and, for a solid, the largest transverse
        component (src/solid/geometry.rs; the plate's is the first term)."""
        ua, bs = u.getArray(), self.p.bs
        ub = np.concatenate(self.p.comm.allgather(ua[self.bottom_idx]))[self.order]
        ux = ua[::bs] if bs > 1 else ua
        local = np.abs(ux - ub[self.base_pos])[self.has_base].max(initial=0.0)
        if bs > 1:
            local = max(local, np.abs(ua.reshape(-1, bs)[:, 1:]).max(initial=0.0))
        return self.p.comm.allreduce(float(local), op=MPI.MAX)

    def l2(self, u, t):
        """(‖u_h − u(t)‖, ‖I_h u(t)‖) in L²(Ω) (exact; see engine.exact). A solid: the x-error
        of the plane wave plus the transverse components' ``‖u_t‖²`` (unit mass)."""
        p = self.p
        self.fn.x.array[: p.n_owned] = u.getArray()
        self.fn.x.scatter_forward()
        bs = p.bs
        vals = self.fn.x.array.reshape(-1, bs)[self.cell_dofs, 0]
        if p.scene.solid and p.scene.dim == 3:
            e2 = exact_mod.l2_error_squared_box(self.cell_points, vals, self.bar, t)
        else:
            kind = "quad" if p.scene.cells == "quad" else "triangle"
            e2 = exact_mod.l2_error_squared(self.cell_points[..., :2], vals, kind, self.bar, t)
        e2 = p.comm.allreduce(e2)
        if bs > 1:
            tr = u.copy()
            tr.getArray()[::bs] = 0.0
            e2 += max(_quad(p.M1, tr), 0.0)
        if bs > 1:
            ih = p.interpolate(lambda i, x, y, z: self.bar.u(x, t) if i == 0 else 0.0 * x)
        else:
            ih = p.interpolate(lambda x, y: self.bar.u(x, t))
        return math.sqrt(e2), math.sqrt(max(_quad(p.M1, ih), 0.0))

    def sample(self, s):
        """The fields of a ``sample`` record (src/engine/stream.rs) of the state of scheme ``s``."""
        p, comm = self.p, self.p.comm
        u, lam = s.u, s.lam
        uc = u.getArray()[p.contact]
        gap = uc - s.lb
        force = comm.allreduce(float(lam.sum()))
        # u0: the reference node (plates), the plain mean over the face nodes (solids).
        u0 = p.contact_node_mean(u) if p.scene.solid else p.at_ref(u)
        t = s.n * p.scene.dt
        out = {"n": int(s.n), "t": t, "energy": p.energy(u, s.v), "u0": u0,
               "u_mean": p.contact_mean(u), "contact_force": force, "pressure": force / p.contact_measure,
               "y_variation": self.y_variation(u), "l2_error": math.nan, "exact_interp_norm": math.nan,
               "iterations": int(s.iterations),
               "min_u": comm.allreduce(float(uc.min(initial=np.inf)), op=MPI.MIN),
               "max_lambda": comm.allreduce(float(lam.max(initial=-np.inf)), op=MPI.MAX),
               "max_product": comm.allreduce(float(np.abs(gap * lam).max(initial=0.0)), op=MPI.MAX),
               # node by node, as src/driver.rs ContactStats: some node carries force (λ_c < 0)
               "touching": comm.allreduce(bool((lam < 0.0).any()), op=MPI.LOR)}
        if self.with_l2:
            out["l2_error"], out["exact_interp_norm"] = self.l2(u, t)
        return out


def load_energy(p):
    """``E_F = ½ F_rᵀ S_rr⁻¹ F_r`` over the unknowns off Γ_C (src/driver.rs), 0 without load."""
    if p.F.norm(PETSc.NormType.INFINITY) == 0.0:
        return 0.0
    if getattr(p, "load_energy", None) is not None:
        # A body: the Rust run's E_F (src/engine/body.rs: for a free body S_rr is singular).
        return p.load_energy
    start = p.S.getOwnershipRange()[0]
    held = np.union1d(p.contact, p.dirichlet).astype(np.int32) + start
    s = p.S.copy()
    s.zeroRowsColumns(held, diag=1.0)
    f = p.F.copy()
    f.getArray()[held - start] = 0.0
    return 0.5 * qp.direct_solve(s, f, p.comm).dot(f)


class Fields:
    """``fields.xdmf``/``.h5``: displacement and velocity, one temporal collection each, at the
    states shown every ``output.vtu_every`` steps (a time series), or the last state shown
    without ``output.vtu``; then merged into one collection for readers that take one
    (:func:`merge_collections`)."""

    def __init__(self, p, folder, scene):
        self.p, self.scene, self.path = p, scene, f"{folder}/fields.xdmf"
        self.every = scene.vtu_every
        self.file = io.XDMFFile(p.comm, self.path, "w")
        self.file.write_mesh(p.msh)
        self.fields = [(fem.Function(p.V, name="displacement"), lambda s: s.u),
                       (fem.Function(p.V, name="velocity"), lambda s: s.v)]
        self.last = None

    def shown(self, s):
        """State ``s`` was shown to massredist's observers (due at the cadence: written)."""
        self.last = s.n
        if self.every and s.n % self.every == 0:
            self.write(s)

    def write(self, s):
        for fn, vec in self.fields:
            fn.x.array[: self.p.n_owned] = vec(s).getArray()
            fn.x.scatter_forward()
            self.file.write_function(fn, s.n * self.scene.dt)

    def close(self, s):
        """Writes the last state shown if no cadence was asked for (``s`` is still it)."""
        if not self.every and self.last is not None and self.last == s.n:
            self.write(s)
        self.file.close()
        self.p.comm.Barrier()
        if self.p.comm.rank == 0:
            with open(self.path) as f:
                text = f.read()
            with open(self.path, "w") as f:
                f.write(merge_collections(text))


def merge_collections(text):
    """dolfinx 0.5 writes one temporal collection per function; ParaView reads that, but meshio's
    ``TimeSeriesReader`` (and other readers) take one collection: this moves the attributes of
    every later collection into the first one's grid of the same time. Pure: XML in, XML out."""
    import xml.etree.ElementTree as ET
    ET.register_namespace("xi", "http://www.w3.org/2001/XInclude")
    root = ET.fromstring(text)
    domain = root.find("Domain")
    cols = [g for g in domain.findall("Grid") if g.get("CollectionType") == "Temporal"]
    if len(cols) < 2:
        return text
    first = cols[0]
    at = {g.find("Time").get("Value"): g for g in first.findall("Grid")}
    for col in cols[1:]:
        for g in col.findall("Grid"):
            target = at[g.find("Time").get("Value")]
            for a in g.findall("Attribute"):
                target.append(a)
        domain.remove(col)
    first.set("Name", "fields")
    return '<?xml version="1.0"?>\n<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>\n' + ET.tostring(root, encoding="unicode") + "\n"


def run(scene, folder, channel, comm=MPI.COMM_WORLD):
    """Steps ``scene``, streaming every state to massredist through ``channel`` and writing
    engine.json and the fields into ``folder`` (massredist's temporary run folder). Returns the
    exit code: 0, or 3 if massredist stopped the run or a state was not finite."""
    started = time.perf_counter()
    if scene.body:
        # A body against a plane: massredist's mesh, weights and contact set (engine.body).
        from .body import BodyProblem, BodySampler
        p = BodyProblem(scene, f"{folder}/body.json", comm)
        sampler = BodySampler(p)
    else:
        p = Problem(scene, comm)
        bar = exact_mod.plane_wave(scene)
        # A solid on simplices has no exact L² error (src/solid/geometry.rs: NaN, not integrated).
        integrates = not (scene.solid and scene.cells in ("triangle", "tet"))
        want_l2 = bar is not None and integrates and (scene.summary_l2 or "l2_error" in scene.series)
        sampler = Sampler(p, bar, want_l2)
    s = schemes.make(p)
    setup = time.perf_counter() - started
    channel.send("head", h=p.h, total_mass=p.total_mass, unknowns=int(p.n_free), load_energy=load_energy(p))
    fields = Fields(p, folder, scene)
    worst = [np.inf, -np.inf, 0.0, 0.0]
    code = 0
    stepping = time.perf_counter()
    for n in range(scene.steps + 1):
        if n > 0:
            try:
                s.step()
                finite = np.isfinite(s.u.getArray()).all() and np.isfinite(s.lam).all()
            except qp.NonFinite:
                finite = False
            if not comm.allreduce(bool(finite), op=MPI.LAND):
                channel.send("non-finite", n=n, t=n * scene.dt)
                fields.last = None   # the state in the vectors is not one shown
                code = 3
                break
            c = [comm.allreduce(v, op=o) for v, o in zip(s.check, (MPI.MIN, MPI.MAX, MPI.MAX, MPI.MAX))]
            worst = [min(worst[0], c[0]), max(worst[1], c[1]), max(worst[2], c[2]), max(worst[3], c[3])]
        reply = channel.state(sampler.sample(s))
        if reply != "hide":
            fields.shown(s)
        if reply != "go":
            code = 3
            break
    fields.close(s)
    step_seconds = time.perf_counter() - stepping
    if comm.rank == 0:
        engine = {"ranks": p.comm.size, "unknowns": p.V.dofmap.index_map.size_global,
                  "contact_dofs": p.n_contact, "solver": s.qp.describe(), "atol_factor": qp.ATOL_FACTOR,
                  "vi_bound_tol": qp.VI_BOUND_TOL, "setup_seconds": setup, "step_seconds": step_seconds,
                  "steps_taken": s.n, "min_gap": worst[0], "max_lambda": worst[1],
                  "max_complementarity_product": worst[2], "max_inactive_multiplier": worst[3]}
        with open(f"{folder}/engine.json", "w") as f:
            f.write(json.dumps({k: _json_number(v) for k, v in engine.items()}, indent=2) + "\n")
    return code


def _json_number(v):
    """JSON has no non-finite numbers: null (as serde_json writes them)."""
    return None if isinstance(v, float) and not math.isfinite(v) else v
