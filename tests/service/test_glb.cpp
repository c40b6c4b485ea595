// write_glb: the container, the accessors read back against the surface (raw and through
// meshoptimizer's decoders for EXT_meshopt_compression), colours, normals, and the errors.
// tests/web/glb_files.test.mjs checks the same files with Khronos's validator and three.js.
#include "glb_reader.h"

#include "ddsimp/protocol/glb.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace {

using ddsimp::Surface;
using ddsimp::protocol::GlbError;
using ddsimp::protocol::GlbOptions;
using ddsimp::protocol::write_glb;
using ddsimp::test::Glb;
using ddsimp::test::rotated;
using json = nlohmann::json;

GlbOptions meshopt() {
    GlbOptions o;
    o.meshopt = true;
    return o;
}
GlbOptions coloured_by(const std::string& field) {
    GlbOptions o;
    o.colour_field = field;
    return o;
}

// A 3 x 2 grid in the plane z = 0 (4 triangles) with a scalar "t" = x, a vector "wind" and a
// 6-component "stress".
Surface grid() {
    Surface s;
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) s.positions.insert(s.positions.end(), {float(x), float(y), 0});
    s.triangles = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4};
    ddsimp::Field t{"t", 1, {}}, wind{"wind speed", 3, {}}, stress{"stress", 6, {}};
    for (int v = 0; v < 6; ++v) {
        t.values.push_back(float(v % 3));
        wind.values.insert(wind.values.end(), {3.0f * v, 4.0f * v, 0});
        for (int c = 0; c < 6; ++c) stress.values.push_back(float(10 * v + c));
    }
    s.fields = {t, wind, stress};
    return s;
}

float linear(uint32_t srgb_byte) {
    const double c = srgb_byte / 255.0;
    return float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

void expect_surface(const Glb& g, const Surface& s) {
    const auto positions = g.attribute("POSITION");
    ASSERT_EQ(positions.size(), s.positions.size());
    for (size_t i = 0; i < positions.size(); ++i) EXPECT_EQ(positions[i], s.positions[i]);
    const auto indices = g.accessor(g.primitive()["indices"]);
    ASSERT_EQ(indices.size(), s.triangles.size());
    const std::vector<double> expected(s.triangles.begin(), s.triangles.end());
    for (size_t t = 0; t < indices.size(); t += 3)
        EXPECT_EQ(rotated(&indices[t]), rotated(&expected[t])) << "triangle " << t / 3;
    const auto normals = g.attribute("NORMAL");
    for (size_t v = 0; v < s.vertex_count(); ++v) {
        EXPECT_NEAR(normals[3 * v], 0, 1e-6);
        EXPECT_NEAR(normals[3 * v + 2], 1, 1e-6); // the grid faces +z
    }
    EXPECT_EQ(g.attribute("_t"), std::vector<double>({0, 1, 2, 0, 1, 2}));
    const auto wind = g.attribute("_wind_speed");
    ASSERT_EQ(wind.size(), 18u);
    EXPECT_EQ(wind[3 * 5 + 1], 20.0);
    // 6 components: _stress_0 holds 0..3, _stress_1 holds 4..5.
    const auto s0 = g.attribute("_stress_0"), s1 = g.attribute("_stress_1");
    ASSERT_EQ(s0.size(), 24u);
    ASSERT_EQ(s1.size(), 12u);
    EXPECT_EQ(s0[4 * 2 + 3], 23.0);
    EXPECT_EQ(s1[2 * 2 + 1], 25.0);
}

TEST(Glb, HoldsPositionsIndicesNormalsAndEveryField) {
    const Surface s = grid();
    const Glb g(write_glb(s));
    expect_surface(g, s);
    EXPECT_EQ(g.doc["asset"]["version"], "2.0");
    EXPECT_EQ(g.doc["accessors"][int(g.primitive()["indices"])]["componentType"], 5123);
    EXPECT_EQ(g.doc["accessors"][int(g.primitive()["attributes"]["POSITION"])]["max"],
              json::array({2.0, 1.0, 0.0}));
    const json& extras = g.doc["meshes"][0]["extras"];
    EXPECT_EQ(extras["fields"][2]["attributes"], json::array({"_stress_0", "_stress_1"}));
    EXPECT_FALSE(g.doc.contains("extensionsUsed"));
}

TEST(Glb, MeshoptCompressedReadsBackTheSame) {
    const Surface s = grid();
    const Glb g(write_glb(s, meshopt()));
    EXPECT_EQ(g.doc["extensionsRequired"], json::array({"EXT_meshopt_compression"}));
    EXPECT_EQ(g.doc["buffers"][1]["extensions"]["EXT_meshopt_compression"]["fallback"], true);
    expect_surface(g, s);
}

TEST(Glb, ColoursAreViridisOfTheFirstVaryingScalar) {
    const Glb g(write_glb(grid()));
    const json& extras = g.doc["meshes"][0]["extras"];
    EXPECT_EQ(extras["colour_field"], "t");
    EXPECT_EQ(extras["colour_range"], json::array({0.0, 2.0}));
    const auto rgb = g.attribute("COLOR_0");
    // t = 0: viridis' first stop #440154; t = 2: its last, #fde725; t = 1: its middle, #21918c.
    EXPECT_NEAR(rgb[0], linear(0x44), 1e-6);
    EXPECT_NEAR(rgb[2], linear(0x54), 1e-6);
    EXPECT_NEAR(rgb[3 * 1 + 1], linear(0x91), 1e-6);
    EXPECT_NEAR(rgb[3 * 2 + 0], linear(0xfd), 1e-6);
    EXPECT_NEAR(rgb[3 * 2 + 1], linear(0xe7), 1e-6);
}

TEST(Glb, ALabelBeforeTheFirstContinuousScalarDoesNotColourByDefault) {
    Surface s = grid();
    ddsimp::Field id{"GlobalNodeId", 1, {}};
    for (int v = 0; v < 6; ++v) id.values.push_back(float(100 + v));
    id.kind = ddsimp::FieldKind::Label;
    s.fields.insert(s.fields.begin(), id);
    EXPECT_EQ(Glb(write_glb(s)).doc["meshes"][0]["extras"]["colour_field"], "t");
    s.fields.erase(s.fields.begin() + 1); // without "t": the label is the only varying scalar
    EXPECT_EQ(Glb(write_glb(s)).doc["meshes"][0]["extras"]["colour_field"], "GlobalNodeId");
}

TEST(Glb, AVectorFieldColoursByItsLengthOverTheRangeAsked) {
    GlbOptions options = coloured_by("wind speed");
    options.colour_range = ddsimp::protocol::ColourRange{0, 25};
    const Glb g(write_glb(grid(), options));
    const auto rgb = g.attribute("COLOR_0");
    // |wind| = 5 v: vertex 0 is viridis(0), vertex 5 (length 25) viridis(1).
    EXPECT_NEAR(rgb[0], linear(0x44), 1e-6);
    EXPECT_NEAR(rgb[3 * 5 + 2], linear(0x25), 1e-6);
    EXPECT_EQ(g.doc["meshes"][0]["extras"]["colour_field"], "wind speed");
}

TEST(Glb, TheSameSurfaceGivesTheSameBytes) {
    EXPECT_EQ(write_glb(grid(), meshopt()), write_glb(grid(), meshopt()));
}

TEST(Glb, ManyVerticesUseUint32Indices) {
    Surface s;
    const int n = 300; // 90,000 vertices
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) s.positions.insert(s.positions.end(), {float(x), float(y), 0});
    for (int y = 0; y + 1 < n; ++y)
        for (int x = 0; x + 1 < n; ++x) {
            const uint32_t v = uint32_t(y * n + x);
            s.triangles.insert(s.triangles.end(), {v, v + 1, v + n + 1, v, v + n + 1, v + n});
        }
    const Glb g(write_glb(s, meshopt()));
    EXPECT_EQ(g.doc["accessors"][int(g.primitive()["indices"])]["componentType"], 5125);
    const auto indices = g.accessor(g.primitive()["indices"]);
    ASSERT_EQ(indices.size(), s.triangles.size());
    EXPECT_EQ(rotated(&indices[indices.size() - 3]),
              rotated(std::vector<double>(s.triangles.end() - 3, s.triangles.end()).data()));
    EXPECT_FALSE(g.primitive()["attributes"].contains("COLOR_0")); // no field: no colours
}

TEST(Glb, BadInputIsRefusedWithTheReason) {
    Surface s = grid();
    try {
        write_glb(s, coloured_by("pressure"));
        FAIL() << "an unknown colour field was accepted";
    } catch (const GlbError& e) {
        EXPECT_NE(std::string(e.what()).find("no field 'pressure'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("wind speed"), std::string::npos) << e.what();
    }
    s.triangles.clear();
    EXPECT_THROW(write_glb(s), GlbError);
    s = grid();
    s.triangles[4] = 99;
    EXPECT_THROW(write_glb(s), GlbError);
}

} // namespace
