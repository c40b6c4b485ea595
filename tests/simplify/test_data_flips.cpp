// A fitted level's edges flipped where the data fits better (data_flips.h): a crease in the data
// that the level's triangles cut across is followed after the flips; folds of the surface and
// non-manifold edges are never flipped; the topology stays; the result is the same on any number
// of threads.
#include "data_error.h"
#include "data_flips.h"
#include "parallel.h"

#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <numbers>

namespace ddsimp::test {
namespace {

constexpr int kFine = 32, kStep = 8, kCoarse = kFine / kStep;

double crease(const Vec3& p) {
    return std::abs(p[0] - p[1]);
}

// The input: a fine grid over the unit square with data |x - y|, a crease along the diagonal,
// lifted to z = height * |x - y| (a roof along it) when height > 0. The level: every kStep-th
// input vertex, each cell split along its other diagonal, across the crease.
struct CreaseCase {
    Surface input, level;
    detail::RefitInput refit;

    explicit CreaseCase(double height) {
        input = grid(kFine, kFine);
        for (size_t v = 0; v < input.vertex_count(); ++v)
            input.positions[3 * v + 2] = float(height * crease(position(input, v)));
        add_field(input, "f", 1, [](const Vec3& p) { return std::vector<double>{crease(p)}; });
        std::vector<uint32_t> coarse; // level vertex -> input vertex
        for (int j = 0; j <= kCoarse; ++j)
            for (int i = 0; i <= kCoarse; ++i)
                coarse.push_back(grid_index(kFine, kStep * i, kStep * j));
        for (uint32_t v : coarse) {
            for (int d = 0; d < 3; ++d) level.positions.push_back(input.positions[3 * v + d]);
        }
        level.fields.push_back({"f", 1, {}, input.fields[0].kind});
        for (uint32_t v : coarse) level.fields[0].values.push_back(input.fields[0].values[v]);
        for (int j = 0; j < kCoarse; ++j)
            for (int i = 0; i < kCoarse; ++i) {
                const uint32_t a = grid_index(kCoarse, i, j), b = grid_index(kCoarse, i + 1, j),
                               c = grid_index(kCoarse, i + 1, j + 1),
                               d = grid_index(kCoarse, i, j + 1);
                add_triangle(level, a, b, d);
                add_triangle(level, b, c, d);
            }
        refit.surface = &input;
        refit.vertices = input.vertex_count();
        refit.triangles = &input.triangles;
        for (int j = 0; j <= kFine; ++j)
            for (int i = 0; i <= kFine; ++i) {
                const int ci = (i + kStep / 2) / kStep, cj = (j + kStep / 2) / kStep;
                refit.owner.push_back(
                    grid_index(kCoarse, std::min(ci, kCoarse), std::min(cj, kCoarse)));
            }
        refit.free.assign(level.vertex_count(), 0); // the level's vertices are the input's own
        refit.components = {{0u, 0u}};
        refit.data_weight = {1.0};
        refit.distance_weight = 0.2;
        refit.flat_cos = std::cos(detail::kFlipFlatDegrees * std::numbers::pi / 180);
    }

    // Level triangles with corners on both sides of the crease.
    size_t across() const {
        size_t count = 0;
        for (size_t t = 0; t < level.triangle_count(); ++t) {
            bool above = false, below = false;
            for (uint32_t v : corners(level, t)) {
                const Vec3 p = position(level, v);
                above = above || p[0] - p[1] > 1e-6, below = below || p[0] - p[1] < -1e-6;
            }
            count += above && below;
        }
        return count;
    }

    void fit(int threads = 1) {
        detail::Parallel parallel(threads);
        detail::refit_data(refit, level, parallel);
    }
};

TEST(DataFlips, FollowACreaseInTheData) {
    CreaseCase flat(0);
    const Topology before = analyze_topology(flat.level);
    EXPECT_EQ(flat.across(), size_t(2 * kCoarse)); // both triangles of each diagonal cell
    const double error_before = two_way_data_rms(flat.input, flat.level);
    flat.fit();
    EXPECT_EQ(flat.across(), 0u);
    EXPECT_EQ(flat.level.triangle_count(), size_t(2 * kCoarse * kCoarse));
    EXPECT_TRUE(topology_kept(before, analyze_topology(flat.level)));
    // The data is linear on each side of the crease: the level now holds it exactly.
    EXPECT_GT(error_before, 0.01);
    EXPECT_LT(two_way_data_rms(flat.input, flat.level), 1e-6);
}

// The same crease on a roof: its two slopes turn 90 degrees apart at the ridge, where the level's
// triangles meet at far more than kFlipFlatDegrees. The flips would follow the data but leave the
// surface: none is made.
TEST(DataFlips, NeverAcrossAFold) {
    CreaseCase roof(1.0);
    const std::vector<uint32_t> triangles = roof.level.triangles;
    roof.fit();
    EXPECT_EQ(roof.level.triangles, triangles);
}

// An edge with a third triangle (a fin standing on it) is no edge between two triangles: it is
// never flipped, nor does a flip beside it make it one.
TEST(DataFlips, NeverAcrossANonManifoldEdge) {
    CreaseCase finned(0);
    // A fin on the other diagonal of every diagonal cell: the edge the crease wants flipped.
    for (int i = 0; i < kCoarse; ++i) {
        const uint32_t b = grid_index(kCoarse, i + 1, i), d = grid_index(kCoarse, i, i + 1);
        const Vec3 pb = position(finned.level, b), pd = position(finned.level, d);
        const uint32_t top = uint32_t(finned.level.vertex_count());
        add_vertex(finned.level, (pb[0] + pd[0]) / 2, (pb[1] + pd[1]) / 2, 0.5);
        finned.level.fields[0].values.push_back(0);
        finned.refit.free.push_back(0);
        add_triangle(finned.level, b, d, top);
    }
    const Topology before = analyze_topology(finned.level);
    ASSERT_EQ(before.nonmanifold_edges, size_t(kCoarse));
    finned.fit();
    EXPECT_EQ(finned.across(), size_t(3 * kCoarse)); // the diagonal cells' and the fins'

    EXPECT_TRUE(topology_kept(before, analyze_topology(finned.level)));
}

TEST(DataFlips, SameBytesOnAnyThreadCount) {
    // As in test_determinism.cpp: as many threads as asked for, also on a two-core machine.
    oneapi::tbb::global_control allow(oneapi::tbb::global_control::max_allowed_parallelism, 17);
    CreaseCase one(0);
    one.fit(1);
    for (int threads : {2, 3, 4}) {
        CreaseCase many(0);
        many.fit(threads);
        EXPECT_TRUE(same_bytes(one.level, many.level)) << threads << " threads";
    }
}

// A flat grid with a crease in its data and a wave along it.
Surface creased_grid() {
    Surface in = grid(40, 40);
    add_field(in, "f", 1, [](const Vec3& p) {
        return std::vector<double>{crease(p) + 0.2 * std::sin(7 * p[0]) * p[1]};
    });
    return in;
}

// A record of every operation of `strategy` at alpha = 0, on one thread.
Options whole_run(Strategy strategy) {
    Options o;
    o.strategy = strategy;
    o.alpha = 0;
    o.keep_fraction = 0;
    o.threads = 1;
    return o;
}

// The level after `operations` of a run with options o on 2 and 4 threads is `level`, byte for
// byte.
void expect_same_level_on_more_threads(const Surface& in, Options o, size_t operations,
                                       const Surface& level) {
    oneapi::tbb::global_control allow(oneapi::tbb::global_control::max_allowed_parallelism, 17);
    for (int threads : {2, 4}) {
        o.threads = threads;
        EXPECT_TRUE(same_bytes(level, ProgressiveRecord::build(in, o).after(operations)))
            << threads << " threads";
    }
}

// Through the library: a flat surface with a crease in its data, reduced by edge collapse with
// least-error data. after() flips some of the recorded level's edges (after_as_recorded() has the
// same vertices), keeps the topology, and gives the same bytes on any number of threads.
TEST(DataFlips, InTheLevelsOfARun) {
    const Surface in = creased_grid();
    Options o = whole_run(Strategy::EdgeCollapse);
    const ProgressiveRecord record = ProgressiveRecord::build(in, o);
    const size_t operations = record.operations_for(in.triangle_count() / 10);
    const Surface flipped = record.after(operations),
                  recorded = record.after_as_recorded(operations);
    ASSERT_EQ(flipped.positions, recorded.positions);
    EXPECT_NE(flipped.triangles, recorded.triangles);
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(flipped)));
    expect_same_level_on_more_threads(in, o, operations, flipped);
}

// Vertex removal's levels keep input vertices and their data: after() flips edges of the
// recorded level, and moves vertices to other input vertices (level_relocation.h), where the data
// fits better; it keeps the topology and gives the same bytes on any number of threads. At
// alpha = 1 the data weighs nothing, and on this plane no flip or move lowers the distance:
// nothing changes.
TEST(DataFlips, InTheLevelsOfAVertexRemovalRun) {
    const Surface in = creased_grid();
    Options o = whole_run(Strategy::VertexRemoval);
    const ProgressiveRecord record = ProgressiveRecord::build(in, o);
    const size_t operations = record.operations_for(in.triangle_count() / 10);
    const Surface flipped = record.after(operations),
                  recorded = record.after_as_recorded(operations);
    ASSERT_EQ(flipped.vertex_count(), recorded.vertex_count());
    EXPECT_NE(flipped.triangles, recorded.triangles);
    EXPECT_NE(flipped.positions, recorded.positions);
    // Each vertex is an input vertex with its data.
    for (size_t v = 0; v < flipped.vertex_count(); ++v) {
        const Vec3 p = position(flipped, v);
        const uint32_t i = grid_index(40, int(std::lround(p[0] * 40)), int(std::lround(p[1] * 40)));
        ASSERT_EQ(position(in, i), p);
        ASSERT_EQ(in.fields[0].values[i], flipped.fields[0].values[v]);
    }
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(flipped)));
    EXPECT_LT(two_way_data_rms(in, flipped), 0.97 * two_way_data_rms(in, recorded));
    expect_same_level_on_more_threads(in, o, operations, flipped);
    o.alpha = 1;
    const ProgressiveRecord geometric = ProgressiveRecord::build(in, o);
    const size_t at = geometric.operations_for(in.triangle_count() / 10);
    EXPECT_TRUE(same_bytes(geometric.after(at), geometric.after_as_recorded(at)));
}

// Fins stand on a row of the grid's edges, each edge with three triangles, across creases in the
// data: every level of either strategy keeps the input's topology (no non-manifold edge lost or
// made, the same Euler characteristic) while the flips (and vertex removal's moves of vertices,
// level_relocation.h) change it.
TEST(DataFlips, KeepNonManifoldEdgesInTheLevelsOfARun) {
    constexpr int n = 40;
    Surface in = grid(n, n);
    for (int i = 4; i < n - 4; i += 2) {
        const uint32_t apex = add_vertex(in, (i + 0.5) / n, 0.5, 1.0 / n);
        add_triangle(in, grid_index(n, i, n / 2), grid_index(n, i + 1, n / 2), apex);
    }
    add_field(in, "f", 1, [](const Vec3& p) {
        return std::vector<double>{std::abs(p[0] - p[1]) + std::abs(p[0] + p[1] - 1)};
    });
    const Topology before = analyze_topology(in);
    for (Strategy strategy : {Strategy::EdgeCollapse, Strategy::VertexRemoval}) {
        const ProgressiveRecord record = ProgressiveRecord::build(in, whole_run(strategy));
        size_t changed = 0;
        for (size_t keep : {2, 4, 8, 16, 32}) {
            const size_t operations = record.operations_for(in.triangle_count() * keep / 100);
            const Surface level = record.after(operations);
            const Surface recorded = record.after_as_recorded(operations);
            changed +=
                level.triangles != recorded.triangles || level.positions != recorded.positions;
            EXPECT_TRUE(topology_kept(before, analyze_topology(level)))
                << "strategy " << int(strategy) << ", " << keep << "%";
        }
        EXPECT_GT(changed, 0u) << "strategy " << int(strategy);
    }
}

} // namespace
} // namespace ddsimp::test
