// PLY files beyond what OpenMesh's reader takes: faces stored as triangle strips (an element
// "tristrips" whose list "vertex_indices" holds strips separated by -1, as Stanford's range scans
// store them) and ASCII files whose lines carry more values than the header declares (PLY's
// reference reader and VTK's read each element from its own line and ignore the rest of it).
#pragma once

#include "ddsimp/io/surface_io.h"

#include <optional>
#include <string>

namespace ddsimp::io {

// The surface of a .ply file that holds triangle strips, or of an ASCII .ply whose lines carry
// more values than declared; nullopt for any other file (OpenMesh's reader and the checks before
// it read it, or refuse it with their own message). Vertex properties other than coordinates,
// normals, colours and texture coordinates become fields, as OpenMesh's reader makes them (see
// read_openmesh_file), the normals the field "Normals"; faces are split into triangles, strips
// into theirs, each counted in a note. Throws IoError("<context>: ...") for a strip file that ends
// before what its header declares (saying where) or that refers to a vertex it does not have.
std::optional<Surface> read_ply_with_strips_or_long_lines(const std::string& path,
                                                          const std::string& context, Notes* notes);

} // namespace ddsimp::io
