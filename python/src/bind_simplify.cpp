// ddsimp.simplify, ddsimp.Mesh, ddsimp.Result and ddsimp.ProgressiveRecord.
#include "arrays.h"
#include "bindings.h"
#include "options.h"

namespace ddsimp::python {

namespace {

// What ddsimp.simplify returns: the reduced mesh and how the run went.
struct SimplifyResult : Mesh {
    bool target_reached = false;
    std::string stop;        // stop_name(): "target_reached", ...
    std::string stop_reason; // describe(): "target reached", ...
    size_t triangles_in = 0, triangles_out = 0, operations = 0;
    py::dict repairs;
};

py::dict repairs_dict(const RepairReport& r) {
    py::dict d;
    d["degenerate_triangles_dropped"] = r.degenerate_triangles_dropped;
    d["duplicate_triangles_dropped"] = r.duplicate_triangles_dropped;
    d["unused_vertices"] = r.unused_vertices;
    d["triangles_flipped"] = r.triangles_flipped;
    return d;
}

SimplifyResult simplify_arrays(py::handle points, py::handle triangles, py::handle fields,
                               py::kwargs kwargs) {
    const Surface input = surface_from_arrays(points, triangles, fields, take_kinds(kwargs));
    Options options = options_from_kwargs(kwargs);
    Progress progress(kwargs);
    progress.install(options);
    Result r;
    {
        py::gil_scoped_release released;
        r = simplify(input, options);
    }
    progress.rethrow();
    SimplifyResult out;
    static_cast<Mesh&>(out) = mesh_from_surface(std::move(r.surface));
    out.target_reached = r.target_reached;
    out.stop = stop_name(r.stop);
    out.stop_reason = describe(r.stop);
    out.triangles_in = r.triangles_in;
    out.triangles_out = r.triangles_out;
    out.operations = r.operations;
    out.repairs = repairs_dict(r.repairs);
    return out;
}

// ProgressiveRecord with the GIL released while it is built and levels are extracted.
class Record {
public:
    Record(py::handle points, py::handle triangles, py::handle fields, py::kwargs kwargs) {
        if (!kwargs.contains("keep")) kwargs["keep"] = 0.0; // record every operation
        const Surface input = surface_from_arrays(points, triangles, fields, take_kinds(kwargs));
        Options options = options_from_kwargs(kwargs);
        Progress progress(kwargs);
        progress.install(options);
        {
            py::gil_scoped_release released;
            record_ = ProgressiveRecord::build(input, options);
        }
        progress.rethrow();
    }

    // The triangle target of `keep`, counted as the library (and the server) counts it.
    size_t target(double keep) const {
        Options o;
        o.keep_fraction = keep;
        check_options(o);
        return target_triangles(o, record_.triangles_in());
    }
    size_t target(const py::object& keep, const py::object& triangles) const {
        if (keep.is_none() == triangles.is_none())
            throw InputError("give either keep (a fraction) or triangles (a count)");
        return triangles.is_none() ? target(keep.cast<double>()) : triangles.cast<size_t>();
    }

    Mesh level(const py::object& keep, const py::object& triangles) const {
        const size_t n = target(keep, triangles);
        Surface s;
        {
            py::gil_scoped_release released;
            s = record_.level(n);
        }
        return mesh_from_surface(std::move(s));
    }

    py::dict error(const py::object& keep, const py::object& triangles) const {
        const LevelError e = record_.error_after(record_.operations_for(target(keep, triangles)));
        py::dict d;
        d["geometric"] = e.geometric;
        d["data"] = e.data;
        d["data_components"] = e.data_components;
        return d;
    }

    const ProgressiveRecord& record() const { return record_; }

private:
    ProgressiveRecord record_;
};

std::string mesh_repr(py::object self) {
    const Mesh& m = self.cast<const Mesh&>();
    std::string fields;
    for (auto item : m.fields)
        fields += (fields.empty() ? "" : ", ") + py::str(item.first).cast<std::string>();
    return "<ddsimp." + py::str(self.get_type().attr("__name__")).cast<std::string>() + " " +
           std::to_string(m.points.shape(0)) + " points, " + std::to_string(m.triangles.shape(0)) +
           " triangles, fields [" + fields + "]>";
}

} // namespace

void bind_simplify(py::module_& m) {
    py::class_<Mesh>(m, "Mesh", "A triangle surface as numpy arrays.")
        .def_readonly("points", &Mesh::points, "(N, 3) float32 vertex positions")
        .def_readonly("triangles", &Mesh::triangles, "(M, 3) uint32 vertex indices")
        .def_readonly("fields", &Mesh::fields,
                      "dict: name -> (N,) or (N, k) float32 per-vertex values")
        .def_readonly("kinds", &Mesh::kinds,
                      "dict: name -> \"continuous\", \"label\" (ids: never mixed, not driving the "
                      "data term by default) or \"direction\" (normals: kept unit length)")
        .def("__repr__", &mesh_repr);

    py::class_<SimplifyResult, Mesh>(m, "Result", "The reduced surface and how the run went.")
        .def_readonly("target_reached", &SimplifyResult::target_reached)
        .def_readonly("stop", &SimplifyResult::stop,
                      "why the run stopped: \"target_reached\", \"weight_bound\", "
                      "\"nothing_removable\" or \"cancelled\"")
        .def_readonly("stop_reason", &SimplifyResult::stop_reason,
                      "the same for a person (\"target reached\", ...)")
        .def_readonly("triangles_in", &SimplifyResult::triangles_in)
        .def_readonly("triangles_out", &SimplifyResult::triangles_out)
        .def_readonly("operations", &SimplifyResult::operations)
        .def_readonly("repairs", &SimplifyResult::repairs,
                      "what the input checks repaired (counts by kind)");

    m.def("option_defaults", &option_defaults);
    m.def("simplify", &simplify_arrays, py::arg("points"), py::arg("triangles"),
          py::arg("fields") = py::none());

    py::class_<Record>(m, "ProgressiveRecord")
        .def(py::init<py::handle, py::handle, py::handle, py::kwargs>(), py::arg("points"),
             py::arg("triangles"), py::arg("fields") = py::none())
        .def("level", &Record::level, py::arg("keep") = py::none(),
             py::arg("triangles") = py::none())
        .def("error", &Record::error, py::arg("keep") = py::none(),
             py::arg("triangles") = py::none())
        .def("triangles_for", py::overload_cast<double>(&Record::target, py::const_),
             py::arg("keep"))
        .def_property_readonly("operations",
                               [](const Record& r) { return r.record().operations(); })
        .def_property_readonly("triangles_in",
                               [](const Record& r) { return r.record().triangles_in(); })
        .def_property_readonly("stop", [](const Record& r) { return stop_name(r.record().stop()); })
        .def_property_readonly("stop_reason",
                               [](const Record& r) { return describe(r.record().stop()); })
        .def_property_readonly("repairs",
                               [](const Record& r) { return repairs_dict(r.record().repairs()); });
}

} // namespace ddsimp::python
