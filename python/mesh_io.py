"""Mesh files through meshio (2D triangle or quadrilateral meshes, e.g. gmsh ``.msh``)."""
from pathlib import Path

import meshio
import numpy as np


def read_mesh(path):
    """Return ``(points (n, 2) float64, cells (k, nv) int64, cell_type)`` of a 2D mesh file.

    Triangles are taken if present, else quadrilaterals (meshio's order is counter-clockwise).
    Points that belong to no such cell (gmsh geometry points) are dropped and the cells
    renumbered, so every returned vertex is a mesh vertex. gmsh files are read with
    ``file_format="gmsh"``: meshio's auto-detection tries another reader first and prints.
    """
    path = Path(path)
    mesh = meshio.read(path, file_format="gmsh" if path.suffix == ".msh" else None)
    for cell_type in ("triangle", "quad"):
        blocks = [block.data for block in mesh.cells if block.type == cell_type]
        if blocks:
            break
    else:
        raise ValueError(f"{path}: no triangle or quad cells (found "
                         f"{sorted({block.type for block in mesh.cells})})")
    cells = np.concatenate(blocks).astype(np.int64)
    used, cells = np.unique(cells, return_inverse=True)
    points = np.ascontiguousarray(mesh.points[used, :2], dtype=np.float64)
    return points, cells.reshape(-1, blocks[0].shape[1]).astype(np.int64), cell_type


def read_point_data(path, name):
    """Return ``(points (n, 3) float64, point_data[name] as float64 (n,) or (n, k))`` of a file
    meshio reads (e.g. the ``.vtu`` frames written by ``massredist run`` with ``vtu = true``)."""
    mesh = meshio.read(Path(path))
    data = np.ascontiguousarray(mesh.point_data[name], dtype=np.float64)
    return np.ascontiguousarray(mesh.points, dtype=np.float64), data.reshape(len(mesh.points), -1)
