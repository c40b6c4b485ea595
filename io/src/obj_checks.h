// Checks of a Wavefront .obj file that OpenMesh's OBJ reader does not make before it trusts it.
#pragma once

#include <string>
#include <string_view>

namespace ddsimp::io {

// OpenMesh 9.0's OBJ reader asserts that a face corner has a vertex index before it reads the
// texture or normal index after it, so "f /1/1 2/2/1 3/3/1" aborts the program (Debian builds
// OpenMesh with assertions on); a corner it cannot parse, or a "v" line without three
// coordinates, shifts every index after it. Returns "" if every "v" line has x y z and every "f"
// line has at least 3 corners v, v/vt, v//vn or v/vt/vn, each v an index of a vertex in the file
// (1..n, or -1..-k for the k vertices before the line), else what is wrong ("line 19: face corner
// '/1/1' has no vertex index"). One pass to count the vertices, one to check; lines are read as
// OpenMesh reads them (trimmed, "#" lines skipped, a "#" word ends a face line).
std::string check_obj_lines(std::string_view text);

} // namespace ddsimp::io
