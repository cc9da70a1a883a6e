#!/usr/bin/env bash
# The whole test suite, including the live FEniCSx (dolfinx) and scikit-fem cross-checks.
# Installs what it needs first (idempotent: Debian's python3-dolfinx-real, python3-meshio,
# python3-h5py via apt; scikit-fem 12.0.2 into .pydeps via pip --no-deps), then runs every test
# with the `python` feature on. Usage: bash tests/run-all.sh
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

echo "== installing the Python side (python/install-deps.sh)"
bash python/install-deps.sh

echo "== formatting"
cargo fmt --all -- --check

echo "== tests (with live dolfinx / scikit-fem cross-checks)"
# Open MPI would otherwise start an orted daemon when mpi4py is imported (TOOLCHAIN.md).
export OMPI_MCA_ess_singleton_isolated=1
# The solver (root package) and the study beside it (study/: massredist-study); the study's
# engine_live finds the binary the first package's tests built.
cargo test -p massredist -p massredist-study --features massredist/python,massredist-study/python --all-targets

echo "== the crosscheck command"
cargo run --quiet --features python -- crosscheck --json target/crosscheck.json

echo "== the Python package: pytest and the demos, in a venv (numpy 2) and with Debian's python3 (numpy 1.24, dolfinx)"
cargo build --release --bin massredist
export MASSREDIST_BIN="$PWD/target/release/massredist"
for env in "${MASSREDIST_VENV:-target/python/venv}" "${MASSREDIST_DEBIAN_VENV:-target/python/debian-venv}"; do
    echo "-- $env"
    "$env/bin/python" -m pytest -q -p no:cacheprovider python/tests
    out="target/python/demos-out/$(basename "$env")"
    mkdir -p "$out"
    for demo in python/demos/*.py; do
        # The dolfinx demos need Debian's python3 (dolfinx is not on PyPI).
        if grep -q "^import dolfinx" "$demo" && ! "$env/bin/python" -c "import dolfinx" 2>/dev/null; then
            echo "   $demo: skipped (no dolfinx in $env)"
            continue
        fi
        echo "   $demo"
        MASSREDIST_DEMO_OUT="$out" "$env/bin/python" "$demo" >"$out/$(basename "$demo" .py).log"
    done
done
