"""One engine run: the problem, the scheme, the loop over the steps with the samples the Rust
driver shows its observers (src/driver.rs: energy, u0, u_mean, λ, contact force, L² error,
y-variation, divergence criterion), and rank 0's output. Collective: every rank calls it."""
import json
import math
import time

import numpy as np
from dolfinx import fem, io
from mpi4py import MPI
from petsc4py import PETSc

from . import exact as exact_mod
from . import observe, output, qp, schemes
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
        p, comm = self.p, self.p.comm
        u, lam = s.u, s.lam
        uc = u.getArray()[p.contact]
        gap = uc - s.lb
        force = comm.allreduce(float(lam.sum()))
        # u0: the reference node (plates), the plain mean over the face nodes (solids).
        u0 = p.contact_node_mean(u) if p.scene.solid else p.at_ref(u)
        out = {"n": s.n, "t": s.n * p.scene.dt, "energy": p.energy(u, s.v), "u0": u0,
               "u_mean": p.contact_mean(u), "contact_force": force, "lambda": force / p.contact_measure,
               "min_uc": comm.allreduce(float(uc.min(initial=np.inf)), op=MPI.MIN),
               "max_lambda": comm.allreduce(float(lam.max(initial=-np.inf)), op=MPI.MAX),
               "max_product": comm.allreduce(float(np.abs(gap * lam).max(initial=0.0)), op=MPI.MAX),
               "y_variation": self.y_variation(u), "pivots": s.iterations,
               "l2_error": math.nan, "exact_interp_norm": math.nan}
        if self.with_l2:
            out["l2_error"], out["exact_interp_norm"] = self.l2(u, out["t"])
        return out


def load_energy(p):
    """``E_F = ½ F_rᵀ S_rr⁻¹ F_r`` over the unknowns off Γ_C (src/driver.rs), 0 without load."""
    if p.F.norm(PETSc.NormType.INFINITY) == 0.0:
        return 0.0
    start = p.S.getOwnershipRange()[0]
    held = np.union1d(p.contact, p.dirichlet).astype(np.int32) + start
    s = p.S.copy()
    s.zeroRowsColumns(held, diag=1.0)
    f = p.F.copy()
    f.getArray()[held - start] = 0.0
    return 0.5 * qp.direct_solve(s, f, p.comm).dot(f)


def run(scene, folder, resolved_text, comm=MPI.COMM_WORLD):
    """Steps ``scene`` and writes its files into ``folder`` (an existing, private folder: the
    caller handles the atomic layout). Returns the exit code of a Rust run (0, or 3 if diverged)."""
    started = time.perf_counter()
    p = Problem(scene, comm)
    bar = exact_mod.plane_wave(scene)
    # A solid on simplices has no exact L² error (src/solid/geometry.rs: NaN, not integrated).
    integrates = not (scene.solid and scene.cells in ("triangle", "tet"))
    want_l2 = bar is not None and integrates and (scene.summary_l2 or "l2_error" in scene.series)
    sampler = Sampler(p, bar, want_l2)
    s = schemes.make(p)
    setup = time.perf_counter() - started
    summ = observe.SummaryObserver(scene.steps, p.h, scene.dt, 0.0 - scene.gap, bar,
                                   bar.energy() * scene.face_area if bar else math.nan,
                                   bar.first_contact() if bar else None,
                                   with_l2=scene.summary_l2 and integrates)
    rows, e_load, reference, divergence = [], load_energy(p), None, None
    frames = scene.vtu_every
    xdmf = io.XDMFFile(comm, f"{folder}/fields.xdmf", "w")
    xdmf.write_mesh(p.msh)
    fields = [(fem.Function(p.V, name="displacement"), lambda: s.u),
              (fem.Function(p.V, name="velocity"), lambda: s.v)]
    worst = [np.inf, -np.inf, 0.0, 0.0]

    def write_frame():
        for fn, vec in fields:
            fn.x.array[: p.n_owned] = vec().getArray()
            fn.x.scatter_forward()
            xdmf.write_function(fn, s.n * scene.dt)

    stepping = time.perf_counter()
    for n in range(scene.steps + 1):
        if n > 0:
            try:
                s.step()
            except qp.NonFinite:
                divergence = {"step": n, "time": n * scene.dt, "reason": "non-finite-state"}
                break
            c = [comm.allreduce(v, op=o) for v, o in zip(s.check, (MPI.MIN, MPI.MAX, MPI.MAX, MPI.MAX))]
            worst = [min(worst[0], c[0]), max(worst[1], c[1]), max(worst[2], c[2]), max(worst[3], c[3])]
            finite = np.isfinite(s.u.getArray()).all() and np.isfinite(s.lam).all()
            if not comm.allreduce(bool(finite), op=MPI.LAND):
                divergence = {"step": n, "time": n * scene.dt, "reason": "non-finite-state"}
                break
        smp = sampler.sample(s)
        e = smp["energy"]
        if not math.isfinite(e):
            divergence = {"step": n, "time": n * scene.dt, "reason": "non-finite-energy"}
            break
        if comm.rank == 0:
            summ.observe(smp)
            if scene.series and n % scene.every == 0:
                rows.append(observe.series_row(scene.series, smp, bar))
        if frames and n % frames == 0:
            write_frame()
        if reference is None:
            reference = max(abs(e), e_load)
        elif abs(e) > scene.divergence_factor * reference:
            divergence = {"step": n, "time": n * scene.dt, "reason": "energy-factor", "energy": e,
                          "reference": reference, "factor": scene.divergence_factor}
            break
    if not frames:
        write_frame()
    xdmf.close()
    step_seconds = time.perf_counter() - stepping
    if comm.rank == 0:
        if divergence:
            summ.diverged(divergence)
        timing = {"setup_seconds": setup, "step_seconds": step_seconds, "steps_taken": s.n}
        _write(folder, scene, p, s, summ, rows, worst, timing, resolved_text)
    return 3 if divergence else 0


def _write(folder, scene, p, s, summ, rows, worst, timing, resolved_text):
    """Rank 0's files: summary.json and series.csv as the Rust run, engine.json, the scene."""
    head = {"scheme": scene.scheme, "mass": scene.mass, "elements": scene.nx, "length": scene.length,
            "end": scene.end, "height": scene.height, "nx": scene.nx, "ny": scene.ny,
            "cells": scene.cells,
            "initial": scene.initial if isinstance(scene.initial, str) else "expressions",
            "total_mass": p.total_mass}
    if scene.solid:
        three = scene.dim == 3
        head = {"scheme": scene.scheme, "mass": scene.mass, "elements": scene.nx, "length": scene.length,
                "end": scene.end, "dim": scene.dim, "height": scene.height,
                **({"depth": scene.depth} if three else {}), "nx": scene.nx, "ny": scene.ny,
                **({"nz": scene.nz} if three else {}), "cells": scene.cells, "lateral": scene.lateral,
                "lame_lambda": scene.lame_lambda, "lame_mu": scene.lame_mu, "density": scene.density,
                "gap": scene.gap, "initial": "paper" if scene.initial == "paper" else "fields",
                "total_mass": p.total_mass,
                "unknowns": p.n_free}
    engine = {"ranks": p.comm.size, "unknowns": p.V.dofmap.index_map.size_global,
              "contact_dofs": p.n_contact, "solver": s.qp.describe(), "atol_factor": qp.ATOL_FACTOR,
              "vi_bound_tol": qp.VI_BOUND_TOL, **timing, "min_gap": worst[0], "max_lambda": worst[1],
              "max_complementarity_product": worst[2], "max_inactive_multiplier": worst[3]}
    files = {"summary.json": output.summary_json(head, summ.finish(timing["step_seconds"])),
             "scene.resolved.toml": resolved_text,
             "engine.json": json.dumps(output._json_ready(engine), indent=2) + "\n"}
    if scene.series:
        files["series.csv"] = output.series_csv(["t"] + scene.series, rows)
    output.write_files(folder, files)
