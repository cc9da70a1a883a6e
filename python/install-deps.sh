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
