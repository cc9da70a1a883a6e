"""Writes the small gmsh 2.2 ASCII meshes of the body scenes (scenes/body-*.toml), no gmsh needed:

- disc.msh: a polygonal disc of radius 1 centred at (1, 1.05) (x_min = 0, 0.05 above y = 0),
  a centre node and 4 rings of 24 nodes, P1 triangles; physical groups "disc" (2D) and
  "bottom" (the outer nodes with y <= 0.15, as 1D line elements).
- block.msh: the square (0, 1) x (0.02, 1.02), 8 x 8 quads; groups "block", "top" (y = 1.02)
  and "bottom" (y = 0.02).

Run: /usr/bin/python3 scenes/body-gmsh/make_body_meshes.py (writes next to itself).
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def write(path, points, cells, cell_type, facets, names):
    """points: list of (x, y); cells: node lists (0-based); facets: {name: [(a, b)]} line elements."""
    tags = {name: k + 1 for k, name in enumerate(names)}
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names))]
    lines += [f"{1 if n in facets else 2} {tags[n]} \"{n}\"" for n in names]
    lines += ["$EndPhysicalNames", "$Nodes", str(len(points))]
    lines += [f"{i + 1} {x!r} {y!r} 0" for i, (x, y) in enumerate(points)]
    lines += ["$EndNodes", "$Elements"]
    elements = []
    for name, segs in facets.items():
        for a, b in segs:
            elements.append(f"1 2 {tags[name]} {tags[name]} {a + 1} {b + 1}")
    body = [n for n in names if n not in facets][0]
    for c in cells:
        elements.append(f"{cell_type} 2 {tags[body]} {tags[body]} " + " ".join(str(v + 1) for v in c))
    lines += [str(len(elements))]
    lines += [f"{k + 1} {e}" for k, e in enumerate(elements)]
    lines += ["$EndElements"]
    with open(os.path.join(HERE, path), "w") as f:
        f.write("\n".join(lines) + "\n")


def disc(r=1.0, cx=1.0, cy=1.05, rings=4, m=24):
    pts = [(cx, cy)]
    for k in range(1, rings + 1):
        for j in range(m):
            a = 2 * math.pi * j / m
            pts.append((cx + r * k / rings * math.cos(a), cy + r * k / rings * math.sin(a)))
    node = lambda k, j: 0 if k == 0 else 1 + (k - 1) * m + j % m
    cells = [(0, node(1, j), node(1, j + 1)) for j in range(m)]
    for k in range(1, rings):
        for j in range(m):
            cells.append((node(k, j), node(k + 1, j), node(k + 1, j + 1)))
            cells.append((node(k, j), node(k + 1, j + 1), node(k, j + 1)))
    low = lambda v: pts[v][1] <= 0.15
    bottom = [(node(rings, j), node(rings, j + 1)) for j in range(m) if low(node(rings, j)) and low(node(rings, j + 1))]
    write("disc.msh", pts, cells, 2, {"bottom": bottom}, ["disc", "bottom"])


def block(n=8, y0=0.02):
    pts = [(i / n, y0 + j / n) for j in range(n + 1) for i in range(n + 1)]
    node = lambda i, j: j * (n + 1) + i
    cells = [(node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)) for j in range(n) for i in range(n)]
    top = [(node(i, n), node(i + 1, n)) for i in range(n)]
    bottom = [(node(i, 0), node(i + 1, 0)) for i in range(n)]
    write("block.msh", pts, cells, 3, {"top": top, "bottom": bottom}, ["block", "top", "bottom"])


if __name__ == "__main__":
    disc()
    block()
