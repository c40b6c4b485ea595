"""The example that goes through VTK's numpy support (python/examples/vtk_numpy.py)."""
import importlib.util
import pathlib
import subprocess
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

import ddsimp

EXAMPLE = pathlib.Path(__file__).parent.parent / "examples" / "vtk_numpy.py"


def load_example():
    spec = importlib.util.spec_from_file_location("vtk_numpy", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_example_writes_the_reduced_surface_with_every_field(data, tmp_path):
    source = data / "surfaces" / "SurfaceVectors.vtk"
    out = tmp_path / "reduced.vtp"
    run = subprocess.run([sys.executable, str(EXAMPLE), str(source), str(out), "--keep", "0.25",
                          "--strategy", "vertex"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "756 -> " in run.stdout, run.stdout
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(out))
    reader.Update()
    poly = reader.GetOutput()
    assert 0 < poly.GetNumberOfPolys() <= 756 // 4
    assert poly.GetPolys().IsHomogeneous() == 3  # triangles only
    # What the library gives for the arrays VTK read: the example loses nothing on the way back.
    example = load_example()
    read = example.read_polydata(str(source))  # the arrays below are views into it
    points, triangles, fields = example.to_arrays(read)
    expected = ddsimp.simplify(points, triangles, fields, keep=0.25, strategy="vertex")
    np.testing.assert_array_equal(vtk_to_numpy(poly.GetPoints().GetData()), expected.points)
    pd = poly.GetPointData()
    assert [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())] == list(expected.fields)
    for name, values in expected.fields.items():
        np.testing.assert_array_equal(vtk_to_numpy(pd.GetArray(name)), values)


def test_vtk_and_the_own_reader_read_the_same_surface(data):
    source = data / "surfaces" / "SurfaceVectors.vtk"
    example = load_example()
    read = example.read_polydata(str(source))  # the arrays below are views into it
    points, triangles, fields = example.to_arrays(read)
    own = ddsimp.read(source)
    np.testing.assert_array_equal(points, own.points)
    np.testing.assert_array_equal(triangles, own.triangles)
    assert list(fields) == list(own.fields)
    for name, values in fields.items():
        np.testing.assert_allclose(values, own.fields[name], rtol=1e-6)
