#!/usr/bin/python3
"""Renders a surface and its reductions side by side, coloured by their data (VTK, off-screen).

    render.py ORIGINAL MESH_DIR OUT.png [--field NAME] [--size W H]

MESH_DIR holds the reductions report.py wrote (<surface>-<simplifier>.vtp); each gets a panel
with the same camera and colour range as the original. VTK's OpenGL needs a display: run.sh runs
this under xvfb-run. Needs python3-vtk9.
"""

import argparse
import os
import sys

import vtk

ORDER = ["ddsimp-edge", "ddsimp-vertex", "meshopt", "vtk-quadric", "vtk-decimatepro", "openmesh"]
TITLES = {"ddsimp-edge": "ddsimp edge, alpha=0", "ddsimp-vertex": "ddsimp vertex, alpha=0",
          "meshopt": "meshopt_simplify", "vtk-quadric": "vtkQuadricDecimation",
          "vtk-decimatepro": "vtkDecimatePro", "openmesh": "OpenMesh Decimater"}


def read(path):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("original")
    ap.add_argument("mesh_dir")
    ap.add_argument("out")
    ap.add_argument("--field", help="point field to colour by (default: the first)")
    ap.add_argument("--size", nargs=2, type=int, default=[960, 480])
    args = ap.parse_args()

    surface = os.path.basename(args.original)[:-4]
    original = read(args.original)
    field = args.field or original.GetPointData().GetArrayName(0)
    array = original.GetPointData().GetArray(field)
    if array is None:
        sys.exit(f"render.py: {args.original} has no field {field}")
    magnitude = array.GetNumberOfComponents() > 1
    value_range = array.GetRange(-1 if magnitude else 0)

    panels = [(f"original, {original.GetNumberOfPolys():,} triangles", original)]
    for name in ORDER:
        path = os.path.join(args.mesh_dir, f"{surface}-{name}.vtp")
        if os.path.exists(path):
            poly = read(path)
            panels.append((f"{TITLES[name]}, {poly.GetNumberOfPolys():,}", poly))
        else:
            panels.append((f"{TITLES[name]}: no output (see report)", None))

    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.667, 0.0)
    lut.SetTableRange(value_range)
    lut.Build()

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*args.size)
    cols, rows = 4, 2
    camera = None
    for i, (title, poly) in enumerate(panels):
        renderer = vtk.vtkRenderer()
        c, r = i % cols, i // cols
        renderer.SetViewport(c / cols, 1 - (r + 1) / rows, (c + 1) / cols, 1 - r / rows)
        renderer.SetBackground(1, 1, 1)
        if poly is not None:
            mapper = vtk.vtkPolyDataMapper()
            mapper.SetInputData(poly)
            mapper.SetScalarModeToUsePointFieldData()
            mapper.SelectColorArray(field)
            if magnitude:
                lut.SetVectorModeToMagnitude()
            mapper.SetLookupTable(lut)
            mapper.SetScalarRange(value_range)
            mapper.ScalarVisibilityOn()
            actor = vtk.vtkActor()
            actor.SetMapper(mapper)
            renderer.AddActor(actor)
        text = vtk.vtkTextActor()
        text.SetInput(title)
        text.GetTextProperty().SetColor(0, 0, 0)
        text.GetTextProperty().SetFontSize(13)
        text.SetPosition(6, 6)
        renderer.AddViewProp(text)
        if camera is None:
            renderer.ResetCamera()
            camera = renderer.GetActiveCamera()
            camera.Azimuth(30)
            camera.Elevation(20)
            camera.Zoom(1.3)
        else:
            renderer.SetActiveCamera(camera)
        window.AddRenderer(renderer)
    # The last panel: the colour bar.
    renderer = vtk.vtkRenderer()
    renderer.SetViewport(0.75, 0, 1, 0.5)
    renderer.SetBackground(1, 1, 1)
    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle(field + (" |·|" if magnitude else ""))
    bar.GetTitleTextProperty().SetColor(0, 0, 0)
    bar.GetLabelTextProperty().SetColor(0, 0, 0)
    bar.SetOrientationToHorizontal()
    bar.SetPosition(0.1, 0.3)
    bar.SetWidth(0.8)
    bar.SetHeight(0.35)
    renderer.AddViewProp(bar)
    window.AddRenderer(renderer)
    window.Render()

    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(args.out)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    print(f"render.py: wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
