// Binary .stl files, including those cut short (ASCII ones are read through OpenMesh).
#pragma once

#include "ddsimp/io/surface_io.h"

#include <optional>
#include <string>

namespace ddsimp::io {

// The surface of a binary STL file: its facets' corners merged where they are the same point
// (as OpenMesh's reader merges them), in order of first use. A file that ends before the facet
// count of its header is read up to its last whole facet, and a note says where it ends. nullopt
// for an ASCII STL file (a size that is not the binary layout's and a start that is all text, or
// "solid" with a facet soon after). Throws IoError("<context>: ...") for a binary file without one
// whole facet.
std::optional<Surface> read_binary_stl(const std::string& path, const std::string& context,
                                       Notes* notes);

} // namespace ddsimp::io
