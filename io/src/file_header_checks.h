// What a mesh file's header promises, checked against what it holds. OpenMesh's readers do not
// notice a truncated file (the OFF reader repeats the last face), nor say when they skip faces.
#pragma once

#include <optional>
#include <string>

namespace ddsimp::io {

// The number of faces the file says it holds: from the header (.off, .ply), the facet count
// (.stl) or the "f" lines (.obj); nullopt if it cannot tell.
std::optional<size_t> declared_face_count(const std::string& path, const std::string& extension);

// "" if the body is long enough for the counts in the header, else what is wrong ("the file ends
// early: ..."). Checks ASCII .off (tokens), ASCII .ply (tokens) and binary .ply (bytes), then
// walks .off, .ply and .obj files the way OpenMesh's readers will (off_checks.h, ply_checks.h,
// obj_checks.h) so that a malformed file is an error here, not an abort, a hang or gigabytes
// allocated there.
std::string check_file_body(const std::string& path, const std::string& extension);

} // namespace ddsimp::io
