// Checks of a legacy .vtk file that VTK's reader does not make before it trusts the file.
#pragma once

#include <string>

namespace ddsimp::io {

// VTK 9.1's legacy readers trust their input: a cell array's counts are walked without checking
// them against its length (a wrong count reads past the end), a second CELL_TYPES section and a
// data set's FIELD section VTK cannot read are null dereferences, vtkUnstructuredGridReader
// returns on each error it finds without freeing the cell types and cells it has read, and
// vtkPolyDataReader reads on from a closed stream after a cell array it cannot read, and the
// decoding of names and strings reads past one of one or two characters with a '%'. So the file
// is checked first, in two passes: a line scan (each cell array holds its cells, no section
// repeats, ASCII point coordinates are numbers, no count declares more values than the file
// holds, no word VTK decodes overruns), then a walk of the data set with VTK's own parser,
// section by section and attribute by attribute as VTK's POLYDATA and UNSTRUCTURED_GRID readers
// take them, to the end: every error those readers would return on is refused here, and so is
// what they would read past or leak (fewer cell types than cells, format 5 offsets outside their
// connectivity, string arrays where numbers belong, binary string lengths the file cannot hold).
// Volumes (STRUCTURED_POINTS, STRUCTURED_GRID, RECTILINEAR_GRID) are refused as not surfaces.
// Returns "" if VTK reads the data set, else what is wrong, with its line where there is one
// ("line 103: '17' is not a section keyword; the section before it is CELL_TYPES (line 83)").
// Linear in the file: the scan reads it once, the walk parses each array once more than VTK.
std::string check_legacy_vtk(const std::string& path);

} // namespace ddsimp::io
