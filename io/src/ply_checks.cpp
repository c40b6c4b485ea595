#include "ply_checks.h"

#include "ply_types.h"
#include "text_scanner.h"

#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

namespace ddsimp::io {

namespace {

// What OpenMesh does with a property's values (PLYReader.cc, read_ascii and read_binary).
enum class Use {
    AsFloat,    // vertex x y z nx ny nz u v s t: read as a float whatever the declared type
    AsDeclared, // colours, texnumber, custom properties: read as the declared type
    Indices,    // the face's vertex_indices list
    Skipped,    // properties of other elements: one word, or one item's bytes, each
};

struct Property {
    std::string name;
    PlyType type;
    bool list = false;
    PlyType count_type;
    Use use = Use::AsDeclared;
};

struct Element {
    std::string name;
    int64_t count = 0;
    std::vector<Property> properties;
};

struct Header {
    bool ascii = true;
    bool big_endian = false;
    std::vector<Element> elements;
    size_t lines = 0;         // the header's lines, end_header included
    size_t data_offset = 0;   // after the end_header line
    size_t openmesh_data = 0; // where OpenMesh's binary reader starts
};

bool is_vertex_float(std::string_view name) {
    return name == "x" || name == "y" || name == "z" || name == "nx" || name == "ny" ||
           name == "nz" || name == "u" || name == "v" || name == "s" || name == "t";
}

std::vector<std::string_view> words_of(std::string_view line) {
    std::vector<std::string_view> words;
    TextScanner scanner(line);
    while (auto word = scanner.next()) words.push_back(*word);
    return words;
}

std::string header_error(size_t line, const std::string& what) {
    return "PLY header line " + std::to_string(line) + ": " + what;
}

// One header line (its words) into `header`; "" or what is wrong.
std::string read_header_line(const std::vector<std::string_view>& words, size_t line,
                             Header& header) {
    const std::string_view keyword = words[0];
    if (keyword == "comment") return "";
    if (keyword == "obj_info") {
        // OpenMesh reads each word of it as a keyword.
        for (size_t i = 1; i < words.size(); ++i)
            if (words[i] == "element" || words[i] == "property" || words[i] == "comment" ||
                words[i] == "end_header")
                return header_error(line, "OpenMesh's reader would take the word " +
                                              quoted(words[i]) + " in obj_info for a keyword");
        return "";
    }
    if (keyword == "element") {
        Element element;
        if (words.size() != 3 || !is_integer_word(words[2], element.count) || element.count < 0 ||
            element.count > std::numeric_limits<uint32_t>::max())
            return header_error(line, "'element' needs a name and a count from 0 to 2^32-1");
        element.name = std::string(words[1]);
        header.elements.push_back(element);
        return "";
    }
    if (keyword == "property") {
        if (header.elements.empty()) return header_error(line, "a property before any element");
        Element& element = header.elements.back();
        Property p;
        if (words.size() > 1 && words[1] == "list") {
            if (words.size() != 5)
                return header_error(line,
                                    "'property list' needs a count type, an item type and a name");
            const auto count = ply_type(words[2]), item = ply_type(words[3]);
            if (words[2] != "uchar" && words[2] != "uint8" && words[2] != "uint16" &&
                words[2] != "int")
                return header_error(line, "OpenMesh's reader takes list counts of type uchar, "
                                          "uint8, uint16 or int, not " +
                                              quoted(words[2]));
            if (!item) return header_error(line, quoted(words[3]) + " is not a PLY type");
            p.name = std::string(words[4]);
            p.type = *item;
            p.list = true;
            p.count_type = *count;
        } else {
            if (words.size() != 3) return header_error(line, "'property' needs a type and a name");
            // OpenMesh takes either word as the type.
            const auto first = ply_type(words[1]), second = ply_type(words[2]);
            if (!first && !second)
                return header_error(line, "neither " + quoted(words[1]) + " nor " +
                                              quoted(words[2]) + " is a PLY type");
            p.name = std::string(first ? words[2] : words[1]);
            p.type = first ? *first : *second;
        }
        if (element.name == "vertex" && !p.list && is_vertex_float(p.name)) {
            p.use = Use::AsFloat;
            if (!header.ascii && !p.type.is_float)
                return header_error(line, "OpenMesh's binary reader reads vertex property " +
                                              quoted(p.name) + " only as float or double");
        } else if (element.name == "face" && p.list &&
                   (p.name == "vertex_index" || p.name == "vertex_indices")) {
            if (p.type.is_float)
                return header_error(line, "vertex indices must be of an integer type");
            element.properties.clear(); // OpenMesh drops the face properties before them
            p.use = Use::Indices;
        } else if (element.name == "face" && (p.name == "texcoord" || p.name == "texnumber")) {
            // Read as floats (texcoord) or an index (texnumber) by OpenMesh's own code.
            if (p.name == "texcoord" ? !p.type.is_float : p.type.is_float || p.list)
                return header_error(line, "OpenMesh's reader cannot read face property " +
                                              quoted(p.name) + " of this type");
        } else if (element.name != "vertex" && element.name != "face") {
            p.use = Use::Skipped;
        }
        element.properties.push_back(p);
        return "";
    }
    return header_error(line, "unknown keyword " + quoted(keyword));
}

// The header, or what is wrong with it; nullopt if it does not start with "ply" (OpenMesh
// refuses such files itself).
std::optional<Header> read_header(std::string_view file, std::string& problem) {
    Header header;
    size_t start = 0, line = 0;
    size_t after_last_word = 0; // where OpenMesh's stream stands before it reads a keyword
    bool format_seen = false;
    while (start < file.size()) {
        ++line;
        size_t end = file.find('\n', start);
        const size_t next = end == std::string_view::npos ? file.size() : end + 1;
        if (end == std::string_view::npos) end = file.size();
        const std::string_view text = file.substr(start, end - start);
        const std::vector<std::string_view> words = words_of(text);
        if (line == 1) {
            if (words.size() != 1 || (words[0] != "ply" && words[0] != "PLY")) return std::nullopt;
        } else if (!words.empty()) {
            if (!format_seen) {
                if (words.size() != 3 || words[0] != "format" || !is_float_word(words[2]) ||
                    (words[1] != "ascii" && words[1] != "binary_little_endian" &&
                     words[1] != "binary_big_endian")) {
                    problem = header_error(line, "expected 'format ascii|binary_little_endian|"
                                                 "binary_big_endian VERSION'");
                    return header;
                }
                format_seen = true;
                header.ascii = words[1] == "ascii";
                header.big_endian = words[1] == "binary_big_endian";
            } else if (words[0] == "end_header") {
                if (words.size() != 1) {
                    problem = header_error(line, "end_header must be alone on its line");
                    return header;
                }
                header.lines = line;
                header.data_offset = next;
                // OpenMesh seeks 12 bytes ("\nend_header\n") past where it stood, 14 after
                // "\r\n".
                header.openmesh_data =
                    after_last_word + (file.substr(after_last_word, 2) == "\r\n" ? 14 : 12);
                return header;
            } else if (problem = read_header_line(words, line, header); !problem.empty()) {
                return header;
            }
            const std::string_view last = words.back();
            after_last_word =
                words[0] == "comment" ? next : size_t(last.data() - file.data()) + last.size();
        }
        start = next;
    }
    problem = "the PLY header has no end_header line";
    return header;
}

// Reads binary values as OpenMesh does, refusing to run past the end of the file.
class Bytes {
public:
    Bytes(std::string_view file, size_t at, bool big_endian)
        : file_(file), at_(at), big_endian_(big_endian) {}

    bool skip(uint64_t n) {
        if (n > file_.size() - at_) return false;
        at_ += size_t(n);
        return true;
    }
    // A list count; nullopt if the file ends.
    std::optional<int64_t> count(const PlyType& type) {
        if (size_t(type.size) > file_.size() - at_) return std::nullopt;
        uint64_t value = 0;
        for (int i = 0; i < type.size; ++i) {
            const int byte = big_endian_ ? i : type.size - 1 - i;
            value = value << 8 | static_cast<unsigned char>(file_[at_ + size_t(byte)]);
        }
        at_ += size_t(type.size);
        if (type.is_signed && type.size == 4) return int64_t(int32_t(uint32_t(value)));
        return int64_t(value);
    }
    size_t remaining() const { return file_.size() - at_; }

private:
    std::string_view file_;
    size_t at_;
    bool big_endian_;
};

std::string item_name(const Element& e, int64_t i) {
    return e.name + " " + std::to_string(i);
}

std::string check_binary(std::string_view file, const Header& header) {
    Bytes bytes(file, header.data_offset, header.big_endian);
    for (const Element& e : header.elements) {
        for (int64_t i = 0; i < e.count; ++i) {
            for (const Property& p : e.properties) {
                if (!p.list || p.use == Use::Skipped) { // OpenMesh skips one item of a list
                    if (!bytes.skip(uint64_t(p.type.size)))
                        return "the file ends in " + item_name(e, i);
                    continue;
                }
                const std::optional<int64_t> n = bytes.count(p.count_type);
                if (!n) return "the file ends in " + item_name(e, i);
                if (*n < 0 || uint64_t(*n) > bytes.remaining() / uint64_t(p.type.size))
                    return item_name(e, i) + ": a list '" + p.name + "' of " + std::to_string(*n) +
                           " items, more than the file holds";
                bytes.skip(uint64_t(*n) * uint64_t(p.type.size));
            }
        }
        if (e.name == "face") break; // OpenMesh stops after the faces
    }
    return "";
}

// One ASCII word of element `i` as OpenMesh reads it: any word (Skipped), a number (AsFloat or a
// float type), else an integer; a list count (`count` set) must be an unsigned int.
class AsciiValues {
public:
    AsciiValues(std::string_view file, size_t header_lines) : words_(file) {
        for (size_t line = 0; line < header_lines; ++line) words_.rest_of_line();
    }

    std::string read(const Element& e, int64_t i, const PlyType& type, Use use,
                     int64_t* count = nullptr) {
        const auto word = words_.next();
        if (!word) return "the file ends in " + item_name(e, i);
        int64_t n = 0;
        const bool as_float = count == nullptr && (use == Use::AsFloat || type.is_float);
        const bool ok =
            use == Use::Skipped || (as_float ? is_float_word(*word) : is_integer_word(*word, n));
        if (ok && count == nullptr) return "";
        if (ok && n >= 0 && n <= std::numeric_limits<uint32_t>::max()) {
            *count = n;
            return "";
        }
        return "line " + std::to_string(words_.line()) + ": " + item_name(e, i) + ": " +
               quoted(*word) +
               (count      ? " is not a list count"
                : as_float ? " is not a number"
                           : " is not an integer");
    }

private:
    TextScanner words_;
};

std::string check_ascii(std::string_view file, const Header& header) {
    AsciiValues values(file, header.lines);
    for (const Element& e : header.elements) {
        for (int64_t i = 0; i < e.count; ++i) {
            for (const Property& p : e.properties) {
                if (!p.list || p.use == Use::Skipped) { // OpenMesh reads one word of a list
                    if (std::string problem = values.read(e, i, p.type, p.use); !problem.empty())
                        return problem;
                    continue;
                }
                int64_t n = 0;
                if (std::string problem = values.read(e, i, p.count_type, p.use, &n);
                    !problem.empty())
                    return problem;
                // Each item is a word in the file, so this is as long as the file at most.
                for (int64_t k = 0; k < n; ++k)
                    if (std::string problem = values.read(e, i, p.type, p.use); !problem.empty())
                        return problem;
            }
        }
        if (e.name == "face") break; // OpenMesh stops after the faces
    }
    return "";
}

} // namespace

std::string check_ply_file(std::string_view file) {
    std::string problem;
    const std::optional<Header> header = read_header(file, problem);
    if (!header || !problem.empty()) return problem;
    if (header->ascii) return check_ascii(file, *header);
    if (header->openmesh_data != header->data_offset)
        return "PLY header: OpenMesh's binary reader would start reading the data " +
               std::to_string(int64_t(header->openmesh_data) - int64_t(header->data_offset)) +
               " bytes off (a comment or spaces just before end_header)";
    return check_binary(file, *header);
}

} // namespace ddsimp::io
