#!/usr/bin/env python3
"""Simplify a VTK surface in memory: VTK's numpy support in, ddsimp, and back to vtkPolyData.

    PYTHONPATH=build/release/python python3 python/examples/vtk_numpy.py IN.vtp OUT.vtp --keep 0.1

IN is any surface VTK reads (.vtp, or legacy .vtk polydata / unstructured grid); its polygons
are triangulated and every numeric point-data array goes along as a field.
"""
import argparse

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersCore import vtkTriangleFilter
from vtkmodules.vtkFiltersGeometry import vtkDataSetSurfaceFilter
from vtkmodules.vtkIOLegacy import vtkDataSetReader
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPolyDataWriter

import ddsimp


def read_polydata(path):
    reader = vtkXMLPolyDataReader() if path.endswith(".vtp") else vtkDataSetReader()
    reader.SetFileName(path)
    surface = vtkDataSetSurfaceFilter()  # any dataset -> polydata, in a stable order
    surface.SetInputConnection(reader.GetOutputPort())
    triangles = vtkTriangleFilter()
    triangles.SetInputConnection(surface.GetOutputPort())
    triangles.Update()
    return triangles.GetOutput()


def to_arrays(poly):
    """vtkPolyData of triangles -> (points, triangles, fields).

    Points and fields are views into VTK's arrays: keep `poly` alive while they are used. The
    triangles are a copy, since VTK may hand out a cell array's connectivity as a temporary.
    """
    points = vtk_to_numpy(poly.GetPoints().GetData())
    triangles = vtk_to_numpy(poly.GetPolys().GetConnectivityArray()).reshape(-1, 3).copy()
    pd = poly.GetPointData()
    fields = {}
    for i in range(pd.GetNumberOfArrays()):
        array = pd.GetArray(i)  # None for a string or other non-numeric array
        if array is not None and array.GetName():
            fields[array.GetName()] = vtk_to_numpy(array)
    return points, triangles, fields


def to_polydata(mesh):
    """A ddsimp mesh -> vtkPolyData (VTK keeps references to the arrays: keep `mesh` alive)."""
    poly = vtkPolyData()
    points = vtkPoints()
    points.SetData(numpy_to_vtk(mesh.points))
    poly.SetPoints(points)
    offsets = np.arange(0, 3 * len(mesh.triangles) + 1, 3, dtype=np.int64)
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True),
                  numpy_to_vtkIdTypeArray(mesh.triangles.astype(np.int64).ravel(), deep=True))
    poly.SetPolys(cells)
    for name, values in mesh.fields.items():
        array = numpy_to_vtk(values)
        array.SetName(name)
        poly.GetPointData().AddArray(array)
    return poly


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("input")
    parser.add_argument("output", help="a .vtp file")
    parser.add_argument("--keep", type=float, default=0.1)
    parser.add_argument("--alpha", type=float, default=0.5)
    parser.add_argument("--strategy", choices=["edge", "vertex"], default="edge")
    args = parser.parse_args()

    poly = read_polydata(args.input)
    points, triangles, fields = to_arrays(poly)
    result = ddsimp.simplify(points, triangles, fields, keep=args.keep, alpha=args.alpha,
                             strategy=args.strategy)
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(args.output)
    writer.SetInputData(to_polydata(result))
    writer.Write()
    print(f"{args.output}: {len(triangles)} -> {len(result.triangles)} triangles, "
          f"{result.stop_reason}")


if __name__ == "__main__":
    main()
