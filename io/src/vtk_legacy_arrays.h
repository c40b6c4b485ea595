// Arrays VTK 9.1's legacy reader would read past or allocate without a bound: string and variant
// values, and the arrays of a FIELD section.
#pragma once

#include "ddsimp/io/vtk_messages.h"

#include <cstdint>
#include <ios>
#include <string>

class vtkDataReader;

namespace ddsimp::io::legacy_vtk {

// VTK's ReadArray reads a binary string array as a length, in one to eight bytes, and that many
// bytes, for each value, and allocates each length before it reads it; a variant array as a
// type and a word for each value, each word decoded (see overruns_decode). Both are walked first,
// on VTK's stream, which is left where it was. "" or what is wrong.
std::string string_values_problem(vtkDataReader& reader, const std::string& type, int64_t values,
                                  std::streamoff file_size);

// Reads a FIELD section (just after the word FIELD) the way VTK 9.1's
// vtkDataReader::ReadFieldData does, with VTK's own ReadString, Read and ReadArray, but checks
// the counts before VTK allocates for them (an array count or array size the file cannot hold
// is gigabytes; a negative one a std::length_error thrown through VTK, which leaks what it had
// built). "" if VTK reads every array, else what is wrong.
std::string field_data_problem(vtkDataReader& reader, VtkMessageCapture& messages, int64_t limit,
                               std::streamoff file_size);

} // namespace ddsimp::io::legacy_vtk
