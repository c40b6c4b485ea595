"""ddsimp.simplify: numpy in and out, the options, and what the run reports."""
import json
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

import ddsimp


@pytest.fixture(scope="module")
def vectors(data):
    return ddsimp.read(data / "surfaces" / "SurfaceVectors.vtk")


@pytest.fixture(scope="module")
def earth(data):
    return ddsimp.read(data / "surfaces" / "earth.vtp")


def test_edge_collapse_reaches_the_target_and_carries_every_field(vectors):
    r = ddsimp.simplify(vectors.points, vectors.triangles, vectors.fields, alpha=0.5, keep=0.25)
    assert r.triangles_in == 756
    assert r.triangles_out == len(r.triangles) <= 756 // 4
    assert r.target_reached and r.stop == "target_reached" and r.stop_reason == "target reached"
    assert r.points.shape == (len(r.points), 3) and r.points.dtype == np.float32
    assert r.triangles.shape[1] == 3 and r.triangles.dtype == np.uint32
    assert r.triangles.max() < len(r.points)
    assert list(r.fields) == list(vectors.fields)
    for name, values in vectors.fields.items():
        out = r.fields[name]
        assert out.shape == (len(r.points),) + values.shape[1:]
        # Data at a new point is interpolated along an edge: never outside the input's range.
        assert (out.min(axis=0) >= values.min(axis=0) - 1e-5 * np.abs(values).max()).all()
        assert (out.max(axis=0) <= values.max(axis=0) + 1e-5 * np.abs(values).max()).all()


def test_vertex_removal_keeps_the_input_points_and_their_data_exactly(vectors):
    r = ddsimp.simplify(vectors, strategy="vertex", keep=0.3)
    assert r.target_reached and len(r.triangles) <= int(0.3 * 756)
    index = {tuple(p): i for i, p in enumerate(vectors.points.tolist())}
    for j, p in enumerate(r.points.tolist()):
        i = index[tuple(p)]  # a KeyError would be a point that is not an input point
        for name, values in vectors.fields.items():
            np.testing.assert_array_equal(r.fields[name][j], values[i])


def test_output_arrays_own_the_library_memory_without_a_copy(vectors):
    r = ddsimp.simplify(vectors, keep=0.5)
    for a in [r.points, r.triangles, *r.fields.values()]:
        assert not a.flags.owndata and a.base is not None  # held by the library's buffer
        assert a.flags.c_contiguous and a.flags.writeable


def test_same_input_and_options_give_the_same_bytes_at_any_thread_count(earth):
    one = ddsimp.simplify(earth, keep=0.2, alpha=0.3, threads=1)
    two = ddsimp.simplify(earth, keep=0.2, alpha=0.3, threads=2)
    assert one.points.tobytes() == two.points.tobytes()
    assert one.triangles.tobytes() == two.triangles.tobytes()
    assert one.fields["bottomDepth"].tobytes() == two.fields["bottomDepth"].tobytes()


def test_target_triangles_wins_over_keep(vectors):
    r = ddsimp.simplify(vectors, keep=0.9, target_triangles=100)
    assert len(r.triangles) <= 100 and r.target_reached


def test_other_dtypes_and_layouts_are_accepted(vectors):
    points64 = np.asfortranarray(vectors.points.astype(np.float64))
    triangles64 = vectors.triangles.astype(np.int64)
    a = ddsimp.simplify(points64, triangles64, {"T": vectors.fields["Temp"].astype(np.float64)},
                        keep=0.5)
    b = ddsimp.simplify(vectors.points, vectors.triangles, {"T": vectors.fields["Temp"]}, keep=0.5)
    assert a.points.tobytes() == b.points.tobytes()
    assert a.triangles.tobytes() == b.triangles.tobytes()
    assert a.fields["T"].tobytes() == b.fields["T"].tobytes()


def test_the_options_mean_what_the_command_line_options_mean(earth, data, cli, tmp_path):
    """The same options through the command line give the same surface (the options mapping)."""
    out = tmp_path / "earth.vtp"
    args = ["--alpha", "0.3", "--keep", "0.15", "--strategy", "edge", "--placement", "midpoint",
            "--data", "interpolated", "--feature-angle", "60", "--max-normal-turn", "45",
            "--line-tolerance", "10"]
    report = subprocess.run([cli, "simplify", str(data / "surfaces" / "earth.vtp"), "-o",
                             str(out), "--json", *args], check=True, capture_output=True, text=True)
    r = ddsimp.simplify(earth, alpha=0.3, keep=0.15, strategy="edge", placement="midpoint",
                        data_placement="interpolated", feature_angle=60, max_normal_turn=45,
                        line_tolerance=10)
    assert json.loads(report.stdout)["triangles_out"] == len(r.triangles)
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(out))
    reader.Update()
    poly = reader.GetOutput()
    np.testing.assert_array_equal(vtk_to_numpy(poly.GetPoints().GetData()), r.points)
    cells = vtk_to_numpy(poly.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    np.testing.assert_array_equal(cells, r.triangles)
    np.testing.assert_array_equal(
        vtk_to_numpy(poly.GetPointData().GetArray("bottomDepth")), r.fields["bottomDepth"])


def test_data_placement_chooses_the_new_points_data(earth):
    """Least error (the default) and interpolation give the same kind of surface with other data."""
    least = ddsimp.simplify(earth, alpha=0.0, keep=0.2)
    assert ddsimp.simplify(earth, alpha=0.0, keep=0.2, data_placement="least-error").fields[
        "bottomDepth"].tobytes() == least.fields["bottomDepth"].tobytes()
    interpolated = ddsimp.simplify(earth, alpha=0.0, keep=0.2, data_placement="interpolated")
    assert least.fields["bottomDepth"].tobytes() != interpolated.fields["bottomDepth"].tobytes()


def test_gradient_fields_choose_the_data_that_drives_the_weight(vectors):
    by_temp = ddsimp.simplify(vectors, keep=0.3, alpha=0.0, gradient_fields=["Temp"])
    by_velocity = ddsimp.simplify(vectors, keep=0.3, alpha=0.0, gradient_fields=["V"])
    assert by_temp.triangles.tobytes() != by_velocity.triangles.tobytes()


def test_progress_is_reported_and_false_cancels(earth):
    seen = []
    r = ddsimp.simplify(earth, keep=0.1, progress=seen.append)
    assert r.target_reached and seen and all(0 <= f <= 1 for f in seen)
    assert seen == sorted(seen)
    cancelled = ddsimp.simplify(earth, keep=0.1, progress=lambda done: False)
    assert cancelled.stop == "cancelled" and not cancelled.target_reached
    assert len(cancelled.triangles) > len(r.triangles)


def test_an_exception_in_progress_stops_the_run_and_is_raised(earth):
    def fail(done):
        raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        ddsimp.simplify(earth, keep=0.1, progress=fail)


def test_other_python_threads_run_while_it_computes(earth):
    """Between two progress calls the library computes. With a switch interval far longer than
    the run, a thread holding the GIL there would keep the main thread from running at all; with
    the GIL released, the main thread counts on meanwhile (it hands the GIL back at each sleep)."""
    state = {"ticks": 0, "gaps": []}
    last = [None]

    def progress(done):
        if last[0] is not None:
            state["gaps"].append(state["ticks"] - last[0])
        last[0] = state["ticks"]

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1000)
    try:
        worker = threading.Thread(target=ddsimp.simplify, args=(earth,),
                                  kwargs={"keep": 0.05, "progress": progress})
        worker.start()
        while worker.is_alive():
            state["ticks"] += 1
            time.sleep(0)
        worker.join()
    finally:
        sys.setswitchinterval(interval)
    assert len(state["gaps"]) > 10
    assert any(gap > 0 for gap in state["gaps"])


def test_a_label_field_is_carried_never_mixed(vectors):
    n = len(vectors.points)
    fields = dict(vectors.fields)
    fields["PointId"] = np.arange(n, dtype=np.float32) * 10 + 1
    r = ddsimp.simplify(vectors.points, vectors.triangles, fields, keep=0.1,
                        kinds={"PointId": "label"})
    assert r.kinds["PointId"] == "label"
    assert r.kinds[next(iter(vectors.fields))] == "continuous"
    assert set(r.fields["PointId"].tolist()) <= set(fields["PointId"].tolist())
    # The same run from a mesh takes the mesh's kinds.
    record = ddsimp.ProgressiveRecord(vectors.points, vectors.triangles, fields,
                                      kinds={"PointId": "label"})
    level = record.level(0.1)
    assert level.kinds["PointId"] == "label"
    np.testing.assert_array_equal(level.fields["PointId"], r.fields["PointId"])


def test_an_unknown_kind_or_field_in_kinds_is_an_input_error(vectors):
    with pytest.raises(ddsimp.InputError, match="is not one of continuous, label, direction"):
        ddsimp.simplify(vectors, kinds={next(iter(vectors.fields)): "integer"})
    with pytest.raises(ddsimp.InputError, match='names the field "nope"'):
        ddsimp.simplify(vectors, kinds={"nope": "label"})
