// The parts of the _ddsimp extension module, each adding its functions and classes to it.
#pragma once

#include <pybind11/pybind11.h>

namespace ddsimp::python {

namespace py = pybind11;

void bind_errors(py::module_& m);   // InputError, IoError, ClientError
void bind_simplify(py::module_& m); // Mesh, Result, simplify, ProgressiveRecord
void bind_io(py::module_& m);       // read, write
void bind_client(py::module_& m);   // Client and what it returns

} // namespace ddsimp::python
