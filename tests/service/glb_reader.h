// Reads a .glb back for tests: the container checked, the JSON document, and every accessor's
// elements as doubles (decoded with meshoptimizer's decoders under EXT_meshopt_compression).
#pragma once

#include <gtest/gtest.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace ddsimp::test {

// A triangle's corners rotated so the least comes first: meshoptimizer's index codec may rotate
// a triangle (keeping its orientation).
inline std::array<double, 3> rotated(const double* t) {
    const int first = int(std::min_element(t, t + 3) - t);
    return {t[first], t[(first + 1) % 3], t[(first + 2) % 3]};
}

inline uint32_t u32(const std::string& b, size_t at) {
    uint32_t x;
    std::memcpy(&x, b.data() + at, 4);
    return x;
}

// A parsed .glb: the document, and every accessor's elements as doubles (decoded when needed).
struct Glb {
    using json = nlohmann::json;
    json doc;
    std::string bin;

    explicit Glb(const std::string& bytes) {
        EXPECT_EQ(u32(bytes, 0), 0x46546C67u);
        EXPECT_EQ(u32(bytes, 4), 2u);
        EXPECT_EQ(u32(bytes, 8), bytes.size());
        const uint32_t json_length = u32(bytes, 12);
        EXPECT_EQ(u32(bytes, 16), 0x4E4F534Au);
        EXPECT_EQ(json_length % 4, 0u);
        doc = json::parse(bytes.substr(20, json_length));
        const size_t bin_at = 20 + json_length;
        EXPECT_EQ(u32(bytes, bin_at + 4), 0x004E4942u);
        bin = bytes.substr(bin_at + 8, u32(bytes, bin_at));
        EXPECT_EQ(bin_at + 8 + bin.size(), bytes.size());
    }

    std::string view_bytes(int index) const {
        const json& v = doc["bufferViews"][index];
        if (!v.contains("extensions")) {
            EXPECT_EQ(v["buffer"], 0);
            return bin.substr(v["byteOffset"], v["byteLength"]);
        }
        const json& m = v["extensions"]["EXT_meshopt_compression"];
        const size_t count = m["count"], stride = m["byteStride"];
        std::string out(count * stride, '\0');
        const auto* src =
            reinterpret_cast<const unsigned char*>(bin.data()) + size_t(m["byteOffset"]);
        const size_t size = m["byteLength"];
        int rc = m["mode"] == "TRIANGLES"
                     ? meshopt_decodeIndexBuffer(out.data(), count, stride, src, size)
                     : meshopt_decodeVertexBuffer(out.data(), count, stride, src, size);
        EXPECT_EQ(rc, 0);
        EXPECT_EQ(out.size(), size_t(v["byteLength"]));
        return out;
    }

    std::vector<double> accessor(int index) const {
        const json& a = doc["accessors"][index];
        const std::string bytes = view_bytes(a["bufferView"]);
        const int width = a["type"] == "SCALAR" ? 1
                          : a["type"] == "VEC2" ? 2
                          : a["type"] == "VEC3" ? 3
                                                : 4;
        const size_t n = size_t(a["count"]) * width;
        std::vector<double> out(n);
        for (size_t i = 0; i < n; ++i) {
            if (a["componentType"] == 5126) {
                float f;
                std::memcpy(&f, bytes.data() + 4 * i, 4);
                out[i] = f;
            } else if (a["componentType"] == 5123) {
                uint16_t s;
                std::memcpy(&s, bytes.data() + 2 * i, 2);
                out[i] = s;
            } else {
                out[i] = u32(bytes, 4 * i);
            }
        }
        return out;
    }

    const json& primitive() const { return doc["meshes"][0]["primitives"][0]; }
    std::vector<double> attribute(const std::string& name) const {
        return accessor(primitive()["attributes"][name]);
    }
};

} // namespace ddsimp::test
