# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---

# %% [markdown]
# # A dolfinx mesh, a massredist run, a dolfinx `Function` in XDMF
#
# For FEniCSx users (dolfinx 0.5, Debian's `/usr/bin/python3`): the plate of
# `scenes/plate-bump-quad-cn.toml` (40 × 40 Q1 cells, Crank–Nicolson, mass mod3, a bump that
# hits the obstacle at x = 0) meshed by dolfinx, run by massredist, and the displacement written
# every 10 steps as a P1 `Function` on the dolfinx mesh to `plate_bump.xdmf` (open it in
# ParaView). The callback of `massredist.run` sees the state every k steps; massredist's nodes
# are matched to dolfinx's dofs by their coordinates (dolfinx renumbers them).
# Run from the repository root with Debian's Python (it sees dolfinx).

# %%
import logging
import os

os.environ.setdefault("OMPI_MCA_ess_singleton_isolated", "1")  # no orted daemon for mpi4py
import numpy as np
from mpi4py import MPI
import dolfinx
import dolfinx.io
import ufl

logging.getLogger().setLevel(logging.WARNING)  # the form compiler's INFO lines

import massredist as mr

scene = mr.load("scenes/plate-bump-quad-cn.toml").replace({"output.series": ["u0", "energy"]})
plate = mr.check(scene)["plate"]
L, H, nx, ny = plate["length"], plate["height"], plate["nx"], plate["ny"]

# %% [markdown]
# The dolfinx mesh of the same plate, and its P1 space.

# %%
msh = dolfinx.mesh.create_rectangle(
    MPI.COMM_SELF, [np.array([0.0, 0.0]), np.array([L, H])], [nx, ny], dolfinx.mesh.CellType.quadrilateral
)
V = dolfinx.fem.FunctionSpace(msh, ("Lagrange", 1))
uh = dolfinx.fem.Function(V, name="u")

# %% [markdown]
# massredist's nodes in dolfinx's dof order: the operators give massredist's mesh; both are the
# same grid, so the coordinates match to round-off (keys rounded to 1e-9 of the plate).

# %%
points = mr.operators(scene).points
key = lambda p: (round(p[0] / L * 1e9), round(p[1] / H * 1e9))
node_of = {key(p): i for i, p in enumerate(points)}
dofs = V.tabulate_dof_coordinates()[:, :2]
order = np.array([node_of[key(p)] for p in dofs])
assert len(order) == len(points) == len(set(order))

# %% [markdown]
# The run, writing a frame every 10 steps from the callback.

# %%
out = os.path.join(os.environ.get("MASSREDIST_DEMO_OUT", "."), "plate_bump.xdmf")
with dolfinx.io.XDMFFile(MPI.COMM_SELF, out, "w") as xdmf:
    xdmf.write_mesh(msh)

    def write(state: mr.State) -> None:
        uh.x.array[:] = state.u[order, 0]
        xdmf.write_function(uh, state.t)

    run = mr.run(scene, callback=write, every=10)
print(run.status, "final u(0, 0) =", run.summary["final_u0"], "->", out)

# %% [markdown]
# The last frame is the run's final field, now a dolfinx `Function`: its value at the dof at
# (0, 0) is the summary's `final_u0`, and dolfinx integrates it like any other Function.

# %%
uh.x.array[:] = run.fields.u[order, 0]
origin = int(np.argmin(np.linalg.norm(dofs, axis=1)))
assert uh.x.array[origin] == run.summary["final_u0"]
print("∫ u dx =", dolfinx.fem.assemble_scalar(dolfinx.fem.form(uh * ufl.dx)))
