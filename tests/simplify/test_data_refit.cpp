// The data of an edge-collapse level fitted to the input over the whole level (data_refit.h):
// it lowers the two-way data error below the collapses' own values, stays within the data's
// range, and leaves the input's own and locked vertices' data as they were; the made points move
// onto the input.
#include "data_error.h"
#include "working_mesh.h"

#include <algorithm>

namespace ddsimp::test {
namespace {

Options collapse_to(double keep) {
    Options o;
    o.strategy = Strategy::EdgeCollapse;
    o.alpha = 0.0;
    o.keep_fraction = keep;
    o.threads = 1;
    return o;
}

TEST(DataRefit, LowersTheTwoWayDataError) {
    const Surface in = wavy_sphere();
    for (double keep : {0.2, 0.05}) {
        const ProgressiveRecord record = ProgressiveRecord::build(in, collapse_to(0));
        const size_t operations = record.operations_for(size_t(keep * in.triangle_count()));
        const double fitted = two_way_data_rms(in, record.after(operations));
        const double collapsed = two_way_data_rms(in, record.after_as_recorded(operations));
        EXPECT_LT(fitted, 0.97 * collapsed) << "keep " << keep;
    }
}

// The made points move to where their samples lie, where that lowers their stars' joint error:
// the level's distance to the input falls well below the record's, its data error too; the
// input's own vertices stay where they are, and the topology stays.
TEST(DataRefit, MovesTheMadePointsOntoTheInput) {
    const Surface in = wavy_sphere();
    for (double alpha : {0.0, 0.5}) {
        Options o = collapse_to(0);
        o.alpha = alpha;
        const ProgressiveRecord record = ProgressiveRecord::build(in, o);
        const size_t operations = record.operations_for(in.triangle_count() / 10);
        const Surface fitted = record.after(operations),
                      recorded = record.after_as_recorded(operations);
        SCOPED_TRACE(alpha);
        ASSERT_EQ(fitted.vertex_count(), recorded.vertex_count());
        EXPECT_LT(two_way_distance_rms(in, fitted), 0.9 * two_way_distance_rms(in, recorded));
        EXPECT_LT(two_way_data_rms(in, fitted), two_way_data_rms(in, recorded));
        EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(fitted)));
        const std::vector<uint32_t> ids = record.indexed_triangles(operations);
        for (size_t c = 0; c < ids.size(); ++c) {
            if (ids[c] < in.vertex_count()) {
                EXPECT_EQ(position(fitted, recorded.triangles[c]), position(in, ids[c]));
            }
        }
    }
}

TEST(DataRefit, StaysWithinTheDataRange) {
    const Surface in = wavy_sphere();
    const auto [lo, hi] =
        std::minmax_element(in.fields[0].values.begin(), in.fields[0].values.end());
    const Result r = simplify(in, collapse_to(0.05));
    for (float x : r.surface.fields[0].values) {
        EXPECT_GE(x, *lo);
        EXPECT_LE(x, *hi);
    }
}

// Every output vertex that sits where a locked input vertex does has that vertex's data; so does
// every input vertex that is still in a level.
TEST(DataRefit, KeepsTheInputsAndTheLockedVerticesData) {
    const Surface in = wavy_sphere();
    Options o = collapse_to(0.1);
    o.locked.assign(in.vertex_count(), 0);
    for (size_t v = 0; v < in.vertex_count(); v += 7) o.locked[v] = 1;
    const Result r = simplify(in, o);
    size_t locked_seen = 0;
    for (size_t v = 0; v < in.vertex_count(); ++v) {
        if (!o.locked[v]) continue;
        for (size_t w = 0; w < r.surface.vertex_count(); ++w) {
            if (position(r.surface, w)[0] != position(in, v)[0] ||
                position(r.surface, w)[1] != position(in, v)[1] ||
                position(r.surface, w)[2] != position(in, v)[2])
                continue;
            EXPECT_EQ(r.surface.fields[0].values[w], in.fields[0].values[v]) << "vertex " << v;
            ++locked_seen;
        }
    }
    EXPECT_GT(locked_seen, in.vertex_count() / 8);

    // Through the record's ids: every input vertex still in the level has its own data.
    o.keep_fraction = 0;
    o.locked.clear();
    const ProgressiveRecord record = ProgressiveRecord::build(in, o);
    const size_t operations = record.operations_for(in.triangle_count() / 2); // some stay
    // after_as_recorded() has after()'s vertices, in the same order, and its corners are those
    // of indexed_triangles() (after() may have flipped edges).
    const std::vector<uint32_t> ids = record.indexed_triangles(operations);
    const std::vector<uint32_t> corners = record.after_as_recorded(operations).triangles;
    const Surface level = record.after(operations);
    size_t input_corners = 0;
    for (size_t c = 0; c < ids.size(); ++c)
        if (ids[c] < in.vertex_count()) {
            EXPECT_EQ(level.fields[0].values[corners[c]], in.fields[0].values[ids[c]]);
            ++input_corners;
        }
    EXPECT_GT(input_corners, 0u);
}

// Interpolated data is the paper's rule along the edge and is not fitted: a level's data is the
// record's, vertex for vertex.
TEST(DataRefit, LeavesInterpolatedDataAlone) {
    const Surface in = wavy_sphere();
    Options o = collapse_to(0);
    o.data_placement = DataPlacement::Interpolated;
    const ProgressiveRecord record = ProgressiveRecord::build(in, o);
    const size_t operations = record.operations_for(in.triangle_count() / 10);
    EXPECT_TRUE(same_bytes(record.after(operations), record.after_as_recorded(operations)));
}

} // namespace
} // namespace ddsimp::test
