"""ddsimp.ProgressiveRecord: one run, every coarser level."""
import numpy as np
import pytest

import ddsimp


@pytest.fixture(scope="module")
def earth(data):
    return ddsimp.read(data / "surfaces" / "earth.vtp")


@pytest.mark.parametrize("strategy", ["edge", "vertex"])
def test_a_level_equals_simplify_to_that_target(earth, strategy):
    record = ddsimp.ProgressiveRecord(earth, alpha=0.4, strategy=strategy)
    assert record.triangles_in == 81920 and record.operations > 0
    for keep in [0.5, 0.2, 0.05]:
        level = record.level(keep)
        direct = ddsimp.simplify(earth, alpha=0.4, strategy=strategy, keep=keep)
        assert direct.target_reached
        assert record.triangles_for(keep) == int(keep * 81920)
        assert level.points.tobytes() == direct.points.tobytes()
        assert level.triangles.tobytes() == direct.triangles.tobytes()
        assert level.fields["bottomDepth"].tobytes() == direct.fields["bottomDepth"].tobytes()


def test_levels_by_count_coarsen_and_their_error_never_falls(earth):
    record = ddsimp.ProgressiveRecord(earth, keep=0.01)
    counts, errors = [], []
    for n in [40000, 20000, 5000, 1000]:
        level = record.level(triangles=n)
        assert len(level.triangles) <= n
        counts.append(len(level.triangles))
        errors.append(record.error(triangles=n))
    assert counts == sorted(counts, reverse=True)
    geometric = [e["geometric"] for e in errors]
    assert geometric == sorted(geometric) and geometric[-1] > 0
    assert all(e["data_components"] == 1 for e in errors)


def test_keep_and_triangles_are_one_or_the_other(earth):
    record = ddsimp.ProgressiveRecord(earth, keep=0.5)
    with pytest.raises(ddsimp.InputError, match="either keep"):
        record.level(0.5, triangles=100)
    with pytest.raises(ddsimp.InputError, match="keep fraction must be in"):
        record.level(1.5)


def test_the_input_level_is_the_repaired_input(data):
    mesh = ddsimp.read(data / "surfaces" / "SurfaceVectors.vtk")
    record = ddsimp.ProgressiveRecord(mesh)
    whole = record.level(1.0)
    np.testing.assert_array_equal(whole.points, mesh.points)
    assert len(whole.triangles) == 756
    assert record.stop in {"target_reached", "nothing_removable"}
