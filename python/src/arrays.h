// numpy arrays <-> ddsimp::Surface. Input arrays are copied once into the Surface (the library
// owns its arrays); output arrays take over the Surface's vectors without copying them.
#pragma once

#include "ddsimp/ddsimp.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace ddsimp::python {

namespace py = pybind11;

// A surface as numpy arrays: points (N, 3) float32, triangles (M, 3) uint32, and one array per
// field, (N,) for a scalar or (N, k) for k components, float32, in the surface's field order.
struct Mesh {
    py::array points;
    py::array triangles;
    py::dict fields;
};

// The surface of `points` (N, 3), `triangles` (M, 3) and `fields` (a mapping of name to (N,) or
// (N, k) arrays, or None). Any real dtype for points and fields, any integer dtype for
// triangles; throws InputError naming the array and what is wrong with its shape or values.
// Everything else (index range, finite values, field lengths) is ddsimp::validate's to check.
Surface surface_from_arrays(py::handle points, py::handle triangles, py::handle fields);

// The arrays of `surface`, moved out of it (no copy).
Mesh mesh_from_surface(Surface&& surface);

// A float32 array over `values`, which it takes over; `shape` must match its size.
py::array float_array(std::vector<float>&& values, std::vector<py::ssize_t> shape);

} // namespace ddsimp::python
