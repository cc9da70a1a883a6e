"""The FEniCSx engine: a plate or solid scene stepped by dolfinx and PETSc under MPI (issue 12).

    mpirun -n N /usr/bin/python3 python/fenicsx_engine.py RESOLVED_SCENE OUT_DIR [--staged]

RESOLVED_SCENE is a ``scene.resolved.toml`` written by ``massredist`` (``check`` or ``run``).
OUT_DIR receives series.csv, summary.json, scene.resolved.toml (the columns and keys of the
Rust run), engine.json (ranks, solver, tolerances, timings, complementarity record) and
fields.xdmf/.h5 (ParaView). The folder is written under a temporary sibling and renamed into
place; with ``--staged`` OUT_DIR is already such a folder (``massredist run --engine fenicsx``
prepared it and renames it). Exit codes as a Rust run: 0, 1 failure, 2 invalid input,
3 diverged (folder written).
"""
import os
import shutil
import sys

os.environ.setdefault("OMPI_MCA_ess_singleton_isolated", "1")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import logging  # noqa: E402

logging.getLogger().setLevel(logging.WARNING)

from mpi4py import MPI  # noqa: E402

from engine import output, scene as scene_mod  # noqa: E402
from engine.run import run  # noqa: E402


def main(argv):
    comm = MPI.COMM_WORLD
    args = [a for a in argv if a != "--staged"]
    staged = "--staged" in argv
    if len(args) != 2:
        if comm.rank == 0:
            print(__doc__, file=sys.stderr)
        return 2
    path, out = args
    # Every rank reads the scene; rank 0 alone prepares the folder and tells the others.
    try:
        with open(path) as f:
            text = f.read()
        scene = scene_mod.parse(text)
        folder = None
        if comm.rank == 0:
            folder = out if staged else output.prepare(out)
        error = None
    except (OSError, scene_mod.SceneError, output.OutputError, KeyError, ValueError) as e:
        error = f"error: {path}: {e}"
    error = comm.bcast(error if comm.rank == 0 else None, root=0) or error
    if error:
        if comm.rank == 0:
            print(error, file=sys.stderr)
        return 2
    folder = comm.bcast(folder, root=0)
    logging.getLogger().setLevel(logging.WARNING)  # the form compiler logs every gcc call
    try:
        code = run(scene, folder, text, comm)
    except Exception:
        if comm.rank == 0 and not staged:
            shutil.rmtree(folder, ignore_errors=True)
        raise
    comm.Barrier()
    if comm.rank == 0 and not staged:
        output.commit(folder, out)
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
