#include "vtk_legacy_checks.h"

#include "ddsimp/io/vtk_messages.h"
#include "text_scanner.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <vector>

#include <vtkAbstractArray.h>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkDataReader.h>
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

// Walks the `size` integers of an array of `cells` cells, taken one at a time from `ints` (an
// IntReader or anything with next()); "" if they hold them exactly.
template <class Ints>
std::string walk_cells(Ints& ints, const std::string& keyword, int64_t cells, int64_t size) {
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

// VTK 9.1's DecodeString, which turns "%20" back into " " in the names and strings it reads,
// reads and writes past the end of a string of one or two characters with a '%' in it (its test
// that two characters follow a '%' underflows). True for such a string (up to a NUL, as VTK sees
// it).
bool overruns_decode(std::string_view text) {
    text = text.substr(0, text.find('\0'));
    return !text.empty() && text.size() < 3 && text.find('%') != std::string_view::npos;
}

// Such a word or line (a name, a string value, a component name) is never a number or a keyword,
// so a line scan refuses it wherever VTK could decode it: anywhere after an ASCII file's header,
// in the METADATA blocks of a binary file (the rest of a binary file is not split in lines and
// words, and its names are checked by the data-set walk). "" or what is wrong.
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

// VTK's ReadArray reads a binary string array as a length, in one to eight bytes, and that many
// bytes, for each value, and allocates each length before it reads it; a variant array as a
// type and a word for each value, each word decoded (see overruns_decode). Both are walked first,
// on VTK's stream, which is left where it was. "" or what is wrong.
std::string string_values_problem(vtkDataReader& reader, const std::string& type, int64_t values,
                                  std::streamoff file_size) {
    const std::string kind = lower(type);
    const bool strings = kind.rfind("string", 0) == 0 || kind.rfind("utf8_string", 0) == 0;
    const bool variants = kind.rfind("variant", 0) == 0;
    if (!strings && !variants) return "";
    // Each value takes a byte of the file at least; VTK makes an empty one for each it misses.
    if (values > file_size) return std::to_string(values) + " strings, more than the file holds";
    if (strings && reader.GetFileType() != VTK_BINARY) return ""; // lines, checked by the scan
    std::istream& in = *reader.GetIStream();
    const std::ios::iostate state = in.rdstate();
    in.clear();
    const std::streamoff start = in.tellg();
    in.clear(state);
    std::string problem;
    if (variants) {
        for (int64_t i = 0; i < values && problem.empty(); ++i) {
            int value_type = 0;
            std::string word;
            if (!(in >> value_type >> word)) break; // VTK reads empty words from here on
            if (overruns_decode(word))
                problem = "variant " + std::to_string(i) + " " + io::quoted(word) +
                          ": VTK 9.1 reads past a string of one or two characters with a '%'";
        }
    } else {
        char rest[256];
        in.getline(rest, 256); // as VTK reads it
        for (int64_t i = 0; i < values && problem.empty(); ++i) {
            const int first = in.peek();
            uint64_t length = 0;
            const int bytes = first == EOF ? 0 : std::array{8, 4, 2, 1}[first >> 6];
            if (bytes == 1) length = uint64_t(in.get()) & 0x3f;
            for (int b = 0; b < bytes && bytes > 1; ++b) length = length << 8 | uint8_t(in.get());
            if (bytes == 2) length &= 0x3fff;
            if (bytes == 4) length &= 0x3fffffff;
            if (first == EOF || !in) {
                problem = "the file ends in string " + std::to_string(i);
            } else if (length > uint64_t(file_size - in.tellg())) {
                problem = "string " + std::to_string(i) + " is " + std::to_string(length) +
                          " bytes long, more than the file holds";
            } else {
                in.seekg(std::streamoff(length), std::ios::cur);
            }
        }
    }
    in.clear();
    in.seekg(start);
    in.clear(state);
    return problem;
}

// Reads a FIELD section (just after the word FIELD) the way VTK 9.1's
// vtkDataReader::ReadFieldData does, with VTK's own ReadString, Read and ReadArray, but checks
// the counts before VTK allocates for them (an array count or array size the file cannot hold
// is gigabytes; a negative one a std::length_error thrown through VTK, which leaks what it had
// built). "" if VTK reads every array, else what is wrong.
std::string field_data_problem(vtkDataReader& reader, VtkMessageCapture& messages, int64_t limit,
                               std::streamoff file_size) {
    char name[1024];
    int arrays = 0;
    if (!reader.ReadString(name) || !reader.Read(&arrays)) return "no name and number of arrays";
    if (arrays < 0 || arrays > limit)
        return std::to_string(arrays) + " arrays, more than the file holds";
    for (int i = 0; i < arrays; ++i) {
        const std::string array = "array " + std::to_string(i);
        char type[1024];
        vtkIdType components = 0, tuples = 0;
        if (!reader.ReadString(name)) return "the file ends before " + array;
        if (std::string(name) == "NULL_ARRAY") continue;
        if (overruns_decode(name))
            return array + " is named " + io::quoted(name) +
                   ": VTK 9.1 reads past a name of one or two characters with a '%'";
        if (!reader.Read(&components) || !reader.Read(&tuples) || !reader.ReadString(type))
            return array + " has no component count, tuple count and type";
        if (components < 0 || tuples < 0 || (components > 0 && tuples > limit / components))
            return array + " declares " + std::to_string(components) + " components of " +
                   std::to_string(tuples) + " tuples, more than the file holds";
        if (std::string problem =
                string_values_problem(reader, type, tuples * components, file_size);
            !problem.empty())
            return array + ": " + problem;
        messages.clear();
        vtkAbstractArray* data = reader.ReadArray(type, tuples, components);
        if (data == nullptr)
            return messages.has_error() ? messages.first_error() : array + ": VTK cannot read it";
        data->Delete();
    }
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

// The line (from 1) that holds the byte at `offset` of the file: the newlines before it, counted
// when a message needs them.
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

// The first line "# vtk DataFile Version x.y" gives VTK's reader its major version (0 if it
// cannot read "x.y"); from 5 on, cells are offsets and connectivity.
int vtk_major_version(const std::string& first_line) {
    const std::string prefix = "# vtk DataFile Version";
    int major = 0, minor = 0;
    if (first_line.compare(0, prefix.size(), prefix) != 0 ||
        std::sscanf(first_line.c_str() + prefix.size(), "%d.%d", &major, &minor) != 2)
        return 0;
    return major;
}

bool starts_with(const std::string& word, const char* prefix) {
    return word.rfind(prefix, 0) == 0;
}

// The integers of a cell array VTK has read, one at a time, for walk_cells.
struct VectorInts {
    const std::vector<int>& values;
    size_t at = 0;
    std::optional<int64_t> next() {
        if (at == values.size()) return std::nullopt;
        return values[at++];
    }
};

// Walks the data set of a POLYDATA or UNSTRUCTURED_GRID file the way VTK 9.1's
// vtkPolyDataReader::ReadMeshSimple and vtkUnstructuredGridReader::ReadMeshSimple do, section
// by section, with VTK's own ReadString, Read, ReadArray and ReadCellsLegacy on VTK's own stream
// (so every word is the word VTK meets), then its point and cell data as vtkDataReader's
// ReadPointData and ReadCellData do, to the end of the file. Those readers
// return on each error they find without freeing what they have read (the grid reader's cell
// types and cells; the poly data reader goes on reading a closed stream after a cell array it
// cannot read), so every such error is found here first. Besides, the walk refuses what VTK does
// not check and would read past: CELL_TYPES with fewer types than the cells of CELLS, format 5
// offsets that leave their connectivity, a second CELLS or CELL_TYPES in a grid (the first
// leaks), string arrays where VTK needs numbers (it loses them). Every array is read once more
// than VTK reads it (and freed at once).
class DataSetWalk {
public:
    DataSetWalk(const std::string& path, int64_t most_values)
        : path_(path), limit_(most_values), file_size_(most_values / 8),
          reader_(vtkSmartPointer<vtkDataReader>::New()) {}
    ~DataSetWalk() { reader_->CloseVTKFile(); }
    DataSetWalk(const DataSetWalk&) = delete;
    DataSetWalk& operator=(const DataSetWalk&) = delete;

    // "" if VTK reads the data set without an error, else what is wrong.
    std::string problem() {
        if (!reader_->OpenVTKFile(path_.c_str()) || !reader_->ReadHeader(path_.c_str()))
            return ""; // VTK reports a bad header itself
        // vtkDataSetReader reads nothing but "DATASET type" here (else VTK's message has an
        // address in it).
        char word[256];
        if (!reader_->ReadString(word)) return "the file ends after its header";
        if (!starts_with(lower(word), "dataset"))
            return at(here()) + io::quoted(word) + " where DATASET should be";
        if (!reader_->ReadString(word)) return "the file ends after DATASET";
        const std::string type = lower(word);
        // As vtkDataSetReader picks its reader; the others read volumes, not surfaces.
        if (starts_with(type, "structured_points")) return not_a_surface("vtkStructuredPoints");
        if (starts_with(type, "structured_grid")) return not_a_surface("vtkStructuredGrid");
        if (starts_with(type, "rectilinear_grid")) return not_a_surface("vtkRectilinearGrid");
        grid_ = starts_with(type, "unstructured_grid");
        if (!grid_ && !starts_with(type, "polydata"))
            return at(here()) + io::quoted(word) +
                   " is not a data set type (POLYDATA, UNSTRUCTURED_GRID, STRUCTURED_POINTS, "
                   "STRUCTURED_GRID, RECTILINEAR_GRID)";
        return sections();
    }

private:
    static std::string not_a_surface(const std::string& type) {
        return "it holds a " + type +
               ", not a triangle surface (for a volume, use `ddsimp isosurface`)";
    }

    // Where VTK's stream is: just after the word it read last (found without disturbing the
    // stream's state).
    std::streamoff here() const {
        std::istream& in = *reader_->GetIStream();
        const std::ios::iostate state = in.rdstate();
        in.clear();
        const std::streamoff at = in.tellg();
        in.clear(state);
        return std::max<std::streamoff>(at - 1, 0);
    }

    std::string sections() {
        std::string previous;           // the section before
        std::streamoff previous_at = 0; // and where
        std::streamoff field_at = -1;   // a FIELD section just read
        for (char raw[256]; reader_->ReadString(raw);) {
            const std::string word = raw, keyword = lower(raw);
            const std::streamoff word_at = here();
            // VTK takes a misread "cells0" for CELLS, then leaks the cells on its error return:
            // a FIELD section is followed by a whole keyword.
            static const std::set<std::string> keywords{
                "points",   "cells",           "cell_types", "vertices",  "lines",
                "polygons", "triangle_strips", "point_data", "cell_data", "field"};
            if (field_at >= 0 && !keywords.count(keyword))
                return field_problem(field_at,
                                     "it is followed by " + io::quoted(word) + ", not a section");
            field_at = -1;
            std::string problem;
            if (starts_with(keyword, "field")) {
                problem = field_data_problem(*reader_, messages_, limit_, file_size_);
                if (!problem.empty()) return field_problem(word_at, problem);
                field_at = word_at;
            } else if (starts_with(keyword, "points")) {
                problem = points(word);
            } else if (!grid_ &&
                       (starts_with(keyword, "vertices") || starts_with(keyword, "lines") ||
                        starts_with(keyword, "polygons") ||
                        starts_with(keyword, "triangle_strips"))) {
                vtkIdType cells = 0;
                problem = cell_array(word, cells);
                poly_cells_[vtk_section(keyword)] = cells; // a second one replaces the first
            } else if (grid_ && starts_with(keyword, "cells")) {
                if (grid_cells_) return at(word_at) + "a second " + word + " section";
                vtkIdType cells = 0;
                problem = cell_array(word, cells);
                grid_cells_ = cells;
                if (major_version() < 5) last_count_ = cells;
                if (problem.empty()) problem = types_for_cells();
            } else if (grid_ && starts_with(keyword, "cell_types")) {
                problem = cell_types(word);
                if (problem.empty()) problem = types_for_cells();
            } else if (starts_with(keyword, "cell_data") || starts_with(keyword, "point_data")) {
                // VTK reads on with the attributes, to the end of the file.
                const bool point_data = starts_with(keyword, "point_data");
                vtkIdType count = 0;
                problem = point_data ? data_count(word, points_, "points", count)
                                     : data_count(word, grid_ ? last_count_ : poly_cell_count(),
                                                  "cells", count);
                return problem.empty() ? attributes(point_data, count) : problem;
            } else {
                return at(word_at) + io::quoted(word) + " is not a section keyword" +
                       (previous.empty() ? ""
                                         : "; the section before it is " + previous + " (line " +
                                               std::to_string(line_of(path_, previous_at)) + ")");
            }
            if (!problem.empty()) return at(word_at) + problem;
            previous = word;
            previous_at = word_at;
        }
        return "";
    }

    int major_version() const { return reader_->GetFileMajorVersion(); }

    // "line n: ", n the line of `offset`.
    std::string at(std::streamoff offset) const {
        return "line " + std::to_string(line_of(path_, offset)) + ": ";
    }

    std::string field_problem(std::streamoff field_at, const std::string& problem) const {
        return "the data set's FIELD section (line " + std::to_string(line_of(path_, field_at)) +
               ") cannot be read: " + problem;
    }

    bool too_many(vtkIdType tuples, vtkIdType components) const {
        return tuples < 0 || components < 0 || (components > 0 && tuples > limit_ / components);
    }

    // ReadArray of a `tuples` x `components` array of `type`; `what` names it. The array, or
    // null and `problem` says why. `numeric`: the reader needs a vtkDataArray (VTK's attribute
    // and point readers leak a string array they cannot use).
    vtkSmartPointer<vtkAbstractArray> read_array(const std::string& what, const char* type,
                                                 vtkIdType tuples, vtkIdType components,
                                                 bool numeric, std::string& problem) {
        if (too_many(tuples, components)) {
            problem = what + ": " + std::to_string(tuples) + " tuples of " +
                      std::to_string(components) + " components, more than the file holds";
            return nullptr;
        }
        problem = string_values_problem(*reader_, type, tuples * components, file_size_);
        if (!problem.empty()) {
            problem = what + ": " + problem;
            return nullptr;
        }
        messages_.clear();
        auto array = vtk::TakeSmartPointer(reader_->ReadArray(type, tuples, components));
        if (!array)
            problem = what + ": " +
                      (messages_.has_error() ? messages_.first_error() : "VTK cannot read it");
        else if (numeric && !vtkDataArray::SafeDownCast(array))
            problem = what + ": " + io::quoted(type) + " is not a numeric type";
        return problem.empty() ? array : nullptr;
    }

    // The same, its type the next word.
    vtkSmartPointer<vtkAbstractArray> read_array(const std::string& what, vtkIdType tuples,
                                                 vtkIdType components, bool numeric,
                                                 std::string& problem) {
        char type[256];
        if (reader_->ReadString(type))
            return read_array(what, type, tuples, components, numeric, problem);
        problem = what + ": the file ends before its data type";
        return nullptr;
    }

    std::string points(const std::string& word) {
        if (!reader_->Read(&points_)) return word + " has no point count";
        const std::string what = word + " " + std::to_string(points_);
        if (too_many(points_, 3)) return what + ": more points than the file holds";
        std::string problem;
        read_array(what, points_, 3, true, problem);
        return problem;
    }

    // VERTICES, LINES, POLYGONS, TRIANGLE_STRIPS or CELLS, in the layout of the file's version;
    // `cells` is how many cells VTK makes of it.
    std::string cell_array(const std::string& word, vtkIdType& cells) {
        vtkIdType first = 0, second = 0;
        if (!reader_->Read(&first) || !reader_->Read(&second))
            return word + " has no cell count and size";
        const std::string what = word + " " + std::to_string(first) + " " + std::to_string(second);
        if (first < 0 || second < 0 || first > limit_ || second > limit_)
            return what + ": more than the file holds";
        if (major_version() < 5) {
            // "WORD cells size", then size integers: a count and that many ids for each cell.
            std::vector<int> values(static_cast<size_t>(second));
            if (!reader_->ReadCellsLegacy(second, values.data()))
                return what + ": the file ends, or has a word that is not an integer, in its " +
                       std::to_string(second) + " numbers";
            VectorInts ints{values};
            cells = first;
            return walk_cells(ints, word, first, second);
        }
        // "WORD offsets connectivity", then "OFFSETS type" and "CONNECTIVITY type" arrays.
        if (first < 1) return ""; // VTK reads no arrays
        cells = first - 1;
        std::string problem;
        char header[256];
        if (!reader_->ReadString(header) || lower(header) != "offsets")
            return what + ": no OFFSETS array";
        const auto offsets_array = read_array(what + " OFFSETS", first, 1, true, problem);
        auto* offsets = vtkDataArray::SafeDownCast(offsets_array);
        if (!offsets) return problem;
        if (!reader_->ReadString(header) || lower(header) != "connectivity")
            return what + ": no CONNECTIVITY array";
        const auto connectivity_array =
            read_array(what + " CONNECTIVITY", second, 1, true, problem);
        auto* connectivity = vtkDataArray::SafeDownCast(connectivity_array);
        if (!connectivity) return problem;
        messages_.clear();
        if (!vtkSmartPointer<vtkCellArray>::New()->SetData(offsets, connectivity))
            return what + ": " +
                   (messages_.has_error() ? messages_.first_error()
                                          : "VTK takes no cells of these array types");
        // VTK does not check the offsets, and a cell past the connectivity is read past it.
        double before = 0;
        for (vtkIdType i = 0; i < first; ++i) {
            const double offset = offsets->GetComponent(i, 0);
            if ((i == 0 && offset != 0) || offset < before || offset > double(second))
                return what + ": offset " + std::to_string(i) + " is " + number(offset) +
                       " (offsets go from 0 up to the " + std::to_string(second) +
                       " ids of the connectivity)";
            before = offset;
        }
        if (before != double(second))
            return what + ": the offsets end at " + number(before) + ", not at the " +
                   std::to_string(second) + " ids of the connectivity";
        return "";
    }

    static std::string number(double value) {
        std::ostringstream out;
        out << value;
        return out.str();
    }

    std::string cell_types(const std::string& word) {
        vtkIdType count = 0;
        if (!reader_->Read(&count)) return word + " has no count";
        const std::string what = word + " " + std::to_string(count);
        if (types_) return "a second " + word + " section";
        if (count < 0 || count > limit_) return what + ": more types than the file holds";
        std::istream& in = *reader_->GetIStream();
        if (reader_->GetFileType() == VTK_BINARY) {
            char rest[256];
            in.getline(rest, 256); // as VTK reads them
            std::vector<char> bytes(sizeof(int) * size_t(count));
            in.read(bytes.data(), std::streamsize(bytes.size()));
            if (in.eof()) return what + ": the file ends in its types";
        } else {
            for (vtkIdType i = 0; i < count; ++i) {
                int type = 0;
                if (!reader_->Read(&type))
                    return what + ": type " + std::to_string(i) +
                           " is not an integer, or the file ends before it";
            }
        }
        types_ = count;
        last_count_ = count;
        return "";
    }

    // VTK's grid copies one type for each cell of CELLS, whatever CELL_TYPES holds.
    std::string types_for_cells() const {
        if (!types_ || !grid_cells_ || *types_ >= *grid_cells_) return "";
        return "CELL_TYPES has " + std::to_string(*types_) + " types for the " +
               std::to_string(*grid_cells_) + " cells of CELLS";
    }

    vtkIdType poly_cell_count() const {
        vtkIdType total = 0;
        for (const auto& [section, cells] : poly_cells_) total += cells;
        return total;
    }

    // POINT_DATA or CELL_DATA and its count, which VTK compares with the data set's.
    std::string data_count(const std::string& word, vtkIdType expected, const char* of,
                           vtkIdType& count) const {
        const std::streamoff word_at = here();
        if (!reader_->Read(&count)) return at(word_at) + word + " has no count";
        if (count != expected)
            return at(word_at) + word + " " + std::to_string(count) + " for a data set of " +
                   std::to_string(expected) + " " + of;
        return "";
    }

    // The point data (or cell data) of `count` tuples, as vtkDataReader::ReadPointData and
    // ReadCellData read it, up to the end of the file: each attribute's header, then its array.
    // Their errors do not leak, but what VTK reads past an array it cannot use does: an
    // attribute whose type is not numeric (ReadScalarData and the others lose the string array
    // they cannot use) and a LOOKUP_TABLE that ends early (ReadLutData).
    std::string attributes(bool point_data, vtkIdType count) {
        const std::string of = point_data ? "POINT_DATA" : "CELL_DATA";
        for (char raw[256]; reader_->ReadString(raw);) {
            const std::string word = raw, keyword = lower(raw);
            const std::streamoff word_at = here();
            std::string problem;
            if (starts_with(keyword, "scalars")) {
                problem = scalars(word, count);
            } else if (starts_with(keyword, "vectors") || starts_with(keyword, "normals")) {
                problem = named_array(word, count, 3, true);
            } else if (starts_with(keyword, "tensors6")) {
                problem = named_array(word, count, 6, true);
            } else if (starts_with(keyword, "tensors")) {
                problem = named_array(word, count, 9, true);
            } else if (starts_with(keyword, "texture_coordinates")) {
                problem = texture_coordinates(word, count);
            } else if (starts_with(keyword, "global_ids")) {
                problem = named_array(word, count, 1, true);
            } else if (starts_with(keyword, "pedigree_ids") ||
                       (point_data && starts_with(keyword, "edge_flags"))) {
                problem = named_array(word, count, 1, false);
            } else if (starts_with(keyword, "color_scalars")) {
                problem = color_scalars(word, count);
            } else if (starts_with(keyword, "lookup_table")) {
                problem = lookup_table(word);
            } else if (starts_with(keyword, "field")) {
                problem = field_data_problem(*reader_, messages_, limit_, file_size_);
                if (!problem.empty()) problem = word + " of " + of + " cannot be read: " + problem;
            } else if (starts_with(keyword, point_data ? "cell_data" : "point_data")) {
                // VTK reads the other kind in a call nested in this one: each switch is a
                // deeper stack.
                if (++switches_ > kMostSwitches)
                    return at(word_at) + "more than " + std::to_string(kMostSwitches) +
                           " switches between POINT_DATA and CELL_DATA";
                vtkIdType other = 0;
                if (!reader_->Read(&other)) return at(word_at) + word + " has no count";
                if (too_many(other, 1))
                    return at(word_at) + word + " " + std::to_string(other) +
                           ": more values than the file holds";
                return attributes(!point_data, other);
            } else {
                return at(word_at) + io::quoted(word) + " is not an attribute of " + of;
            }
            if (!problem.empty()) return at(word_at) + problem;
        }
        return "";
    }

    // An attribute "KEYWORD name type" of `components` components (SCALARS, VECTORS, ...);
    // `numeric`: VTK needs a vtkDataArray for it.
    std::string named_array(const std::string& word, vtkIdType count, vtkIdType components,
                            bool numeric) {
        char name[256];
        if (!reader_->ReadString(name)) return word + " has no name and type";
        if (overruns_decode(name)) return name_overrun(word, name);
        return array_problem(word + " " + name, count, components, numeric);
    }

    // ReadArray's problem with the array whose type comes next, "" if none.
    std::string array_problem(const std::string& what, vtkIdType tuples, vtkIdType components,
                              bool numeric) {
        std::string problem;
        read_array(what, tuples, components, numeric, problem);
        return problem;
    }

    static std::string name_overrun(const std::string& word, const char* name) {
        return word + " " + io::quoted(name) +
               ": VTK 9.1 reads past a name of one or two characters with a '%'";
    }

    // "SCALARS name type [components]" then "LOOKUP_TABLE name", then the array.
    std::string scalars(const std::string& word, vtkIdType count) {
        char name[256], type[256], key[256], table[256];
        if (!reader_->ReadString(name) || !reader_->ReadString(type) || !reader_->ReadString(key))
            return word + " has no name and type";
        if (overruns_decode(name)) return name_overrun(word, name);
        int components = 1;
        if (lower(key) != "lookup_table") {
            components = std::atoi(key);
            if (components < 1 || !reader_->ReadString(key))
                return word + " " + name + ": " + io::quoted(key) + " is not a component count";
        }
        if (lower(key) != "lookup_table" || !reader_->ReadString(table))
            return word + " " + name + ": no LOOKUP_TABLE name after its type";
        // The type came before the table name.
        std::string problem;
        read_array(word + " " + name, type, count, components, true, problem);
        return problem;
    }

    // "TEXTURE_COORDINATES name dimension type".
    std::string texture_coordinates(const std::string& word, vtkIdType count) {
        char name[256];
        int dimension = 0;
        if (!reader_->ReadString(name) || !reader_->Read(&dimension))
            return word + " has no name and dimension";
        if (overruns_decode(name)) return name_overrun(word, name);
        if (dimension < 1 || dimension > 3)
            return word + " " + name + ": dimension " + std::to_string(dimension) +
                   " (VTK reads 1 to 3)";
        return array_problem(word + " " + name, count, dimension, true);
    }

    // "COLOR_SCALARS name components", then unsigned chars (binary) or floats (ASCII).
    std::string color_scalars(const std::string& word, vtkIdType count) {
        char name[256];
        int components = 0;
        if (!reader_->ReadString(name) || !reader_->Read(&components))
            return word + " has no name and component count";
        if (overruns_decode(name)) return name_overrun(word, name);
        std::string problem;
        read_array(word + " " + name,
                   reader_->GetFileType() == VTK_BINARY ? "unsigned_char" : "float", count,
                   components, false, problem);
        return problem;
    }

    // "LOOKUP_TABLE name size", then size RGBA colours: VTK leaks the table if they end early.
    std::string lookup_table(const std::string& word) {
        char name[256];
        int size = 0;
        if (!reader_->ReadString(name) || !reader_->Read(&size))
            return word + " has no name and size";
        const std::string what = word + " " + name + " " + std::to_string(size);
        if (too_many(size, 4)) return what + ": more colours than the file holds";
        std::istream& in = *reader_->GetIStream();
        if (reader_->GetFileType() == VTK_BINARY) {
            char rest[256];
            in.getline(rest, 256); // as VTK reads it
            std::vector<char> bytes(4 * size_t(size));
            in.read(bytes.data(), std::streamsize(bytes.size()));
            if (in.eof()) return what + ": the file ends in its colours";
            return "";
        }
        for (int i = 0; i < 4 * size; ++i) {
            float value = 0;
            if (!reader_->Read(&value))
                return what + ": colour " + std::to_string(i / 4) +
                       " is not 4 numbers, or the file ends in it";
        }
        return "";
    }

    std::string path_;
    int64_t limit_;
    std::streamoff file_size_;
    vtkSmartPointer<vtkDataReader> reader_;
    VtkMessageCapture messages_;
    bool grid_ = false;
    vtkIdType points_ = 0;
    std::map<std::string, vtkIdType> poly_cells_;
    std::optional<vtkIdType> grid_cells_, types_;
    vtkIdType last_count_ = 0; // VTK's ncells: the last count of a legacy CELLS or of CELL_TYPES
    // VTK reads POINT_DATA after CELL_DATA (and back) in a call nested in the one before: a file
    // of thousands of switches overflows the stack. No real file has more than one.
    static constexpr int kMostSwitches = 100;
    int switches_ = 0;
};

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
