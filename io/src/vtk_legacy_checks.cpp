// The legacy .vtk checks: a line scan of the file, then the data-set walk (vtk_legacy_walk.h).
#include "vtk_legacy_checks.h"

#include "text_scanner.h"
#include "vtk_legacy_cells.h"
#include "vtk_legacy_walk.h"
#include "vtk_legacy_words.h"

#include <cstdint>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace ddsimp::io {
namespace {

using namespace legacy_vtk;

// A line that ends a binary file's METADATA block: a section or attribute keyword, or the header
// of a FIELD array ("name components tuples type").
bool ends_metadata(const std::vector<std::string>& words) {
    static const char* const keywords[] = {
        "points",     "cells",           "cell_types", "vertices",      "lines",
        "polygons",   "triangle_strips", "point_data", "cell_data",     "field",
        "scalars",    "vectors",         "normals",    "tensors",       "texture_coordinates",
        "global_ids", "pedigree_ids",    "edge_flags", "color_scalars", "lookup_table",
        "offsets",    "connectivity"};
    const std::string first = lower(words[0]);
    for (const char* k : keywords)
        if (first.rfind(k, 0) == 0) return true;
    return words.size() == 4 && is_vtk_type(words[3]);
}

// VTK allocates what an array header or a count declares before it reads a value (a declared
// count of billions is gigabytes, a negative one a std::length_error). A value takes at least a
// byte in ASCII and a bit in a binary bit array, so no section can declare more values than 8
// times the file's bytes. "" or what is wrong.
std::string check_declared_size(const std::vector<std::string>& words, int64_t limit) {
    auto too_many = [&](int64_t a, int64_t b) {
        return a < 0 || b < 0 || (a > 0 && b > limit / a);
    };
    int64_t a = 0, b = 0;
    auto integer = [](const std::string& w, int64_t& v) {
        std::istringstream in(w);
        std::string rest;
        return bool(in >> v) && !(in >> rest);
    };
    const std::string section = vtk_section(words[0]);
    if (words.size() == 4 && integer(words[1], a) && integer(words[2], b) &&
        is_vtk_type(words[3]) && too_many(a, b))
        return "array " + words[0] + " declares " + words[1] + " components of " + words[2] +
               " tuples, more than the file holds";
    if (section == "points" && words.size() == 3 && integer(words[1], a) && too_many(3, a))
        return "POINTS declares " + words[1] + " points, more than the file holds";
    if (is_counted_section(section) && words.size() == 2 && integer(words[1], a) && too_many(1, a))
        return words[0] + " declares " + words[1] + " values, more than the file holds";
    return "";
}

} // namespace

std::string check_legacy_vtk(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string line;
    // "# vtk DataFile Version x.y", a title, ASCII or BINARY; VTK itself reports a bad header.
    std::string version, title, type;
    if (!std::getline(in, version) || !std::getline(in, title) || !std::getline(in, type))
        return "";
    // From format 5 on, cells are offsets and connectivity (walked with the data set below).
    const bool legacy_cells = vtk_major_version(version) < 5;
    const bool binary = lower(type).rfind("binary", 0) == 0;
    IntReader ints(in, binary);
    std::set<std::string> sections; // a data set has each at most once
    bool in_metadata = false;       // of a binary file, after a METADATA line
    in.seekg(0, std::ios::end);
    const int64_t most_values = 8 * int64_t(in.tellg());
    in.seekg(0);
    for (int i = 0; i < 3; ++i) std::getline(in, line);
    for (size_t number = 4;; ++number) {
        if (!std::getline(in, line)) break;
        std::vector<std::string> all_words;
        {
            std::istringstream split(line);
            for (std::string w; split >> w;) all_words.push_back(w);
        }
        if (all_words.empty()) continue;
        if (binary && in_metadata && ends_metadata(all_words)) in_metadata = false;
        if (!binary || in_metadata)
            if (std::string problem = decode_overrun(line, all_words); !problem.empty())
                return "line " + std::to_string(number) + ": " + problem;
        if (binary && lower(all_words[0]).rfind("metadata", 0) == 0) in_metadata = true;
        if (std::string problem = check_declared_size(all_words, most_values); !problem.empty())
            return "line " + std::to_string(number) + ": " + problem;
        std::istringstream words(line);
        std::string keyword, extra;
        int64_t cells = 0, size = 0;
        if (!(words >> keyword)) continue;
        const std::string section = vtk_section(keyword);
        // VTK's polydata reader ignores a failure to read the points and takes the next word
        // for a keyword: "-4.2FieldData" in the coordinates became a FIELD section it could not
        // read, and a null Delete(). ASCII coordinates must all be numbers.
        if (section == "points" && !binary && all_words.size() == 3) {
            int64_t points = 0;
            std::istringstream count(all_words[1]);
            if (count >> points && points >= 0) {
                int64_t read = 0; // line by line, so that the line numbers stay right
                while (read < 3 * points) {
                    if (!std::getline(in, line))
                        return "POINTS " + all_words[1] + ": the file ends in point " +
                               std::to_string(read / 3);
                    ++number;
                    std::istringstream values(line);
                    for (std::string word; read < 3 * points && values >> word; ++read)
                        if (!is_number_word(word))
                            return "line " + std::to_string(number) + ": POINTS " + all_words[1] +
                                   ": point " + std::to_string(read / 3) + " has " +
                                   io::quoted(word) + ", not a number";
                }
            }
            continue;
        }
        if (!legacy_cells) continue;
        if (is_counted_section(section) && (words >> cells) && !(words >> extra)) {
            // VTK 9.1 dereferences a null pointer at a second CELL_TYPES.
            if (!sections.insert(section).second) return "a second " + keyword + " section";
            continue;
        }
        if (!is_cell_keyword(section)) continue;
        if (!(words >> cells >> size) || (words >> extra)) continue; // not a cell array line
        if (!sections.insert(section).second) return "a second " + keyword + " section";
        if (cells < 0 || size < 0)
            return keyword + ": " + std::to_string(cells) + " cells in " + std::to_string(size) +
                   " numbers";
        if (std::string problem = walk_cells(ints, keyword, cells, size); !problem.empty())
            return problem;
    }
    // Then the data set as VTK's reader walks it, which finds the rest: its FIELD sections (VTK
    // 9.1's readers Delete() the null ReadFieldData returns for one they cannot read), and every
    // error VTK would return on.
    return DataSetWalk(path, most_values).problem();
}

} // namespace ddsimp::io
