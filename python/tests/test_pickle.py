"""Scenes and runs as Python values (issue 32, "tried as a new user would"): they pickle (so
multiprocessing and joblib can ship them), compare equal when equal, and a scene's resolved
values can be read back by dotted key. Before these existed, ``pickle.dumps(scene)`` raised
TypeError ("cannot pickle 'massredist._core.Scene' object"), a Run compared with ``==`` raised
ValueError (numpy's ambiguous truth value) and ``scene["time.dt"]`` raised TypeError."""

import dataclasses
import multiprocessing
import pickle
import tomllib

import numpy as np
import pytest

import massredist as mr
from conftest import SCENES

FIG11 = SCENES / "fig11-mod3.toml"


def _flatten(table, prefix=""):
    for k, v in table.items():
        key = f"{prefix}{k}"
        yield key, v
        if isinstance(v, dict):
            yield from _flatten(v, key + ".")


def _energy(scene):
    """A worker's job: the final energy of a run (module level, so a pool can call it)."""
    return mr.run(scene).summary["energy_final"]


def test_every_resolved_key_reads_back_as_check_prints_it():
    scene = mr.load(FIG11).replace({"time.end": 0.5})
    resolved = mr.check(scene)
    keys = list(_flatten(resolved))
    assert len(keys) > 20, keys
    for key, value in keys:
        assert scene[key] == value, key
    assert scene["time.dt"] == scene.dt
    # Defaults the source does not spell out read as they apply (the loop above read them).
    given = {k for k, _ in _flatten(tomllib.loads(scene.source_toml()))}
    assert [k for k, _ in keys if k not in given], "no default among the resolved keys"
    with pytest.raises(KeyError, match="time.nope"):
        scene["time.nope"]
    with pytest.raises(KeyError, match="time.dt.x"):
        scene["time.dt.x"]


def test_scenes_pickle_and_compare_equal_when_equal(tmp_path):
    toml_scene = mr.load(FIG11)
    dict_scene = mr.load(tomllib.loads(FIG11.read_text()))
    assert toml_scene == dict_scene and hash(toml_scene) == hash(dict_scene)
    other = toml_scene.replace({"mass.kind": "mod2"})
    assert other != toml_scene
    assert toml_scene != "fig11"
    assert isinstance(toml_scene.base, str)
    # A plate from arrays: the arrays travel with the pickle.
    points = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    cells = np.array([[0, 1, 2], [1, 3, 2]], dtype=np.int64)
    plate = mr.load({"plate": {}, "mass": {"kind": "standard"}, "time": {"dt": 0.01, "end": 0.05}}, mesh=(points, cells, "triangle"))
    for scene in (toml_scene, other, plate):
        copy = pickle.loads(pickle.dumps(scene))
        assert copy == scene and hash(copy) == hash(scene)
        assert copy.resolved_toml() == scene.resolved_toml()
    moved = mr.load({"plate": {}, "mass": {"kind": "standard"}, "time": {"dt": 0.01, "end": 0.05}}, mesh=(points * [1.0, 2.0], cells, "triangle"))
    assert moved != plate


def test_runs_pickle_and_a_pool_gives_the_runs_of_this_process():
    scenes = [mr.load(FIG11).replace({"time.end": 1.0, "mass.kind": k}) for k in ("mod1", "mod3")]
    here = [_energy(s) for s in scenes]
    with multiprocessing.get_context("fork").Pool(2) as pool:
        there = pool.map(_energy, scenes)
    assert there == here  # the same binary, the same scene: the same digits
    run = mr.run(scenes[0])
    copy = pickle.loads(pickle.dumps(run))
    assert copy == run
    assert copy.fields == run.fields and copy.scene == run.scene
    assert mr.run(scenes[1]) != run
    # Arrays are compared entry by entry (not by identity, not skipped).
    shifted = dataclasses.replace(run, series={**run.series, "t": run.series["t"] + 1e-12})
    assert shifted != run
    assert dataclasses.replace(run, series={k: v.copy() for k, v in run.series.items()}) == run
