"""Bodies from arrays: a [plate] or [solid] scene whose mesh is given as points and cells (as a
dolfinx mesh gives them) runs exactly as the same mesh built by the scene's own generator."""

import tomllib

import numpy as np
import pytest

import massredist as mr
from conftest import SCENES

GEOMETRY_KEYS = ["length", "height", "nx", "ny", "cells"]


def without_geometry(name):
    tables = tomllib.loads((SCENES / f"{name}.toml").read_text())
    table = "plate" if "plate" in tables else "solid"
    for k in GEOMETRY_KEYS:
        tables[table].pop(k, None)
    tables["output"].pop("vtu", None)
    tables["output"].pop("vtu_every", None)
    return tables


def same_run(a, b):
    # The head keys describe the mesh's origin (nx, ny, elements: 0 for a mesh from a file or
    # arrays; h its largest cell diameter), and max_y_variation is measured on a structured grid
    # only (0 otherwise); every other computed quantity must be identical.
    head = {"elements", "nx", "ny", "h", "max_y_variation", "wall_seconds"}
    for k in a.summary:
        if k not in head:
            assert a.summary[k] == b.summary[k], k
    for name in a.series:
        np.testing.assert_array_equal(a.series[name], b.series[name], err_msg=name)


@pytest.mark.parametrize("name", ["plate-bump-quad-cn", "solid-2d-roller-triangle"])
def test_mesh_from_arrays_runs_as_the_generated_mesh(name):
    generated = mr.load(SCENES / f"{name}.toml").replace({"output.vtu": None, "output.vtu_every": None})
    ops = mr.operators(generated)
    arrays = mr.load(without_geometry(name), mesh=(ops.points, ops.cells))
    assert "<arrays>" in arrays.resolved_toml()
    same_run(mr.run(arrays), mr.run(generated))
    # A sweep keeps the arrays.
    assert mr.run(arrays.replace({"time.dt": 0.025})).summary["dt"] == 0.025


def test_mesh_arrays_are_checked_as_a_mesh_file():
    ops = mr.operators(SCENES / "plate-bump-quad-cn.toml")
    tables = without_geometry("plate-bump-quad-cn")
    bad = ops.cells.copy()
    bad[0, 0] = len(ops.points) + 5  # a vertex that names no point
    with pytest.raises(mr.SceneError, match="plate.mesh"):
        mr.load(tables, mesh=(ops.points, bad))
    with pytest.raises(mr.SceneError, match="does not apply"):
        mr.load(SCENES / "plate-bump-quad-cn.toml", mesh=(ops.points, ops.cells))
    with pytest.raises(mr.SceneError, match=r"\[plate\] or \[solid\]"):
        mr.load(SCENES / "fig11-mod3.toml", mesh=(ops.points, ops.cells))
