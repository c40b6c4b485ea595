// Options::locked: a locked vertex stays in the output with the same position and the same data
// (bit for bit), whatever the strategy; so do the vertices of the input's folds; a wrong-length
// lock list is rejected.
#include "test_surfaces.h"

#include <cstring>

namespace ddsimp::test {
namespace {

class LockedVertices : public ::testing::TestWithParam<Config> {
protected:
    Options options() const { return options_for(GetParam()); }
};

INSTANTIATE_TEST_SUITE_P(All, LockedVertices, ::testing::ValuesIn(all_configs()), config_name);

// The vertex's position and every field value, as raw floats.
std::vector<float> vertex_record(const Surface& s, size_t v) {
    std::vector<float> r(s.positions.begin() + 3 * v, s.positions.begin() + 3 * v + 3);
    for (const Field& f : s.fields)
        r.insert(r.end(), f.values.begin() + v * size_t(f.components),
                 f.values.begin() + (v + 1) * size_t(f.components));
    return r;
}

// How many vertices of `s` have exactly (bit for bit) this position and data.
size_t count_exact(const Surface& s, const std::vector<float>& record) {
    size_t n = 0;
    for (size_t v = 0; v < s.vertex_count(); ++v) {
        const std::vector<float> r = vertex_record(s, v);
        n += r.size() == record.size() &&
             std::memcmp(r.data(), record.data(), r.size() * sizeof(float)) == 0;
    }
    return n;
}

// Each locked vertex of `in` appears exactly once in `out` with its position and data.
::testing::AssertionResult locked_survive(const Surface& in, const std::vector<uint8_t>& locked,
                                          const Surface& out) {
    for (size_t v = 0; v < in.vertex_count(); ++v) {
        if (!locked[v]) continue;
        const size_t n = count_exact(out, vertex_record(in, v));
        if (n != 1)
            return ::testing::AssertionFailure()
                   << "locked vertex " << v << " appears " << n << " times in the output";
    }
    return ::testing::AssertionSuccess();
}

// 40 x 40 grid: the column i = 20 (41 vertices, a cut through the middle, like a border between
// two pieces of a larger surface) and the interior vertex (5, 30) locked.
std::vector<uint8_t> column_and_one(int n) {
    std::vector<uint8_t> locked(size_t((n + 1) * (n + 1)), 0);
    for (int j = 0; j <= n; ++j) locked[grid_index(n, n / 2, j)] = 1;
    locked[grid_index(n, 5, 30)] = 1;
    return locked;
}

TEST_P(LockedVertices, SurviveWithTheirPositionAndData) {
    const Surface in = with_test_fields(grid(40, 40));
    Options o = options();
    o.keep_fraction = 0.1; // 320 of 3200 triangles
    o.locked = column_and_one(40);
    const Result r = simplify(in, o);
    EXPECT_TRUE(r.target_reached) << describe(r.stop);
    EXPECT_LE(r.triangles_out, 320u);
    EXPECT_TRUE(locked_survive(in, o.locked, r.surface));
    EXPECT_TRUE(well_formed(r.surface));
    EXPECT_TRUE(fields_carried(in, r.surface));
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(r.surface)));
}

// Simplified as far as it goes: the locks hold even when every free vertex around them has been
// collapsed into them or removed (a collapse into a locked end must pass the lock on).
TEST_P(LockedVertices, HoldWhenEverythingElseIsGone) {
    const Surface in = with_test_fields(grid(40, 40));
    Options o = options();
    o.keep_fraction = 0;
    o.locked = column_and_one(40);
    const Result r = simplify(in, o);
    EXPECT_TRUE(locked_survive(in, o.locked, r.surface));
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(r.surface)));
    // Without locks the same run goes further: the locks are what stopped it.
    Options free = options();
    free.keep_fraction = 0;
    EXPECT_LT(simplify(in, free).triangles_out, r.triangles_out);
}

// A vertex in the middle of a straight boundary edge would normally go (a Line vertex); locked,
// it stays. Grid 10 x 10: boundary vertex (5, 0) in the middle of the bottom edge.
TEST_P(LockedVertices, StraightBoundaryVertexStays) {
    const Surface in = with_test_fields(grid(10, 10));
    Options o = options();
    o.keep_fraction = 0;
    o.locked.assign(in.vertex_count(), 0);
    o.locked[grid_index(10, 5, 0)] = 1;
    const Result r = simplify(in, o);
    EXPECT_TRUE(locked_survive(in, o.locked, r.surface));
    // Unlocked, no vertex at (0.5, 0, 0) is left.
    Options free = options();
    free.keep_fraction = 0;
    EXPECT_EQ(count_exact(simplify(in, free).surface, vertex_record(in, grid_index(10, 5, 0))), 0u);
}

// Where the input folds back over itself (neighbouring triangles facing opposite ways), the
// fold's vertices are locked without being asked. Grid 10 x 10 in z = 0 with vertex (5, 5)
// moved from x = 0.5 to `x`: beyond the line (6,5)-(6,6) at x = 0.6 two of its triangles face
// down, folded over their neighbours in the same plane.
Surface grid_with_vertex_moved_to(double x) {
    Surface s = with_test_fields(grid(10, 10));
    s.positions[3 * grid_index(10, 5, 5)] = float(x);
    return s;
}

TEST_P(LockedVertices, FoldOfTheInputStays) {
    Options o = options();
    o.keep_fraction = 0;
    const Surface folded = grid_with_vertex_moved_to(0.65);
    ASSERT_LT(triangle_normal(folded, 2 * (5 * 10 + 5))[2], 0); // cell (5, 5)'s first: folded
    const Result r = simplify(folded, o);
    EXPECT_EQ(count_exact(r.surface, vertex_record(folded, grid_index(10, 5, 5))), 1u);
    EXPECT_TRUE(topology_kept(analyze_topology(folded), analyze_topology(r.surface)));
    // Moved less far, without a fold, the same vertex goes.
    const Surface flat = grid_with_vertex_moved_to(0.55);
    EXPECT_EQ(count_exact(simplify(flat, o).surface, vertex_record(flat, grid_index(10, 5, 5))),
              0u);
}

// Every vertex locked: nothing can be removed or moved.
TEST_P(LockedVertices, AllLockedLeavesTheSurfaceAsItIs) {
    const Surface in = with_test_fields(icosphere(2));
    Options o = options();
    o.keep_fraction = 0.1;
    o.locked.assign(in.vertex_count(), 1);
    const Result r = simplify(in, o);
    EXPECT_EQ(r.stop, StopReason::NothingRemovable) << describe(r.stop);
    EXPECT_EQ(r.triangles_out, in.triangle_count());
    EXPECT_EQ(canonical_triangles(r.surface), canonical_triangles(in));
}

TEST(LockedVerticesOption, WrongLengthIsRejected) {
    const Surface in = square(); // 4 vertices
    Options o;
    o.locked.assign(3, 1);
    try {
        simplify(in, o);
        FAIL() << "a lock list of 3 entries for 4 vertices was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("locked has 3 entries"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("4 vertices"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace ddsimp::test
