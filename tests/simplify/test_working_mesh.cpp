// working_mesh.h (internal): the fans walked side by side (rings) must list what walking them one
// at a time (ring) lists, in the same order, on closed fans, open ones and ones that overflow.
#include "test_surfaces.h"
#include "working_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
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

} // namespace
} // namespace ddsimp::detail
