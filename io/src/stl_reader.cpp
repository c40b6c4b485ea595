#include "stl_reader.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <iterator>
#include <unordered_map>

namespace ddsimp::io {

namespace {

constexpr size_t kHeader = 84, kFacet = 50;

uint32_t little_endian_u32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

float little_endian_float(const unsigned char* p) {
    const uint32_t bits = little_endian_u32(p);
    float value;
    std::memcpy(&value, &bits, 4);
    return value == 0.0f ? 0.0f : value; // -0 is the same point as 0
}

// A binary file's size is 84 bytes plus 50 per facet of its count; its header is 80 bytes of any
// text (some exporters start it with "solid"), but its count and coordinates are not text. So a
// file whose size does not match and whose first bytes are all text is an ASCII file (OpenMesh
// reads it, or says why not), and so is one that starts with "solid" and has a facet soon after.
bool is_ascii(const std::string& bytes) {
    if (bytes.size() >= kHeader &&
        bytes.size() ==
            kHeader + kFacet * size_t(little_endian_u32(
                                   reinterpret_cast<const unsigned char*>(bytes.data()) + 80)))
        return false;
    const size_t head = std::min<size_t>(bytes.size(), 512);
    const bool text = std::all_of(bytes.begin(), bytes.begin() + long(head), [](char c) {
        return (c >= 32 && c < 127) || c == '\n' || c == '\r' || c == '\t';
    });
    const size_t start = bytes.find_first_not_of(" \t\r\n");
    return text || (start != std::string::npos && bytes.compare(start, 5, "solid") == 0 &&
                    bytes.find("facet", start) < 1024);
}

struct PointHash {
    size_t operator()(const std::array<float, 3>& p) const {
        uint32_t bits[3];
        std::memcpy(bits, p.data(), sizeof bits);
        return size_t(bits[0]) * 73856093u ^ size_t(bits[1]) * 19349663u ^
               size_t(bits[2]) * 83492791u;
    }
};

} // namespace

std::optional<Surface> read_binary_stl(const std::string& path, const std::string& context,
                                       Notes* notes) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes(std::istreambuf_iterator<char>(in), {});
    if (is_ascii(bytes)) return std::nullopt;
    if (bytes.size() < kHeader)
        throw IoError(context + ": the binary STL file ends in its 84-byte header (" +
                      std::to_string(bytes.size()) + " bytes)");
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const size_t declared = little_endian_u32(data + 80);
    const size_t whole = (bytes.size() - kHeader) / kFacet;
    if (whole == 0)
        throw IoError(context +
                      ": the binary STL file ends before its first facet (its header "
                      "declares " +
                      std::to_string(declared) + " facets)");
    // A header that declares no facets is taken to be unfilled: every whole facet is read.
    const size_t facets = declared == 0 ? whole : std::min(declared, whole);
    if (declared == 0 && notes)
        notes->push_back("the header declares 0 facets: the " + std::to_string(whole) +
                         " whole facets the file holds are read");
    if (facets < declared && notes)
        notes->push_back("the file ends in facet " + std::to_string(facets) + " of the " +
                         std::to_string(declared) + " its header declares (byte " +
                         std::to_string(bytes.size()) + "): the " + std::to_string(facets) +
                         " whole facets are read");
    Surface s;
    s.triangles.reserve(3 * facets);
    std::unordered_map<std::array<float, 3>, uint32_t, PointHash> index;
    for (size_t f = 0; f < facets; ++f) {
        const unsigned char* facet = data + kHeader + kFacet * f + 12; // after its normal
        for (int c = 0; c < 3; ++c) {
            const std::array<float, 3> p{little_endian_float(facet + 12 * c),
                                         little_endian_float(facet + 12 * c + 4),
                                         little_endian_float(facet + 12 * c + 8)};
            const auto [it, added] = index.emplace(p, uint32_t(s.vertex_count()));
            if (added) s.positions.insert(s.positions.end(), p.begin(), p.end());
            s.triangles.push_back(it->second);
        }
    }
    return s;
}

} // namespace ddsimp::io
