#include "obj_checks.h"

#include "text_scanner.h"

#include <cstdint>
#include <vector>

namespace ddsimp::io {

namespace {

// The words of each line, as OpenMesh splits them (`>>` on the line).
template <class F> void for_each_line(std::string_view text, F&& f) {
    size_t line = 1;
    for (size_t start = 0; start <= text.size(); ++line) {
        size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        TextScanner words(text.substr(start, end - start));
        if (!f(line, words)) return;
        start = end + 1;
    }
}

std::vector<std::string_view> split(std::string_view word, char at) {
    std::vector<std::string_view> parts;
    for (size_t start = 0;;) {
        const size_t end = word.find(at, start);
        parts.push_back(word.substr(start, end == std::string_view::npos ? end : end - start));
        if (end == std::string_view::npos) return parts;
        start = end + 1;
    }
}

// "" if `corner` is a good corner of a face on a line with `before` vertices above it, in a file
// of `vertices` vertices.
std::string check_corner(std::string_view corner, int64_t before, int64_t vertices) {
    const std::vector<std::string_view> parts = split(corner, '/');
    int64_t index = 0;
    if (parts.size() > 3)
        return "face corner " + quoted(corner) + " is not v, v/vt, v//vn or v/vt/vn";
    for (size_t i = 1; i < parts.size(); ++i)
        if (!parts[i].empty() && !is_integer_word(parts[i], index))
            return "face corner " + quoted(corner) + " has a texture or normal index that is " +
                   "not a number";
    if (parts[0].empty()) return "face corner " + quoted(corner) + " has no vertex index";
    if (!is_integer_word(parts[0], index))
        return "face corner " + quoted(corner) + " is not v, v/vt, v//vn or v/vt/vn";
    if (index == 0) return "face corner " + quoted(corner) + ": OBJ vertex indices start at 1";
    if (index > vertices)
        return "face corner " + quoted(corner) + " refers to vertex " + std::to_string(index) +
               ", but the file has " + std::to_string(vertices) + " vertices";
    if (index < 0 && -index > before)
        return "face corner " + quoted(corner) + " refers to vertex " + std::to_string(index) +
               ", but only " + std::to_string(before) + " vertices come before it";
    return "";
}

} // namespace

std::string check_obj_lines(std::string_view text) {
    std::string problem;
    int64_t vertices = 0;
    for_each_line(text, [&](size_t line, TextScanner& words) {
        const auto keyword = words.next();
        if (!keyword || *keyword != "v") return true;
        for (int c = 0; c < 3; ++c) {
            const auto coordinate = words.next();
            if (!coordinate || !is_float_word(*coordinate)) {
                problem = "line " + std::to_string(line) + ": a vertex needs x y z, " +
                          (coordinate ? quoted(*coordinate) + " is not a number" : "not fewer");
                return false;
            }
        }
        ++vertices;
        return true;
    });
    if (!problem.empty()) return problem;

    int64_t before = 0;
    for_each_line(text, [&](size_t line, TextScanner& words) {
        const auto keyword = words.next();
        if (!keyword) return true;
        if (*keyword == "v") ++before;
        if (*keyword != "f") return true;
        int corners = 0;
        for (auto corner = words.next(); corner && (*corner)[0] != '#'; corner = words.next()) {
            problem = check_corner(*corner, before, vertices);
            if (!problem.empty()) {
                problem = "line " + std::to_string(line) + ": " + problem;
                return false;
            }
            ++corners;
        }
        if (corners < 3) {
            problem = "line " + std::to_string(line) + ": a face needs 3 corners, this one has " +
                      std::to_string(corners);
            return false;
        }
        return true;
    });
    return problem;
}

} // namespace ddsimp::io
