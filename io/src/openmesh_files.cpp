#include "openmesh_files.h"

#include "ddsimp/io/surface_io.h"
#include "ddsimp/openmesh.h" // TriMesh
#include "file_header_checks.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/exporter/ExporterT.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cctype>
#include <cstdint>
#include <optional>

namespace ddsimp::io {

namespace {

// Records faces as the reader delivers them, without OpenMesh's connectivity (which refuses
// non-manifold faces); the mesh keeps only the vertices and their properties. Each face still
// gets a (connectivity-free) face element so that readers can attach face data to its handle.
class SurfaceImporter : public OpenMesh::IO::ImporterT<TriMesh> {
public:
    explicit SurfaceImporter(TriMesh& mesh) : ImporterT(mesh), mesh_(mesh) {}

    OpenMesh::FaceHandle add_face(const VHandles& corners) override {
        const size_t face = faces_++;
        if (corners.size() != 3) {
            if (!first_polygon_) first_polygon_ = {face, corners.size()};
        } else {
            for (OpenMesh::VertexHandle vh : corners)
                triangles.push_back(vh.is_valid() ? uint32_t(vh.idx()) : UINT32_MAX);
        }
        return mesh_.new_face();
    }
    // Texture coordinates are not kept; ImporterT's versions walk the face's (absent) halfedges.
    void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                            const std::vector<OpenMesh::Vec2f>&) override {}
    void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                            const std::vector<OpenMesh::Vec3f>&) override {}
    // Readers must hand polygons over as they are: we report them rather than triangulate.
    bool is_triangle_mesh() const override { return false; }
    size_t n_faces() const override { return faces_; }

    size_t faces() const { return faces_; }
    std::optional<std::pair<size_t, size_t>> first_polygon() const { return first_polygon_; }
    std::vector<uint32_t> triangles;

private:
    TriMesh& mesh_;
    size_t faces_ = 0;
    std::optional<std::pair<size_t, size_t>> first_polygon_; // {face, corners}
};

// Gives OpenMesh's writers the surface's triangles as they are (no connectivity needed, so
// non-manifold surfaces can be written too). The mesh holds the vertices, their properties and
// one connectivity-free face element per triangle.
class SurfaceExporter : public OpenMesh::IO::ExporterT<TriMesh> {
public:
    SurfaceExporter(const TriMesh& mesh, const Surface& surface)
        : ExporterT(mesh), surface_(surface) {}

    unsigned int get_vhandles(OpenMesh::FaceHandle fh,
                              std::vector<OpenMesh::VertexHandle>& corners) const override {
        corners.clear();
        for (int c = 0; c < 3; ++c)
            corners.emplace_back(int(surface_.triangles[3 * size_t(fh.idx()) + c]));
        return 3;
    }
    size_t n_faces() const override { return surface_.triangle_count(); }
    bool is_triangle_mesh() const override { return true; }

private:
    const Surface& surface_;
};

template <class T>
bool copy_if_type(const OpenMesh::BaseProperty& base, size_t n, std::vector<float>& out) {
    auto* p = dynamic_cast<const OpenMesh::PropertyT<T>*>(&base);
    if (p == nullptr) return false;
    out.resize(n);
    for (size_t v = 0; v < n; ++v) out[v] = float((*p)[v]);
    return true;
}

// A scalar vertex property the PLY reader made from the file (any numeric type) as floats.
std::optional<std::vector<float>> scalar_as_floats(const OpenMesh::BaseProperty& base, size_t n) {
    std::vector<float> out;
    if (copy_if_type<float>(base, n, out) || copy_if_type<double>(base, n, out) ||
        copy_if_type<int8_t>(base, n, out) || copy_if_type<uint8_t>(base, n, out) ||
        copy_if_type<int16_t>(base, n, out) || copy_if_type<uint16_t>(base, n, out) ||
        copy_if_type<int32_t>(base, n, out) || copy_if_type<uint32_t>(base, n, out))
        return out;
    return std::nullopt;
}

// Vertex properties "name[0]" .. "name[k-1]" (how we write a k-component field to PLY) become
// one field again.
void regroup_component_fields(Surface& surface) {
    std::vector<Field> grouped;
    for (size_t i = 0; i < surface.fields.size();) {
        const std::string& name = surface.fields[i].name;
        const std::string base = name.size() > 3 && name.substr(name.size() - 3) == "[0]"
                                     ? name.substr(0, name.size() - 3)
                                     : std::string();
        size_t k = 0;
        if (!base.empty())
            while (i + k < surface.fields.size() && surface.fields[i + k].components == 1 &&
                   surface.fields[i + k].name == base + "[" + std::to_string(k) + "]")
                ++k;
        if (k < 2) {
            grouped.push_back(std::move(surface.fields[i++]));
            continue;
        }
        Field field;
        field.name = base;
        field.components = int(k);
        const size_t n = surface.vertex_count();
        field.values.resize(n * k);
        for (size_t c = 0; c < k; ++c)
            for (size_t v = 0; v < n; ++v)
                field.values[v * k + c] = surface.fields[i + c].values[v];
        grouped.push_back(std::move(field));
        i += k;
    }
    surface.fields = std::move(grouped);
}

// OpenMesh prints its complaints to stderr; we turn them into one error instead.
class QuietOpenMesh {
public:
    QuietOpenMesh() {
        omerr().disable();
        omlog().disable();
    }
    ~QuietOpenMesh() {
        omerr().enable();
        omlog().enable();
    }
};

} // namespace

Surface read_openmesh_file(const std::string& path, const std::string& extension) {
    const std::string context = "cannot read " + path;
    // The header check first: its message says more than the reader's failure, and OpenMesh's
    // readers trust a header's counts.
    if (std::string problem = check_file_body(path, extension); !problem.empty())
        throw IoError(context + ": " + problem);
    TriMesh mesh;
    SurfaceImporter importer(mesh);
    OpenMesh::IO::Options options = OpenMesh::IO::Options::Custom; // PLY vertex properties
    bool ok;
    {
        QuietOpenMesh quiet;
        ok = OpenMesh::IO::IOManager().read(path, importer, options);
    }
    if (!ok)
        throw IoError(context + ": OpenMesh's " + extension + " reader failed (malformed file?)");
    if (auto polygon = importer.first_polygon())
        throw IoError(context + ": face " + std::to_string(polygon->first) + " has " +
                      std::to_string(polygon->second) + " vertices; only triangles are supported");
    if (auto declared = declared_face_count(path, extension);
        declared && *declared != importer.faces())
        throw IoError(context + ": the file declares " + std::to_string(*declared) +
                      " faces but OpenMesh's reader delivered " + std::to_string(importer.faces()) +
                      " (malformed, or faces it skips such as degenerate STL facets)");

    Surface surface;
    surface.positions.reserve(3 * mesh.n_vertices());
    for (auto vh : mesh.vertices())
        for (int c = 0; c < 3; ++c) surface.positions.push_back(mesh.point(vh)[c]);
    surface.triangles = std::move(importer.triangles);
    for (auto it = mesh.vprops_begin(); it != mesh.vprops_end(); ++it)
        if (*it != nullptr && (*it)->name().rfind("v:", 0) != 0)
            if (auto values = scalar_as_floats(**it, mesh.n_vertices()))
                surface.fields.push_back({(*it)->name(), 1, std::move(*values)});
    regroup_component_fields(surface);
    return surface;
}

void write_openmesh_file(const Surface& surface, const std::string& path,
                         const std::string& extension) {
    TriMesh mesh;
    const size_t n = surface.vertex_count();
    mesh.reserve(n, 0, surface.triangle_count());
    for (size_t v = 0; v < n; ++v) {
        const float* p = &surface.positions[3 * v];
        mesh.add_vertex(TriMesh::Point(p[0], p[1], p[2]));
    }
    for (size_t t = 0; t < surface.triangle_count(); ++t) mesh.new_face();

    OpenMesh::IO::Options options = OpenMesh::IO::Options::Default;
    if (extension == ".ply") {
        // OpenMesh's PLY writer writes persistent scalar vertex properties (not vectors), so a
        // k-component field goes out as k scalar properties.
        options += OpenMesh::IO::Options::Binary;
        options += OpenMesh::IO::Options::Custom;
        for (const Field& field : surface.fields) {
            for (int c = 0; c < field.components; ++c) {
                OpenMesh::VPropHandleT<float> prop;
                std::string name =
                    field.components == 1 ? field.name : field.name + "[" + std::to_string(c) + "]";
                for (char& ch : name) // a PLY header is split at white space
                    if (std::isspace(static_cast<unsigned char>(ch))) ch = '_';
                mesh.add_property(prop, name);
                mesh.property(prop).set_persistent(true);
                for (size_t v = 0; v < n; ++v)
                    mesh.property(prop, TriMesh::VertexHandle(int(v))) =
                        field.values[v * field.components + c];
            }
        }
    }
    SurfaceExporter exporter(mesh, surface);
    bool ok;
    {
        QuietOpenMesh quiet;
        ok = OpenMesh::IO::IOManager().write(path, exporter, options, 9);
    }
    if (!ok) throw IoError("cannot write " + path + ": OpenMesh's " + extension + " writer failed");
}

} // namespace ddsimp::io
