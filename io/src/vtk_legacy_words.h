// The words of a legacy .vtk file as VTK 9.1's reader takes them: keywords by their start, type
// names, numbers, the version line, and the names VTK's decoding reads past.
#pragma once

#include <cstddef>
#include <ios>
#include <string>
#include <string_view>
#include <vector>

namespace ddsimp::io::legacy_vtk {

std::string lower(std::string s);

bool starts_with(const std::string& word, const char* prefix);

// Sections "KEYWORD n" (a count and nothing else on the line).
bool is_counted_section(const std::string& word);

bool is_cell_keyword(const std::string& word);

bool is_vtk_type(const std::string& word);

// The section VTK's readers take `word` for: they compare the lower-cased word's start with each
// keyword ("FIELDvtkidty" is a FIELD section to them), so this does too.
std::string vtk_section(const std::string& word);

// A number as `>>` reads a double (digits, sign, point, exponent; not "nan" or "inf", which
// libstdc++ does not read either).
bool is_number_word(const std::string& word);

// The first line "# vtk DataFile Version x.y" gives VTK's reader its major version (0 if it
// cannot read "x.y"); from 5 on, cells are offsets and connectivity.
int vtk_major_version(const std::string& first_line);

// The line (from 1) that holds the byte at `offset` of the file: the newlines before it, counted
// when a message needs them.
size_t line_of(const std::string& path, std::streamoff offset);

// VTK 9.1's DecodeString, which turns "%20" back into " " in the names and strings it reads,
// reads and writes past the end of a string of one or two characters with a '%' in it (its test
// that two characters follow a '%' underflows). True for such a string (up to a NUL, as VTK sees
// it).
bool overruns_decode(std::string_view text);

// Such a word or line (a name, a string value, a component name) is never a number or a keyword,
// so a line scan refuses it wherever VTK could decode it: anywhere after an ASCII file's header,
// in the METADATA blocks of a binary file (the rest of a binary file is not split in lines and
// words, and its names are checked by the data-set walk). "" or what is wrong.
std::string decode_overrun(std::string_view line, const std::vector<std::string>& words);

} // namespace ddsimp::io::legacy_vtk
