"""The demos are jupytext percent-format notebooks (tests/run-all.sh runs them as scripts)."""

import pathlib

import pytest

jupytext = pytest.importorskip("jupytext")
DEMOS = sorted((pathlib.Path(__file__).resolve().parents[1] / "demos").glob("*.py"))


@pytest.mark.parametrize("demo", DEMOS, ids=lambda p: p.name)
def test_demo_is_a_percent_notebook(demo):
    notebook = jupytext.read(demo, fmt="py:percent")
    kinds = [cell.cell_type for cell in notebook.cells]
    assert kinds.count("markdown") >= 1 and kinds.count("code") >= 1, kinds
    assert notebook.cells[0].cell_type == "markdown" and notebook.cells[0].source.startswith("# ")


def test_there_are_the_three_demos():
    assert {d.name for d in DEMOS} >= {"fig11.py", "sweep.py", "dolfinx_plate.py"}
