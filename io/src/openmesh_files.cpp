#include "openmesh_files.h"

#include "ddsimp/io/surface_io.h"
#include "ddsimp/openmesh.h" // TriMesh
#include "field_kinds.h"
#include "file_header_checks.h"
#include "polygons.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/exporter/ExporterT.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cctype>
#include <cstdint>
#include <fstream>
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
        for (OpenMesh::VertexHandle vh : corners)
            corners_.push_back(vh.is_valid() ? uint32_t(vh.idx()) : UINT32_MAX);
        ends_.push_back(corners_.size());
        return mesh_.new_face();
    }
    // Texture coordinates are not kept; ImporterT's versions walk the face's (absent) halfedges.
    void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                            const std::vector<OpenMesh::Vec2f>&) override {}
    void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                            const std::vector<OpenMesh::Vec3f>&) override {}
    // Readers must hand polygons over as they are: they are split once the points are known.
    bool is_triangle_mesh() const override { return false; }
    size_t n_faces() const override { return ends_.size(); }

    size_t faces() const { return ends_.size(); }
    // The faces in file order as triangles (polygons split, see PolygonSplitter).
    std::vector<uint32_t> triangles(const std::vector<float>& positions,
                                    PolygonSplitter& splitter) const {
        std::vector<uint32_t> out;
        out.reserve(corners_.size());
        size_t begin = 0;
        for (size_t end : ends_) {
            splitter.split(positions, corners_.data() + begin, end - begin, out);
            begin = end;
        }
        return out;
    }

private:
    TriMesh& mesh_;
    std::vector<uint32_t> corners_; // every face's corners, one after the other
    std::vector<size_t> ends_;      // where each face's corners end
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

// A scalar vertex property the PLY reader made from the file (any numeric type) as a float field
// of the kind its type and name say (see field_kind).
std::optional<Field> scalar_as_field(const OpenMesh::BaseProperty& base, size_t n) {
    Field field{base.name(), 1, {}};
    std::vector<float>& v = field.values;
    bool integer = false;
    if (copy_if_type<float>(base, n, v) || copy_if_type<double>(base, n, v))
        integer = false;
    else if (copy_if_type<int8_t>(base, n, v) || copy_if_type<uint8_t>(base, n, v) ||
             copy_if_type<int16_t>(base, n, v) || copy_if_type<uint16_t>(base, n, v) ||
             copy_if_type<int32_t>(base, n, v) || copy_if_type<uint32_t>(base, n, v))
        integer = true;
    else
        return std::nullopt;
    field.kind = field_kind(field.name, 1, integer);
    return field;
}

// OBJ's point ("p") and line ("l") elements, which OpenMesh's reader skips: a note says how many.
std::string obj_points_and_lines(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    size_t points = 0, lines = 0;
    for (std::string line; std::getline(in, line);) {
        const size_t f = line.find_first_not_of(" \t\r");
        if (f == std::string::npos || line.size() < f + 2 ||
            (line[f + 1] != ' ' && line[f + 1] != '\t'))
            continue;
        points += line[f] == 'p', lines += line[f] == 'l';
    }
    if (points + lines == 0) return "";
    std::string what;
    if (points > 0) what = std::to_string(points) + " point";
    if (lines > 0) what += (what.empty() ? "" : " and ") + std::to_string(lines) + " line";
    return what + (points + lines == 1 ? " element" : " elements") +
           " set aside (a surface is made of its faces)";
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

Surface read_openmesh_file(const std::string& path, const std::string& extension, Notes* notes) {
    const std::string context = "cannot read " + path;
    // The header check first: its message says more than the reader's failure, and OpenMesh's
    // readers trust a header's counts.
    if (std::string problem = check_file_body(path, extension); !problem.empty())
        throw IoError(context + ": " + problem);
    TriMesh mesh;
    SurfaceImporter importer(mesh);
    mesh.request_vertex_normals();
    OpenMesh::IO::Options options = OpenMesh::IO::Options::Custom; // PLY vertex properties
    if (extension == ".ply") options += OpenMesh::IO::Options::VertexNormal;
    bool ok;
    {
        QuietOpenMesh quiet;
        ok = OpenMesh::IO::IOManager().read(path, importer, options);
    }
    if (!ok)
        throw IoError(context + ": OpenMesh's " + extension + " reader failed (malformed file?)");
    if (auto declared = declared_face_count(path, extension);
        declared && *declared != importer.faces())
        throw IoError(context + ": the file declares " + std::to_string(*declared) +
                      " faces but OpenMesh's reader delivered " + std::to_string(importer.faces()) +
                      " (malformed, or faces it skips such as degenerate STL facets)");

    Surface surface;
    surface.positions.reserve(3 * mesh.n_vertices());
    for (auto vh : mesh.vertices())
        for (int c = 0; c < 3; ++c) surface.positions.push_back(mesh.point(vh)[c]);
    PolygonSplitter splitter;
    surface.triangles = importer.triangles(surface.positions, splitter);
    if (notes && !splitter.note().empty()) notes->push_back(splitter.note());
    if (notes && extension == ".obj")
        if (std::string note = obj_points_and_lines(path); !note.empty()) notes->push_back(note);
    for (auto it = mesh.vprops_begin(); it != mesh.vprops_end(); ++it)
        if (*it != nullptr && (*it)->name().rfind("v:", 0) != 0)
            if (auto field = scalar_as_field(**it, mesh.n_vertices()))
                surface.fields.push_back(std::move(*field));
    regroup_component_fields(surface);
    if (options.vertex_has_normal()) {
        Field normals{"Normals", 3, {}, FieldKind::Direction};
        normals.values.reserve(3 * mesh.n_vertices());
        for (auto vh : mesh.vertices())
            for (int c = 0; c < 3; ++c) normals.values.push_back(mesh.normal(vh)[c]);
        surface.fields.push_back(std::move(normals));
    }
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
