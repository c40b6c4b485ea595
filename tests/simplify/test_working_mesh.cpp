// working_mesh.h (internal): the fans walked side by side (rings) must list what walking them one
// at a time (ring) lists, in the same order, on closed fans, open ones and ones that overflow.
// And the kinds of boundary vertices: a zigzag of the sampling is a line, a polygon's corner not.
#include "test_surfaces.h"
#include "working_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace ddsimp::detail {
namespace {

using namespace ddsimp::test;

void expect_rings_as_one_at_a_time(Surface s, size_t max) {
    validate(s);
    WorkingMesh mesh;
    mesh.build(s, s.vertex_count(), Limits{});
    std::vector<uint32_t> vertices;
    for (uint32_t v = 0; v < s.vertex_count(); ++v)
        if (mesh.kind[v] != VertexKind::Dead && mesh.kind[v] != VertexKind::Complex)
            vertices.push_back(v);
    ASSERT_FALSE(vertices.empty());
    // Batches of every size up to 64, so that walks of different lengths end at different steps.
    for (size_t begin = 0, k = 1; begin < vertices.size(); begin += k, k = k % 64 + 1) {
        const size_t count = std::min(k, vertices.size() - begin);
        std::vector<uint32_t> together(count * max), alone(max);
        std::vector<size_t> counts(count);
        mesh.rings(&vertices[begin], count, together.data(), max, counts.data());
        for (size_t i = 0; i < count; ++i) {
            const uint32_t v = vertices[begin + i];
            const size_t n = mesh.ring(v, alone.data(), max);
            ASSERT_EQ(counts[i], n) << "vertex " << v << ", max " << max;
            for (size_t j = 0; j < n; ++j)
                ASSERT_EQ(together[i * max + j], alone[j]) << "vertex " << v << ", neighbour " << j;
        }
    }
}

TEST(WorkingMesh, RingsWalkedSideBySideAreEachVertexsRing) {
    for (size_t max : {64u, 6u, 5u}) { // 5 and 6: some fans do not fit, both inner and boundary
        expect_rings_as_one_at_a_time(icosphere(2), max);
        expect_rings_as_one_at_a_time(grid_with_hole(8, 3, 5), max);
        expect_rings_as_one_at_a_time(fan(9), max);
        expect_rings_as_one_at_a_time(moebius(12), max);
    }
}

// The kinds of a surface's boundary vertices with a line tolerance of `degrees`.
std::vector<VertexKind> kinds(Surface s, double degrees) {
    validate(s);
    Limits limits;
    limits.straight_cos = std::cos(degrees * std::numbers::pi / 180);
    WorkingMesh mesh;
    mesh.build(s, s.vertex_count(), limits);
    return {mesh.kind.begin(), mesh.kind.begin() + s.vertex_count()};
}

// A 12 x 12 grid whose bottom row zigzags: its inner vertices alternately raised by 0.3 of a cell,
// so that each turns by 2 atan 0.3 = 33 degrees, more than a tolerance of 20, and lies 0.3 cells
// from the segment between its neighbours, less than half the mean edge length (about 0.57
// cells). They are line vertices, turning one way and the other: a zigzag of the sampling. The
// grid's corners (right angles, 0.8 cells off) stay corners, and a tolerance of 0 keeps every
// vertex that turns.
TEST(WorkingMesh, AZigzagOfTheSamplingIsALine) {
    Surface s = grid(12, 12);
    for (int i = 1; i < 12; i += 2) s.positions[3 * size_t(i) + 1] += float(0.3 / 12);
    const std::vector<VertexKind> wide = kinds(s, 20), none = kinds(s, 0);
    for (int i = 1; i < 12; ++i) {
        EXPECT_EQ(wide[size_t(i)], VertexKind::Line) << i;
        EXPECT_EQ(none[size_t(i)], VertexKind::Corner) << i;
    }
    EXPECT_EQ(wide[0], VertexKind::Corner);
    EXPECT_EQ(wide[12], VertexKind::Corner);
}

// A polygon's corners all turn one way: the octagon fan's rim turns by 45 degrees at each vertex,
// 0.29 of its radius off the segment between its neighbours (half the mean edge length: 0.46),
// and every rim vertex stays a corner. So do those of a 24-gon whose rim turns by 15 degrees
// once the tolerance is 10.
TEST(WorkingMesh, APolygonsCornersAreNoZigzag) {
    for (const auto& [n, degrees] : {std::pair{8, 20.0}, std::pair{24, 10.0}}) {
        const std::vector<VertexKind> k = kinds(fan(n), degrees);
        for (int i = 1; i <= n; ++i) EXPECT_EQ(k[size_t(i)], VertexKind::Corner) << n << ", " << i;
        EXPECT_EQ(k[0], VertexKind::Free);
    }
}

} // namespace
} // namespace ddsimp::detail
