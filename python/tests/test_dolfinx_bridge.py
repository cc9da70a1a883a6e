"""``massredist.dolfinx`` (issue 32, for dolfinx users): a dolfinx mesh becomes a scene's mesh in
meshio's node order (P1 and P2), and a run's nodal fields become dolfinx Functions. Runs where
dolfinx is importable (Debian's python3; the other venv skips it)."""

import os

import numpy as np
import pytest

os.environ.setdefault("OMPI_MCA_ess_singleton_isolated", "1")  # no orted daemon for mpi4py
dolfinx = pytest.importorskip("dolfinx")
import dolfinx.mesh  # noqa: E402
import ufl  # noqa: E402
from mpi4py import MPI  # noqa: E402

import massredist as mr  # noqa: E402
import massredist.dolfinx as mrd  # noqa: E402
from conftest import SCENES  # noqa: E402


def _close(a, b):
    return abs(a - b) <= 1e-11 * max(abs(a), abs(b), 1e-300)


def test_a_dolfinx_plate_runs_as_the_shipped_scene_and_comes_back_as_a_function():
    msh = dolfinx.mesh.create_rectangle(
        MPI.COMM_SELF, [np.array([0.0, 0.0]), np.array([1.0, 1.0])], [40, 40], dolfinx.mesh.CellType.quadrilateral
    )
    points, cells, kind = mrd.mesh_arrays(msh)
    assert kind == "quad" and points.shape == (41 * 41, 2)
    # The demo's hand-written reordering, which the module replaces.
    assert (cells == msh.geometry.dofmap.array.reshape(-1, 4)[:, [0, 1, 3, 2]]).all()
    shipped = mr.load(SCENES / "plate-bump-quad-cn.toml").replace({"time.end": 0.3})
    scene = shipped.replace({f"plate.{k}": None for k in ("length", "height", "nx", "ny", "cells")})
    run = mr.run(mr.load(scene, mesh=(points, cells, kind)))
    reference = mr.run(shipped)
    # dolfinx numbers the nodes otherwise: the same run to round-off, not bit for bit.
    for key in ("energy_final", "final_u0", "min_u0"):
        assert _close(run.summary[key], reference.summary[key]), key
    uh = mrd.to_function(run.fields.u, dolfinx.fem.Function(dolfinx.fem.FunctionSpace(msh, ("Lagrange", 1))))
    origin = int(np.argmin(np.linalg.norm(uh.function_space.tabulate_dof_coordinates(), axis=1)))
    assert uh.x.array[origin] == run.summary["final_u0"]


@pytest.mark.parametrize(
    "name, cell, kind, dolfinx_of_meshio, dim",
    [
        ("body-getfem-disc-p2-standard", ufl.triangle, "triangle6", [0, 1, 2, 5, 3, 4], 2),
        ("body-sphere-drop", ufl.tetrahedron, "tetra10", [0, 1, 2, 3, 9, 6, 8, 7, 5, 4], 3),
    ],
)
def test_p2_bodies_from_dolfinx_run_as_the_gmsh_files(name, cell, kind, dolfinx_of_meshio, dim):
    """A P2 dolfinx mesh built from a shipped body's own nodes and cells (the permutation written
    out here from Basix's edge numbering, independently of the module's table): back in meshio's
    order it is the same body (a wrong edge order misplaces mid-edge nodes), runs as the gmsh
    file does, and a vector P2 Function receives each node's value at that node's coordinates."""
    scene = mr.load(SCENES / f"{name}.toml").replace({"time.end": 2 * mr.load(SCENES / f"{name}.toml").dt})
    ops = mr.operators(scene)
    points, cells = ops.points[:, :dim], ops.cells
    to_dolfinx = np.argsort(dolfinx_of_meshio)  # meshio node k sits at dolfinx position to_dolfinx⁻¹
    element = ufl.VectorElement("Lagrange", cell, 2)
    msh = dolfinx.mesh.create_mesh(MPI.COMM_SELF, cells[:, to_dolfinx], points, ufl.Mesh(element))
    p, c, got = mrd.mesh_arrays(msh)
    assert got == kind
    # The same cells, node for node, up to dolfinx's renumbering of the nodes and the cells.
    assert np.array_equal(np.sort(p[c].reshape(len(c), -1), axis=0), np.sort(points[cells].reshape(len(c), -1), axis=0))
    run = mr.run(mr.load(scene, mesh=(p, c, kind)))
    reference = mr.run(scene)
    for key in ("energy_final", "total_mass", "max_contact_force"):
        assert _close(run.summary[key], reference.summary[key]), key
    V = dolfinx.fem.VectorFunctionSpace(msh, ("Lagrange", 2))
    uh = mrd.to_function(p, dolfinx.fem.Function(V))
    # dolfinx maps its dof coordinates from the reference cell: a few ulps of the radius 20.
    np.testing.assert_allclose(uh.x.array.reshape(-1, dim), V.tabulate_dof_coordinates()[:, :dim], rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="components"):
        mrd.to_function(p[:, :1], dolfinx.fem.Function(V))
