// ddsimp.read and ddsimp.write: the command line's file formats (io/, ddsimp/io/surface_io.h).
#include "arrays.h"
#include "bindings.h"
#include "ddsimp/io/surface_io.h"

namespace ddsimp::python {

void bind_io(py::module_& m) {
    m.def(
        "read",
        [](const std::string& path) {
            Surface s;
            {
                py::gil_scoped_release released;
                s = io::read_surface(path);
            }
            return mesh_from_surface(std::move(s));
        },
        py::arg("path"));
    m.def(
        "write",
        [](const std::string& path, py::handle points, py::handle triangles, py::handle fields,
           py::handle kinds) {
            const Surface s = surface_from_arrays(points, triangles, fields, kinds);
            py::gil_scoped_release released;
            io::write_surface(s, path);
        },
        py::arg("path"), py::arg("points"), py::arg("triangles"), py::arg("fields") = py::none(),
        py::arg("kinds") = py::none());
}

} // namespace ddsimp::python
