#include "ply_reader.h"

#include "field_kinds.h"
#include "ply_types.h"
#include "polygons.h"
#include "text_scanner.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <vector>

namespace ddsimp::io {

namespace {

struct Property {
    std::string name;
    PlyType type;
    bool list = false;
    PlyType count_type;
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
    size_t lines = 0;       // end_header included
    size_t data_offset = 0; // after the end_header line
};

std::vector<std::string_view> words_of(std::string_view line) {
    std::vector<std::string_view> words;
    TextScanner scanner(line);
    while (auto word = scanner.next()) words.push_back(*word);
    return words;
}

// The header, or nullopt if it is not one this reader understands (left to OpenMesh's reader
// and the checks before it, which say what is wrong).
// A header longer than this (thousands of comment lines) is left to OpenMesh's reader.
constexpr size_t kHeaderBytes = 1 << 16;

std::optional<Header> read_header(std::string_view file) {
    Header header;
    size_t start = 0;
    bool format_seen = false;
    while (start < file.size()) {
        size_t end = file.find('\n', start);
        const size_t next = end == std::string_view::npos ? file.size() : end + 1;
        if (end == std::string_view::npos) end = file.size();
        const std::vector<std::string_view> words = words_of(file.substr(start, end - start));
        start = next;
        if (++header.lines == 1) {
            if (words.size() != 1 || (words[0] != "ply" && words[0] != "PLY")) return std::nullopt;
            continue;
        }
        if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
        if (!format_seen) {
            if (words.size() != 3 || words[0] != "format") return std::nullopt;
            format_seen = true;
            header.ascii = words[1] == "ascii";
            header.big_endian = words[1] == "binary_big_endian";
            if (!header.ascii && !header.big_endian && words[1] != "binary_little_endian")
                return std::nullopt;
        } else if (words[0] == "end_header" && words.size() == 1) {
            header.data_offset = next;
            return header;
        } else if (words[0] == "element" && words.size() == 3) {
            Element element;
            element.name = std::string(words[1]);
            if (!is_integer_word(words[2], element.count) || element.count < 0) return std::nullopt;
            header.elements.push_back(std::move(element));
        } else if (words[0] == "property" && !header.elements.empty()) {
            Property p;
            p.list = words.size() == 5 && words[1] == "list";
            if (!p.list && words.size() != 3) return std::nullopt;
            const auto type = ply_type(words[p.list ? 3 : 1]);
            const auto count = p.list ? ply_type(words[2]) : type;
            if (!type || !count || (p.list && count->is_float)) return std::nullopt;
            p.name = std::string(words.back());
            p.type = *type;
            p.count_type = *count;
            header.elements.back().properties.push_back(std::move(p));
        } else {
            return std::nullopt;
        }
    }
    return std::nullopt;
}

// The values of the elements, one item (a vertex, a face) at a time: in ASCII one line each,
// whose words past the declared ones are counted and ignored; in binary the declared bytes.
class ItemValues {
public:
    ItemValues(std::string_view file, const Header& header)
        : file_(file), header_(header), words_(file), at_(header.data_offset) {
        for (size_t line = 0; line < header.lines; ++line) words_.rest_of_line();
    }

    // Starts the next item; false if the file has ended.
    bool begin_item() {
        if (!header_.ascii) return at_ < file_.size();
        line_.clear();
        while (line_.empty()) {
            if (words_.offset() >= file_.size()) return false;
            line_number_ = words_.line();
            line_ = words_of(words_.rest_of_line());
        }
        next_word_ = 0;
        return true;
    }
    // After the item's last value: counts an ASCII line that carried more.
    void end_item() {
        if (header_.ascii && next_word_ < line_.size()) ++long_lines_;
    }

    // The next value of the item as a double; nullopt if the item or the file ends first, or
    // if an ASCII word is not a number.
    std::optional<double> next(const PlyType& type) {
        if (header_.ascii) {
            if (next_word_ == line_.size()) return std::nullopt;
            const std::string_view word = line_[next_word_++];
            double value = 0;
            if (!is_float_word(word) ||
                std::from_chars(word.data() + (word[0] == '+'), word.data() + word.size(), value)
                        .ec != std::errc())
                return std::nullopt;
            return value;
        }
        if (size_t(type.size) > file_.size() - at_) return std::nullopt;
        unsigned char bytes[8];
        std::memcpy(bytes, file_.data() + at_, size_t(type.size));
        at_ += size_t(type.size);
        if (header_.big_endian != (std::endian::native == std::endian::big))
            std::reverse(bytes, bytes + type.size);
        auto as = [&]<class T>(T) {
            T v;
            std::memcpy(&v, bytes, sizeof v);
            return double(v);
        };
        if (type.is_float) return type.size == 4 ? as(float()) : as(double());
        switch (type.size) {
        case 1:
            return type.is_signed ? as(int8_t()) : as(uint8_t());
        case 2:
            return type.is_signed ? as(int16_t()) : as(uint16_t());
        default:
            return type.is_signed ? as(int32_t()) : as(uint32_t());
        }
    }

    size_t long_lines() const { return long_lines_; }
    size_t line() const { return line_number_; }

private:
    std::string_view file_;
    const Header& header_;
    TextScanner words_;
    size_t at_;
    std::vector<std::string_view> line_;
    size_t next_word_ = 0, line_number_ = 0, long_lines_ = 0;
};

// Vertex properties OpenMesh's reader keeps for itself (coordinates, normals, colours, texture
// coordinates) rather than as custom properties.
bool is_standard_vertex_property(const std::string& name) {
    static const std::set<std::string> names{"x",   "y",     "z",         "nx",       "ny", "nz",
                                             "red", "green", "blue",      "alpha",    "u",  "v",
                                             "s",   "t",     "texture_u", "texture_v"};
    return names.count(name) > 0;
}

class PlyParser {
public:
    PlyParser(std::string_view file, const Header& header, std::string context)
        : values_(file, header), header_(header), context_(std::move(context)) {}

    // False if the file has no strips and no long line, or if it is not one this reader reads.
    bool read(bool throw_errors) {
        throw_ = throw_errors;
        for (const Element& e : header_.elements) {
            std::vector<size_t> field_of(e.properties.size(), SIZE_MAX);
            if (e.name == "vertex" && !start_vertices(e, field_of)) return false;
            for (int64_t i = 0; i < e.count; ++i)
                if (!read_item(e, i, field_of)) return false;
        }
        return true;
    }

    Surface take(Notes* notes) {
        if (notes) {
            if (std::string note = splitter_.note(); !note.empty()) notes->push_back(note);
            if (strips_ > 0)
                notes->push_back(std::to_string(strips_) +
                                 (strips_ == 1 ? " triangle strip" : " triangle strips") +
                                 " split into " + std::to_string(strip_triangles_) + " triangles");
            if (size_t n = values_.long_lines(); n > 0)
                notes->push_back(std::to_string(n) + (n == 1 ? " line carries" : " lines carry") +
                                 " more values than the header declares; the rest of each is "
                                 "ignored, as VTK's reader does");
        }
        regroup_component_fields(surface_);
        if (has_normals_)
            surface_.fields.push_back({"Normals", 3, std::move(normals_), FieldKind::Direction});
        return std::move(surface_);
    }

    bool has_strips() const { return strips_ > 0; }
    size_t long_lines() const { return values_.long_lines(); }

private:
    bool fail(const std::string& problem) {
        if (throw_) throw IoError(context_ + ": " + problem);
        return false;
    }

    bool start_vertices(const Element& e, std::vector<size_t>& field_of) {
        int xyz = 0;
        for (size_t p = 0; p < e.properties.size(); ++p) {
            const Property& property = e.properties[p];
            if (property.list) continue;
            if (property.name == "x" || property.name == "y" || property.name == "z") ++xyz;
            has_normals_ = has_normals_ || property.name == "nx";
            if (is_standard_vertex_property(property.name)) continue;
            field_of[p] = surface_.fields.size();
            surface_.fields.push_back(
                {property.name, 1, {}, field_kind(property.name, 1, !property.type.is_float)});
        }
        if (xyz != 3) return fail("the vertices have no x, y and z");
        vertices_ = e.count;
        surface_.positions.reserve(size_t(3 * e.count));
        return true;
    }

    bool read_item(const Element& e, int64_t i, const std::vector<size_t>& field_of) {
        const std::string item = e.name + " " + std::to_string(i);
        if (!values_.begin_item())
            return fail("the file ends before " + item + " (its header declares " +
                        std::to_string(e.count) + " " + e.name + " elements)");
        float point[3] = {0, 0, 0}, normal[3] = {0, 0, 0};
        for (size_t p = 0; p < e.properties.size(); ++p) {
            const Property& property = e.properties[p];
            int64_t n = 1;
            if (property.list) {
                const auto count = values_.next(property.count_type);
                if (!count || *count < 0 || *count > double(std::numeric_limits<uint32_t>::max()))
                    return fail(where() + item + ": no list count for '" + property.name + "'");
                n = int64_t(*count);
            }
            corners_.clear();
            for (int64_t k = 0; k < n; ++k) {
                const auto value = values_.next(property.type);
                if (!value)
                    return fail(where() + item + " ends in its property '" + property.name +
                                "' (or holds a word that is not a number)");
                if (property.list) {
                    corners_.push_back(*value);
                } else if (e.name == "vertex") {
                    const std::string& name = property.name;
                    if (name.size() == 1 && name[0] >= 'x' && name[0] <= 'z')
                        point[name[0] - 'x'] = float(*value);
                    else if (name.size() == 2 && name[0] == 'n' && name[1] >= 'x' && name[1] <= 'z')
                        normal[name[1] - 'x'] = float(*value);
                    else if (field_of[p] != SIZE_MAX)
                        surface_.fields[field_of[p]].values.push_back(float(*value));
                }
            }
            const bool indices = property.list && (property.name == "vertex_indices" ||
                                                   property.name == "vertex_index");
            if (indices && e.name == "face" && !add_face(item)) return false;
            if (indices && e.name == "tristrips" && !add_strips(item)) return false;
        }
        values_.end_item();
        if (e.name == "vertex") {
            surface_.positions.insert(surface_.positions.end(), point, point + 3);
            if (has_normals_) normals_.insert(normals_.end(), normal, normal + 3);
        }
        return true;
    }

    std::string where() const {
        return header_.ascii ? "line " + std::to_string(values_.line()) + ": " : "";
    }

    bool check_corner(double v, const std::string& item) {
        if (v >= 0 && v < double(vertices_) && v == double(int64_t(v))) return true;
        return fail(item + " refers to vertex " + std::to_string(int64_t(v)) + "; the file has " +
                    std::to_string(vertices_));
    }

    bool add_face(const std::string& item) {
        std::vector<uint32_t> corners;
        for (double v : corners_) {
            if (!check_corner(v, item)) return false;
            corners.push_back(uint32_t(v));
        }
        splitter_.split(surface_.positions, corners.data(), corners.size(), surface_.triangles);
        return true;
    }

    // Strips separated by a negative index; in each, (p0 p1 p2), (p2 p1 p3), (p2 p3 p4), ...:
    // every other triangle reversed to keep one orientation.
    bool add_strips(const std::string& item) {
        size_t begin = 0;
        for (size_t end = 0; end <= corners_.size(); ++end) {
            if (end < corners_.size() && corners_[end] >= 0) {
                if (!check_corner(corners_[end], item)) return false;
                continue;
            }
            if (end - begin >= 3) ++strips_;
            for (size_t i = begin; i + 2 < end; ++i) {
                const bool even = (i - begin) % 2 == 0;
                for (double v : {even ? corners_[i] : corners_[i + 1],
                                 even ? corners_[i + 1] : corners_[i], corners_[i + 2]})
                    surface_.triangles.push_back(uint32_t(v));
                ++strip_triangles_;
            }
            begin = end + 1;
        }
        return true;
    }

    ItemValues values_;
    const Header& header_;
    std::string context_;
    bool throw_ = false;
    Surface surface_;
    bool has_normals_ = false;
    std::vector<float> normals_;
    int64_t vertices_ = 0;
    std::vector<double> corners_; // the list being read
    PolygonSplitter splitter_;
    size_t strips_ = 0, strip_triangles_ = 0;
};

} // namespace

std::optional<Surface> read_ply_with_strips_or_long_lines(const std::string& path,
                                                          const std::string& context,
                                                          Notes* notes) {
    // The header from the file's start, the rest only if this reader may be the one to read it.
    std::ifstream in(path, std::ios::binary);
    std::string file(kHeaderBytes, '\0');
    in.read(file.data(), std::streamsize(file.size()));
    file.resize(size_t(in.gcount()));
    const std::optional<Header> header = read_header(file);
    if (!header) return std::nullopt;
    bool strips = false;
    for (const Element& e : header->elements) strips = strips || e.name == "tristrips";
    if (!strips && !header->ascii) return std::nullopt;
    file.append(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    // A strip file is this reader's to refuse; any other is read only if it has long lines.
    PlyParser parser(file, *header, context);
    if (!parser.read(strips) || (!strips && parser.long_lines() == 0)) return std::nullopt;
    return parser.take(notes);
}

} // namespace ddsimp::io
