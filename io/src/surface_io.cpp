// Chooses the reader or writer by extension and turns every failure into one IoError line.
#include "ddsimp/io/surface_io.h"

#include "off_reader.h"
#include "openmesh_files.h"
#include "ply_reader.h"
#include "stl_reader.h"
#include "vtk_files.h"

#include "ddsimp/protocol/glb.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <optional>

namespace ddsimp::io {

namespace {

bool is_vtk_format(const std::string& ext) {
    return ext == ".vtk" || ext == ".vtp";
}
bool is_openmesh_readable(const std::string& ext) {
    return ext == ".ply" || ext == ".obj" || ext == ".off" || ext == ".stl";
}
bool is_openmesh_writable(const std::string& ext) {
    return ext == ".ply" || ext == ".obj" || ext == ".off";
}
bool is_writable(const std::string& ext) {
    return is_vtk_format(ext) || is_openmesh_writable(ext) || ext == ".glb";
}

void write_glb_file(const Surface& surface, const std::string& path, const WriteOptions& options) {
    std::string bytes;
    try {
        protocol::GlbOptions glb;
        glb.colour_field = options.colour_field;
        glb.meshopt = options.meshopt;
        bytes = protocol::write_glb(surface, glb);
    } catch (const protocol::GlbError& e) {
        throw IoError("cannot write " + path + ": " + e.what());
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    if (!out.flush()) throw IoError("cannot write " + path + ": the disk refused the bytes");
}

// Catches what the format libraries report badly or not at all: a missing or unreadable file.
void check_readable(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(status)) throw IoError("cannot read " + path + ": no such file");
    if (std::filesystem::is_directory(status))
        throw IoError("cannot read " + path + ": it is a directory");
    if (!std::ifstream(path, std::ios::binary))
        throw IoError("cannot read " + path + ": permission denied");
    if (std::filesystem::file_size(path, ec) == 0)
        throw IoError("cannot read " + path + ": the file is empty");
}

void check_writable(const std::string& path) {
    // Opening for append neither truncates an existing file nor leaves a new one behind.
    const bool existed = std::filesystem::exists(path);
    if (!std::ofstream(path, std::ios::binary | std::ios::app))
        throw IoError("cannot write " + path +
                      ": cannot create the file (missing directory or "
                      "no permission?)");
    if (!existed) std::filesystem::remove(path);
}

// The writers trust the sizes; a wrong field length would write garbage.
void check_shape(const Surface& s, const std::string& path) {
    const std::string context = "cannot write " + path + ": ";
    if (s.positions.size() % 3 != 0 || s.triangles.size() % 3 != 0)
        throw IoError(context + "positions or triangles not a multiple of 3");
    for (uint32_t index : s.triangles)
        if (index >= s.vertex_count())
            throw IoError(context + "a triangle refers to vertex " + std::to_string(index) +
                          ", but there are " + std::to_string(s.vertex_count()));
    for (const Field& f : s.fields)
        if (f.components < 1 || f.values.size() != s.vertex_count() * size_t(f.components))
            throw IoError(context + "field '" + f.name + "' has " +
                          std::to_string(f.values.size()) + " values for " +
                          std::to_string(s.vertex_count()) + " vertices");
}

} // namespace

std::string extension_of(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

Surface read_surface(const std::string& path, Notes* notes) {
    const std::string ext = extension_of(path);
    if (!is_vtk_format(ext) && !is_openmesh_readable(ext))
        throw IoError("cannot read " + path + ": unknown extension '" + ext +
                      "' (readable: .vtk .vtp .ply .obj .off .stl)");
    check_readable(path);
    std::optional<Surface> read;
    if (is_vtk_format(ext))
        read = read_vtk_file(path, ext, notes);
    else if (ext == ".off")
        read = read_ascii_off(path, "cannot read " + path, notes);
    else if (ext == ".stl")
        read = read_binary_stl(path, "cannot read " + path, notes);
    else if (ext == ".ply")
        read = read_ply_with_strips_or_long_lines(path, "cannot read " + path, notes);
    if (!read) read = read_openmesh_file(path, ext, notes); // also binary .off, ASCII .stl
    Surface surface = std::move(*read);
    if (surface.triangle_count() == 0)
        throw IoError("cannot read " + path + ": the file holds no triangles");
    return surface;
}

void check_output_path(const std::string& path) {
    const std::string ext = extension_of(path);
    if (!is_writable(ext))
        throw IoError("cannot write " + path + ": unknown extension '" + ext +
                      "' (writable: .vtk .vtp .ply .obj .off .glb)");
    check_writable(path);
}

void write_surface(const Surface& surface, const std::string& path, const WriteOptions& options,
                   Notes* notes) {
    check_output_path(path);
    check_shape(surface, path);
    const std::string ext = extension_of(path);
    if (ext == ".glb")
        write_glb_file(surface, path, options);
    else if (is_vtk_format(ext))
        write_vtk_file(surface, path, ext);
    else
        write_openmesh_file(surface, path, ext);
    if (notes && (ext == ".obj" || ext == ".off") && !surface.fields.empty()) {
        std::string names;
        for (const Field& f : surface.fields) names += (names.empty() ? "" : ", ") + f.name;
        notes->push_back("the " + ext + " format holds no per-vertex data: " + names +
                         (surface.fields.size() == 1 ? " is" : " are") +
                         " not written (.vtk, .vtp and .ply keep fields)");
    }
}

} // namespace ddsimp::io
