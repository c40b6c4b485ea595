// numpy arrays <-> ddsimp::Surface. Input arrays are copied once into the Surface (the library
// owns its arrays); output arrays take over the Surface's vectors without copying them.
#pragma once

#include "ddsimp/ddsimp.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace ddsimp::python {

namespace py = pybind11;

// A surface as numpy arrays: points (N, 3) float32, triangles (M, 3) uint32, and one array per
// field, (N,) for a scalar or (N, k) for k components, float32, in the surface's field order;
// `kinds` names each field's kind ("continuous", "label" or "direction", see ddsimp::FieldKind).
struct Mesh {
    py::array points;
    py::array triangles;
    py::dict fields;
    py::dict kinds;
};

// The surface of `points` (N, 3), `triangles` (M, 3) and `fields` (a mapping of name to (N,) or
// (N, k) arrays, or None). Any real dtype for points and fields, any integer dtype for
// triangles; throws InputError naming the array and what is wrong with its shape or values.
// Everything else (index range, finite values, field lengths) is ddsimp::validate's to check.
// `kinds` (a mapping of field name to "continuous", "label" or "direction", or None) sets the
// kinds of the fields it names (the others are continuous); an unknown name or kind is an
// InputError.
Surface surface_from_arrays(py::handle points, py::handle triangles, py::handle fields,
                            py::handle kinds = py::none());

// The "kinds" keyword argument taken out of `kwargs` (None if absent).
py::object take_kinds(py::kwargs& kwargs);

// The arrays of `surface`, moved out of it (no copy).
Mesh mesh_from_surface(Surface&& surface);

// A float32 array over `values`, which it takes over; `shape` must match its size.
py::array float_array(std::vector<float>&& values, std::vector<py::ssize_t> shape);

} // namespace ddsimp::python
