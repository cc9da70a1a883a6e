"""Benchmark bodies meshed with gmsh (Debian's python3-gmsh; run with /usr/bin/python3).

Each function builds one model in the current gmsh session, with named physical groups, and
meshes it at size ``h`` and order 1 or 2 (second order: triangle6 / tetra10 with the boundary
nodes on the curved geometry). ``write`` saves it as MSH 2.2 or 4.1, ASCII or binary.

- ``disc``: GetFEM's ``demo_dynamic_contact.m`` disc, radius 20 centred at (0, 20), on the
  plane y = 0; groups "body" (surface), "boundary" (circle), "bottom" (the point (0, 0)).
- ``half_disc``: its lower half (y <= 20), clamped along its flat side; groups "body",
  "top" (the segment y = 20), "arc", "bottom".
- ``sphere``: radius 20 centred at (0, 0, 20); groups "body", "surface", "bottom" (the pole
  (0, 0, 0)).
- ``hemisphere``: its lower half (z <= 20); groups "body", "top" (the disc z = 20), "surface",
  "bottom".
- ``hertz_disc``: the disc, with a gmsh size field refining it near the contact point (0, 0):
  size ``h`` within distance 3 of it (1.5 times the Hertz half-width 2 that
  ``study/src/paper/hertz.rs`` loads it to), growing linearly to 4 at distance 15 (``Distance``
  + ``Threshold`` fields); the same groups as ``disc``.
- ``hertz_poles``: the same, refined near both poles (0, 0) and (0, 40): two copies, one above
  the other, meet pole to pole (``study/src/paper/two_discs.rs``).
"""
import math

import gmsh

R = 20.0


def _arcs(points, centre):
    """Circle arcs through ``points`` (geo kernel tags) around ``centre``, closed."""
    return [gmsh.model.geo.addCircleArc(points[i], centre, points[(i + 1) % len(points)])
            for i in range(len(points))]


def _group(dim, tags, name):
    tag = gmsh.model.addPhysicalGroup(dim, tags)
    gmsh.model.setPhysicalName(dim, tag, name)


def _mesh(dim, h, order):
    gmsh.option.setNumber("Mesh.CharacteristicLengthMax", h)
    gmsh.option.setNumber("Mesh.CharacteristicLengthMin", h / 2)
    gmsh.model.mesh.generate(dim)
    if order == 2:
        gmsh.model.mesh.setOrder(2)


def disc(h, order):
    disc_geometry()
    _mesh(2, h, order)


def disc_geometry():
    """The disc's model and groups, not meshed; returns the tag of the bottom point (0, 0)."""
    gmsh.model.add("disc")
    geo = gmsh.model.geo
    centre = geo.addPoint(0, R, 0)
    # Bottom, right, top, left: the bottom point (0, 0) is a node of every mesh.
    pts = [geo.addPoint(0, 0, 0), geo.addPoint(R, R, 0), geo.addPoint(0, 2 * R, 0), geo.addPoint(-R, R, 0)]
    arcs = _arcs(pts, centre)
    surface = geo.addPlaneSurface([geo.addCurveLoop(arcs)])
    geo.synchronize()
    _group(2, [surface], "body")
    _group(1, arcs, "boundary")
    _group(0, [pts[0]], "bottom")
    return pts[0]


def hertz_disc(h, order):
    _refined_disc(h, order, [disc_geometry()])


def hertz_poles(h, order):
    bottom = disc_geometry()
    _refined_disc(h, order, [bottom, _point_at(0.0, 2 * R)])


def _point_at(x, y):
    """The geometry point at (x, y)."""
    for _, tag in gmsh.model.getEntities(0):
        p = gmsh.model.getValue(0, tag, [])
        if abs(p[0] - x) + abs(p[1] - y) < 1e-9 * R:
            return tag
    raise ValueError(f"no geometry point at ({x}, {y})")


def _refined_disc(h, order, points):
    # Size field: h within distance 3 of the points, 4 beyond distance 15.
    field = gmsh.model.mesh.field
    dist = field.add("Distance")
    field.setNumbers(dist, "PointsList", points)
    field.setNumbers(dist, "CurvesList", [])
    thr = field.add("Threshold")
    field.setNumber(thr, "InField", dist)
    field.setNumber(thr, "SizeMin", h)
    field.setNumber(thr, "SizeMax", 4.0)
    field.setNumber(thr, "DistMin", 3.0)
    field.setNumber(thr, "DistMax", 15.0)
    field.setAsBackgroundMesh(thr)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.model.mesh.generate(2)
    if order == 2:
        gmsh.model.mesh.setOrder(2)


def half_disc(h, order):
    gmsh.model.add("half_disc")
    geo = gmsh.model.geo
    centre = geo.addPoint(0, R, 0)
    left, bottom, right = geo.addPoint(-R, R, 0), geo.addPoint(0, 0, 0), geo.addPoint(R, R, 0)
    arcs = [geo.addCircleArc(left, centre, bottom), geo.addCircleArc(bottom, centre, right)]
    top = geo.addLine(right, left)
    surface = geo.addPlaneSurface([geo.addCurveLoop(arcs + [top])])
    geo.synchronize()
    _group(2, [surface], "body")
    _group(1, [top], "top")
    _group(1, arcs, "arc")
    _group(0, [bottom], "bottom")
    _mesh(2, h, order)


def _pole(z):
    """The geometry point at (0, 0, z)."""
    for dim, tag in gmsh.model.getEntities(0):
        x = gmsh.model.getValue(0, tag, [])
        if abs(x[0]) + abs(x[1]) + abs(x[2] - z) < 1e-9 * R:
            return tag
    raise ValueError(f"no geometry point at (0, 0, {z})")


def sphere(h, order):
    gmsh.model.add("sphere")
    volume = gmsh.model.occ.addSphere(0, 0, R, R)
    gmsh.model.occ.synchronize()
    _group(3, [volume], "body")
    _group(2, [t for _, t in gmsh.model.getBoundary([(3, volume)], oriented=False)], "surface")
    _group(0, [_pole(0.0)], "bottom")
    _mesh(3, h, order)


def hemisphere(h, order):
    gmsh.model.add("hemisphere")
    volume = gmsh.model.occ.addSphere(0, 0, R, R, angle1=-math.pi / 2, angle2=0.0)
    gmsh.model.occ.synchronize()
    faces = [t for _, t in gmsh.model.getBoundary([(3, volume)], oriented=False)]
    flat = [t for t in faces if abs(gmsh.model.occ.getCenterOfMass(2, t)[2] - R) < 1e-9 * R]
    _group(3, [volume], "body")
    _group(2, flat, "top")
    _group(2, [t for t in faces if t not in flat], "surface")
    _group(0, [_pole(0.0)], "bottom")
    _mesh(3, h, order)


SHAPES = {"disc": disc, "hertz_disc": hertz_disc, "hertz_poles": hertz_poles, "half_disc": half_disc, "sphere": sphere, "hemisphere": hemisphere}


def write(path, version=2.2, binary=False):
    """Save the current model's mesh (physical groups only, as gmsh does by default)."""
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", 1 if binary else 0)
    gmsh.write(str(path))


def generate(shape, h, order, path, version=2.2, binary=False):
    """One mesh file: ``shape`` (a key of ``SHAPES``) at size ``h`` and ``order``."""
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        SHAPES[shape](h, order)
        write(path, version, binary)
    finally:
        gmsh.finalize()
