"""Shared fixtures: the repository, the CLI binary the Python results are compared with."""

import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"


@pytest.fixture(scope="session")
def cli() -> pathlib.Path:
    """The massredist CLI: $MASSREDIST_BIN, else target/release/massredist (built if missing)."""
    given = os.environ.get("MASSREDIST_BIN")
    if given:
        return pathlib.Path(given)
    binary = REPO / "target" / "release" / "massredist"
    if not binary.exists():
        subprocess.run(["cargo", "build", "--release", "--bin", "massredist"], cwd=REPO, check=True)
    return binary
