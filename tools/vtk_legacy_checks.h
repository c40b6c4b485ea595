// Checks of a legacy .vtk file that VTK's reader does not make before it trusts the file.
#pragma once

#include <string>

namespace ddsimp::io {

// Legacy files (before format 5.1) list cells as one array of counts and ids: "POLYGONS n size"
// (or VERTICES, LINES, TRIANGLE_STRIPS, CELLS), then `size` integers, for each of the n cells its
// point count and that many point ids. VTK 9.1 walks that array without checking the counts
// against its length, so a wrong count reads past the end (a crash, not an error); a second
// CELL_TYPES section crashes it too, and so does a data set's FIELD section (the one before
// POINT_DATA and CELL_DATA) that VTK cannot read: its readers Delete() the null it gets back.
// Returns "" if every cell array holds its cells, no section repeats and VTK's own parser reads
// each such FIELD section, else what is wrong ("POLYGONS 4 16: cell 3 has -7 points", "the data
// set's FIELD section (line 5) cannot be read: ..."). The line scan is linear in the file; each
// FIELD section is parsed once more.
std::string check_legacy_vtk(const std::string& path);

} // namespace ddsimp::io
