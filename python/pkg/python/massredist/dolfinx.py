"""dolfinx meshes and Functions for massredist (dolfinx 0.5, Debian's ``/usr/bin/python3``).

``import massredist.dolfinx`` where dolfinx is installed (it is not on PyPI: Debian's
python3-dolfinx-real). Two conversions, so that a FEniCSx user needs no reordering of their own:

- :func:`mesh_arrays`: a dolfinx mesh as ``mesh=(points, cells, kind)`` for
  :func:`massredist.load`: the geometry nodes in dolfinx's order, the cells' nodes in meshio's
  order (massredist reads meshes as meshio does), for P1 and P2 geometries of triangles,
  quadrilaterals, tetrahedra and hexahedra (P2: triangles and tetrahedra).
- :func:`to_function`: nodal values of a run (``run.fields.u``, a callback's ``state.u``) into a
  dolfinx ``Function`` of a Lagrange space of the mesh's own degree (its dofs sit on the
  geometry nodes), scalar or vector.
"""

from __future__ import annotations

from typing import Any

import numpy as np

try:
    import dolfinx  # noqa: F401  (the module is for dolfinx users: say so if it is missing)
except ImportError as e:  # pragma: no cover - depends on the interpreter
    raise ImportError(
        "massredist.dolfinx needs dolfinx (Debian: apt install python3-dolfinx-real, then use /usr/bin/python3)"
    ) from e

# dolfinx's node order of a cell (DOLFINx/Basix: vertices in tensor-product order, then one node
# per edge, edge i of a simplex opposite vertex i ordered by its vertices) -> meshio's (VTK's):
# meshio node k is dolfinx node _TO_MESHIO[cell][k].
_TO_MESHIO = {
    ("triangle", 1): ("triangle", [0, 1, 2]),
    ("quadrilateral", 1): ("quad", [0, 1, 3, 2]),
    ("tetrahedron", 1): ("tetra", [0, 1, 2, 3]),
    ("hexahedron", 1): ("hexahedron", [0, 1, 3, 2, 4, 5, 7, 6]),
    # Triangle edges: dolfinx e0 = (1, 2), e1 = (0, 2), e2 = (0, 1); meshio (0, 1), (1, 2), (2, 0).
    ("triangle", 2): ("triangle6", [0, 1, 2, 5, 3, 4]),
    # Tetrahedron edges: dolfinx e0 = (2, 3), e1 = (1, 3), e2 = (1, 2), e3 = (0, 3), e4 = (0, 2),
    # e5 = (0, 1); meshio (0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3).
    ("tetrahedron", 2): ("tetra10", [0, 1, 2, 3, 9, 6, 8, 7, 5, 4]),
}


def _cell_key(msh: Any) -> tuple[str, int]:
    name = msh.topology.cell_type.name
    degree = int(msh.ufl_domain().ufl_coordinate_element().degree())
    if (name, degree) not in _TO_MESHIO:
        supported = ", ".join(f"{c} P{d}" for c, d in _TO_MESHIO)
        raise ValueError(f"mesh: {name} cells of degree {degree}; massredist reads {supported}")
    return name, degree


def mesh_arrays(msh: Any) -> tuple[np.ndarray, np.ndarray, str]:
    """``(points, cells, kind)`` of a serial dolfinx mesh for ``massredist.load(..., mesh=)``:
    the geometry nodes (dolfinx's order; ``dim`` coordinates) and the cells' nodes in meshio's
    order, ``kind`` meshio's cell name."""
    if msh.comm.size != 1:
        raise ValueError("mesh: a distributed mesh; give massredist the mesh of one process (MPI.COMM_SELF)")
    kind, order = _TO_MESHIO[_cell_key(msh)]
    nodes = msh.geometry.dofmap.array.reshape(-1, len(order))
    points = np.ascontiguousarray(msh.geometry.x[:, : msh.geometry.dim])
    return points, np.ascontiguousarray(nodes[:, order], dtype=np.int64), kind


def to_function(values: np.ndarray, function: Any) -> Any:
    """Writes nodal ``values`` (one row per geometry node of the mesh, as :func:`mesh_arrays`
    numbers them, one column per component) into the dolfinx ``function`` and returns it. Its
    space must be Lagrange of the mesh's own degree (its dofs on the geometry nodes), with as
    many components as ``values`` has columns."""
    space = function.function_space
    msh = space.mesh
    _, degree = _cell_key(msh)
    element = space.ufl_element()
    if element.family() not in ("Lagrange", "Q", "P") or element.degree() != degree:
        raise ValueError(f"function: a {element.family()} P{element.degree()} space; a Lagrange P{degree} space is needed")
    values = np.asarray(values, dtype=np.float64)
    values = values.reshape(len(values), -1)
    bs = space.dofmap.index_map_bs
    if values.shape[1] != bs:
        raise ValueError(f"function: {bs} components per node, the values have {values.shape[1]}")
    nodes = msh.geometry.dofmap
    dof_of_node = np.full(len(msh.geometry.x), -1, dtype=np.int64)
    for c in range(msh.topology.index_map(msh.topology.dim).size_local):
        dof_of_node[nodes.links(c)] = space.dofmap.cell_dofs(c)
    if len(values) != len(dof_of_node) or (dof_of_node < 0).any():
        raise ValueError(f"values: {len(values)} rows, the mesh has {len(dof_of_node)} geometry nodes")
    function.x.array.reshape(-1, bs)[dof_of_node] = values
    return function
