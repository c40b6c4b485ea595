// Conversion between ddsimp::Surface and OpenMesh's TriMesh (fields <-> vertex properties).
#include "ddsimp/openmesh.h"

#include <OpenMesh/Core/System/omstream.hh>

#include <string>

namespace ddsimp {

namespace {

// OpenMesh prints "complex edge" for every refused face; we report them in one error instead.
class QuietOpenMeshErrors {
public:
    QuietOpenMeshErrors() { omerr().disable(); }
    ~QuietOpenMeshErrors() { omerr().enable(); }
    QuietOpenMeshErrors(const QuietOpenMeshErrors&) = delete;
    QuietOpenMeshErrors& operator=(const QuietOpenMeshErrors&) = delete;
};

void add_field_property(TriMesh& mesh, const Field& field) {
    const size_t n = mesh.n_vertices();
    const int k = field.components;
    if (field.values.size() != n * size_t(k))
        throw InputError("field '" + field.name + "' has " + std::to_string(field.values.size()) +
                         " values, expected " + std::to_string(n * size_t(k)));
    if (k == 1) {
        OpenMesh::VPropHandleT<float> prop;
        mesh.add_property(prop, field.name);
        for (size_t v = 0; v < n; ++v)
            mesh.property(prop, TriMesh::VertexHandle(int(v))) = field.values[v];
    } else if (k == 3) {
        OpenMesh::VPropHandleT<OpenMesh::Vec3f> prop;
        mesh.add_property(prop, field.name);
        for (size_t v = 0; v < n; ++v) {
            const float* x = &field.values[3 * v];
            mesh.property(prop, TriMesh::VertexHandle(int(v))) = OpenMesh::Vec3f(x[0], x[1], x[2]);
        }
    } else {
        OpenMesh::VPropHandleT<std::vector<float>> prop;
        mesh.add_property(prop, field.name);
        for (size_t v = 0; v < n; ++v)
            mesh.property(prop, TriMesh::VertexHandle(int(v)))
                .assign(field.values.begin() + v * k, field.values.begin() + (v + 1) * k);
    }
}

// Reads one vertex property into a field if it is of a kind we know; false otherwise.
bool read_field_property(const TriMesh& mesh, const OpenMesh::BaseProperty& base,
                         const std::vector<TriMesh::VertexHandle>& vertices, Field& field) {
    field.name = base.name();
    field.values.clear();
    if (auto* p = dynamic_cast<const OpenMesh::PropertyT<float>*>(&base)) {
        field.components = 1;
        field.values.reserve(vertices.size());
        for (auto vh : vertices) field.values.push_back((*p)[vh.idx()]);
        return true;
    }
    if (auto* p = dynamic_cast<const OpenMesh::PropertyT<OpenMesh::Vec3f>*>(&base)) {
        field.components = 3;
        field.values.reserve(3 * vertices.size());
        for (auto vh : vertices)
            for (int c = 0; c < 3; ++c) field.values.push_back((*p)[vh.idx()][c]);
        return true;
    }
    if (auto* p = dynamic_cast<const OpenMesh::PropertyT<std::vector<float>>*>(&base)) {
        field.components = vertices.empty() ? 1 : int((*p)[vertices.front().idx()].size());
        if (field.components < 1)
            throw InputError("vertex property '" + field.name + "' has empty vectors");
        field.values.reserve(size_t(field.components) * vertices.size());
        for (auto vh : vertices) {
            const std::vector<float>& x = (*p)[vh.idx()];
            if (x.size() != size_t(field.components))
                throw InputError("vertex property '" + field.name + "' has " +
                                 std::to_string(x.size()) + " values at vertex " +
                                 std::to_string(vh.idx()) + " but " +
                                 std::to_string(field.components) + " at the first vertex");
            field.values.insert(field.values.end(), x.begin(), x.end());
        }
        return true;
    }
    (void)mesh;
    return false;
}

} // namespace

TriMesh to_openmesh(const Surface& surface) {
    if (surface.positions.size() % 3 != 0 || surface.triangles.size() % 3 != 0)
        throw InputError("positions and triangles must hold 3 values per element");
    TriMesh mesh;
    const size_t n = surface.vertex_count();
    mesh.reserve(n, 3 * surface.triangle_count(), surface.triangle_count());
    for (size_t v = 0; v < n; ++v) {
        const float* p = &surface.positions[3 * v];
        mesh.add_vertex(TriMesh::Point(p[0], p[1], p[2]));
    }

    size_t refused = 0;
    size_t first_refused = 0;
    {
        QuietOpenMeshErrors quiet;
        for (size_t t = 0; t < surface.triangle_count(); ++t) {
            const uint32_t* c = &surface.triangles[3 * t];
            // Checked here because OpenMesh's add_face does not check them itself.
            const bool in_range = c[0] < n && c[1] < n && c[2] < n;
            const bool distinct = c[0] != c[1] && c[1] != c[2] && c[0] != c[2];
            bool added = false;
            if (in_range && distinct)
                added = mesh.add_face(TriMesh::VertexHandle(int(c[0])),
                                      TriMesh::VertexHandle(int(c[1])),
                                      TriMesh::VertexHandle(int(c[2])))
                            .is_valid();
            if (!added && refused++ == 0) first_refused = t;
        }
    }
    if (refused > 0)
        throw InputError("OpenMesh refused " + std::to_string(refused) + " of " +
                         std::to_string(surface.triangle_count()) +
                         " triangles (non-manifold, degenerate or out of range); the first is "
                         "triangle " +
                         std::to_string(first_refused));

    for (const Field& field : surface.fields) add_field_property(mesh, field);
    return mesh;
}

Surface from_openmesh(const TriMesh& mesh) {
    Surface surface;
    // Compact indices: deleted vertices (if the mesh has status and garbage) are skipped.
    std::vector<TriMesh::VertexHandle> vertices;
    std::vector<uint32_t> index(mesh.n_vertices(), UINT32_MAX);
    vertices.reserve(mesh.n_vertices());
    for (auto vh : mesh.vertices()) {
        index[vh.idx()] = uint32_t(vertices.size());
        vertices.push_back(vh);
    }
    surface.positions.reserve(3 * vertices.size());
    for (auto vh : vertices) {
        const auto& p = mesh.point(vh);
        for (int c = 0; c < 3; ++c) surface.positions.push_back(float(p[c]));
    }
    surface.triangles.reserve(3 * mesh.n_faces());
    for (auto fh : mesh.faces())
        for (auto vh : mesh.fv_range(fh)) surface.triangles.push_back(index[vh.idx()]);

    for (auto it = mesh.vprops_begin(); it != mesh.vprops_end(); ++it) {
        const OpenMesh::BaseProperty* base = *it;
        if (base == nullptr || base->name().rfind("v:", 0) == 0) continue; // OpenMesh's own
        Field field;
        if (read_field_property(mesh, *base, vertices, field))
            surface.fields.push_back(std::move(field));
    }
    return surface;
}

} // namespace ddsimp
