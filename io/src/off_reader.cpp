#include "off_reader.h"

#include "polygons.h"
#include "text_scanner.h"

#include <charconv>
#include <fstream>
#include <iterator>
#include <regex>

namespace ddsimp::io {

namespace {

// The text with each comment ('#' to the end of its line) blanked out, line ends kept, so that
// the scanner's line numbers are the file's.
std::string without_comments(std::string text) {
    bool in_comment = false;
    for (char& c : text) {
        if (c == '\n')
            in_comment = false;
        else if (c == '#')
            in_comment = true;
        if (in_comment) c = ' ';
    }
    return text;
}

class OffParser {
public:
    OffParser(std::string_view text, std::string context)
        : words_(text), context_(std::move(context)), most_(int64_t(text.size() / 2 + 1)) {}

    [[noreturn]] void fail(const std::string& problem) const {
        throw IoError(context_ + ": line " + std::to_string(words_.line()) + ": " + problem);
    }
    [[noreturn]] void ends(const std::string& where) const {
        throw IoError(context_ + ": the file ends in " + where + " (line " +
                      std::to_string(words_.line()) + "): its counts declare " +
                      std::to_string(vertices_) + " vertices and " + std::to_string(faces_) +
                      " faces");
    }

    std::string_view word(const std::string& where) {
        const auto w = words_.next();
        if (!w) ends(where);
        return *w;
    }
    float number(const std::string& where) {
        const std::string_view w = word(where);
        float value = 0;
        if (!is_float_word(w) ||
            std::from_chars(w.data() + (w[0] == '+'), w.data() + w.size(), value).ec != std::errc())
            fail(where + ": " + quoted(w) + " is not a number");
        return value;
    }
    int64_t count(const std::string& where, int64_t most) {
        const std::string_view w = word(where);
        int64_t value = 0;
        if (!is_integer_word(w, value) || value < 0 || value > most)
            fail(where + ": " + quoted(w) + " is not a count from 0 to " + std::to_string(most));
        return value;
    }

    Surface parse(bool normals, Notes* notes) {
        const int64_t most = most_;
        vertices_ = count("the vertex count", most);
        faces_ = count("the face count", most);
        if (!words_.line_is_done()) count("the edge count", most); // not used
        Surface s;
        s.positions.resize(3 * size_t(vertices_));
        Field normal{"Normals", 3, {}, FieldKind::Direction};
        if (normals) normal.values.resize(3 * size_t(vertices_));
        for (int64_t v = 0; v < vertices_; ++v) {
            const std::string where = "vertex " + std::to_string(v);
            for (int c = 0; c < 3; ++c) s.positions[3 * size_t(v) + c] = number(where);
            for (int c = 0; c < 3 && normals; ++c) normal.values[3 * size_t(v) + c] = number(where);
            words_.rest_of_line(); // colour, texture coordinates
        }
        if (normals) s.fields.push_back(std::move(normal));
        PolygonSplitter splitter;
        std::vector<uint32_t> corners;
        for (int64_t f = 0; f < faces_; ++f) {
            const std::string where = "face " + std::to_string(f);
            const int64_t k = count(where, most);
            corners.resize(size_t(k));
            for (int64_t c = 0; c < k; ++c) {
                const std::string_view w = word(where);
                int64_t index = -1;
                if (!is_integer_word(w, index) || index < 0 || index >= vertices_)
                    fail(where + ": " + quoted(w) + " is not a vertex index below " +
                         std::to_string(vertices_));
                corners[size_t(c)] = uint32_t(index);
            }
            words_.rest_of_line(); // colour
            splitter.split(s.positions, corners.data(), corners.size(), s.triangles);
        }
        if (notes && !splitter.note().empty()) notes->push_back(splitter.note());
        return s;
    }

    TextScanner& words() { return words_; }

private:
    TextScanner words_;
    std::string context_;
    int64_t most_; // no count can exceed the words the file holds: a word takes two bytes
    int64_t vertices_ = 0, faces_ = 0;
};

} // namespace

std::optional<Surface> read_ascii_off(const std::string& path, const std::string& context,
                                      Notes* notes) {
    std::ifstream in(path, std::ios::binary);
    const std::string text = without_comments(std::string(std::istreambuf_iterator<char>(in), {}));
    OffParser parser(text, context);
    TextScanner peek(text);
    const auto first = peek.next();
    if (!first) throw IoError(context + ": the file holds only comments");
    static const std::regex header("(ST)?(C)?(N)?(4)?(n)?OFF");
    std::match_results<std::string_view::const_iterator> m;
    bool normals = false;
    if (std::regex_match(first->begin(), first->end(), m, header)) {
        if (m[4].matched || m[5].matched)
            throw IoError(context + ": " + quoted(*first) +
                          " (homogeneous or n-dimensional OFF) is not supported");
        normals = m[3].matched;
        if (const auto second = peek.next(); second && *second == "BINARY") return std::nullopt;
        parser.words().next(); // the header word; the counts may follow on its line
    } else if (int64_t n = 0; !is_integer_word(*first, n)) {
        throw IoError(context + ": line 1: " + quoted(*first) +
                      " is neither an OFF header nor a vertex count");
    }
    return parser.parse(normals, notes);
}

} // namespace ddsimp::io
