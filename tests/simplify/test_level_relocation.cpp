// A vertex-removal level's vertices moved to other input vertices where the input fits better
// (level_relocation.h): a level vertex beside a peak in the data moves onto it; every vertex stays
// an input vertex with its exact position and data; the triangles and the topology stay and none
// folds; locked vertices, and data the level already holds exactly, stay; the result is the same
// on any number of threads; a boundary vertex moves only along the boundary; where the data
// weighs nothing, the surface decides the moves, which may then turn the surface further; a move
// lands each sample at its closest point on the star; moves and flips in turns leave a level where
// neither gains any more.
#include "data_error.h"
#include "data_flips.h"
#include "level_relocation.h"
#include "parallel.h"

#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <numbers>
#include <numeric>

namespace ddsimp::test::level_relocation {
namespace {

constexpr int kFine = 32, kStep = 8, kCoarse = kFine / kStep;
// The input vertex at the top of the bump: three fine cells right of and two above the level
// vertex at the middle of the square.
constexpr int kPeakI = kFine / 2 + 3, kPeakJ = kFine / 2 + 2;

double bump(const Vec3& p) {
    const double dx = p[0] - double(kPeakI) / kFine, dy = p[1] - double(kPeakJ) / kFine;
    return std::exp(-(dx * dx + dy * dy) * 200);
}

// The input: a fine flat grid over the unit square with data `field`. The level: every kStep-th
// input vertex, as a grid of its own; each input vertex it does not keep landed on its closest
// level triangle (found by trying them all).
struct LevelCase {
    Surface input, level;
    detail::RefitInput refit;
    std::vector<uint32_t> source; // level vertex -> input vertex
    std::vector<detail::Landing> forward;
    std::vector<uint8_t> locked;

    explicit LevelCase(double (*field)(const Vec3&)) {
        input = grid(kFine, kFine);
        add_field(input, "f", 1, [&](const Vec3& p) { return std::vector<double>{field(p)}; });
        level = grid(kCoarse, kCoarse);
        level.positions.clear();
        for (int j = 0; j <= kCoarse; ++j)
            for (int i = 0; i <= kCoarse; ++i)
                source.push_back(grid_index(kFine, kStep * i, kStep * j));
        level.fields.push_back({"f", 1, {}, input.fields[0].kind});
        for (uint32_t v : source) {
            for (int d = 0; d < 3; ++d) level.positions.push_back(input.positions[3 * v + d]);
            level.fields[0].values.push_back(input.fields[0].values[v]);
        }
        land_all();
        refit.surface = &input;
        refit.vertices = input.vertex_count();
        refit.triangles = &input.triangles;
        refit.components = {{0u, 0u}};
        refit.data_weight = {1.0};
        refit.distance_weight = 0.2;
        refit.flat_cos = std::cos(detail::kFlipFlatDegrees * std::numbers::pi / 180);
    }

    // Each input vertex the level does not keep landed on its closest level triangle.
    void land_all() {
        forward.resize(input.vertex_count());
        for (uint32_t v : source) forward[v].triangle = detail::kNoOwner;
        for (uint32_t i = 0; i < input.vertex_count(); ++i) {
            if (std::find(source.begin(), source.end(), i) != source.end()) continue;
            double best = INFINITY;
            for (uint32_t t = 0; t < level.triangle_count(); ++t) {
                const auto k = corners(level, t);
                const detail::ClosestPoint c =
                    detail::closest_on_triangle(position(input, i), position(level, k[0]),
                                                position(level, k[1]), position(level, k[2]));
                const Vec3 d = c.point - position(input, i);
                if (dot(d, d) < best) best = dot(d, d), forward[i] = {t, c.weights};
            }
        }
    }

    bool relocate(int threads = 1, const std::vector<uint8_t>& boundary_line = {}) {
        detail::Parallel parallel(threads);
        std::vector<uint32_t> all(level.vertex_count());
        std::iota(all.begin(), all.end(), 0u);
        return !detail::relocate_level_vertices(refit, locked, boundary_line, source, forward,
                                                level, parallel, all)
                    .empty();
    }
    bool flip() {
        detail::Parallel parallel(1);
        return !detail::flip_edges_for_data(refit, forward, level, parallel).empty();
    }
    void settle(int threads = 1) {
        detail::Parallel parallel(threads);
        detail::settle_level(refit, locked, {}, source, forward, level, parallel);
    }

    // Each level vertex is its source input vertex, with that vertex's position and data.
    ::testing::AssertionResult vertices_are_the_inputs() const {
        for (uint32_t v = 0; v < level.vertex_count(); ++v)
            if (position(level, v) != position(input, source[v]) ||
                level.fields[0].values[v] != input.fields[0].values[source[v]])
                return ::testing::AssertionFailure() << "level vertex " << v;
        return ::testing::AssertionSuccess();
    }
};

double waves(const Vec3& p) {
    return std::sin(9 * p[0]) * std::cos(7 * p[1]) + bump(p);
}

// The level vertex at the middle of the square.
constexpr uint32_t kMiddle = (kCoarse + 1) * (kCoarse / 2) + kCoarse / 2;

TEST(LevelRelocation, MovesAVertexOntoAPeakInTheData) {
    LevelCase c(bump);
    const std::vector<uint32_t> triangles = c.level.triangles;
    const Topology before = analyze_topology(c.level);
    const double error_before = two_way_data_rms(c.input, c.level);
    ASSERT_LT(c.level.fields[0].values[kMiddle], 0.1); // the peak is between the level's vertices
    EXPECT_TRUE(c.relocate());
    EXPECT_EQ(c.source[kMiddle], grid_index(kFine, kPeakI, kPeakJ));
    EXPECT_EQ(c.level.fields[0].values[kMiddle], 1.0f);
    EXPECT_TRUE(c.vertices_are_the_inputs());
    EXPECT_EQ(c.level.triangles, triangles);
    EXPECT_TRUE(topology_kept(before, analyze_topology(c.level)));
    EXPECT_LT(two_way_data_rms(c.input, c.level), 0.5 * error_before);
    // The input vertex left behind lands on the level; the peak is the level's own.
    EXPECT_NE(c.forward[grid_index(kFine, kFine / 2, kFine / 2)].triangle, detail::kNoOwner);
    EXPECT_EQ(c.forward[grid_index(kFine, kPeakI, kPeakJ)].triangle, detail::kNoOwner);
}

// The input's boundary vertices but its four corners: where the boundary runs on.
std::vector<uint8_t> boundary_line(const Surface& input) {
    std::vector<uint8_t> line(input.vertex_count(), 0);
    for (int k = 1; k < kFine; ++k)
        for (uint32_t v : {grid_index(kFine, k, 0), grid_index(kFine, k, kFine),
                           grid_index(kFine, 0, k), grid_index(kFine, kFine, k)})
            line[v] = 1;
    return line;
}

// A peak in the data on the boundary, three fine cells right of the level vertex (2, 0), or one
// cell inside it.
double peak_at(const Vec3& p, int j) {
    const double dx = p[0] - double(kPeakI) / kFine, dy = p[1] - double(j) / kFine;
    return std::exp(-(dx * dx + dy * dy) * 200);
}
double boundary_peak(const Vec3& p) {
    return peak_at(p, 0);
}
double peak_inside(const Vec3& p) {
    return peak_at(p, 1);
}
constexpr uint32_t kOnBoundary = 2; // the level vertex (2, 0), at the middle of the bottom edge

// A boundary vertex moves along the boundary onto the peak; without the input's boundary line
// given, boundary vertices stay.
TEST(LevelRelocation, MovesABoundaryVertexAlongTheBoundary) {
    LevelCase c(boundary_peak);
    const std::vector<uint8_t> line = boundary_line(c.input);
    const double error_before = two_way_data_rms(c.input, c.level);
    EXPECT_TRUE(c.relocate(1, line));
    EXPECT_EQ(c.source[kOnBoundary], grid_index(kFine, kPeakI, 0));
    EXPECT_EQ(c.level.fields[0].values[kOnBoundary], 1.0f);
    EXPECT_TRUE(c.vertices_are_the_inputs());
    EXPECT_LT(two_way_data_rms(c.input, c.level), 0.5 * error_before);

    LevelCase stays(boundary_peak);
    stays.relocate();
    EXPECT_EQ(stays.source[kOnBoundary], grid_index(kFine, kFine / 2, 0));
}

// With the peak one cell inside, the boundary vertex may not leave the boundary for it: every
// level vertex on the boundary stays on it.
TEST(LevelRelocation, ABoundaryVertexNeverLeavesTheBoundary) {
    LevelCase c(peak_inside);
    c.relocate(1, boundary_line(c.input));
    EXPECT_TRUE(c.vertices_are_the_inputs());
    for (int k = 0; k <= kCoarse; ++k)
        for (uint32_t v : {uint32_t(k), uint32_t(kCoarse * (kCoarse + 1) + k),
                           uint32_t(k * (kCoarse + 1)), uint32_t(k * (kCoarse + 1) + kCoarse)}) {
            const Vec3 p = position(c.level, v);
            EXPECT_TRUE(p[0] == 0 || p[0] == 1 || p[1] == 0 || p[1] == 1) << "level vertex " << v;
        }
}

// Where no data weighs, the distance alone decides, and a move may turn the star's triangles as
// far as the run lets any operation (RefitInput::turn_cos), not only as far as where data weighs
// (flat_cos): beside a steep hill, the level vertex moves onto its top and the level follows the
// hill far better than when moves may turn the triangles only as far as where data weighs.
TEST(LevelRelocation, ByTheDistanceAloneAMoveTurnsAsFarAsTheRunAllows) {
    auto relocated = [](double turn_degrees, uint32_t& middle) {
        LevelCase c([](const Vec3&) { return 0.0; });
        for (size_t v = 0; v < c.input.vertex_count(); ++v)
            c.input.positions[3 * v + 2] = float(0.35 * bump(position(c.input, v)));
        for (uint32_t v = 0; v < c.level.vertex_count(); ++v)
            c.level.positions[3 * v + 2] = c.input.positions[3 * size_t(c.source[v]) + 2];
        c.refit.components.clear();
        c.refit.data_weight.clear();
        c.refit.distance_weight = 1;
        c.refit.turn_cos = std::cos(turn_degrees * std::numbers::pi / 180);
        const double before = two_way_distance_rms(c.input, c.level);
        c.relocate();
        EXPECT_TRUE(c.vertices_are_the_inputs());
        middle = c.source[kMiddle];
        return two_way_distance_rms(c.input, c.level) / before;
    };
    uint32_t far = 0, flat = 0;
    const double as_far = relocated(60, far), as_flat = relocated(detail::kFlipFlatDegrees, flat);
    EXPECT_EQ(far, grid_index(kFine, kPeakI, kPeakJ));
    EXPECT_NE(flat, grid_index(kFine, kPeakI, kPeakJ));
    EXPECT_LT(as_far, 0.7 * as_flat);
}

// A move lands the star's samples where the measure finds them: each at its closest point on the
// star, which on a curved star may be on another triangle than the one its projection falls in.
TEST(LevelRelocation, AMoveLandsEachSampleAtItsClosestPointOnTheStar) {
    LevelCase c([](const Vec3&) { return 0.0; });
    // A bump; only the middle vertex may move.
    for (size_t v = 0; v < c.input.vertex_count(); ++v)
        c.input.positions[3 * v + 2] = float(0.35 * bump(position(c.input, v)));
    for (uint32_t v = 0; v < c.level.vertex_count(); ++v)
        c.level.positions[3 * v + 2] = c.input.positions[3 * size_t(c.source[v]) + 2];
    c.land_all();
    c.locked.assign(c.input.vertex_count(), 1);
    c.locked[c.source[kMiddle]] = 0;
    c.refit.components.clear();
    c.refit.data_weight.clear();
    c.refit.distance_weight = 1;
    c.refit.turn_cos = std::cos(60 * std::numbers::pi / 180);
    ASSERT_TRUE(c.relocate());
    std::vector<uint32_t> star;
    for (uint32_t t = 0; t < c.level.triangle_count(); ++t) {
        const auto k = corners(c.level, t);
        if (k[0] == kMiddle || k[1] == kMiddle || k[2] == kMiddle) star.push_back(t);
    }
    size_t on_star = 0;
    for (uint32_t i = 0; i < c.input.vertex_count(); ++i) {
        const detail::Landing& l = c.forward[i];
        if (std::find(star.begin(), star.end(), l.triangle) == star.end()) continue;
        const auto k = corners(c.level, l.triangle);
        Vec3 at{0, 0, 0};
        for (int j = 0; j < 3; ++j)
            for (int d = 0; d < 3; ++d) at[d] += l.weights[j] * position(c.level, k[j])[d];
        const Vec3 p = position(c.input, i);
        double nearest = INFINITY;
        for (uint32_t t : star) {
            const auto m = corners(c.level, t);
            const Vec3 q =
                detail::closest_on_triangle(p, position(c.level, m[0]), position(c.level, m[1]),
                                            position(c.level, m[2]))
                    .point;
            nearest = std::min(nearest, dot(q - p, q - p));
        }
        EXPECT_LE(dot(at - p, at - p), nearest * (1 + 1e-9) + 1e-15) << "sample " << i;
        ++on_star;
    }
    EXPECT_GT(on_star, 60u);
}

TEST(LevelRelocation, LockedVerticesStay) {
    LevelCase c(bump);
    c.locked.assign(c.input.vertex_count(), 0);
    c.locked[c.source[kMiddle]] = 1;
    c.relocate();
    EXPECT_EQ(c.source[kMiddle], grid_index(kFine, kFine / 2, kFine / 2));
    EXPECT_TRUE(c.vertices_are_the_inputs());
}

// A linear field on a plane: the level holds it exactly, so no move can lower the error.
TEST(LevelRelocation, DataTheLevelHoldsStays) {
    LevelCase c([](const Vec3& p) { return 0.3 * p[0] - 0.7 * p[1]; });
    const std::vector<float> positions = c.level.positions;
    EXPECT_FALSE(c.relocate());
    EXPECT_EQ(c.level.positions, positions);
}

// Data that waves across the square, fitted by many moves: each keeps every triangle of the
// plane facing up, none of them a sliver.
TEST(LevelRelocation, NeverFoldsTheLevel) {
    LevelCase c(waves);
    EXPECT_TRUE(c.relocate());
    EXPECT_TRUE(c.vertices_are_the_inputs());
    for (uint32_t t = 0; t < c.level.triangle_count(); ++t) {
        const auto k = corners(c.level, t);
        const Vec3 a = position(c.level, k[0]);
        const Vec3 n = cross(position(c.level, k[1]) - a, position(c.level, k[2]) - a);
        EXPECT_GT(n[2], 1e-6 / (kCoarse * kCoarse)) << "triangle " << t;
    }
}

TEST(LevelRelocation, SameBytesOnAnyThreadCount) {
    // As in test_determinism.cpp: as many threads as asked for, also on a two-core machine.
    oneapi::tbb::global_control allow(oneapi::tbb::global_control::max_allowed_parallelism, 17);
    LevelCase one(waves), settled(waves);
    one.relocate(1);
    settled.settle(1);
    for (int threads : {2, 3, 4}) {
        LevelCase many(waves), many_settled(waves);
        many.relocate(threads);
        many_settled.settle(threads);
        EXPECT_TRUE(same_bytes(one.level, many.level)) << threads << " threads";
        EXPECT_EQ(one.source, many.source) << threads << " threads";
        EXPECT_TRUE(same_bytes(settled.level, many_settled.level)) << threads << " threads";
        EXPECT_EQ(settled.source, many_settled.source) << threads << " threads";
    }
}

// Moves and flips in turns: a flip changes the stars the moves searched and a move the quads the
// flips tried, so one round of each leaves moves that gain (the premise); settled, the level has
// neither a move nor a flip left that lowers the samples' error, and fits the data better.
TEST(LevelRelocation, SettledLevelsHaveNoMoveOrFlipLeftThatGains) {
    LevelCase once(waves);
    once.relocate();
    ASSERT_TRUE(once.flip());
    LevelCase settled(waves);
    settled.settle();
    EXPECT_TRUE(settled.vertices_are_the_inputs());
    EXPECT_LT(two_way_data_rms(settled.input, settled.level),
              two_way_data_rms(once.input, once.level));
    EXPECT_TRUE(once.relocate()); // the premise: one round of each is not the end
    EXPECT_FALSE(settled.relocate());
    EXPECT_FALSE(settled.flip());
}

// Through the library: where the data weighs nothing (alpha = 1, or a surface with no data), a
// vertex removal run's levels still move their vertices to other input vertices, where the
// surface fits better: hills and dales that the recorded level's vertices miss. Every vertex stays
// an input vertex, the topology stays, the distances fall.
TEST(LevelRelocation, InTheLevelsOfARunTheSurfaceDecidesWhereTheDataWeighsNothing) {
    constexpr int n = 40;
    Surface hills = grid(n, n);
    for (size_t v = 0; v < hills.vertex_count(); ++v) {
        const Vec3 p = position(hills, v);
        hills.positions[3 * v + 2] = float(0.08 * std::sin(9 * p[0]) * std::cos(7 * p[1]));
    }
    Surface with_data = hills;
    add_field(with_data, "f", 1, [](const Vec3& p) { return std::vector<double>{p[0] * p[1]}; });
    for (const auto& [in, alpha] : {std::pair{hills, 0.5}, std::pair{with_data, 1.0}}) {
        Options o;
        o.strategy = Strategy::VertexRemoval;
        o.alpha = alpha;
        o.keep_fraction = 0;
        o.threads = 1;
        const ProgressiveRecord record = ProgressiveRecord::build(in, o);
        const size_t operations = record.operations_for(in.triangle_count() / 10);
        const Surface level = record.after(operations),
                      recorded = record.after_as_recorded(operations);
        SCOPED_TRACE(in.fields.empty() ? "no data, alpha 0.5" : "data, alpha 1");
        ASSERT_EQ(level.vertex_count(), recorded.vertex_count());
        EXPECT_NE(level.positions, recorded.positions);
        for (size_t v = 0; v < level.vertex_count(); ++v) {
            const Vec3 p = position(level, v);
            const uint32_t i =
                grid_index(n, int(std::lround(p[0] * n)), int(std::lround(p[1] * n)));
            ASSERT_EQ(position(in, i), p) << "level vertex " << v;
        }
        EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(level)));
        EXPECT_LT(two_way_distance_rms(in, level), 0.95 * two_way_distance_rms(in, recorded));
    }
}

} // namespace
} // namespace ddsimp::test::level_relocation
