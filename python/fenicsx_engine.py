"""The FEniCSx engine: a plate or solid scene stepped by dolfinx and PETSc under MPI (issue 12),
streaming every state to ``massredist``, which observes it (src/engine/).

    mpirun -n N /usr/bin/python3 python/fenicsx_engine.py SCENE_JSON DIR

started by ``massredist run SCENE --engine fenicsx --ranks N --out OUT`` (not by hand: the series,
the summary and the divergence rule are massredist's). SCENE_JSON is the
``scene.engine.json`` it wrote into DIR, the temporary folder of OUT (the validated scene with
every value written out, src/engine/document.rs); the engine adds
engine.json (ranks, solver, tolerances, timings, complementarity record) and fields.xdmf/.h5
(ParaView) there. Rank 0's standard output carries the records (python/engine/stream.py), its
standard input massredist's replies; everything else goes to standard error. Exit codes: 0,
1 failure, 2 invalid input, 3 stopped (massredist's divergence rule, or a non-finite state).
"""
import os
import sys

os.environ.setdefault("OMPI_MCA_ess_singleton_isolated", "1")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from engine import stream  # noqa: E402  (pure: no dolfinx)

# Before dolfinx, PETSc or MPI can print anything: file descriptor 1 becomes stderr.
PROTOCOL_OUT = stream.isolate_stdout()

import logging  # noqa: E402

logging.getLogger().setLevel(logging.WARNING)

from mpi4py import MPI  # noqa: E402

from engine import scene as scene_mod  # noqa: E402
from engine.run import run  # noqa: E402


def main(argv):
    comm = MPI.COMM_WORLD
    if len(argv) != 2:
        if comm.rank == 0:
            print(__doc__, file=sys.stderr)
        return 2
    path, folder = argv
    # Every rank reads the scene; an error is rank 0's to tell.
    try:
        with open(path) as f:
            scene = scene_mod.parse(f.read())
        error = None
    except (OSError, scene_mod.SceneError, KeyError, ValueError) as e:
        error = f"error: {path}: {e}"
    error = comm.bcast(error if comm.rank == 0 else None, root=0) or error
    if error:
        if comm.rank == 0:
            print(error, file=sys.stderr)
        return 2
    logging.getLogger().setLevel(logging.WARNING)  # the form compiler logs every gcc call
    code = run(scene, folder, stream.Channel(comm, PROTOCOL_OUT), comm)
    comm.Barrier()
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
