// numpy arrays <-> ddsimp::Surface (see arrays.h).
#include "arrays.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

namespace ddsimp::python {

namespace {

std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

// `values` as a C-contiguous float32 array: the same object when it is one already.
py::array_t<float, py::array::c_style> as_float32(py::handle values, const std::string& what) {
    py::array a = py::array::ensure(values);
    if (!a) throw InputError(what + " is not an array of numbers");
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        throw InputError(what + " must hold real numbers, not dtype " +
                         py::str(a.dtype()).cast<std::string>());
    return py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
}

// Owns a vector whose buffer a numpy array points into.
template <class T> py::array take_vector(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
    auto* owner = new std::vector<T>(std::move(values));
    py::capsule free_owner(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<T>(std::move(shape), owner->data(), free_owner);
}

std::vector<uint32_t> triangle_indices(py::handle triangles) {
    py::array a = py::array::ensure(triangles);
    if (!a) throw InputError("triangles is not an array of vertex indices");
    if (a.ndim() != 2 || a.shape(1) != 3)
        throw InputError("triangles must have shape (M, 3), got " + shape_text(a));
    const char kind = a.dtype().kind();
    if (kind != 'i' && kind != 'u')
        throw InputError("triangles must hold integers, not dtype " +
                         py::str(a.dtype()).cast<std::string>());
    std::vector<uint32_t> out(size_t(a.size()));
    if (kind == 'u' && a.itemsize() == 4) {
        auto c = py::array_t<uint32_t, py::array::c_style | py::array::forcecast>::ensure(a);
        if (!out.empty()) std::memcpy(out.data(), c.data(), out.size() * sizeof(uint32_t));
        return out;
    }
    // Other widths and signed types go through int64 so that a negative or too large index is
    // reported, not wrapped around.
    auto c = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    const int64_t* in = c.data();
    for (size_t i = 0; i < out.size(); ++i) {
        if (in[i] < 0 || in[i] > int64_t(std::numeric_limits<uint32_t>::max()))
            throw InputError("triangle " + std::to_string(i / 3) + " refers to vertex " +
                             std::to_string(in[i]) + ", which is not a valid index");
        out[i] = uint32_t(in[i]);
    }
    return out;
}

} // namespace

namespace {

const char* kind_name(FieldKind kind) {
    switch (kind) {
    case FieldKind::Label:
        return "label";
    case FieldKind::Direction:
        return "direction";
    case FieldKind::Continuous:
        break;
    }
    return "continuous";
}

void set_kinds(Surface& s, py::handle kinds) {
    if (kinds.is_none()) return;
    if (!py::isinstance<py::dict>(kinds) && !py::hasattr(kinds, "items"))
        throw InputError("kinds must be a mapping of field name to kind, e.g. {\"id\": \"label\"}");
    for (auto item : kinds.attr("items")()) {
        auto pair = item.cast<py::tuple>();
        const std::string name = py::str(pair[0]).cast<std::string>();
        const std::string kind = py::str(pair[1]).cast<std::string>();
        auto field = std::find_if(s.fields.begin(), s.fields.end(),
                                  [&](const Field& f) { return f.name == name; });
        if (field == s.fields.end())
            throw InputError("kinds names the field \"" + name + "\", which is not given");
        if (kind == "continuous")
            field->kind = FieldKind::Continuous;
        else if (kind == "label")
            field->kind = FieldKind::Label;
        else if (kind == "direction")
            field->kind = FieldKind::Direction;
        else
            throw InputError("field \"" + name + "\": kind \"" + kind +
                             "\" is not one of continuous, label, direction");
    }
}

} // namespace

py::object take_kinds(py::kwargs& kwargs) {
    return kwargs.attr("pop")("kinds", py::none());
}

Surface surface_from_arrays(py::handle points, py::handle triangles, py::handle fields,
                            py::handle kinds) {
    Surface s;
    {
        auto p = as_float32(points, "points");
        if (p.ndim() != 2 || p.shape(1) != 3)
            throw InputError("points must have shape (N, 3), got " + shape_text(p));
        s.positions.assign(p.data(), p.data() + p.size());
    }
    s.triangles = triangle_indices(triangles);
    if (fields.is_none()) {
        set_kinds(s, kinds);
        return s;
    }
    if (!py::isinstance<py::dict>(fields) && !py::hasattr(fields, "items"))
        throw InputError("fields must be a mapping of name to array, e.g. {\"T\": t}");
    for (auto item : fields.attr("items")()) {
        auto pair = item.cast<py::tuple>();
        if (!py::isinstance<py::str>(pair[0]))
            throw InputError("field names must be strings, got " +
                             py::repr(pair[0]).cast<std::string>());
        Field f;
        f.name = pair[0].cast<std::string>();
        auto v = as_float32(pair[1], "field \"" + f.name + "\"");
        if (v.ndim() == 1)
            f.components = 1;
        else if (v.ndim() == 2 && v.shape(1) >= 1)
            f.components = int(v.shape(1));
        else
            throw InputError("field \"" + f.name + "\" must have shape (N,) or (N, k), got " +
                             shape_text(v));
        f.values.assign(v.data(), v.data() + v.size());
        s.fields.push_back(std::move(f));
    }
    set_kinds(s, kinds);
    return s;
}

py::array float_array(std::vector<float>&& values, std::vector<py::ssize_t> shape) {
    return take_vector(std::move(values), std::move(shape));
}

Mesh mesh_from_surface(Surface&& surface) {
    Mesh m;
    const auto vertices = py::ssize_t(surface.vertex_count());
    const auto triangles = py::ssize_t(surface.triangle_count());
    m.points = take_vector(std::move(surface.positions), {vertices, 3});
    m.triangles = take_vector(std::move(surface.triangles), {triangles, 3});
    for (Field& f : surface.fields) {
        std::vector<py::ssize_t> shape{vertices};
        if (f.components != 1) shape.push_back(f.components);
        m.kinds[py::str(f.name)] = kind_name(f.kind);
        m.fields[py::str(f.name)] = take_vector(std::move(f.values), std::move(shape));
    }
    return m;
}

} // namespace ddsimp::python
