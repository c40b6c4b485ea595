"""pvpython, headless: the plugin's DataDependentDecimation filter on real surfaces."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pvtest  # noqa: E402  (sets up ParaView's modules first)

import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

simple = pvtest.load_plugin(globals())
data = pvtest.required("DDSIMP_SHARED_DATA")


def point_arrays(poly):
    pd = poly.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}


def points(poly):
    return vtk_to_numpy(poly.GetPoints().GetData())


def only_triangles(poly):
    return (poly.GetNumberOfVerts() == 0 and poly.GetNumberOfLines() == 0
            and poly.GetNumberOfStrips() == 0 and poly.GetPolys().IsHomogeneous() == 3)


# The filter is in the Filters menu's proxies, with its properties.
assert "DataDependentDecimation" in dir(simple.servermanager.filters)
assert "PublishToSession" in dir(simple.servermanager.filters)
vectors = simple.ExtractSurface(Input=simple.LegacyVTKReader(
    FileNames=[os.path.join(data, "surfaces", "SurfaceVectors.vtk")]))
source = pvtest.fetch(vectors)
assert source.GetNumberOfPolys() == 756
decimate = DataDependentDecimation(Input=vectors)
for name in ["Alpha", "Keep", "Strategy", "Placement", "DataPlacement", "DrivingFields",
             "FeatureAngle"]:
    assert name in decimate.ListProperties(), name
assert list(decimate.DrivingFields) == []  # none chosen: every field drives the data term

# Edge collapse to a quarter: triangles, every point array with its components, the report.
decimate.Keep = 0.25
decimate.Alpha = 0.5
out = pvtest.fetch(decimate)
assert 0 < out.GetNumberOfPolys() <= 756 // 4, out.GetNumberOfPolys()
assert only_triangles(out)
arrays_in, arrays_out = point_arrays(source), point_arrays(out)
assert list(arrays_out) == list(arrays_in), (list(arrays_out), list(arrays_in))
for name, values in arrays_in.items():
    assert arrays_out[name].shape[1:] == values.shape[1:], name
    assert len(arrays_out[name]) == out.GetNumberOfPoints()
assert pvtest.field_value(out, "TargetReached") == 1
assert pvtest.field_value(out, "StopReason") == "target reached"
assert pvtest.field_value(out, "TrianglesIn") == 756
assert pvtest.field_value(out, "TrianglesOut") == out.GetNumberOfPolys()
first = points(out).copy()
assert np.array_equal(points(pvtest.fetch(decimate)), first)  # the same again

# Vertex removal keeps input points with exactly their data.
decimate.Strategy = "vertex"
out = pvtest.fetch(decimate)
assert 0 < out.GetNumberOfPolys() <= 756 // 4
index = {tuple(p): i for i, p in enumerate(points(source).tolist())}
arrays_out = point_arrays(out)
for j, p in enumerate(points(out).tolist()):
    i = index[tuple(p)]
    for name, values in arrays_in.items():
        assert np.array_equal(arrays_out[name][j], values[i].astype(np.float32)), name

# The choices reach the library: other driving fields, another placement, another result.
decimate.Strategy = "edge"
decimate.Alpha = 0.0
decimate.DrivingFields = ["Temp"]
by_temp = points(pvtest.fetch(decimate)).copy()
decimate.DrivingFields = ["V"]
by_velocity = points(pvtest.fetch(decimate)).copy()
assert by_temp.shape != by_velocity.shape or not np.array_equal(by_temp, by_velocity)
decimate.DrivingFields = []
decimate.Placement = "midpoint"
midpoint = points(pvtest.fetch(decimate)).copy()
decimate.Placement = "least-error"
least_error = points(pvtest.fetch(decimate)).copy()
assert midpoint.shape != least_error.shape or not np.array_equal(midpoint, least_error)
assert decimate.DataPlacement == "least-error"  # the library's default
least_error_data = point_arrays(pvtest.fetch(decimate))["Temp"].copy()
decimate.DataPlacement = "interpolated"
interpolated = point_arrays(pvtest.fetch(decimate))["Temp"].copy()
assert (least_error_data.shape != interpolated.shape
        or not np.array_equal(least_error_data, interpolated))
decimate.DataPlacement = "least-error"

# A closed surface with its scalar field, read by ParaView's XML reader.
earth = simple.XMLPolyDataReader(FileName=[os.path.join(data, "surfaces", "earth.vtp")])
on_earth = DataDependentDecimation(Input=earth, Keep=0.1, Strategy="vertex")
out = pvtest.fetch(on_earth)
assert 0 < out.GetNumberOfPolys() <= 8192 and only_triangles(out)
assert "bottomDepth" in point_arrays(out)
assert pvtest.field_value(out, "TargetReached") == 1

# Quadrilaterals are triangulated first (a 20 x 20 plane: 800 triangles).
plane = simple.Plane(XResolution=20, YResolution=20)
out = pvtest.fetch(DataDependentDecimation(Input=plane, Keep=0.5))
assert 0 < out.GetNumberOfPolys() <= 400 and only_triangles(out)
assert pvtest.field_value(out, "TrianglesIn") == 800

# Feature lines: on the fandisk (a machined part), 45 degrees makes its sharp edges feature
# lines, which are kept like boundaries: another result than without feature lines.
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData  # noqa: E402


def produce(poly):
    producer = simple.TrivialProducer()
    producer.GetClientSideObject().SetOutput(poly)
    return producer


def read_off(path):
    """ParaView reads no .off: header, counts, coordinates, then "3 i j k" faces."""
    words = open(path).read().split()
    assert words[0] == "OFF"
    n_points, n_faces = int(words[1]), int(words[2])
    values = words[4:]
    poly, pts, cells = vtkPolyData(), vtkPoints(), vtkCellArray()
    for i in range(n_points):
        pts.InsertNextPoint(*map(float, values[3 * i:3 * i + 3]))
    faces = values[3 * n_points:]
    for f in range(n_faces):
        assert faces[4 * f] == "3"
        cells.InsertNextCell(3, [int(v) for v in faces[4 * f + 1:4 * f + 4]])
    poly.SetPoints(pts)
    poly.SetPolys(cells)
    return poly


fandisk = produce(read_off(os.path.join(data, "geometry", "fandisk.off")))
with_features = points(pvtest.fetch(
    DataDependentDecimation(Input=fandisk, Keep=0.1, FeatureAngle=45))).copy()
without = points(pvtest.fetch(
    DataDependentDecimation(Input=fandisk, Keep=0.1, FeatureAngle=180))).copy()
assert with_features.shape != without.shape or not np.array_equal(with_features, without)

# Input the library refuses (a coordinate that is not a number): an error, an empty output.

bad = vtkPolyData()
bad_points = vtkPoints()
for p in [(0, 0, 0), (1, 0, 0), (0, math.nan, 0)]:
    bad_points.InsertNextPoint(p)
bad.SetPoints(bad_points)
cells = vtkCellArray()
cells.InsertNextCell(3, [0, 1, 2])
bad.SetPolys(cells)
refused = DataDependentDecimation(Input=produce(bad))
out = pvtest.fetch(refused)
assert out.GetNumberOfPoints() == 0 and out.GetNumberOfPolys() == 0
print("decimation: all checks passed")
