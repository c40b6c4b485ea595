#include "off_checks.h"

#include "text_scanner.h"

#include <cstdint>
#include <limits>

namespace ddsimp::io {

namespace {

constexpr int64_t kMaxUnsigned = std::numeric_limits<uint32_t>::max();

std::string at_line(const TextScanner& words, const std::string& what) {
    return "line " + std::to_string(words.line()) + ": " + what;
}

uint32_t little_endian_u32(std::string_view bytes, size_t at) {
    uint32_t value = 0;
    for (int i = 3; i >= 0; --i) value = value << 8 | static_cast<unsigned char>(bytes[at + i]);
    return value;
}

// Binary OFF as OpenMesh 9.0 reads it (read_binary): three uint32 counts, per vertex 3 floats
// (+3 normal floats, +3 colour ints, +2 texture floats), per face a uint32 corner count and that
// many uint32 indices (no face colours: ddsimp does not ask for them). OpenMesh reserves memory
// for the counts and pushes a handle per corner before it notices the file has ended.
std::string check_binary_off(std::string_view body, bool colours, bool normals, bool texture) {
    if (body.size() < 12) return "the binary OFF file ends before its counts";
    const uint64_t vertices = little_endian_u32(body, 0), faces = little_endian_u32(body, 4);
    const uint64_t vertex_bytes = 12 + (normals ? 12 : 0) + (colours ? 12 : 0) + (texture ? 8 : 0);
    const std::string declares = "its header declares " + std::to_string(vertices) +
                                 " vertices and " + std::to_string(faces) + " faces";
    if (vertices * vertex_bytes + faces * 4 > body.size() - 12)
        return "the file ends early: " + declares;
    size_t at = size_t(12 + vertices * vertex_bytes);
    for (uint64_t f = 0; f < faces; ++f) {
        if (body.size() - at < 4) return "the file ends early: " + declares;
        const uint64_t corners = little_endian_u32(body, at);
        at += 4;
        if (corners > (body.size() - at) / 4)
            return "face " + std::to_string(f) + " has " + std::to_string(corners) +
                   " corners, more than the file holds";
        at += size_t(corners * 4);
    }
    return "";
}

} // namespace

std::string check_off_file(std::string_view text) {
    TextScanner words(text);
    // OpenMesh's header: [ST][C][N]OFF, then " BINARY" for binary files (not checked here).
    const std::string_view header = words.rest_of_line();
    std::string_view kind = header;
    const bool texture = kind.substr(0, 2) == "ST";
    if (texture) kind.remove_prefix(2);
    const bool colours = !kind.empty() && kind[0] == 'C';
    if (colours) kind.remove_prefix(1);
    const bool normals = !kind.empty() && kind[0] == 'N';
    if (normals) kind.remove_prefix(1);
    if (kind.substr(0, 3) != "OFF") return "";
    // OpenMesh's test: "BINARY" one character after OFF.
    if (kind.size() > 4 && kind.substr(4, 6) == "BINARY")
        return check_binary_off(text.substr(words.offset()), colours, normals, texture);

    int64_t counts[3] = {0, 0, 0};
    const char* const count_names[3] = {"vertex count", "face count", "edge count"};
    for (int i = 0; i < 3; ++i) {
        const auto word = words.next();
        if (!word) return "the file ends before the " + std::string(count_names[i]);
        if (!is_integer_word(*word, counts[i]) || counts[i] < 0 || counts[i] > kMaxUnsigned)
            return at_line(words, "the " + std::string(count_names[i]) + " " + quoted(*word) +
                                      " is not a number from 0 to 2^32-1");
    }
    const int64_t vertices = counts[0], faces = counts[1];

    const int per_vertex = normals ? 6 : 3;
    for (int64_t v = 0; v < vertices; ++v) {
        for (int i = 0; i < per_vertex; ++i) {
            const auto word = words.next();
            if (!word) return "the file ends in vertex " + std::to_string(v);
            if (!is_float_word(*word))
                return at_line(words, "vertex " + std::to_string(v) + ": " + quoted(*word) +
                                          " is not a number");
        }
        words.rest_of_line(); // colour, texture coordinates: read apart by OpenMesh
    }
    for (int64_t f = 0; f < faces; ++f) {
        const std::string face = "face " + std::to_string(f);
        const auto count_word = words.next();
        int64_t corners = 0;
        if (!count_word) return "the file ends before " + face;
        if (!is_integer_word(*count_word, corners) || corners < 0 || corners > kMaxUnsigned)
            return at_line(words, face + ": " + quoted(*count_word) + " is not a corner count");
        // Each corner is a word in the file, so this loop is as long as the file at most.
        for (int64_t c = 0; c < corners; ++c) {
            const auto word = words.next();
            int64_t index = 0;
            if (!word) return "the file ends in " + face;
            if (!is_integer_word(*word, index) || index < std::numeric_limits<int32_t>::min() ||
                index > kMaxUnsigned)
                return at_line(words, face + ": " + quoted(*word) + " is not a vertex index");
        }
        if (colours) {
            words.rest_of_line();
        } else if (!words.line_is_done()) {
            // OpenMesh would take what follows for the next face's corner count.
            return at_line(words, face + " has more on its line than its " +
                                      std::to_string(corners) +
                                      " corners (a face colour needs a COFF header)");
        }
    }
    return "";
}

} // namespace ddsimp::io
