"""The API's pieces: scene errors (the CLI's messages, the key), check, replace, the callback,
the operators against the paper's formulas, the exact solution against its closed form."""

import subprocess
import sys

import numpy as np
import pytest

import massredist as mr
from conftest import SCENES

FIG11 = SCENES / "fig11-mod3.toml"


@pytest.mark.parametrize(
    "changes, key",
    [
        ({"time.dt": -1.0}, "time.dt"),
        ({"time.dt": 0.007}, "time.dt"),  # end/dt = 428.57…: not an integer
        ({"mass.kind": "heavy"}, "mass.kind"),
        ({"bar.elements": 1}, "bar.elements"),
        ({"output.divergence_factor": 0.5}, "output.divergence_factor"),
    ],
)
def test_scene_error_names_the_key(changes, key):
    with pytest.raises(mr.SceneError) as info:
        mr.load(FIG11).replace(changes)
    assert isinstance(info.value, ValueError)
    assert info.value.key == key
    assert key in str(info.value)


def test_scene_error_message_is_the_cli_message(cli, tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(FIG11.read_text().replace("dt = 0.01", "dt = -0.5"))
    out = subprocess.run([str(cli), "check", str(path)], capture_output=True, text=True)
    assert out.returncode == 2
    with pytest.raises(mr.SceneError) as info:
        mr.load(path)
    assert str(info.value) in out.stderr


def test_unknown_key_and_bad_type_are_scene_errors():
    with pytest.raises(mr.SceneError, match="colour"):
        mr.load({"bar": {"colour": "red"}})
    with pytest.raises(mr.SceneError) as info:
        mr.load({"bar": {"elements": object()}})
    assert info.value.key == "bar.elements"
    with pytest.raises(mr.SceneError):
        mr.load("[bar]\nelements = = 3\n")
    with pytest.raises(mr.SceneError, match="cannot read"):
        mr.load("no/such/scene.toml")


def test_check_fills_every_default():
    resolved = mr.check({"bar": {"elements": 6}})
    assert set(resolved) >= {"bar", "mass", "scheme", "time", "output"}
    assert resolved["time"]["end"] == 3.0  # the default end is 3 L
    assert resolved["output"]["divergence_factor"] == 1e6
    assert resolved["bar"]["elements"] == 6


def test_replace_removes_with_none_and_keeps_the_original():
    scene = mr.load(FIG11)
    changed = scene.replace({"time.dt": 0.02, "mass.kind": "mod2"})
    assert (scene.dt, changed.dt) == (0.01, 0.02)
    assert "mod2" in changed.resolved_toml() and "mod3" in scene.resolved_toml()
    by_table = scene.replace(time={"dt": 0.02}, mass={"kind": "mod2"})
    assert by_table.resolved_toml() == changed.resolved_toml()
    with pytest.raises(mr.SceneError) as info:
        scene.replace({"time.dt.x": 1})
    assert info.value.key == "time.dt.x"
    default_series = scene.replace({"output.series": None})
    assert "series" not in default_series.source_toml().split("[output]")[1]


def test_callback_sees_every_kth_state():
    seen = []
    # The arrays are views refreshed in place: a state kept past its call is copied.
    keep = lambda s: seen.append(s._replace(u=s.u.copy(), v=s.v.copy(), reaction=s.reaction.copy()))
    run = mr.run(FIG11, callback=keep, every=50)
    assert [s.n for s in seen] == list(range(0, 301, 50))
    for s in seen:
        assert s.u.shape == (7, 1) and s.reaction.shape == (1,)
        # The energy the callback gets is the series' energy at that step.
        assert s.energy == run.series["energy"][s.n]
        assert s.u[0, 0] == run.series["u0"][s.n]
    np.testing.assert_array_equal(seen[-1].u, run.fields.u)


def test_callback_arrays_are_read_only_views_refreshed_in_place():
    arrays, u0 = [], []

    def look(s):
        arrays.append((s.u, s.v, s.reaction))
        u0.append(s.u[0, 0])
        with pytest.raises(ValueError, match="read-only"):
            s.u[0, 0] = 1.0

    run = mr.run(FIG11, callback=look, every=100)
    # The same three arrays at every call ...
    assert all(a[k] is arrays[0][k] for a in arrays for k in range(3))
    # ... holding that call's state (u0 moves between the calls), and the last state after.
    assert u0 == [run.series["u0"][n] for n in (0, 100, 200, 300)] and len(set(u0)) > 1
    np.testing.assert_array_equal(arrays[0][0], run.fields.u)
    np.testing.assert_array_equal(arrays[0][1], run.fields.v)


def test_callback_exception_stops_the_run():
    calls = []

    def boom(state):
        calls.append(state.n)
        if state.n == 20:
            raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        mr.run(FIG11, callback=boom, every=10)
    assert calls == [0, 10, 20]


def test_fields_are_the_final_state_on_the_mesh():
    run = mr.run(FIG11)
    f = run.fields
    assert f.points.shape == (7, 1) and f.cells.shape == (6, 2) and f.cell_kind == "line"
    np.testing.assert_array_equal(f.points[:, 0], np.arange(7) / 6)
    assert f.t == 3.0 and f.u[6, 0] == 0.0  # the clamped end
    assert f.u[0, 0] == run.summary["final_u0"]
    np.testing.assert_array_equal(f.weights, [0.0, 2.0, 1.0, 1.0, 1.0, 1.0])


def test_operators_are_the_weighted_p1_matrices():
    # M_ii = h/3 (w_{i-1} + w_i), M_{i,i+1} = h/6 w_i, S = (1/h) tridiag(-1, 2, -1) with
    # S_00 = 1/h (docs/schemes.md's formulas, paper §3), on the free nodes 0..m-1; built here
    # independently from the weights and compared to ~round-off (entries are O(h), 1e-15).
    ops = mr.operators(FIG11)
    w, m = ops.weights, 6
    h = 1.0 / m
    mass = np.zeros((m, m))
    stiff = np.zeros((m, m))
    for e in range(m):
        for a in range(2):
            for b in range(2):
                i, j = e + a, e + b
                if i < m and j < m:
                    mass[i, j] += w[e] * h * (2 if a == b else 1) / 6
                    stiff[i, j] += (1 if a == b else -1) / h
    np.testing.assert_allclose(ops.mass.toarray(), mass, rtol=0, atol=1e-15)
    np.testing.assert_allclose(ops.stiffness.toarray(), stiff, rtol=0, atol=1e-12)
    assert list(ops.contact) == [0] and ops.massless[0] and not ops.massless[1:].any()
    # The initial energy ½ u⁰ᵀ S u⁰ is the summary's energy_initial (v⁰ = 0, no load).
    u0 = ops.u0
    assert 0.5 * u0 @ (ops.stiffness @ u0) == pytest.approx(mr.run(FIG11).summary["energy_initial"], rel=1e-14)


def test_operators_without_scipy_are_csr_triples():
    code = (
        "import sys; sys.modules['scipy'] = None\n"
        "import massredist as mr, numpy as np\n"
        f"o = mr.operators({str(FIG11)!r})\n"
        "data, indices, indptr, shape = o.mass\n"
        "assert shape == (6, 6) and indptr[-1] == len(data) == len(indices) == 16\n"
        "print('ok')\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.stdout.strip() == "ok", out.stderr


def test_exact_solution_broadcasts_and_is_the_paper_closed_form():
    ex = mr.exact(FIG11)
    x = np.linspace(0, 1, 11)
    np.testing.assert_allclose(ex.u(x, 0.0), (1 - x) / 2, rtol=0, atol=1e-15)
    grid = ex.u(x[:, None], np.array([0.0, 0.5, 1.5, 3.0]))
    assert grid.shape == (11, 4)
    # 3-periodic (paper §4.1): u(·, 3) = u(·, 0); in contact at t = 1.5, u(0) = 0.
    np.testing.assert_allclose(grid[:, 3], grid[:, 0], rtol=0, atol=1e-15)
    assert ex.u0(1.5) == 0.0 and ex.reaction(1.5) < 0
    # The series' exact columns are these values.
    run = mr.run(mr.load(FIG11).replace({"output.series": ["exact_u0", "exact_lambda"]}))
    np.testing.assert_array_equal(ex.u0(run.series["t"]), run.series["exact_u0"])
    np.testing.assert_array_equal(ex.reaction(run.series["t"]), run.series["exact_lambda"])


def test_exact_of_a_general_bar_and_refusals():
    ex = mr.exact(SCENES / "rebound-free-bar.toml")
    t = np.linspace(0, ex.end, 7)
    assert ex.u(np.zeros_like(t), t).shape == (7,)
    np.testing.assert_array_equal(ex.u(np.zeros_like(t), t), ex.u0(t))
    with pytest.raises(mr.SceneError, match="allowed range"):
        ex.u(0.0, ex.end * 2)
    with pytest.raises(mr.SceneError, match=r"\[bar\] scene"):
        mr.exact(SCENES / "solid-2d-roller-triangle.toml")


# One scene per kind of refusal and the one key it names (issue 28): the compatibility rule of
# geometry, mass, scheme and contact law, and the parser's own refusals. `load` refuses them
# (not only `check` or `run`), and the CLI's `check` prints the same key first.
REFUSALS = [
    ('[bar]\n[mass]\nkind = "mod3"\n[scheme]\nkind = "hybrid"\n[contact]\nmethod = "penalty"\npenalty = 1e4\n',
     "contact.method"),
    ('[bar]\n[mass]\nkind = "mod3"\n[scheme]\nkind = "moreau-jean"\n', "mass.kind"),
    ('[solid]\n[contact]\nmethod = "nitsche"\n', "contact.method"),
    ('[bar]\ncolour = "red"\n', "bar.colour"),
    ("[colour]\nshade = 1\n", "colour"),
    ('[bar]\ninitial = { displacement = "1 +", velocity = "0" }\n', "bar.initial.displacement"),
    ('[bar]\nforce = "1/x"\n', "bar.force"),
    ('[bar]\nelements = 3\n[mass]\nkind = "custom"\nweights = [0.0, -1.0, 1.0]\n', "mass.weights"),
    ('[solid]\nmesh = "no/such/mesh.msh"\n', "solid.mesh"),
]


@pytest.mark.parametrize("text, key", REFUSALS)
def test_load_names_the_one_key_as_the_cli_does(text, key, cli, tmp_path):
    with pytest.raises(mr.SceneError) as info:
        mr.load(text)
    assert info.value.key == key, str(info.value)
    path = tmp_path / "scene.toml"
    path.write_text(text)
    out = subprocess.run([str(cli), "check", str(path)], capture_output=True, text=True)
    assert out.returncode == 2
    # `error: <scene path>: <message>`: the message opens with the key.
    first = out.stderr.splitlines()[0].removeprefix("error: ").removeprefix(f"{path}: ")
    assert first.startswith(key) or first.startswith(f"[{key}]"), first


def test_replace_refuses_a_conflict_at_once():
    # Penalty with the hybrid scheme is refused by `replace` itself, naming contact.method.
    scene = mr.load('[bar]\n[mass]\nkind = "mod3"\n[scheme]\nkind = "hybrid"\n')
    with pytest.raises(mr.SceneError) as info:
        scene.replace({"contact.method": "penalty", "contact.penalty": 1e4})
    assert info.value.key == "contact.method"


def test_errors_quote_only_toml_the_user_wrote():
    """A dict-built or replaced scene's error quotes no line and column of TOML (issue 32: the
    package serialises a dict to TOML, and its errors quoted "line 2, column 12" of that text);
    a scene from TOML text quotes the user's own line."""
    bad = {"bar": {"elements": "six"}, "time": {"dt": 0.01}}
    with pytest.raises(mr.SceneError) as info:
        mr.load(bad)
    assert info.value.key == "bar.elements"
    assert str(info.value) == 'bar.elements: invalid type: string "six", expected i64'
    with pytest.raises(mr.SceneError) as info:
        mr.load(FIG11).replace({"bar.elements": "six"})
    assert "line" not in str(info.value) and "column" not in str(info.value), str(info.value)
    text = "# a comment\n\n[time]\ndt = 0.01\n\n[bar]\nelements = \"six\"\n"
    with pytest.raises(mr.SceneError) as info:
        mr.load(text)
    assert "line 7, column 12" in str(info.value), str(info.value)


def test_progress_is_shown_beside_the_callback(capsys):
    """``run(progress=True)`` writes a progress line on stderr about every percent of the steps
    and a final line, and the user's callback still sees every ``every``-th step."""
    scene = mr.load(FIG11)
    seen = []
    run = mr.run(scene, callback=lambda s: seen.append(s.n), every=7, progress=True)
    err = capsys.readouterr().err
    assert seen == list(range(0, scene.steps + 1, 7))
    lines = err.split("\r")
    assert sum("% of 300 steps" in line for line in lines) == len(seen), err[:300]  # 300 // 7 < 100: every call
    assert f"300 of 300 steps, {run.status}" in lines[-1] and err.endswith("\n"), lines[-1]
    assert mr.run(scene).summary["energy_final"] == run.summary["energy_final"]
