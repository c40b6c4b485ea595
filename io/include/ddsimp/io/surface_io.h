// Reading and writing surfaces with their per-vertex fields.
//
// VTK formats go through VTK's IO modules, the others through OpenMesh's IO (with an importer
// and exporter of our own, so that non-manifold triangles are neither dropped nor split).
//
//   format          read  write  fields
//   .vtk (legacy)   yes   yes    all point-data arrays (written as binary POLYDATA)
//   .vtp (XML)      yes   yes    all point-data arrays
//   .ply            yes   yes    scalar vertex properties; a k-component field is written as k
//                                properties "name[0]".."name[k-1]" and regrouped when read;
//                                white space in names becomes '_'
//   .obj, .off      yes   yes    none (the formats hold no per-vertex data)
//   .stl            yes   no     none
//   .glb (glTF)     no    yes    all, as custom vertex attributes "_name"; one field also as
//                                vertex colours (see ddsimp/protocol/glb.h)
#pragma once

#include "ddsimp/ddsimp.h"

#include <stdexcept>
#include <string>

namespace ddsimp::io {

// A file that cannot be read or written; what() names the file and the problem
// ("cannot read x.vtk: cell 12 is a quad; only triangles are supported").
struct IoError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Reads a triangle surface, the format chosen by the file's extension. Every numeric point-data
// array (any type) becomes a float field, in the file's order; bit and string arrays are skipped.
// Throws IoError for a missing, unreadable or malformed file, a non-triangle cell or face, or a
// file without triangles. The surface is returned as stored (no repair; see ddsimp::validate).
Surface read_surface(const std::string& path);

// What only a .glb takes: the field shown as colours ("" : the first scalar that varies) and
// EXT_meshopt_compression.
struct WriteOptions {
    std::string colour_field;
    bool meshopt = false;
};

// Writes a surface, the format chosen by the extension; fields are kept where the format can hold
// them (see the table above). The bytes depend only on the surface and options (no timestamps).
// Throws IoError if the file cannot be written or the extension is not a writable format.
void write_surface(const Surface& surface, const std::string& path,
                   const WriteOptions& options = {});

// Throws the IoError write_surface would throw for an unknown extension or a file that cannot be
// created, so that a command fails before a long computation rather than after it.
void check_output_path(const std::string& path);

// Lower-case extension of `path` with its dot (".vtk"), or "" if it has none.
std::string extension_of(const std::string& path);

} // namespace ddsimp::io
