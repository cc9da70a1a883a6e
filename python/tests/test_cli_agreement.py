"""The Python run of a scene against the CLI run of the same scene: identical summary.json (but
wall_seconds, the clock), identical series.csv values (the CSV holds shortest round-trip floats,
so parsing it gives the very doubles), the same status and divergence."""

import json
import subprocess

import numpy as np
import pytest

import massredist as mr
from conftest import SCENES


def cli_run(cli, scene_path, out):
    done = subprocess.run([str(cli), "run", str(scene_path), "--out", str(out)], capture_output=True, text=True)
    summary = json.loads((out / "summary.json").read_text())
    # The CLI's exit code is 0 for a run that went to its end, 3 for a diverged one.
    assert done.returncode == {"ok": 0, "diverged": 3}[summary["status"]], done.stderr
    summary = json.loads((out / "summary.json").read_text())
    series_file = out / "series.csv"
    series = None
    if series_file.exists():
        names = series_file.read_text().splitlines()[0].split(",")
        values = np.loadtxt(series_file, delimiter=",", skiprows=1, ndmin=2)
        series = {n: values[:, k] for k, n in enumerate(names)}
    return summary, series


def assert_same_run(run, summary, series):
    py = dict(run.summary)
    py.pop("wall_seconds")
    summary.pop("wall_seconds")
    assert py == summary
    assert run.status == summary["status"]
    if series is not None:
        assert set(series) == set(run.series)
        for name, values in series.items():
            np.testing.assert_array_equal(run.series[name], values, err_msg=name)


@pytest.mark.parametrize(
    "name",
    ["fig11-standard", "fig11-mod1", "fig11-mod2", "fig11-mod3", "rebound-free-bar", "solid-2d-roller-triangle"],
)
def test_shipped_scene_summary_identical_to_cli(cli, tmp_path, name):
    path = SCENES / f"{name}.toml"
    summary, series = cli_run(cli, path, tmp_path / "out")
    scene = mr.load(path)
    frames = tmp_path / "py-frames" if scene["output"].get("vtu") else None
    assert_same_run(mr.run(scene, vtu_dir=frames), summary, series)
    if frames is not None:
        # The frames Python writes are the CLI's, byte for byte (issue 32: they were dropped).
        written = sorted(p.relative_to(frames) for p in frames.rglob("*") if p.is_file())
        assert len(written) > 2, written
        for rel in written:
            assert (frames / rel).read_bytes() == (tmp_path / "out" / rel).read_bytes(), rel


def test_vtu_output_is_written_where_asked_or_refused_by_name(tmp_path):
    roller = mr.load(SCENES / "solid-2d-roller-triangle.toml").replace({"time.end": 0.1})
    with pytest.raises(mr.SceneError) as info:
        mr.run(roller)
    assert info.value.key == "output.vtu" and "vtu_dir" in str(info.value)
    with pytest.raises(mr.SceneError) as info:
        mr.run(mr.load(SCENES / "fig11-mod3.toml"), vtu_dir=tmp_path / "none")
    assert info.value.key == "output.vtu"
    assert not (tmp_path / "none").exists()
    mr.run(roller, vtu_dir=tmp_path / "once")
    before = sorted((tmp_path / "once").rglob("*"))
    with pytest.raises(FileExistsError):
        mr.run(roller, vtu_dir=tmp_path / "once")
    assert sorted((tmp_path / "once").rglob("*")) == before


def test_changed_dt_matches_cli_on_the_resolved_file(cli, tmp_path):
    # The sweep path: a shipped scene with dt changed, against the CLI run of the resolved
    # scene written to a file.
    scene = mr.load(SCENES / "fig11-mod2.toml").replace({"time.dt": 0.005})
    assert scene.steps == 600
    path = tmp_path / "changed.toml"
    path.write_text(scene.resolved_toml())
    summary, series = cli_run(cli, path, tmp_path / "out")
    assert summary["dt"] == 0.005
    assert_same_run(mr.run(scene), summary, series)


def test_diverged_run_has_the_cli_status(cli, tmp_path):
    # Standard mass with Paoli-Schatzman-free CN at a tiny divergence factor: the energy
    # criterion stops the run; both sides say where.
    text = (SCENES / "fig11-standard.toml").read_text() + "divergence_factor = 1.5\n"
    path = tmp_path / "diverges.toml"
    path.write_text(text)
    summary, series = cli_run(cli, path, tmp_path / "out")
    run = mr.run(mr.load(path))
    assert run.status == "diverged" == summary["status"]
    assert run.summary["divergence"] == summary["divergence"]
    assert_same_run(run, summary, series)


def test_dict_scene_equals_file_scene():
    path = SCENES / "fig11-mod3.toml"
    import tomllib

    tables = tomllib.loads(path.read_text())
    a, b = mr.run(mr.load(tables)), mr.run(mr.load(path))
    for k in a.summary:
        if k != "wall_seconds":
            assert a.summary[k] == b.summary[k], k
