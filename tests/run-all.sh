#!/usr/bin/env bash
# The whole test suite, including the live FEniCSx (dolfinx) and scikit-fem cross-checks.
# Installs what it needs first (idempotent: Debian's python3-dolfinx-real, python3-meshio,
# python3-h5py via apt; scikit-fem 12.0.2 into .pydeps via pip --no-deps), then runs every test
# with the `python` feature on. Usage: bash tests/run-all.sh
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

# Each stage's wall time goes into docs/testing.md when the whole suite has passed (the README
# links to it): written from a temporary file at the end, so a failed run leaves the last
# passing run's figures in place.
times="$(mktemp)"
trap 'rm -f "$times"' EXIT
stage_start=$SECONDS
stage() { # stage "name": ends the previous stage (its time recorded), announces the next
    if [ -n "${stage_name:-}" ]; then
        printf '| %s | %d |\n' "$stage_name" "$((SECONDS - stage_start))" >>"$times"
    fi
    stage_name="$1"
    stage_start=$SECONDS
    [ -n "$1" ] && echo "== $1"
    return 0
}

# A clean clone gains nothing from incremental compilation's caches, which took 2.9 GB of
# target/ on a CI run whose disk filled; the free space is printed for the same reason.
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
echo "free disk at the start: $(df -h --output=avail . | tail -1 | tr -d ' ')"

stage "installing the Python side (python/install-deps.sh)"
bash python/install-deps.sh

stage "formatting"
cargo fmt --all -- --check

stage "fast tier: cargo test (the solver, no Python)"
cargo test

stage "full Rust tier: both packages with the python feature (live dolfinx / scikit-fem / GetFEM cross-checks, MPI engine)"
# Open MPI would otherwise start an orted daemon when mpi4py is imported (TOOLCHAIN.md).
export OMPI_MCA_ess_singleton_isolated=1
# The solver (root package) and the study beside it (study/: massredist-study); the study's
# engine_live finds the binary the first package's tests built.
cargo test -p massredist -p massredist-study --features massredist/python,massredist-study/python --all-targets

stage "the crosscheck command"
cargo run --quiet --features python -- crosscheck --json target/crosscheck.json

stage "the Python package: pytest and the demos, in a venv (numpy 2) and with Debian's python3 (numpy 1.24, dolfinx)"
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
stage ""

{
    echo "# How long the tests take"
    echo
    echo "Written by \`bash tests/run-all.sh\` when every stage passed (the last such run on this"
    echo "machine; do not edit). Wall seconds per stage, including the builds each stage needs; a"
    echo "stage's build is reused by the later ones. Machine: $(nproc) cores; load average at the end:"
    echo "$(cut -d' ' -f1-3 /proc/loadavg) (1, 5, 15 min); $(date -u +%Y-%m-%d)."
    echo
    echo "| stage | wall s |"
    echo "|---|---|"
    cat "$times"
    echo "| **total** | $SECONDS |"
} >docs/testing.md.tmp
mv docs/testing.md.tmp docs/testing.md
echo "== all passed in ${SECONDS} s (stage times: docs/testing.md)"
