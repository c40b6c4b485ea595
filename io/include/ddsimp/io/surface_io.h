// Reading and writing surfaces with their per-vertex fields.
//
// VTK formats go through VTK's IO modules, the others through OpenMesh's IO (with an importer
// and exporter of our own, so that non-manifold triangles are neither dropped nor split).
//
//   format          read  write  fields
//   .vtk (legacy)   yes   yes    all point-data arrays (written as binary POLYDATA)
//   .vtp (XML)      yes   yes    all point-data arrays
//   .ply            yes   yes    scalar vertex properties and the normals; a k-component field is
//                                written as k properties "name[0]".."name[k-1]" and regrouped
//                                when read; white space in names becomes '_'
//   .obj, .off      yes   yes    none (the formats hold no per-vertex data; a note names the
//                                fields a write leaves out)
//   .stl            yes   no     none
//   .glb (glTF)     no    yes    all, as custom vertex attributes "_name"; one field also as
//                                vertex colours (see ddsimp/protocol/glb.h)
//
// What a reader accepts beyond triangles, each counted in a note: quads and polygons (split into
// triangles), triangle strips (VTK strips, PLY "tristrips"), vertex and line cells (set aside);
// a binary STL cut short (read up to its last whole triangle). A field's kind (ddsimp::FieldKind)
// comes from the file: integer arrays and ids are labels, the normals directions.
#pragma once

#include "ddsimp/ddsimp.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace ddsimp::io {

// A file that cannot be read or written; what() names the file and the problem
// ("cannot read x.vtk: cell 12 is a quad; only triangles are supported").
struct IoError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// What a reader changed to make a triangle surface of a file, or what a writer left out: one
// sentence each ("12 quads triangulated into 24 triangles").
using Notes = std::vector<std::string>;

// Reads a triangle surface, the format chosen by the file's extension. Every numeric point-data
// array (any type) becomes a float field, in the file's order; bit and string arrays are skipped.
// Throws IoError for a missing, unreadable or malformed file (one that ends before what its
// header declares: where it ends and what was expected), a volume cell, or a file without
// triangles. Faces and cells that are not triangles are handled as the table above says, and
// `notes`, if given, says what was done. The triangles are otherwise returned as stored (no
// repair; see ddsimp::validate).
Surface read_surface(const std::string& path, Notes* notes = nullptr);

// What only a .glb takes: the field shown as colours ("" : the first continuous scalar that varies) and
// EXT_meshopt_compression.
struct WriteOptions {
    std::string colour_field;
    bool meshopt = false;
};

// Writes a surface, the format chosen by the extension; fields are kept where the format can hold
// them (see the table above), and `notes`, if given, names those it cannot. The bytes depend only
// on the surface and options (no timestamps). Throws IoError if the file cannot be written or the
// extension is not a writable format.
void write_surface(const Surface& surface, const std::string& path,
                   const WriteOptions& options = {}, Notes* notes = nullptr);

// "continuous", "label" or "direction".
const char* describe(FieldKind kind);

// Throws the IoError write_surface would throw for an unknown extension or a file that cannot be
// created, so that a command fails before a long computation rather than after it.
void check_output_path(const std::string& path);

// Lower-case extension of `path` with its dot (".vtk"), or "" if it has none.
std::string extension_of(const std::string& path);

} // namespace ddsimp::io
