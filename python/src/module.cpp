// _ddsimp: the compiled part of the ddsimp Python package (python/ddsimp/__init__.py wraps it).
#include "bindings.h"

PYBIND11_MODULE(_ddsimp, m) {
    m.doc() = "ddsimp's library, file I/O and client (use the ddsimp package, not this module)";
    ddsimp::python::bind_errors(m);
    ddsimp::python::bind_simplify(m);
    ddsimp::python::bind_io(m);
    ddsimp::python::bind_client(m);
}
