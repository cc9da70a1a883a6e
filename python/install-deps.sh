#!/usr/bin/env bash
# Install the Python side of the cross-checks (idempotent; a second run takes about a second):
#   - Debian's FEniCSx 0.5 stack, meshio, h5py, GetFEM 5.4 and gmsh 4.8 for /usr/bin/python3
#     (apt, needs root);
#   - scikit-fem 12.0.2 into <repo>/.pydeps with --no-deps (pip would otherwise pull numpy 2.x
#     there, which breaks Debian's dolfinx: "numpy.dtype size changed").
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PY=/usr/bin/python3
PYDEPS="${MASSREDIST_PYDEPS:-$REPO/.pydeps}"
SKFEM_VERSION=12.0.2

die() { echo "install-deps: $*" >&2; exit 1; }

[ -x "$PY" ] || die "$PY not found (Debian's python3 is required: apt-get install python3)"

if ! OMPI_MCA_ess_singleton_isolated=1 "$PY" -c "import dolfinx, meshio, h5py, getfem, gmsh" 2>/dev/null; then
    [ "$(id -u)" -eq 0 ] || die "dolfinx/meshio/h5py/getfem/gmsh missing and not root: run as root, or apt-get install python3-dolfinx-real python3-meshio python3-h5py python3-getfem python3-gmsh"
    echo "install-deps: installing python3-dolfinx-real python3-meshio python3-h5py python3-getfem python3-gmsh with apt-get"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq >/dev/null || die "apt-get update failed"
    apt-get install -y -qq --no-install-recommends python3-dolfinx-real python3-meshio python3-h5py python3-getfem python3-gmsh \
        >/dev/null || die "apt-get install python3-dolfinx-real python3-meshio python3-h5py python3-getfem python3-gmsh failed"
    OMPI_MCA_ess_singleton_isolated=1 "$PY" -c "import dolfinx, meshio, h5py, getfem, gmsh" \
        || die "dolfinx, meshio, h5py, getfem or gmsh still not importable by $PY after apt-get install"
fi

skfem_ok() {
    PYTHONPATH="$PYDEPS" "$PY" -c \
        "import skfem, sys; sys.exit(skfem.__version__ != '$SKFEM_VERSION')" 2>/dev/null
}
if ! skfem_ok; then
    echo "install-deps: installing scikit-fem==$SKFEM_VERSION into $PYDEPS"
    "$PY" -m pip help >/dev/null 2>&1 || die "pip missing for $PY: apt-get install python3-pip"
    "$PY" -m pip install --quiet --disable-pip-version-check --root-user-action=ignore \
        --no-deps --upgrade --target "$PYDEPS" "scikit-fem==$SKFEM_VERSION" \
        || die "pip install --no-deps --target $PYDEPS scikit-fem==$SKFEM_VERSION failed"
    skfem_ok || die "scikit-fem $SKFEM_VERSION not importable from $PYDEPS after pip install"
fi

# The Python package `massredist` (python/pkg: a pyo3 extension, abi3 for CPython >= 3.11) for
# two interpreters, idempotent (a second run rebuilds nothing and reinstalls one wheel, ~2 s):
#   - a virtual environment of the `python3` on PATH ($MASSREDIST_PYTHON; numpy 2 from PyPI)
#     in target/python/venv ($MASSREDIST_VENV);
#   - Debian's /usr/bin/python3 next to dolfinx: a venv with --system-site-packages in
#     target/python/debian-venv ($MASSREDIST_DEBIAN_VENV), so that it sees dolfinx and numpy
#     1.24; pytest, jupytext and matplotlib go into it with numpy pinned to Debian's (pip would
#     otherwise pull numpy 2 and break dolfinx).
# One wheel is built by maturin (release) and installed into both.
VENV="${MASSREDIST_VENV:-$REPO/target/python/venv}"
DEBIAN_VENV="${MASSREDIST_DEBIAN_VENV:-$REPO/target/python/debian-venv}"
PIP_FLAGS=(--quiet --disable-pip-version-check)
TOOLS=(maturin numpy scipy pytest jupytext matplotlib)

if [ ! -x "$VENV/bin/python" ]; then
    echo "install-deps: creating the virtual environment $VENV"
    "${MASSREDIST_PYTHON:-python3}" -m venv "$VENV" || die "python3 -m venv $VENV failed"
fi
"$VENV/bin/python" -c "import maturin, numpy, scipy, pytest, jupytext, matplotlib" 2>/dev/null \
    || "$VENV/bin/python" -m pip install "${PIP_FLAGS[@]}" "${TOOLS[@]}" \
    || die "pip install ${TOOLS[*]} into $VENV failed"

if [ ! -x "$DEBIAN_VENV/bin/python" ]; then
    echo "install-deps: creating $DEBIAN_VENV (Debian's python3, --system-site-packages)"
    "$PY" -m venv --system-site-packages "$DEBIAN_VENV" || die "$PY -m venv failed (apt-get install python3-venv)"
fi
if ! "$DEBIAN_VENV/bin/python" -c "import pytest, jupytext, matplotlib, scipy" 2>/dev/null; then
    PIN="$DEBIAN_VENV/numpy-pin.txt"
    "$PY" -c "import numpy; print(f'numpy=={numpy.__version__}')" > "$PIN"
    "$DEBIAN_VENV/bin/python" -m pip install "${PIP_FLAGS[@]}" -c "$PIN" pytest jupytext matplotlib scipy \
        || die "pip install pytest jupytext matplotlib scipy into $DEBIAN_VENV failed"
fi

echo "install-deps: building the massredist wheel (maturin, release)"
WHEELS="$REPO/target/wheels"
rm -f "$WHEELS"/massredist-*.whl
(cd "$REPO/python/pkg" && "$VENV/bin/maturin" build --quiet --release --out "$WHEELS") \
    || die "maturin build of python/pkg failed"
WHEEL="$(ls "$WHEELS"/massredist-*.whl)"
for env in "$VENV" "$DEBIAN_VENV"; do
    "$env/bin/python" -m pip install "${PIP_FLAGS[@]}" --no-deps --force-reinstall "$WHEEL" \
        || die "pip install $WHEEL into $env failed"
done
OMPI_MCA_ess_singleton_isolated=1 "$DEBIAN_VENV/bin/python" -c "import dolfinx, massredist, numpy; assert numpy.__version__.startswith('1.')" \
    || die "massredist and dolfinx (numpy 1.x) not importable together by $DEBIAN_VENV/bin/python"
"$VENV/bin/python" -c "import massredist, numpy; assert int(numpy.__version__.split('.')[0]) >= 2" \
    || die "massredist (numpy 2) not importable by $VENV/bin/python"
