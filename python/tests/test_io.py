"""ddsimp.read and ddsimp.write: the command line's formats, checked against VTK's readers."""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOLegacy import vtkUnstructuredGridReader

import ddsimp


def test_read_gives_what_vtk_reads(data):
    path = data / "surfaces" / "SurfaceVectors.vtk"
    mesh = ddsimp.read(path)
    reader = vtkUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    np.testing.assert_array_equal(mesh.points, vtk_to_numpy(grid.GetPoints().GetData()))
    cells = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 3)
    np.testing.assert_array_equal(mesh.triangles, cells)
    pd = grid.GetPointData()
    names = [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]
    assert list(mesh.fields) == names
    for name in names:  # every array becomes float32, whatever its type in the file
        expected = vtk_to_numpy(pd.GetArray(name)).astype(np.float32)
        np.testing.assert_array_equal(mesh.fields[name], expected)


@pytest.mark.parametrize("extension", [".vtk", ".vtp", ".ply"])
def test_formats_with_fields_round_trip(data, tmp_path, extension):
    mesh = ddsimp.read(data / "surfaces" / "SurfaceVectors.vtk")
    path = tmp_path / ("out" + extension)
    ddsimp.write(path, mesh)
    back = ddsimp.read(path)
    np.testing.assert_array_equal(back.points, mesh.points)
    np.testing.assert_array_equal(back.triangles, mesh.triangles)
    assert list(back.fields) == list(mesh.fields)
    for name, values in mesh.fields.items():
        np.testing.assert_array_equal(back.fields[name], values)


@pytest.mark.parametrize("extension", [".obj", ".off"])
def test_formats_without_fields_round_trip_the_geometry(data, tmp_path, extension):
    mesh = ddsimp.read(data / "surfaces" / "SurfaceVectors.vtk")
    path = tmp_path / ("out" + extension)
    ddsimp.write(path, mesh.points, mesh.triangles)
    back = ddsimp.read(path)
    np.testing.assert_allclose(back.points, mesh.points, rtol=1e-6, atol=1e-6)
    np.testing.assert_array_equal(back.triangles, mesh.triangles)
    assert back.fields == {}


def test_a_simplified_surface_is_written_with_its_fields(data, tmp_path):
    r = ddsimp.simplify(ddsimp.read(data / "surfaces" / "earth.vtp"), keep=0.1)
    ddsimp.write(tmp_path / "earth-10.vtp", r)
    back = ddsimp.read(tmp_path / "earth-10.vtp")
    assert len(back.triangles) == len(r.triangles) <= 8192
    np.testing.assert_array_equal(back.fields["bottomDepth"], r.fields["bottomDepth"])


def test_stl_is_read(data, tmp_path):
    path = tmp_path / "triangle.stl"
    path.write_text("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                    "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n")
    mesh = ddsimp.read(path)
    assert mesh.triangles.shape == (1, 3) and len(mesh.points) == 3


def test_file_errors_name_the_file_and_the_problem(tmp_path):
    with pytest.raises(ddsimp.IoError, match="missing.vtk") as missing:
        ddsimp.read(tmp_path / "missing.vtk")
    assert isinstance(missing.value, OSError)
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")  # two of three vertices, no face
    with pytest.raises(ddsimp.IoError, match="bad.off"):
        ddsimp.read(bad)
    with pytest.raises(ddsimp.IoError, match="stl"):
        ddsimp.write(tmp_path / "out.stl", np.zeros((3, 3)), [[0, 1, 2]])


def test_kinds_are_written_and_read_back(data, tmp_path):
    mesh = ddsimp.read(data / "surfaces" / "SurfaceVectors.vtk")
    assert set(mesh.kinds) == set(mesh.fields)
    fields = dict(mesh.fields)
    fields["PointId"] = np.arange(len(mesh.points), dtype=np.float32)
    path = tmp_path / "ids.vtp"
    ddsimp.write(path, mesh.points, mesh.triangles, fields, kinds={"PointId": "label"})
    back = ddsimp.read(path)
    assert back.kinds["PointId"] == "label"
    np.testing.assert_array_equal(back.fields["PointId"], fields["PointId"])
    # simplify(mesh) takes the mesh's kinds: the ids stay ids.
    r = ddsimp.simplify(back, keep=0.2)
    assert r.kinds["PointId"] == "label"
    assert set(r.fields["PointId"].tolist()) <= set(fields["PointId"].tolist())
