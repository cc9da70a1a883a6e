"""Mesh files through meshio: 2D triangle or quadrilateral meshes, 3D tetrahedron or hexahedron
meshes (e.g. gmsh ``.msh``, ``.vtu``)."""
from pathlib import Path

import meshio
import numpy as np

# meshio cell type -> (dimension, vertices per cell); meshio orders quadrilaterals
# counter-clockwise and hexahedra as VTK (the face z = 0 counter-clockwise, then z = 1), as we do.
_CELLS = {"triangle": (2, 3), "quad": (2, 4), "tetra": (3, 4), "hexahedron": (3, 8)}


def _read(path):
    """meshio's mesh of ``path``; gmsh files with ``file_format="gmsh"`` (meshio's
    auto-detection tries another reader first and prints), their node tags checked first."""
    path = Path(path)
    if path.suffix == ".msh":
        _check_gmsh_node_tags(path)
    return meshio.read(path, file_format="gmsh" if path.suffix == ".msh" else None)


def _check_gmsh_node_tags(path):
    """Refuse an element of an ASCII gmsh file (format 2.2 or 4.x) that refers to a node tag
    below 1. gmsh numbers nodes from 1; meshio subtracts 1 and indexes its tag map with the
    result, so a tag 0 becomes index -1, which numpy reads as the last point: silently another
    mesh. Binary files are left to meshio."""
    with open(path, "rb") as f:
        lines = iter(f)
        for line in lines:
            if line.strip() == b"$MeshFormat":
                version, file_type = next(lines).split()[:2]
                break
        else:
            return
        if file_type != b"0":
            return
        for line in lines:
            if line.strip() == b"$Elements":
                break
        else:
            return
        header = next(lines).split()
        if version.startswith(b"2"):
            for _ in range(int(header[0])):
                row = [int(x) for x in next(lines).split()]
                _refuse_low_tags(path, row[0], row[3 + row[2]:])
        else:
            for _ in range(int(header[0])):
                count = int(next(lines).split()[3])
                for _ in range(count):
                    row = [int(x) for x in next(lines).split()]
                    _refuse_low_tags(path, row[0], row[1:])


def _refuse_low_tags(path, element, nodes):
    low = [tag for tag in nodes if tag < 1]
    if low:
        raise ValueError(f"{path}: gmsh element {element} refers to node tag {low[0]}: gmsh node "
                         f"tags start at 1 (meshio would read tag {low[0]} as another node)")


def _cells_of(mesh, path, cell_types):
    """``(points (n, dim), cells (k, nv), cell_type)`` of the first of ``cell_types`` present
    (the cross-check peers' own reader; the scenes read through ``read_cell_blocks``).

    Points that belong to no such cell (gmsh geometry points, the vertices of boundary facets
    only) are dropped and the cells renumbered, keeping the file's vertex order otherwise.
    """
    for cell_type in cell_types:
        blocks = [block.data for block in mesh.cells if block.type == cell_type]
        if blocks:
            break
    else:
        raise ValueError(f"{path}: no {' or '.join(cell_types)} cells (found "
                         f"{sorted({block.type for block in mesh.cells})})")
    dim = _CELLS[cell_type][0]
    cells = np.concatenate(blocks).astype(np.int64)
    used, cells = np.unique(cells, return_inverse=True)
    points = np.ascontiguousarray(mesh.points[used, :dim], dtype=np.float64)
    return points, cells.reshape(-1, blocks[0].shape[1]).astype(np.int64), cell_type


def read_cells(path):
    """Return ``(points (n, dim) float64, cells (k, nv) int64, cell_type)`` of a 2D or 3D mesh
    file: tetrahedra or hexahedra (dim 3) if present, else triangles or quadrilaterals (dim 2)."""
    return _cells_of(_read(path), path, ("tetra", "hexahedron", "triangle", "quad"))


def write_mesh(path, points, cells):
    """Write ``points`` (n, 2 or 3) and ``cells`` (k, nv; the cell type from ``_CELLS``) with
    meshio; ``.msh`` as gmsh 2.2 ASCII. Coordinates are written shortest round-trip (ASCII) or
    binary, so reading back gives the same floats."""
    points = np.asarray(points, dtype=np.float64)
    cells = np.asarray(cells, dtype=np.int64)
    key = (points.shape[1], cells.shape[1])
    cell_type = next((t for t, k in _CELLS.items() if k == key), None)
    if cell_type is None:
        raise ValueError(f"no cell type with (dimension, vertices per cell) = {key}; "
                         f"allowed: {sorted(_CELLS.values())}")
    path = Path(path)
    points = np.column_stack([points, np.zeros((len(points), 3 - points.shape[1]))])
    if path.suffix == ".msh":
        # gmsh tags every cell with a physical and a geometrical entity (meshio warns without).
        tags = {name: [np.ones(len(cells), dtype=np.int32)] for name in ("gmsh:physical", "gmsh:geometrical")}
        meshio.write(path, meshio.Mesh(points, [(cell_type, cells)], cell_data=tags),
                     file_format="gmsh22", binary=False)
    else:
        meshio.write(path, meshio.Mesh(points, [(cell_type, cells)]))


def read_point_data(path, name):
    """Return ``(points (n, 3) float64, point_data[name] as float64 (n,) or (n, k))`` of a file
    meshio reads (e.g. the ``.vtu`` frames written by ``massredist run`` with ``vtu = true``)."""
    mesh = meshio.read(Path(path))
    data = np.ascontiguousarray(mesh.point_data[name], dtype=np.float64)
    return np.ascontiguousarray(mesh.points, dtype=np.float64), data.reshape(len(mesh.points), -1)


def read_cell_blocks(path):
    """Return ``(points (n, 3) float64, [(cell_type, cells (k, nv) int64), ...])`` of a file, as
    meshio reads it (no points dropped, nothing checked): the Rust side picks and checks the
    cells (``src/mesh_file/mod.rs``), and checks the files it writes."""
    mesh = _read(path)
    blocks = [(block.type, np.ascontiguousarray(block.data, dtype=np.int64)) for block in mesh.cells]
    return np.ascontiguousarray(mesh.points, dtype=np.float64), blocks
