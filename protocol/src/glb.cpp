// Binary glTF: the document (nlohmann::json) and one BIN chunk of buffer views, raw or
// compressed with meshoptimizer's codecs as EXT_meshopt_compression lays them out.
#include "ddsimp/protocol/glb.h"

#include "viridis.h"

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

namespace ddsimp::protocol {

namespace {

using json = nlohmann::json;

constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr int kFloat = 5126;
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;
constexpr int kTriangles = 4;
constexpr const char* kMeshopt = "EXT_meshopt_compression";

void check_shape(const Surface& s) {
    if (s.positions.size() % 3 != 0 || s.triangles.size() % 3 != 0)
        throw GlbError("positions or triangles are not a multiple of 3");
    if (s.triangle_count() == 0) throw GlbError("the surface has no triangles");
    for (uint32_t index : s.triangles)
        if (index >= s.vertex_count())
            throw GlbError("a triangle refers to vertex " + std::to_string(index) +
                           ", but there are " + std::to_string(s.vertex_count()));
    for (const Field& f : s.fields)
        if (f.components < 1 || f.values.size() != s.vertex_count() * size_t(f.components))
            throw GlbError("field '" + f.name + "' has " + std::to_string(f.values.size()) +
                           " values for " + std::to_string(s.vertex_count()) + " vertices");
}

// Area-weighted vertex normals (the cross products summed); a vertex whose triangles have no
// area gets +z, since glTF requires unit normals.
std::vector<float> vertex_normals(const Surface& s) {
    std::vector<double> sum(s.positions.size(), 0.0);
    const float* p = s.positions.data();
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        const uint32_t* v = &s.triangles[3 * t];
        double e1[3], e2[3];
        for (int c = 0; c < 3; ++c) {
            e1[c] = double(p[3 * v[1] + c]) - p[3 * v[0] + c];
            e2[c] = double(p[3 * v[2] + c]) - p[3 * v[0] + c];
        }
        const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
        for (int corner = 0; corner < 3; ++corner)
            for (int c = 0; c < 3; ++c) sum[3 * v[corner] + c] += n[c];
    }
    std::vector<float> normals(sum.size());
    for (size_t v = 0; v < s.vertex_count(); ++v) {
        const double* n = &sum[3 * v];
        const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int c = 0; c < 3; ++c)
            normals[3 * v + c] =
                length > 0 && std::isfinite(length) ? float(n[c] / length) : (c == 2 ? 1.0f : 0.0f);
    }
    return normals;
}

// One number per vertex: the value of a scalar, the length of a vector.
std::vector<float> colour_values(const Field& f) {
    const size_t k = size_t(f.components);
    std::vector<float> out(f.values.size() / k);
    for (size_t v = 0; v < out.size(); ++v) {
        double sq = 0;
        for (size_t c = 0; c < k; ++c) sq += double(f.values[v * k + c]) * f.values[v * k + c];
        out[v] = k == 1 ? f.values[v] : float(std::sqrt(sq));
    }
    return out;
}

ColourRange range_of(const std::vector<float>& values) {
    float lo = std::numeric_limits<float>::infinity();
    float hi = -lo;
    for (float x : values)
        if (std::isfinite(x)) {
            lo = std::min(lo, x);
            hi = std::max(hi, x);
        }
    return lo <= hi ? ColourRange{lo, hi} : ColourRange{0, 0};
}

std::vector<float> vertex_colours(const std::vector<float>& values, ColourRange range) {
    std::vector<float> rgb(3 * values.size());
    const bool spread = range.max > range.min;
    for (size_t v = 0; v < values.size(); ++v) {
        const double t =
            spread ? (double(values[v]) - range.min) / (double(range.max) - range.min) : 0.5;
        const auto srgb = viridis_srgb(t);
        for (int c = 0; c < 3; ++c) rgb[3 * v + c] = srgb_to_linear(srgb[c]);
    }
    return rgb;
}

// "_" and the field's name with every character outside [A-Za-z0-9_] made '_', unique.
std::string attribute_name(const std::string& field, std::set<std::string>& taken) {
    std::string name = "_";
    for (unsigned char ch : field) name += std::isalnum(ch) || ch == '_' ? char(ch) : '_';
    std::string unique = name;
    for (int n = 2; !taken.insert(unique).second; ++n) unique = name + "_" + std::to_string(n);
    return unique;
}

void pad_to_4(std::string& bytes, char with) {
    bytes.append((4 - bytes.size() % 4) % 4, with);
}

// Buffer views and accessors over one BIN chunk. Raw: the chunk holds the views' bytes. With
// meshopt: buffer 0 (the chunk) holds the compressed views, and buffer 1, a fallback without
// data, gives the views their uncompressed place.
class Builder {
public:
    // `raw_bytes`: the views' bytes uncompressed, reserved at once so that the chunk never
    // grows by copying (a .glb is built on a server's thread within its memory bound).
    Builder(bool meshopt, size_t raw_bytes) : meshopt_(meshopt) { chunk_.reserve(raw_bytes); }

    int indices(const std::vector<uint32_t>& triangles, size_t vertex_count) {
        const size_t count = triangles.size();
        const bool narrow = vertex_count <= 0xffff;
        std::string raw;
        if (narrow) {
            std::vector<uint16_t> small(triangles.begin(), triangles.end());
            raw.assign(reinterpret_cast<const char*>(small.data()), 2 * count);
        } else {
            raw.assign(reinterpret_cast<const char*>(triangles.data()), 4 * count);
        }
        std::string packed;
        if (meshopt_) {
            packed.resize(meshopt_encodeIndexBufferBound(count, vertex_count));
            packed.resize(meshopt_encodeIndexBuffer(reinterpret_cast<unsigned char*>(packed.data()),
                                                    packed.size(), triangles.data(), count));
        }
        const int view =
            add_view(raw, packed, narrow ? 2 : 4, count, kElementArrayBuffer, "TRIANGLES");
        accessors_.push_back({{"bufferView", view},
                              {"componentType", narrow ? kUnsignedShort : kUnsignedInt},
                              {"count", count},
                              {"type", "SCALAR"}});
        return int(accessors_.size()) - 1;
    }

    // `count` vertices of `components` floats, tightly packed. POSITION needs its bounds.
    int floats(const float* data, size_t count, int components, bool bounds) {
        const size_t stride = 4 * size_t(components);
        std::string raw(reinterpret_cast<const char*>(data), stride * count);
        std::string packed;
        if (meshopt_) {
            packed.resize(meshopt_encodeVertexBufferBound(count, stride));
            packed.resize(
                meshopt_encodeVertexBuffer(reinterpret_cast<unsigned char*>(packed.data()),
                                           packed.size(), data, count, stride));
        }
        const int view = add_view(raw, packed, stride, count, kArrayBuffer, "ATTRIBUTES");
        static const char* const kTypes[] = {"SCALAR", "VEC2", "VEC3", "VEC4"};
        json accessor = {{"bufferView", view},
                         {"componentType", kFloat},
                         {"count", count},
                         {"type", kTypes[components - 1]}};
        if (bounds) {
            json lo = json::array(), hi = json::array();
            for (int c = 0; c < components; ++c) {
                float a = std::numeric_limits<float>::infinity(), b = -a;
                for (size_t v = 0; v < count; ++v) {
                    a = std::min(a, data[v * components + c]);
                    b = std::max(b, data[v * components + c]);
                }
                lo.push_back(a);
                hi.push_back(b);
            }
            accessor["min"] = lo;
            accessor["max"] = hi;
        }
        accessors_.push_back(std::move(accessor));
        return int(accessors_.size()) - 1;
    }

    // The whole file: `doc` with the views, accessors and buffers added, then the BIN chunk.
    std::string finish(json doc) const {
        doc["bufferViews"] = views_;
        doc["accessors"] = accessors_;
        if (meshopt_) {
            doc["buffers"] = json::array({{{"byteLength", chunk_.size()}},
                                          {{"byteLength", fallback_length_},
                                           {"extensions", {{kMeshopt, {{"fallback", true}}}}}}});
            doc["extensionsUsed"] = json::array({kMeshopt});
            doc["extensionsRequired"] = json::array({kMeshopt});
        } else {
            doc["buffers"] = json::array({{{"byteLength", chunk_.size()}}});
        }
        std::string text = doc.dump();
        pad_to_4(text, ' ');
        // The BIN chunk is the views' bytes padded to 4 (every view ends padded already).
        const size_t bin = (chunk_.size() + 3) / 4 * 4;

        std::string out;
        out.reserve(12 + 8 + text.size() + 8 + bin);
        auto u32 = [&out](uint32_t x) {
            char b[4];
            std::memcpy(b, &x, 4); // glTF is little endian, as every platform this builds on
            out.append(b, 4);
        };
        u32(0x46546C67); // "glTF"
        u32(2);
        u32(uint32_t(12 + 8 + text.size() + 8 + bin));
        u32(uint32_t(text.size()));
        u32(0x4E4F534A); // "JSON"
        out += text;
        u32(uint32_t(bin));
        u32(0x004E4942); // "BIN\0"
        out += chunk_;
        out.append(bin - chunk_.size(), '\0');
        return out;
    }

private:
    int add_view(const std::string& raw, const std::string& packed, size_t stride, size_t count,
                 int target, const char* mode) {
        json view;
        if (meshopt_) {
            view = {{"buffer", 1}, {"byteOffset", fallback_length_}, {"byteLength", raw.size()}};
            view["extensions"][kMeshopt] = {{"buffer", 0},
                                            {"byteOffset", chunk_.size()},
                                            {"byteLength", packed.size()},
                                            {"byteStride", stride},
                                            {"count", count},
                                            {"mode", mode}};
            chunk_ += packed;
            fallback_length_ += (raw.size() + 3) / 4 * 4;
        } else {
            view = {{"buffer", 0}, {"byteOffset", chunk_.size()}, {"byteLength", raw.size()}};
            chunk_ += raw;
        }
        pad_to_4(chunk_, '\0');
        view["target"] = target;
        views_.push_back(std::move(view));
        return int(views_.size()) - 1;
    }

    bool meshopt_;
    json views_ = json::array();
    json accessors_ = json::array();
    std::string chunk_;
    size_t fallback_length_ = 0;
};

} // namespace

const Field* glb_colour_field(const Surface& surface, const std::string& requested) {
    if (!requested.empty()) {
        const Field* f = surface.find_field(requested);
        if (!f) {
            std::string names;
            for (const Field& x : surface.fields) names += (names.empty() ? "" : ", ") + x.name;
            throw GlbError("no field '" + requested + "' to colour by (the surface has: " +
                           (names.empty() ? "none" : names) + ")");
        }
        return f;
    }
    // A label's values are ids, whose colours would say nothing: a continuous scalar first.
    for (const bool continuous_only : {true, false})
        for (const Field& f : surface.fields) {
            if (continuous_only && f.kind != FieldKind::Continuous) continue;
            const ColourRange r = range_of(f.values);
            if (f.components == 1 && r.max > r.min) return &f;
        }
    return surface.fields.empty() ? nullptr : &surface.fields.front();
}

std::string write_glb(const Surface& surface, const GlbOptions& options) {
    check_shape(surface);
    const Field* colour = glb_colour_field(surface, options.colour_field);
    const size_t n = surface.vertex_count();

    size_t components = 3 + 3 + (colour ? 3 : 0); // position, normal, colour
    for (const Field& f : surface.fields) components += size_t(f.components);
    const size_t index_bytes = n <= 0xffff ? 2 : 4;
    Builder b(options.meshopt, surface.triangles.size() * index_bytes + 4 * components * n + 64);
    json attributes;
    const int indices = b.indices(surface.triangles, n);
    attributes["POSITION"] = b.floats(surface.positions.data(), n, 3, true);
    const std::vector<float> normals = vertex_normals(surface);
    attributes["NORMAL"] = b.floats(normals.data(), n, 3, false);

    json extras;
    if (colour) {
        const std::vector<float> values = colour_values(*colour);
        const ColourRange range = options.colour_range.value_or(range_of(values));
        const std::vector<float> rgb = vertex_colours(values, range);
        attributes["COLOR_0"] = b.floats(rgb.data(), n, 3, false);
        extras["colour_field"] = colour->name;
        extras["colour_range"] = {range.min, range.max};
        extras["colour_map"] = "viridis";
    }

    std::set<std::string> taken;
    json fields = json::array();
    for (const Field& f : surface.fields) {
        const std::string base = attribute_name(f.name, taken);
        json names = json::array();
        const int k = f.components;
        for (int first = 0; first < k; first += 4) {
            const int width = std::min(4, k - first);
            const std::string name = k <= 4 ? base : base + "_" + std::to_string(first / 4);
            std::vector<float> part(n * size_t(width));
            for (size_t v = 0; v < n; ++v)
                for (int c = 0; c < width; ++c)
                    part[v * width + c] = f.values[v * size_t(k) + first + c];
            attributes[name] = b.floats(part.data(), n, width, false);
            names.push_back(name);
        }
        fields.push_back({{"name", f.name}, {"components", k}, {"attributes", names}});
    }
    extras["fields"] = fields;

    json doc = {{"asset", {{"version", "2.0"}, {"generator", "ddsimp"}}},
                {"scene", 0},
                {"scenes", json::array({{{"nodes", json::array({0})}}})},
                {"nodes", json::array({{{"mesh", 0}, {"name", options.name}}})}};
    doc["meshes"] = json::array(
        {{{"name", options.name},
          {"primitives",
           json::array({{{"attributes", attributes}, {"indices", indices}, {"mode", kTriangles}}})},
          {"extras", extras}}});
    return b.finish(std::move(doc));
}

} // namespace ddsimp::protocol
