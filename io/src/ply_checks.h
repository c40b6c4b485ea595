// Checks of a .ply file that OpenMesh's PLY reader does not make before it trusts it.
#pragma once

#include <string>
#include <string_view>

namespace ddsimp::io {

// OpenMesh 9.0's PLY reader reads the header word by word until the word "end_header" and stops
// early only on a read error, not at the end of the file: a header whose end_header is taken as
// a property's name loops for ever. It attaches a property to the last element without checking
// that there is one (a crash), reads list counts as unsigned ints and allocates that many items
// (an int -1 is 4294967295), and in ASCII files keeps going after a word that is not a number
// with every later read silently failing. This checks
//   - the header line by line: "ply", "format ascii|binary_little_endian|binary_big_endian V",
//     then "comment ...", "obj_info ...", "element NAME COUNT", "property TYPE NAME",
//     "property list COUNT_TYPE ITEM_TYPE NAME" (types OpenMesh reads) and "end_header", each
//     with exactly those words, so that OpenMesh's word-by-word reading agrees with it;
//   - for binary files, that OpenMesh's guess of where the data starts (12 bytes after the last
//     word before end_header) is where it starts;
//   - the data of every element up to and including "face" (OpenMesh reads no further), read as
//     OpenMesh reads it: numbers of the declared kind in ASCII files, list counts that are not
//     negative and whose items the file holds.
// Returns "" if all holds, else what is wrong ("PLY header line 13: 'property list' needs a count
// type, an item type and a name"; "face 3: a list of 4294967295 items, more than the file
// holds"). Linear in the file's size.
std::string check_ply_file(std::string_view file);

} // namespace ddsimp::io
