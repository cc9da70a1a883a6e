"""Write fixtures/: matrices from both backends, reference trajectories and a gmsh mesh.

Regenerating is deliberate: run ``/usr/bin/python3 python/scripts/gen_fixtures.py`` from anywhere (it
puts python/crosscheck/ and .pydeps/ on sys.path itself). Every file records its parameters; the tool
versions, the command and the date are in fixtures/provenance.json.

Layout:
  fixtures/matrices/<case>__<backend>.json   {"backend", "dim", "case", "points", "cells",
      "weights", "mass": {"nrows", "indptr", "indices", "data"}, "stiffness": {...}}
  fixtures/trajectories/<case>__<scheme>.json   parameters, "record_every", "U", "lam"
  fixtures/meshes/square_4x3_tri.msh   the 2D triangle case as a gmsh 2.2 file
  fixtures/provenance.json
"""
import datetime
import json
import logging
import os
import platform
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def one_d_cases():
    """(name, L, weights) of the 1D matrix cases: the masses of section 3 and two extra ones."""
    cases = []
    for m in (2, 6, 37):
        masses = {
            "standard": [1.0] * m,
            "mod1": [0.0] + [1.0] * (m - 1),
            "mod2": [0.0] + [m / (m - 1)] * (m - 1),
            "mod3": [0.0, 2.0] + [1.0] * (m - 2),
        }
        cases += [(f"m{m}_{mass}_L1", 1.0, w) for mass, w in masses.items()]
    import numpy as np
    rng = np.random.default_rng(20240601)
    cases.append(("m6_random_L1", 1.0, [0.0] + rng.uniform(0.5, 2.0, 5).tolist()))
    cases.append(("m6_mod3_L2.5", 2.5, [0.0, 2.0, 1.0, 1.0, 1.0, 1.0]))
    return cases


def two_d_cases():
    """(name, points, cells, weights): a 4x3 triangle mesh of (0,1)^2, a 3x3 quad mesh of (0,2)x(0,1)."""
    import numpy as np
    rng = np.random.default_rng(7)
    nx, ny = 4, 3
    X, Y = np.meshgrid(np.linspace(0.0, 1.0, nx + 1), np.linspace(0.0, 1.0, ny + 1))
    tri_points = np.column_stack([X.ravel(), Y.ravel()])
    tri_cells = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            tri_cells += [[a, a + 1, a + nx + 2], [a, a + nx + 2, a + nx + 1]]
    X, Y = np.meshgrid(np.linspace(0.0, 2.0, 4), np.linspace(0.0, 1.0, 4))
    quad_points = np.column_stack([X.ravel(), Y.ravel()])
    quad_cells = [[4 * j + i, 4 * j + i + 1, 4 * (j + 1) + i + 1, 4 * (j + 1) + i]
                  for j in range(3) for i in range(3)]
    return [
        ("square_4x3_tri", tri_points, np.array(tri_cells), rng.uniform(0.5, 2.0, len(tri_cells))),
        ("rect_3x3_quad", quad_points, np.array(quad_cells), rng.uniform(0.5, 2.0, len(quad_cells))),
    ]


# (case, L, m, weights, dt, steps, record_every): section 4/5 benchmark runs with dt = 1/100.
TRAJECTORIES = [
    ("m6_mod3", 1.0, 6, [0.0, 2.0, 1.0, 1.0, 1.0, 1.0], 0.01, 300, 1),
    ("m6_mod1", 1.0, 6, [0.0] + [1.0] * 5, 0.01, 300, 1),
    ("m37_mod2", 1.0, 37, [0.0] + [37 / 36] * 36, 0.01, 300, 10),
]


def matrix_record(backend, dim, case, points, cells, weights, out):
    def csr(triplets):
        indptr, indices, data = triplets
        return {"nrows": out["n"], "indptr": indptr.tolist(), "indices": indices.tolist(),
                "data": data.tolist()}
    return {"backend": backend, "dim": dim, "case": case,
            "points": points.reshape(len(points), -1).tolist(), "cells": cells.tolist(), "weights": list(map(float, weights)),
            "mass": csr(out["mass"]), "stiffness": csr(out["stiffness"])}


def write_json(path, record):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(record, separators=(",", ":")) + "\n")


def main():
    sys.path[:0] = [str(REPO / "python" / "crosscheck"), os.environ.get("MASSREDIST_PYDEPS", str(REPO / ".pydeps"))]
    os.environ["OMPI_MCA_ess_singleton_isolated"] = "1"  # before mpi4py: no orted daemon
    import numpy as np
    import scipy
    import dolfinx
    import skfem
    import meshio
    logging.disable(logging.INFO)  # the JIT's build lines (distutils lowers the root level)
    import crosscheck
    import fem_dolfinx
    import fem_skfem

    out_dir = REPO / "fixtures"
    backends = {"dolfinx": fem_dolfinx, "skfem": fem_skfem}
    for case, L, weights in one_d_cases():
        points, cells = crosscheck.bar_mesh(L, len(weights))
        for name, module in backends.items():
            out = module.assemble(points, cells, weights)
            write_json(out_dir / "matrices" / f"1d_{case}__{name}.json",
                       matrix_record(name, 1, case, points, cells, weights, out))
    for case, points, cells, weights in two_d_cases():
        for name, module in backends.items():
            out = module.assemble(points, cells, weights)
            write_json(out_dir / "matrices" / f"2d_{case}__{name}.json",
                       matrix_record(name, 2, case, points, cells, weights, out))
        if cells.shape[1] == 3:
            (out_dir / "meshes").mkdir(parents=True, exist_ok=True)
            tags = {"gmsh:physical": [np.ones(len(cells), dtype=int)],
                    "gmsh:geometrical": [np.ones(len(cells), dtype=int)]}
            mesh = meshio.Mesh(np.column_stack([points, np.zeros(len(points))]), [("triangle", cells)],
                               cell_data=tags)
            meshio.write(out_dir / "meshes" / f"{case}.msh", mesh, file_format="gmsh22", binary=False)

    for case, L, m, weights, dt, steps, every in TRAJECTORIES:
        for scheme in sorted(crosscheck.SCHEMES):
            U, lam = crosscheck.trajectory_1d("dolfinx", L, m, weights, scheme, dt, steps)
            write_json(out_dir / "trajectories" / f"{case}__{scheme}.json", {
                "backend": "dolfinx", "stepper": "python/crosscheck/stepper.py", "scheme": scheme,
                "case": case, "L": L, "m": m, "weights": weights, "dt": dt, "steps": steps,
                "u0": "(L - x)/2 at x_i = i*h, i = 0..m-1", "v0": 0.0, "F": 0.0,
                "record_every": every,
                "U": U[::every].tolist(), "lam": lam[::every].tolist()})

    write_json(out_dir / "provenance.json", {
        "command": "/usr/bin/python3 python/scripts/gen_fixtures.py",
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "python": platform.python_version(), "executable": sys.executable,
        "dolfinx": dolfinx.__version__, "skfem": skfem.__version__,
        "numpy": np.__version__, "scipy": scipy.__version__,
        "meshio": meshio.__version__,  # Debian's build mislabels itself; its package version:
        "python3-meshio": subprocess.run(["dpkg-query", "-W", "-f=${Version}", "python3-meshio"],
                                         capture_output=True, text=True).stdout or "unknown",
    })


if __name__ == "__main__":
    main()
