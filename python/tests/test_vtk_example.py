"""The example that goes through VTK's numpy support (python/examples/vtk_numpy.py)."""
import pathlib
import subprocess
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

import ddsimp

EXAMPLE = pathlib.Path(__file__).parent.parent / "examples" / "vtk_numpy.py"


def test_the_example_writes_the_reduced_surface_with_every_field(data, tmp_path):
    source = data / "surfaces" / "SurfaceVectors.vtk"
    out = tmp_path / "reduced.vtp"
    run = subprocess.run([sys.executable, str(EXAMPLE), str(source), str(out), "--keep", "0.25",
                          "--strategy", "vertex"], check=True, capture_output=True, text=True)
    assert "756 -> " in run.stdout
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(out))
    reader.Update()
    poly = reader.GetOutput()
    assert 0 < poly.GetNumberOfPolys() <= 756 // 4
    assert poly.GetPolys().IsHomogeneous() == 3  # triangles only
    # The same as the library's own reader and writer path.
    expected = ddsimp.simplify(ddsimp.read(source), keep=0.25, strategy="vertex")
    np.testing.assert_array_equal(vtk_to_numpy(poly.GetPoints().GetData()), expected.points)
    pd = poly.GetPointData()
    assert [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())] == list(expected.fields)
    for name, values in expected.fields.items():
        np.testing.assert_array_equal(vtk_to_numpy(pd.GetArray(name)), values)
