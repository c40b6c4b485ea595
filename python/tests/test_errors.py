"""The library's refusals as Python exceptions with its messages."""
import numpy as np
import pytest

import ddsimp

POINTS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], dtype=np.float32)
TRIANGLES = np.array([[0, 1, 2], [1, 3, 2]])


def test_a_valid_square_is_fine():
    r = ddsimp.simplify(POINTS, TRIANGLES, keep=1.0)
    assert len(r.triangles) == 2 and r.target_reached


def test_an_index_out_of_range_is_an_input_error_with_the_library_message():
    with pytest.raises(ddsimp.InputError,
                       match="triangle 1 refers to vertex 9, but the surface has 4 vertices"):
        ddsimp.simplify(POINTS, [[0, 1, 2], [1, 9, 2]])


def test_a_negative_index_is_reported_not_wrapped():
    with pytest.raises(ddsimp.InputError, match="triangle 1 refers to vertex -1"):
        ddsimp.simplify(POINTS, [[0, 1, 2], [1, -1, 2]])


def test_input_errors_are_value_errors():
    assert issubclass(ddsimp.InputError, ValueError)
    assert issubclass(ddsimp.IoError, OSError)
    assert issubclass(ddsimp.ClientError, RuntimeError)


def test_a_non_finite_coordinate_is_refused():
    bad = POINTS.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ddsimp.InputError, match="(?i)finite"):
        ddsimp.simplify(bad, TRIANGLES)


@pytest.mark.parametrize("points, triangles, message", [
    (POINTS[:, :2], TRIANGLES, r"points must have shape \(N, 3\), got \(4, 2\)"),
    (POINTS, TRIANGLES.ravel(), r"triangles must have shape \(M, 3\), got \(6,\)"),
    (POINTS, TRIANGLES.astype(np.float32), "triangles must hold integers"),
    (np.array([["a", "b", "c"]]), TRIANGLES, "points must hold real numbers"),
])
def test_arrays_of_the_wrong_shape_or_type_say_which_and_why(points, triangles, message):
    with pytest.raises(ddsimp.InputError, match=message):
        ddsimp.simplify(points, triangles)


def test_a_field_of_the_wrong_length_is_named():
    with pytest.raises(ddsimp.InputError, match="T"):
        ddsimp.simplify(POINTS, TRIANGLES, {"T": np.zeros(3)})


def test_bad_options_say_what_is_allowed():
    with pytest.raises(ddsimp.InputError, match='"edge", "vertex"'):
        ddsimp.simplify(POINTS, TRIANGLES, strategy="collapse")
    with pytest.raises(ddsimp.InputError, match="least-error"):
        ddsimp.simplify(POINTS, TRIANGLES, placement="centre")
    with pytest.raises(ddsimp.InputError, match='"least-error", "interpolated"'):
        ddsimp.simplify(POINTS, TRIANGLES, data_placement="mean")
    with pytest.raises(ddsimp.InputError, match="(?i)alpha"):
        ddsimp.simplify(POINTS, TRIANGLES, alpha=1.5)
    with pytest.raises(ddsimp.InputError, match="list of field names"):
        ddsimp.simplify(POINTS, TRIANGLES, gradient_fields="T")
    with pytest.raises(ddsimp.InputError, match="unknown field 'P'"):
        ddsimp.simplify(POINTS, TRIANGLES, {"T": np.zeros(4)}, gradient_fields=["P"])
    with pytest.raises(TypeError):
        ddsimp.simplify(POINTS, TRIANGLES, alhpa=0.5)


def test_a_mesh_or_arrays_but_not_points_alone():
    with pytest.raises(ddsimp.InputError, match="give points and triangles"):
        ddsimp.simplify(POINTS)
