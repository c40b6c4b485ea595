// Content addresses: surfaces and results are named by the SHA-256 of what they are.
#pragma once

#include "ddsimp/ddsimp.h"

#include <string>
#include <string_view>

namespace ddsimp::protocol {

// Lower-case hex SHA-256 of the bytes.
std::string sha256_hex(std::string_view bytes);

// The id of a surface: the hash of its positions, triangles and fields (names, components and
// values) in a fixed little-endian layout. Equal surfaces have equal ids whatever their origin.
std::string surface_hash(const Surface& surface);

} // namespace ddsimp::protocol
