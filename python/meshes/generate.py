"""Writes the benchmark meshes (``python/meshes/shapes.py``) and, with ``--fixtures``, the
small ones the tests and scenes use, with meshio's reading of each for comparison.

    /usr/bin/python3 python/meshes/generate.py OUTDIR            # every benchmark mesh
    /usr/bin/python3 python/meshes/generate.py --fixtures        # fixtures/meshes/ (committed)
    /usr/bin/python3 python/meshes/generate.py --bench-fixtures  # the committed benchmark meshes

Benchmark set: the disc at h = 4, 2, 1 (P1 and P2), the sphere at h = 8, 4 (tetra, tetra10),
the half disc and hemisphere (P1, P2) at the coarsest size; MSH 4.1 binary.
Fixtures: the coarse P2 disc and tetra10 sphere in the four formats (2.2/4.1 × ASCII/binary;
meshio checked to read all four alike), the coarse P1 disc and clamped half disc / hemisphere in
2.2 ASCII, and ``<name>.meshio.json`` (for the four formats: of ``_22a``): meshio's points, cell
blocks (its type names, VTK node order) and the gmsh physical groups' nodes as meshio's
``cell_sets`` give them (tools' versions in ``provenance``).
Benchmark fixtures (``BENCH_FIXTURES``, MSH 4.1 binary): the meshes ``massredist reproduce``'s
bodies section runs besides the coarse ones (``study/src/paper/bodies.rs``, ``study/src/paper/hertz.rs``).
"""
import json
import sys
from pathlib import Path

import gmsh
import meshio
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import shapes  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
FORMATS = {"22a": (2.2, False), "22b": (2.2, True), "41a": (4.1, False), "41b": (4.1, True)}


DIMS = {"vertex": 0, "line": 1, "triangle": 2, "quad": 2, "tetra": 3, "hexahedron": 3, "wedge": 3, "pyramid": 3}


def _dim(cell_type):
    return DIMS[cell_type.rstrip("0123456789")]


def meshio_view(path):
    """meshio's reading of a gmsh file: points, cell blocks merged by type (in order of first
    appearance) and, per physical group name, the sorted node indices of its cells. meshio
    gives 4.1 groups as ``cell_sets``; 2.2 ones as ``field_data`` (name -> [tag, dim]) with
    the ``gmsh:physical`` tag of each cell."""
    mesh = meshio.read(path, file_format="gmsh")
    merged = {}
    for b in mesh.cells:
        merged.setdefault(b.type, []).append(np.asarray(b.data))
    blocks = [(t, np.concatenate(d).astype(int).tolist()) for t, d in merged.items()]
    groups = {}
    sets = {k: v for k, v in mesh.cell_sets.items() if not k.startswith("gmsh:")}
    for name, (tag, dim) in mesh.field_data.items():
        nodes = set()
        for k, block in enumerate(mesh.cells):
            if name in sets:
                cells = sets[name][k]
                cells = [] if cells is None else np.asarray(cells, dtype=int)
            elif _dim(block.type) == dim:
                cells = np.nonzero(mesh.cell_data["gmsh:physical"][k] == tag)[0]
            else:
                cells = []
            nodes.update(np.asarray(block.data)[cells].ravel().tolist())
        groups[name] = sorted(nodes)
    return {"points": mesh.points.tolist(), "blocks": blocks, "groups": groups}


def _same(a, b):
    """Equal readings, points to 1e-15 relative to the size (gmsh's ASCII prints %.16g)."""
    pa, pb = np.array(a["points"]), np.array(b["points"])
    close = pa.shape == pb.shape and np.abs(pa - pb).max() <= 1e-15 * np.abs(pa).max()
    return close and a["blocks"] == b["blocks"] and a["groups"] == b["groups"]


def fixtures(out):
    out.mkdir(parents=True, exist_ok=True)
    made = []
    for shape, h, order, name in [("disc", 8.0, 2, "disc_p2"), ("sphere", 20.0, 2, "sphere_tet10")]:
        views = []
        for tag, (version, binary) in FORMATS.items():
            path = out / f"{name}_{tag}.msh"
            shapes.generate(shape, h, order, path, version, binary)
            views.append(meshio_view(path))
        # meshio reads the four formats to the same mesh: one reading is stored (for 22a).
        assert all(_same(v, views[0]) for v in views), f"{name}: meshio reads the formats differently"
        made.append(out / f"{name}_22a.msh")
    for shape, h, order, name in [("disc", 8.0, 1, "disc_p1"), ("half_disc", 8.0, 2, "half_disc_p2"),
                                  ("hemisphere", 20.0, 1, "hemisphere_tet")]:
        path = out / f"{name}.msh"
        shapes.generate(shape, h, order, path)
        made.append(path)
    versions = {"gmsh": gmsh.__version__, "meshio": meshio.__version__, "numpy": np.__version__,
                "command": "/usr/bin/python3 python/meshes/generate.py --fixtures"}
    for path in made:
        view = meshio_view(path)
        view["provenance"] = versions
        path.with_suffix(".meshio.json").write_text(json.dumps(view))
    return made


# (file, shape, h, order): the benchmark meshes committed under fixtures/meshes/.
BENCH_FIXTURES = [
    ("disc_p2_h4.msh", "disc", 4.0, 2),
    ("disc_p2_h2.msh", "disc", 2.0, 2),
    ("sphere_tet10_h16.msh", "sphere", 16.0, 2),
    ("sphere_tet10_h14.msh", "sphere", 14.0, 2),
    ("sphere_tet10_h5.msh", "sphere", 5.0, 2),
    ("sphere_tet10_h4.msh", "sphere", 4.0, 2),
    ("hertz_disc_h0.5.msh", "hertz_disc", 0.5, 2),
    ("hertz_disc_h0.25.msh", "hertz_disc", 0.25, 2),
    ("hertz_disc_h0.125.msh", "hertz_disc", 0.125, 2),
    ("hertz_poles_h0.25.msh", "hertz_poles", 0.25, 2),
]


def bench_fixtures(out):
    out.mkdir(parents=True, exist_ok=True)
    for name, shape, h, order in BENCH_FIXTURES:
        shapes.generate(shape, h, order, out / name, 4.1, True)
        yield out / name


def benchmarks(out):
    out.mkdir(parents=True, exist_ok=True)
    cases = [("disc", h, order) for h in (4.0, 2.0, 1.0) for order in (1, 2)]
    cases += [("sphere", h, order) for h in (8.0, 4.0) for order in (1, 2)]
    cases += [(shape, 8.0, order) for shape in ("half_disc", "hemisphere") for order in (1, 2)]
    for shape, h, order in cases:
        path = out / f"{shape}_p{order}_h{h:g}.msh"
        shapes.generate(shape, h, order, path, 4.1, True)
        print(path)


if __name__ == "__main__":
    if sys.argv[1:] == ["--fixtures"]:
        for p in fixtures(ROOT / "fixtures" / "meshes"):
            print(p, p.stat().st_size)
    elif sys.argv[1:] == ["--bench-fixtures"]:
        for p in bench_fixtures(ROOT / "fixtures" / "meshes"):
            print(p, p.stat().st_size)
    elif len(sys.argv) == 2:
        benchmarks(Path(sys.argv[1]))
    else:
        sys.exit(__doc__)
