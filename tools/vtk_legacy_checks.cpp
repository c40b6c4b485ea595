#include "vtk_legacy_checks.h"

#include "text_scanner.h"
#include "vtk_messages.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include <vtkAbstractArray.h>
#include <vtkPolyDataReader.h>
#include <vtkSmartPointer.h>

namespace ddsimp::io {
namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

// Sections "KEYWORD n" (a count and nothing else on the line).
bool is_counted_section(const std::string& word) {
    return word == "cell_types" || word == "point_data" || word == "cell_data";
}

bool is_cell_keyword(const std::string& word) {
    return word == "vertices" || word == "lines" || word == "polygons" ||
           word == "triangle_strips" || word == "cells";
}

// The integers of one cell array, read one at a time (ASCII tokens or big-endian int32).
class IntReader {
public:
    IntReader(std::istream& in, bool binary) : in_(in), binary_(binary) {}

    std::optional<int64_t> next() {
        if (!binary_) {
            long long v = 0;
            if (!(in_ >> v)) return std::nullopt;
            return v;
        }
        std::array<unsigned char, 4> b{};
        if (!in_.read(reinterpret_cast<char*>(b.data()), 4)) return std::nullopt;
        return int32_t(uint32_t(b[0]) << 24 | uint32_t(b[1]) << 16 | uint32_t(b[2]) << 8 |
                       uint32_t(b[3]));
    }

private:
    std::istream& in_;
    bool binary_;
};

// Walks the `size` integers of an array of `cells` cells; "" if they hold them exactly.
std::string walk_cells(IntReader& ints, const std::string& keyword, int64_t cells, int64_t size) {
    const std::string what = keyword + " " + std::to_string(cells) + " " + std::to_string(size);
    int64_t at = 0;
    for (int64_t c = 0; c < cells; ++c) {
        if (at >= size) return what + ": the array ends before cell " + std::to_string(c);
        const std::optional<int64_t> count = ints.next();
        if (!count) return what + ": the file ends in cell " + std::to_string(c);
        if (*count < 0 || *count > size - at - 1)
            return what + ": cell " + std::to_string(c) + " has " + std::to_string(*count) +
                   " points, more than the array holds";
        for (int64_t i = 0; i < *count; ++i)
            if (!ints.next()) return what + ": the file ends in cell " + std::to_string(c);
        at += 1 + *count;
    }
    if (at != size)
        return what + ": the cells take " + std::to_string(at) + " of the " + std::to_string(size) +
               " numbers";
    return "";
}

// Reads a data set's FIELD section from `offset` (just after the word FIELD) the way VTK 9.1's
// vtkDataReader::ReadFieldData does, with VTK's own ReadString, Read and ReadArray, but checks
// the counts before VTK allocates for them (an array count or array size the file cannot hold
// is gigabytes; a negative one a std::length_error thrown through VTK, which leaks what it had
// built). "" if VTK reads every array, else what is wrong.
std::string check_field_data(const std::string& path, std::streamoff offset, int64_t limit) {
    VtkMessageCapture messages;
    auto reader = vtkSmartPointer<vtkPolyDataReader>::New();
    if (!reader->OpenVTKFile(path.c_str()) || !reader->ReadHeader(path.c_str())) {
        reader->CloseVTKFile();
        return ""; // VTK reports a bad header itself
    }
    reader->GetIStream()->seekg(offset);
    const auto problem = [&](const std::string& what) {
        reader->CloseVTKFile();
        return what;
    };
    char name[1024];
    int arrays = 0;
    if (!reader->ReadString(name) || !reader->Read(&arrays))
        return problem("no name and number of arrays");
    if (arrays < 0 || arrays > limit)
        return problem(std::to_string(arrays) + " arrays, more than the file holds");
    for (int i = 0; i < arrays; ++i) {
        const std::string array = "array " + std::to_string(i);
        char type[1024];
        vtkIdType components = 0, tuples = 0;
        if (!reader->ReadString(name)) return problem("the file ends before " + array);
        if (std::string(name) == "NULL_ARRAY") continue;
        if (!reader->Read(&components) || !reader->Read(&tuples) || !reader->ReadString(type))
            return problem(array + " has no component count, tuple count and type");
        if (components < 0 || tuples < 0 || (components > 0 && tuples > limit / components))
            return problem(array + " declares " + std::to_string(components) + " components of " +
                           std::to_string(tuples) + " tuples, more than the file holds");
        vtkAbstractArray* data = reader->ReadArray(type, tuples, components);
        if (data == nullptr)
            return problem(messages.has_error() ? messages.first_error()
                                                : array + ": VTK cannot read it");
        data->Delete();
    }
    // VTK goes on with the word after the section and takes "cells0" for CELLS (it compares
    // prefixes); a section misread above ends elsewhere than before a keyword. (After a CELLS
    // section, VTK's error returns leak its cell array.)
    static const std::set<std::string> keywords{
        "points",   "cells",           "cell_types", "vertices",  "lines",
        "polygons", "triangle_strips", "point_data", "cell_data", "field"};
    if (reader->ReadString(name) && !keywords.count(lower(name)))
        return problem("it is followed by " + io::quoted(name) + ", not a section");
    reader->CloseVTKFile();
    return "";
}

// The section VTK's readers take `word` for: they compare the lower-cased word's start with each
// keyword ("FIELDvtkidty" is a FIELD section to them), so this does too.
std::string vtk_section(const std::string& word) {
    static const char* const keywords[] = {"points",    "cells",    "cell_types",      "vertices",
                                           "lines",     "polygons", "triangle_strips", "point_data",
                                           "cell_data", "field"};
    const std::string lowered = lower(word);
    for (const char* k : keywords)
        if (lowered.rfind(k, 0) == 0) return k;
    return lowered;
}

// A number as `>>` reads a double (digits, sign, point, exponent; not "nan" or "inf", which
// libstdc++ does not read either).
bool is_number_word(const std::string& word) {
    if (word.find_first_not_of("0123456789+-.eE") != std::string::npos) return false;
    const char* begin = word.data() + (word[0] == '+' ? 1 : 0);
    double value = 0;
    const auto [end, error] = std::from_chars(begin, word.data() + word.size(), value);
    return end == word.data() + word.size() &&
           (error == std::errc() || error == std::errc::result_out_of_range);
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
    // Format 5 lists cells as offsets and connectivity, which VTK checks.
    const bool legacy_cells = version.find("Version 5") == std::string::npos;
    const bool binary = lower(type).rfind("binary", 0) == 0;
    IntReader ints(in, binary);
    std::set<std::string> sections; // a data set has each at most once
    struct Field {
        std::streamoff offset;
        size_t line;
    };
    std::vector<Field> fields; // of the data set (before its point and cell data)
    bool in_attributes = false;
    in.seekg(0, std::ios::end);
    const int64_t most_values = 8 * int64_t(in.tellg());
    in.seekg(0);
    for (int i = 0; i < 3; ++i) std::getline(in, line);
    for (size_t number = 4;; ++number) {
        const std::streamoff start = in.tellg();
        if (!std::getline(in, line)) break;
        std::vector<std::string> all_words;
        {
            std::istringstream split(line);
            for (std::string w; split >> w;) all_words.push_back(w);
        }
        if (all_words.empty()) continue;
        if (std::string problem = check_declared_size(all_words, most_values); !problem.empty())
            return "line " + std::to_string(number) + ": " + problem;
        std::istringstream words(line);
        std::string keyword, extra;
        int64_t cells = 0, size = 0;
        if (!(words >> keyword)) continue;
        const std::string section = vtk_section(keyword);
        if (section == "point_data" || section == "cell_data") in_attributes = true;
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
        if (section == "field" && !in_attributes)
            fields.push_back({start + std::streamoff(words.tellg()), number});
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
    // VTK 9.1's data set readers call Delete() on what ReadFieldData returns without checking it
    // for null, which it is when an array in the section cannot be read.
    for (const Field& field : fields)
        if (std::string problem = check_field_data(path, field.offset, most_values);
            !problem.empty())
            return "the data set's FIELD section (line " + std::to_string(field.line) +
                   ") cannot be read: " + problem;
    return "";
}

} // namespace ddsimp::io
