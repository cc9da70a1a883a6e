"""Hostile Python input (issue 32, E2 and E9): a dict that contains itself, a dict nested 20,000
deep, a 10⁷-entry weights list and a 10⁸-value points array raise an exception naming the key
and the limit; none crashes the interpreter. Each call runs in a child interpreter, so that a
segfault or an abort (the behaviour before the fix: exit -11 and -6) fails the test instead of
ending the test run."""

import subprocess
import sys

import pytest

CASES = {
    "self_referencing_dict": """
d = {"bar": {"elements": 6}, "time": {"dt": 0.01, "end": 3.0}}
d["bar"]["x"] = d
mr.load(d)
""",
    "dict_nested_20000_deep": """
d = {}
inner = d
for _ in range(20_000):
    inner["x"] = {}
    inner = inner["x"]
mr.load({"bar": {"elements": 6, "nested": d}, "time": {"dt": 0.01, "end": 3.0}})
""",
    "self_referencing_list": """
l = [1.0]
l.append(l)
mr.load({"bar": {"elements": 6}, "mass": {"kind": "custom", "weights": l}})
""",
    "weights_list_of_1e7": """
mr.load({"bar": {"elements": 6}, "mass": {"kind": "custom", "weights": [1.0] * 10_000_000}})
""",
    "weights_array_of_1e7": """
mr.load({"bar": {"elements": 6}, "mass": {"kind": "custom", "weights": np.ones(10_000_000)}})
""",
    "points_array_of_1e8": """
points = np.zeros((50_000_000, 2))
cells = np.array([[0, 1, 2]])
mr.load({"plate": {}, "time": {"dt": 0.01, "end": 0.1}}, mesh=(points, cells, "triangle"))
""",
}

# What the child prints: the exception's type, its key and its message.
RUNNER = """
import numpy as np
import massredist as mr
try:
{body}
except (mr.SceneError, RecursionError, MemoryError) as e:
    print(type(e).__name__, "|", getattr(e, "key", None), "|", e)
else:
    print("accepted")
"""


@pytest.mark.parametrize("name", sorted(CASES))
def test_hostile_values_raise_instead_of_crashing(name):
    body = "\n".join("    " + line for line in CASES[name].strip().splitlines())
    out = subprocess.run([sys.executable, "-c", RUNNER.format(body=body)], capture_output=True, text=True)
    assert out.returncode == 0, f"{name}: exit {out.returncode}\n{out.stderr[-2000:]}"
    kind, key, message = (part.strip() for part in out.stdout.split("|", 2))
    assert kind == "SceneError", out.stdout
    if name.startswith(("self", "dict")):
        assert "nested more than 32 levels" in message, message
    elif name.startswith("weights"):
        assert key == "mass.weights" and "8388608 values" in message, message
    else:
        assert key == "mesh" and "limit of 10000000 rows" in message, message
