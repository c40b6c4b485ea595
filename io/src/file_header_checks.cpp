#include "file_header_checks.h"

#include "obj_checks.h"
#include "off_checks.h"
#include "ply_checks.h"

#include <cstdint>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <vector>

namespace ddsimp::io {

namespace {

// Larger element counts or property lists than any file can hold, refused before the sizes they
// imply are added up (so that the sums cannot wrap around).
constexpr size_t kMaxCount = size_t(1) << 40;
constexpr size_t kMaxProperties = 1 << 12;

// Skips "# ..." comment lines between tokens.
bool next_token(std::istream& in, std::string& token) {
    while (in >> std::ws && in.peek() == '#')
        in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    return bool(in >> token);
}

size_t count_tokens(std::istream& in) {
    size_t n = 0;
    std::string token;
    while (next_token(in, token)) ++n;
    return n;
}

size_t ply_type_size(const std::string& type) {
    if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
    if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
    if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" ||
        type == "float32")
        return 4;
    if (type == "double" || type == "float64") return 8;
    return 0;
}

struct PlyElement {
    std::string name;
    size_t count = 0;
    size_t scalar_properties = 0;
    size_t scalar_bytes = 0;
    size_t lists = 0;
    size_t list_count_bytes = 0, list_item_bytes = 0; // of the last list (faces have one)
};

struct PlyHeader {
    std::string format;
    std::vector<PlyElement> elements;
    std::streamoff body = 0; // where the data starts
};

std::optional<PlyHeader> read_ply_header(std::istream& in) {
    PlyHeader header;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "format") {
            words >> header.format;
        } else if (keyword == "element") {
            PlyElement e;
            words >> e.name >> e.count;
            header.elements.push_back(e);
        } else if (keyword == "property" && !header.elements.empty()) {
            PlyElement& e = header.elements.back();
            std::string type;
            words >> type;
            if (type == "list") {
                std::string count_type, item_type;
                words >> count_type >> item_type;
                ++e.lists;
                e.list_count_bytes = ply_type_size(count_type);
                e.list_item_bytes = ply_type_size(item_type);
            } else {
                ++e.scalar_properties;
                e.scalar_bytes += ply_type_size(type);
            }
        } else if (keyword == "end_header") {
            header.body = in.tellg();
            return header;
        }
    }
    return std::nullopt;
}

std::string ends_early(size_t vertices, size_t faces) {
    return "the file ends early: its header declares " + std::to_string(vertices) +
           " vertices and " + std::to_string(faces) + " faces";
}

// A "#" line in an ASCII OFF file (binary OFF files say BINARY on their first line).
bool has_comment_line(std::istream& in) {
    std::string line;
    if (!std::getline(in, line) || line.find("BINARY") != std::string::npos) return false;
    do {
        const size_t first = line.find_first_not_of(" \t\r");
        if (first != std::string::npos && line[first] == '#') return true;
    } while (std::getline(in, line));
    return false;
}

std::string check_off(std::istream& in) {
    std::string word;
    if (!next_token(in, word) || word.size() < 3 || word.substr(word.size() - 3) != "OFF")
        return "";
    std::string nv, nf, ne;
    if (!next_token(in, nv) || !next_token(in, nf) || !next_token(in, ne)) return "";
    if (nv == "BINARY" || nf == "BINARY") return ""; // binary OFF: not checked
    const size_t vertices = std::stoull(nv), faces = std::stoull(nf);
    // At least x y z per vertex and "3 a b c" per face; variants only add tokens. (Counts this
    // large cannot be in any file; checked so that the sum does not wrap around.)
    if (vertices > kMaxCount || faces > kMaxCount || count_tokens(in) < 3 * vertices + 4 * faces)
        return ends_early(vertices, faces);
    return "";
}

std::string check_ply(std::istream& in, std::streamoff file_size) {
    const std::optional<PlyHeader> header = read_ply_header(in);
    if (!header) return "no end_header in the PLY header";
    size_t vertices = 0, faces = 0, least_tokens = 0, least_bytes = 0;
    bool sizes_known = true;
    for (const PlyElement& e : header->elements) {
        if (e.count > kMaxCount || e.scalar_properties + e.lists > kMaxProperties)
            return ends_early(e.name == "vertex" ? e.count : vertices,
                              e.name == "face" ? e.count : faces);
        if (e.name == "vertex") vertices = e.count;
        if (e.name == "face") faces = e.count;
        const size_t per_list_tokens = e.name == "face" ? 4 : 1; // "3 a b c"; else just a count
        least_tokens += e.count * (e.scalar_properties + e.lists * per_list_tokens);
        if (e.lists > 1 || (e.lists == 1 && e.name != "face")) sizes_known = false;
        least_bytes +=
            e.count * (e.scalar_bytes + e.lists * (e.list_count_bytes + 3 * e.list_item_bytes));
    }
    if (header->format == "ascii") {
        if (count_tokens(in) < least_tokens) return ends_early(vertices, faces);
    } else if (sizes_known && file_size - header->body < std::streamoff(least_bytes)) {
        return ends_early(vertices, faces);
    }
    return "";
}

} // namespace

std::optional<size_t> declared_face_count(const std::string& path, const std::string& extension) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    if (extension == ".off") {
        std::string word, vertices, faces;
        if (!next_token(in, word) || word.size() < 3 || word.substr(word.size() - 3) != "OFF")
            return std::nullopt;
        if (!next_token(in, vertices) || !next_token(in, faces)) return std::nullopt;
        try {
            return std::stoull(faces);
        } catch (const std::exception&) {
            return std::nullopt;
        }
    }
    if (extension == ".ply") {
        const std::optional<PlyHeader> header = read_ply_header(in);
        if (header)
            for (const PlyElement& e : header->elements)
                if (e.name == "face") return e.count;
        return std::nullopt;
    }
    if (extension == ".stl") {
        char header[80];
        uint32_t count = 0;
        if (in.read(header, 80) && in.read(reinterpret_cast<char*>(&count), 4)) {
            in.seekg(0, std::ios::end);
            if (size_t(in.tellg()) == 84 + 50 * size_t(count)) return count; // binary STL
        }
        in.clear();
        in.seekg(0);
        size_t facets = 0;
        std::string word;
        while (in >> word)
            if (word == "facet") ++facets;
        return facets;
    }
    if (extension == ".obj") {
        size_t faces = 0;
        std::string line;
        while (std::getline(in, line)) { // (OpenMesh trims each line)
            const size_t f = line.find_first_not_of(" \t\r");
            if (f != std::string::npos && line.size() > f + 1 && line[f] == 'f' &&
                (line[f + 1] == ' ' || line[f + 1] == '\t'))
                ++faces;
        }
        return faces;
    }
    return std::nullopt;
}

std::string check_file_body(const std::string& path, const std::string& extension) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return "";
    try {
        if (extension == ".off") {
            // OpenMesh's OFF reader takes a comment for the counts, then allocates for what it
            // took (gigabytes for the 4-vertex tetrahedron of the fuzz seed tetra-comment.off).
            if (has_comment_line(in))
                return "comment lines are not supported (OpenMesh's OFF reader misreads them)";
            in.clear();
            in.seekg(0);
            if (std::string problem = check_off(in); !problem.empty()) return problem;
            in.clear();
            in.seekg(0);
            return check_off_file(std::string(std::istreambuf_iterator<char>(in), {}));
        }
        if (extension == ".ply") {
            in.seekg(0, std::ios::end);
            const std::streamoff size = in.tellg();
            in.seekg(0);
            if (std::string problem = check_ply(in, size); !problem.empty()) return problem;
            in.clear();
            in.seekg(0);
            return check_ply_file(std::string(std::istreambuf_iterator<char>(in), {}));
        }
        if (extension == ".obj")
            return check_obj_lines(std::string(std::istreambuf_iterator<char>(in), {}));
    } catch (const std::exception&) {
        return "malformed header";
    }
    return "";
}

} // namespace ddsimp::io
