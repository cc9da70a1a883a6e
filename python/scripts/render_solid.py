"""Render one VTU frame of a solid run (massredist `solid.pvd`) to a PNG, offscreen, with VTK.

The frame is warped by its `displacement` point data (factor 1: the true deformed shape) and
coloured by |displacement| or by `contact_pressure`; the undeformed body is drawn as a wire
outline and the rigid obstacle x = 0 as a grey plane, so the picture shows where the solid
stands against it.

    PYTHONPATH=/tmp/vtkpy /usr/bin/python3 python/scripts/render_solid.py OUT_DIR/solid.pvd \
        --time 1.2 --color displacement --out docs/figures/solid-3d-hex-mod3.png

VTK: the `vtk` wheel from PyPI (`/usr/bin/python3 -m pip install --no-deps --target /tmp/vtkpy
vtk`); it renders offscreen through EGL (no X server needed). Only the VTU/PVD files written by
massredist are read; nothing else is touched.
"""

import argparse
import os
import sys
import xml.etree.ElementTree as ET


def frames(pvd_path):
    """[(t, absolute vtu path)] of a `.pvd` collection, in file order."""
    root = ET.parse(pvd_path).getroot()
    base = os.path.dirname(os.path.abspath(pvd_path))
    return [(float(d.get("timestep")), os.path.join(base, d.get("file"))) for d in root.iter("DataSet")]


def nearest(frame_list, t):
    """The frame whose time is closest to t."""
    return min(frame_list, key=lambda f: abs(f[0] - t))


def render(vtu_path, t, color, out_png, size=(1200, 700), title=None):
    """Warp the VTU by `displacement`, colour it, draw the obstacle, write `out_png`."""
    import vtk

    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu_path)
    reader.Update()
    grid = reader.GetOutput()
    grid.GetPointData().SetActiveVectors("displacement")
    warp = vtk.vtkWarpVector()
    warp.SetInputData(grid)
    warp.SetScaleFactor(1.0)
    warp.Update()
    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputConnection(warp.GetOutputPort())
    surface.Update()

    if color == "displacement":
        calc = vtk.vtkArrayCalculator()
        calc.SetInputConnection(surface.GetOutputPort())
        calc.SetAttributeTypeToPointData()
        calc.AddVectorArrayName("displacement")
        calc.SetFunction("mag(displacement)")
        calc.SetResultArrayName("|u|")
        calc.Update()
        data, name, label = calc.GetOutput(), "|u|", "|u|"
    else:
        data, name, label = surface.GetOutput(), "contact_pressure", "contact pressure"
    data.GetPointData().SetActiveScalars(name)
    lo, hi = data.GetPointData().GetArray(name).GetRange()
    if hi - lo < 1e-12:
        lo, hi = lo - 1e-12, hi + 1e-12

    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.667, 0.0)  # blue (low) to red (high)
    lut.SetNumberOfTableValues(256)
    lut.Build()
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(data)
    mapper.SetScalarModeToUsePointData()
    mapper.SelectColorArray(name)
    mapper.SetScalarRange(lo, hi)
    mapper.SetLookupTable(lut)
    body = vtk.vtkActor()
    body.SetMapper(mapper)
    body.GetProperty().EdgeVisibilityOn()
    body.GetProperty().SetEdgeColor(0.15, 0.15, 0.15)
    body.GetProperty().SetLineWidth(0.6)

    # The undeformed body as a wire outline.
    outline = vtk.vtkOutlineFilter()
    outline.SetInputData(grid)
    outline_mapper = vtk.vtkPolyDataMapper()
    outline_mapper.SetInputConnection(outline.GetOutputPort())
    ref = vtk.vtkActor()
    ref.SetMapper(outline_mapper)
    ref.GetProperty().SetColor(0.4, 0.4, 0.4)

    # The obstacle: the plane x = 0, a little larger than the contact face.
    x0, x1, y0, y1, z0, z1 = grid.GetBounds()
    pad = 0.6 * max(y1 - y0, z1 - z0, 1e-9)
    plane = vtk.vtkPlaneSource()
    plane.SetOrigin(0.0, y0 - pad, z0 - pad)
    plane.SetPoint1(0.0, y1 + pad, z0 - pad)
    plane.SetPoint2(0.0, y0 - pad, z1 + pad)
    plane_mapper = vtk.vtkPolyDataMapper()
    plane_mapper.SetInputConnection(plane.GetOutputPort())
    wall = vtk.vtkActor()
    wall.SetMapper(plane_mapper)
    wall.GetProperty().SetColor(0.55, 0.55, 0.55)
    wall.GetProperty().SetOpacity(0.45)

    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle(label)
    bar.SetNumberOfLabels(5)
    bar.SetWidth(0.08)
    bar.SetHeight(0.6)
    bar.SetPosition(0.9, 0.2)
    for p in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        p.SetColor(0.1, 0.1, 0.1)
        p.ShadowOff()
        p.ItalicOff()

    text = vtk.vtkTextActor()
    text.SetInput(title or f"t = {t:g}: warped by displacement (factor 1), colour {label}")
    text.GetTextProperty().SetFontSize(20)
    text.GetTextProperty().SetColor(0.1, 0.1, 0.1)
    text.SetPosition(15, size[1] - 40)

    renderer = vtk.vtkRenderer()
    renderer.SetBackground(1.0, 1.0, 1.0)
    for a in (body, ref, wall, bar, text):
        renderer.AddActor(a)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(renderer)
    window.SetSize(*size)
    cam = renderer.GetActiveCamera()
    cx, cy, cz = (x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2
    cam.SetFocalPoint(cx, cy, cz)
    cam.SetPosition(cx + 0.7 * (x1 - x0), cy - 1.3 * (x1 - x0), cz + 0.7 * (x1 - x0))
    cam.SetViewUp(0.0, 0.0, 1.0)
    renderer.ResetCamera()
    cam.Zoom(1.25)
    window.Render()
    shot = vtk.vtkWindowToImageFilter()
    shot.SetInput(window)
    shot.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(out_png)
    writer.SetInputConnection(shot.GetOutputPort())
    writer.Write()
    return lo, hi


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("pvd", help="solid.pvd of a massredist run")
    ap.add_argument("--time", type=float, default=1.2, help="render the frame nearest this t")
    ap.add_argument("--color", choices=["displacement", "contact_pressure"], default="displacement")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--title", default=None)
    args = ap.parse_args(argv)
    t, path = nearest(frames(args.pvd), args.time)
    lo, hi = render(path, t, args.color, args.out, title=args.title)
    print(f"{args.out}: frame t = {t:g} ({os.path.basename(path)}), {args.color} in [{lo:.4g}, {hi:.4g}]")


if __name__ == "__main__":
    main(sys.argv[1:])
