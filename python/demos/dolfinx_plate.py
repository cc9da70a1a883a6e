# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---

# %% [markdown]
# # A dolfinx mesh, a massredist run, a dolfinx `Function` in XDMF
#
# For FEniCSx users (dolfinx 0.5, Debian's `/usr/bin/python3`): a plate meshed by dolfinx
# (40 × 40 quadrilaterals of (0, 1)², as in `scenes/plate-bump-quad-cn.toml`: Crank–Nicolson,
# mass mod3, a bump that hits the obstacle at x = 0) is handed to massredist as arrays
# (`mesh=(points, cells)`), run, and its displacement written every 10 steps as a P1 `Function`
# on the dolfinx mesh to `plate_bump.xdmf` (open it in ParaView). Run from the repository root
# with Debian's Python (it sees dolfinx).

# %%
import logging
import os
import tomllib

os.environ.setdefault("OMPI_MCA_ess_singleton_isolated", "1")  # no orted daemon for mpi4py
import numpy as np
from mpi4py import MPI
import dolfinx
import dolfinx.io
import ufl

import massredist as mr
import massredist.dolfinx as mrd

logging.getLogger().setLevel(logging.WARNING)  # the form compiler's INFO lines

# %% [markdown]
# The dolfinx mesh and its P1 space.

# %%
msh = dolfinx.mesh.create_rectangle(
    MPI.COMM_SELF, [np.array([0.0, 0.0]), np.array([1.0, 1.0])], [40, 40], dolfinx.mesh.CellType.quadrilateral
)
V = dolfinx.fem.FunctionSpace(msh, ("Lagrange", 1))
uh = dolfinx.fem.Function(V, name="u")

# %% [markdown]
# The mesh as arrays (`massredist.dolfinx.mesh_arrays`): dolfinx's geometry nodes, and its cells
# with their nodes in meshio's order (dolfinx numbers a quadrilateral's vertices in
# tensor-product order, meshio and massredist counter-clockwise). The scene is the shipped one
# without its structured-mesh keys (the arrays give the geometry).

# %%
points, cells, kind = mrd.mesh_arrays(msh)
with open("scenes/plate-bump-quad-cn.toml", "rb") as f:
    tables = tomllib.load(f)
for key in ["length", "height", "nx", "ny", "cells"]:
    del tables["plate"][key]
scene = mr.load(tables, mesh=(points, cells, kind))

# %% [markdown]
# The run, writing a frame every 10 steps from the callback.

# %%
out = os.path.join(os.environ.get("MASSREDIST_DEMO_OUT", "."), "plate_bump.xdmf")
with dolfinx.io.XDMFFile(MPI.COMM_SELF, out, "w") as xdmf:
    xdmf.write_mesh(msh)

    def write(state: mr.State) -> None:
        mrd.to_function(state.u, uh)  # massredist's nodes are the mesh's geometry nodes
        xdmf.write_function(uh, state.t)

    run = mr.run(scene, callback=write, every=10)
print(run.status, "final u(0, 0) =", run.summary["final_u0"], "->", out)

# %% [markdown]
# The last frame is the run's final field, now a dolfinx `Function`: its value at (0, 0) is the
# summary's `final_u0`, the run is the shipped scene's run (the same mesh, built by dolfinx), and
# dolfinx integrates the field like any other Function.

# %%
mrd.to_function(run.fields.u, uh)
origin = int(np.argmin(np.linalg.norm(V.tabulate_dof_coordinates(), axis=1)))
assert uh.x.array[origin] == run.summary["final_u0"]
shipped = mr.run("scenes/plate-bump-quad-cn.toml")
# dolfinx numbers the nodes otherwise: the sums and the factorisation run in another order, so
# the two runs agree to round-off (measured: 6e-14 relative), not bit for bit.
for key in ["energy_final", "final_u0", "min_u0"]:
    assert abs(shipped.summary[key] - run.summary[key]) <= 1e-12 * abs(shipped.summary[key]), key
print("∫ u dx =", dolfinx.fem.assemble_scalar(dolfinx.fem.form(uh * ufl.dx)))
