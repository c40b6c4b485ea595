// ProgressiveRecord: every level extracted from one run equals a direct run to that level, byte
// for byte; after(0) is the repaired input; the triangle counts go down.
#include "test_surfaces.h"

#include <optional>
#include <thread>

namespace ddsimp::test {
namespace {

class Progressive : public ::testing::TestWithParam<Config> {
protected:
    // keep_fraction 0: run until nothing more is removable (the record's usual set-up)
    Options record_options() const {
        Options o = options_for(GetParam());
        o.keep_fraction = 0.0;
        return o;
    }
};

INSTANTIATE_TEST_SUITE_P(All, Progressive, ::testing::ValuesIn(all_configs()), config_name);

Surface sphere_input() {
    return with_test_fields(icosphere(3));
} // 1280 triangles
Surface grid_input() {
    Surface s = with_test_fields(grid(24, 24)); // 1152 triangles
    add_field(s, "step", 1,
              [](const Vec3& p) { return std::vector<double>{p[0] < 0.5 ? 0.0 : 1.0}; });
    return s;
}

// level(n) == simplify(target_triangles = n) for several n, down to the coarsest recorded level
// (below it the direct run would stop for another reason than its target).
TEST_P(Progressive, LevelEqualsADirectRun) {
    for (const Surface& in : {sphere_input(), grid_input()}) {
        ProgressiveRecord rec = ProgressiveRecord::build(in, record_options());
        ASSERT_GT(rec.operations(), 0u);
        const size_t n_in = in.triangle_count();
        const size_t coarsest = rec.triangles_after(rec.operations() - 1);
        std::vector<size_t> levels{n_in,     n_in - 1,  n_in - 2,     n_in * 3 / 4, n_in / 2,
                                   n_in / 4, n_in / 10, coarsest + 3, coarsest};
        for (size_t n : levels) {
            if (n < coarsest) continue;
            Options o = record_options();
            o.target_triangles = n;
            Result direct = simplify(in, o);
            EXPECT_EQ(direct.stop, StopReason::TargetReached) << n;
            EXPECT_TRUE(same_bytes(rec.level(n), direct.surface)) << "level " << n;
            EXPECT_EQ(direct.operations, rec.operations_for(n)) << n;
        }
    }
}

// Past the last resorts as well: a flat 24-gon fan with a line tolerance of 10 degrees (its rim
// turns by 15) loses its centre and then, once the tolerance widens, rim vertices; each level,
// before and after the widening, equals a direct run to it.
TEST_P(Progressive, LevelPastAWidenedLineEqualsADirectRun) {
    const Surface in = with_test_fields(fan(24));
    Options o = record_options();
    o.line_tolerance = 10.0;
    ProgressiveRecord rec = ProgressiveRecord::build(in, o);
    ASSERT_GT(rec.operations(), 0u);
    const size_t coarsest = rec.triangles_after(rec.operations() - 1);
    ASSERT_LT(coarsest, 22u); // past the centre's removal: the rim thinned out
    for (size_t n = 22; n >= coarsest; --n) {
        o.target_triangles = n;
        const Result direct = simplify(in, o);
        EXPECT_EQ(direct.stop, StopReason::TargetReached) << n;
        EXPECT_TRUE(same_bytes(rec.level(n), direct.surface)) << "level " << n;
        EXPECT_EQ(direct.operations, rec.operations_for(n)) << n;
    }
}

// The repaired input (degenerate and duplicate triangles dropped, unused vertices gone) is
// after(0), and level(triangles_in).
TEST_P(Progressive, AfterZeroIsTheRepairedInput) {
    Surface in = grid_input();
    in.triangles.insert(in.triangles.end(),
                        {3, 3, 4, in.triangles[3], in.triangles[4], in.triangles[5]});
    add_vertex(in, 7, 7, 7);
    for (Field& f : in.fields) f.values.insert(f.values.end(), size_t(f.components), 0.5f);
    Surface repaired = in;
    validate(repaired);
    Surface expected = compact(repaired);

    ProgressiveRecord rec = ProgressiveRecord::build(in, record_options());
    EXPECT_EQ(rec.triangles_in(), expected.triangle_count());
    Surface zero = rec.after(0);
    EXPECT_EQ(zero.vertex_count(), expected.vertex_count());
    EXPECT_EQ(canonical_triangles(zero), canonical_triangles(expected));
    EXPECT_TRUE(same_bytes(rec.level(rec.triangles_in()), zero));
    EXPECT_EQ(rec.operations_for(rec.triangles_in()), 0u);
}

// The natural reading of "the repaired input": the input's vertices in their order, unused ones
// left out. (Separate from the test above so that a different but consistent numbering shows up
// as this one failure only.)
TEST_P(Progressive, AfterZeroKeepsTheInputOrder) {
    Surface in = grid_input();
    add_vertex(in, 7, 7, 7);
    for (Field& f : in.fields) f.values.insert(f.values.end(), size_t(f.components), 0.5f);
    ProgressiveRecord rec = ProgressiveRecord::build(in, record_options());
    Surface expected = in;
    validate(expected);
    EXPECT_TRUE(same_bytes(rec.after(0), compact(expected)));
}

// The level's fit reports its progress on the calling thread, fractions in [0, 1] that never go
// down, and stops at once, with nothing, when the callback says so; watched, it gives the same
// level as unwatched.
TEST_P(Progressive, TheLevelFitReportsProgressAndCanBeCancelled) {
    const Surface in = with_test_fields(grid(120, 120)); // 28,800 triangles
    Options o = record_options();
    o.threads = 4;
    const ProgressiveRecord record = ProgressiveRecord::build(in, o);
    const size_t operations = record.operations_for(in.triangle_count() / 10);
    const Surface fitted = record.after(operations);
    ASSERT_FALSE(same_bytes(fitted, record.after_as_recorded(operations)))
        << "the level is not fitted: nothing to watch";
    const std::thread::id caller = std::this_thread::get_id();
    std::vector<double> seen;
    size_t elsewhere = 0;
    const std::optional<Surface> watched = record.after(operations, [&](double f) {
        seen.push_back(f);
        elsewhere += std::this_thread::get_id() != caller;
        return true;
    });
    ASSERT_TRUE(watched.has_value());
    EXPECT_TRUE(same_bytes(*watched, fitted));
    EXPECT_GT(seen.size(), 3u);
    EXPECT_EQ(elsewhere, 0u);
    EXPECT_TRUE(progress_in_order(seen));
    size_t calls = 0;
    EXPECT_FALSE(record.after(operations, [&](double) { return ++calls < 2; }).has_value());
    EXPECT_EQ(calls, 2u) << "called again after it said stop";
}

TEST_P(Progressive, TriangleCountsGoDown) {
    Surface in = sphere_input();
    ProgressiveRecord rec = ProgressiveRecord::build(in, record_options());
    EXPECT_EQ(rec.triangles_in(), in.triangle_count());
    EXPECT_EQ(rec.stop(), StopReason::NothingRemovable);
    ASSERT_GT(rec.operations(), 0u);
    EXPECT_LT(rec.triangles_after(0), rec.triangles_in());
    for (size_t i = 1; i < rec.operations(); ++i)
        EXPECT_LE(rec.triangles_after(i), rec.triangles_after(i - 1)) << i;
    // closed manifold: every operation takes exactly two triangles (see test_edge_collapse /
    // test_vertex_removal), so triangles_after(i) = 1280 - 2 (i + 1)
    for (size_t i = 0; i < rec.operations(); ++i)
        EXPECT_EQ(rec.triangles_after(i), 1280 - 2 * (i + 1)) << i;
}

// after(i + 1) has triangles_after(i) triangles and is a sound surface with the input's topology.
TEST_P(Progressive, EveryPrefixIsASoundSurface) {
    Surface in = grid_input();
    ProgressiveRecord rec = ProgressiveRecord::build(in, record_options());
    Topology t0 = analyze_topology(in);
    const size_t ops = rec.operations();
    for (size_t k : {size_t(1), size_t(2), ops / 3, ops / 2, ops - 1, ops}) {
        if (k == 0 || k > ops) continue;
        Surface s = rec.after(k);
        EXPECT_EQ(s.triangle_count(), rec.triangles_after(k - 1)) << k;
        EXPECT_TRUE(well_formed(s)) << k;
        EXPECT_TRUE(topology_kept(t0, analyze_topology(s))) << k;
        EXPECT_TRUE(fields_carried(in, s)) << k;
    }
}

// indexed_triangles(k) names, through the stable ids of vertices(), the same corners as
// after_as_recorded(k): triangle by triangle, the same positions and the same data (after(k)
// differs only in fitted data, test_data_refit.cpp). At k = 0 the ids are the input's.
TEST_P(Progressive, IndexedTrianglesUseStableVertexIds) {
    Surface in = grid_input();
    ProgressiveRecord rec = ProgressiveRecord::build(in, record_options());
    const Surface& all = rec.vertices();
    EXPECT_EQ(rec.indexed_triangles(0), in.triangles);
    const size_t ops = rec.operations();
    for (size_t k : {size_t(0), size_t(1), ops / 2, ops}) {
        const std::vector<uint32_t> ids = rec.indexed_triangles(k);
        const Surface level = rec.after_as_recorded(k);
        ASSERT_EQ(ids.size(), level.triangles.size()) << k;
        for (size_t c = 0; c < ids.size(); ++c) {
            ASSERT_LT(ids[c], all.vertex_count());
            for (int d = 0; d < 3; ++d)
                EXPECT_EQ(all.positions[3 * ids[c] + d],
                          level.positions[3 * level.triangles[c] + d]);
            for (size_t f = 0; f < all.fields.size(); ++f) {
                const size_t nc = size_t(all.fields[f].components);
                for (size_t j = 0; j < nc; ++j)
                    EXPECT_EQ(all.fields[f].values[nc * ids[c] + j],
                              level.fields[f].values[nc * level.triangles[c] + j]);
            }
        }
    }
}

// operations_for(n) is the first k with triangles_after(k - 1) <= n; level(n) is after(k); below
// the coarsest recorded level, level() gives the coarsest.
TEST_P(Progressive, OperationsForAndLevel) {
    Surface in = grid_input();
    ProgressiveRecord rec = ProgressiveRecord::build(in, record_options());
    const size_t ops = rec.operations();
    const size_t coarsest = rec.triangles_after(ops - 1);
    for (size_t n : {size_t(1100), size_t(801), size_t(800), size_t(333), size_t(50), coarsest}) {
        if (n < coarsest) continue;
        size_t k = rec.operations_for(n);
        ASSERT_GE(k, 1u) << n;
        ASSERT_LE(k, ops) << n;
        EXPECT_LE(rec.triangles_after(k - 1), n) << n;
        if (k >= 2) {
            EXPECT_GT(rec.triangles_after(k - 2), n) << n;
        }
        EXPECT_TRUE(same_bytes(rec.level(n), rec.after(k))) << n;
    }
    EXPECT_TRUE(same_bytes(rec.level(0), rec.after(ops)));
    EXPECT_EQ(rec.level(0).triangle_count(), coarsest);
    EXPECT_EQ(rec.operations_for(0), ops);
}

// A record built with a target stops there, and its levels are still direct runs.
TEST_P(Progressive, RecordWithATarget) {
    Surface in = sphere_input();
    Options o = record_options();
    o.keep_fraction = 0.25; // 320
    ProgressiveRecord rec = ProgressiveRecord::build(in, o);
    EXPECT_EQ(rec.stop(), StopReason::TargetReached);
    EXPECT_LE(rec.triangles_after(rec.operations() - 1), 320u);
    Options d = o;
    d.target_triangles = 640;
    EXPECT_TRUE(same_bytes(rec.level(640), simplify(in, d).surface));
}

} // namespace
} // namespace ddsimp::test
