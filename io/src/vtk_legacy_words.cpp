#include "vtk_legacy_words.h"
#include "text_scanner.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <set>

namespace ddsimp::io::legacy_vtk {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

bool starts_with(const std::string& word, const char* prefix) {
    return word.rfind(prefix, 0) == 0;
}

bool is_counted_section(const std::string& word) {
    return word == "cell_types" || word == "point_data" || word == "cell_data";
}

bool is_cell_keyword(const std::string& word) {
    return word == "vertices" || word == "lines" || word == "polygons" ||
           word == "triangle_strips" || word == "cells";
}

bool is_vtk_type(const std::string& word) {
    static const std::set<std::string> types{"bit",
                                             "unsigned_char",
                                             "char",
                                             "signed_char",
                                             "unsigned_short",
                                             "short",
                                             "unsigned_int",
                                             "int",
                                             "unsigned_long",
                                             "long",
                                             "unsigned_long_long",
                                             "long_long",
                                             "float",
                                             "double",
                                             "vtkidtype",
                                             "vtktypeint64",
                                             "vtktypeuint64",
                                             "string",
                                             "utf8_string",
                                             "variant"};
    return types.count(lower(word)) > 0;
}

std::string vtk_section(const std::string& word) {
    static const char* const keywords[] = {"points",    "cells",    "cell_types",      "vertices",
                                           "lines",     "polygons", "triangle_strips", "point_data",
                                           "cell_data", "field"};
    const std::string lowered = lower(word);
    for (const char* k : keywords)
        if (lowered.rfind(k, 0) == 0) return k;
    return lowered;
}

bool is_number_word(const std::string& word) {
    if (word.find_first_not_of("0123456789+-.eE") != std::string::npos) return false;
    const char* begin = word.data() + (word[0] == '+' ? 1 : 0);
    double value = 0;
    const auto [end, error] = std::from_chars(begin, word.data() + word.size(), value);
    return end == word.data() + word.size() &&
           (error == std::errc() || error == std::errc::result_out_of_range);
}

int vtk_major_version(const std::string& first_line) {
    const std::string prefix = "# vtk DataFile Version";
    int major = 0, minor = 0;
    if (first_line.compare(0, prefix.size(), prefix) != 0 ||
        std::sscanf(first_line.c_str() + prefix.size(), "%d.%d", &major, &minor) != 2)
        return 0;
    return major;
}

size_t line_of(const std::string& path, std::streamoff offset) {
    std::ifstream in(path, std::ios::binary);
    std::array<char, 65536> buffer;
    size_t line = 1;
    while (offset > 0 && (in.read(buffer.data(), std::streamsize(std::min<std::streamoff>(
                                                     offset, std::streamoff(buffer.size())))) ||
                          in.gcount() > 0)) {
        line += size_t(std::count(buffer.data(), buffer.data() + in.gcount(), '\n'));
        offset -= in.gcount();
    }
    return line;
}

bool overruns_decode(std::string_view text) {
    text = text.substr(0, text.find('\0'));
    return !text.empty() && text.size() < 3 && text.find('%') != std::string_view::npos;
}

std::string decode_overrun(std::string_view line, const std::vector<std::string>& words) {
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (overruns_decode(line))
        return io::quoted(line) +
               ": VTK 9.1 reads past a name or string of one or two characters with a '%'";
    for (const std::string& word : words)
        if (overruns_decode(word))
            return io::quoted(word) +
                   ": VTK 9.1 reads past a name or string of one or two characters with a '%'";
    return "";
}

} // namespace ddsimp::io::legacy_vtk
