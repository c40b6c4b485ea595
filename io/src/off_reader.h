// ASCII .off files as Geomview and the tools that write them use the format: '#' comments
// anywhere, the counts on the header line or after it, vertex colours and normals, polygons.
#pragma once

#include "ddsimp/io/surface_io.h"

#include <optional>
#include <string>

namespace ddsimp::io {

// The surface of an ASCII .off file ([ST][C][N]OFF header, or none; counts "V F [E]" after it on
// the same line or the next; each vertex's 3 coordinates, then optional normal (N), colour and
// texture values; each face "k i1 .. ik" and an optional colour). Polygons are split into
// triangles (a note says how many), the normals of an NOFF file become the field "Normals".
// nullopt for a binary OFF file (read through OpenMesh). Throws IoError("<context>: ...") for a
// malformed file, naming the line, or for one that ends before what its counts declare, saying
// where it ends and what was declared.
std::optional<Surface> read_ascii_off(const std::string& path, const std::string& context,
                                      Notes* notes);

} // namespace ddsimp::io
