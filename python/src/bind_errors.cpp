// The library's exceptions as Python exceptions with the library's messages:
//   ddsimp::InputError     -> ddsimp.InputError (a ValueError)
//   ddsimp::io::IoError    -> ddsimp.IoError (an OSError)
//   ddsimp::ClientError    -> ddsimp.ClientError (a RuntimeError) with .code ("NOT_FOUND", ...)
#include "bindings.h"

#include "ddsimp/client.h"
#include "ddsimp/ddsimp.h"
#include "ddsimp/io/surface_io.h"

namespace ddsimp::python {

void bind_errors(py::module_& m) {
    // Kept alive for the process: the translator may run while the interpreter shuts down.
    static py::handle input_error =
        py::exception<InputError>(m, "InputError", PyExc_ValueError).release();
    static py::handle io_error = py::exception<io::IoError>(m, "IoError", PyExc_OSError).release();
    static py::handle client_error =
        py::exception<ClientError>(m, "ClientError", PyExc_RuntimeError).release();
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const ClientError& e) {
            py::object error = py::reinterpret_borrow<py::object>(client_error)(e.what());
            error.attr("code") = error_code_name(e.code());
            PyErr_SetObject(client_error.ptr(), error.ptr());
        } catch (const io::IoError& e) {
            PyErr_SetString(io_error.ptr(), e.what());
        } catch (const InputError& e) {
            PyErr_SetString(input_error.ptr(), e.what());
        }
    });
}

} // namespace ddsimp::python
