// Surfaces in the formats OpenMesh reads and writes (internal to ddsimp_io; use surface_io.h).
#pragma once

#include "ddsimp/io/surface_io.h"

#include <string>

namespace ddsimp::io {

// .ply, .obj, .off or .stl. Faces are taken exactly as the file lists them (OpenMesh's own
// importer would drop or split non-manifold ones); polygons are split into triangles, which a note
// says.
Surface read_openmesh_file(const std::string& path, const std::string& extension, Notes* notes);
// .ply (binary, fields as float vertex properties), .obj or .off (ASCII, 9 significant digits so
// that floats survive the round trip exactly).
void write_openmesh_file(const Surface& surface, const std::string& path,
                         const std::string& extension);

} // namespace ddsimp::io
