// Progressive streaming: a base level plus refinements, applied on the receiving side, gives
// every finer level of the record: the same triangles over the same vertices and data.
#include "ddsimp/protocol/refinement.h"

#include "mesh_comparison.h"
#include "test_surfaces.h"

namespace ddsimp::protocol {
namespace {

using test::triangles_by_content;

class Refinements : public ::testing::TestWithParam<Strategy> {};
INSTANTIATE_TEST_SUITE_P(Strategies, Refinements,
                         ::testing::Values(Strategy::EdgeCollapse, Strategy::VertexRemoval),
                         [](const auto& info) {
                             return info.param == Strategy::EdgeCollapse ? "Edge" : "Vertex";
                         });

TEST_P(Refinements, BaseThenRefinementsGiveEveryLevel) {
    const Surface in = test::with_test_fields(test::icosphere(3)); // 1280 triangles
    Options o;
    o.strategy = GetParam();
    o.keep_fraction = 0;
    o.alpha = 0.5;
    const ProgressiveRecord rec = ProgressiveRecord::build(in, o);
    const std::vector<size_t> levels{100, 320, 640, 1280}; // coarsest first

    RefinementStream stream(rec.vertices());
    const size_t ops0 = rec.operations_for(levels[0]);
    SlotMesh mesh(stream.base(rec.indexed_triangles(ops0)));
    EXPECT_EQ(triangles_by_content(mesh.live()), triangles_by_content(rec.after_as_recorded(ops0)));
    for (size_t i = 1; i < levels.size(); ++i) {
        const size_t ops = rec.operations_for(levels[i]);
        const Refinement r = stream.refine(rec.indexed_triangles(ops));
        // Through the wire format, as a client receives it.
        const EncodedBlob blob = encode_refinement(r, v1::MESHOPT);
        mesh.apply(decode_refinement(blob.bytes, blob.layout));
        const Surface expected = rec.after_as_recorded(ops);
        EXPECT_EQ(mesh.live_triangles(), expected.triangle_count()) << levels[i];
        EXPECT_EQ(triangles_by_content(mesh.live()), triangles_by_content(expected)) << levels[i];
    }
    // The finest level is the input itself.
    EXPECT_EQ(triangles_by_content(mesh.live()), triangles_by_content(in));
}

// A refinement sends only what changed: going from a level to itself writes nothing.
TEST(Refinement, SameLevelTwiceWritesNothing) {
    const Surface in = test::with_test_fields(test::icosphere(2));
    Options o;
    o.keep_fraction = 0;
    const ProgressiveRecord rec = ProgressiveRecord::build(in, o);
    const size_t ops = rec.operations_for(100);
    RefinementStream stream(rec.vertices());
    stream.base(rec.indexed_triangles(ops));
    const Refinement r = stream.refine(rec.indexed_triangles(ops));
    EXPECT_TRUE(r.writes.empty());
    EXPECT_EQ(r.new_vertices.vertex_count(), 0u);
}

TEST(Refinement, BadWritesLeaveTheMeshUnchanged) {
    SlotMesh mesh(test::single_triangle());
    Refinement beyond;
    beyond.writes = {2, 0, 1, 2};
    EXPECT_THROW(mesh.apply(beyond), BlobError);
    Refinement unknown_vertex;
    unknown_vertex.writes = {1, 0, 1, 3};
    EXPECT_THROW(mesh.apply(unknown_vertex), BlobError);
    EXPECT_EQ(mesh.slots().triangle_count(), 1u);
    EXPECT_EQ(mesh.slots().vertex_count(), 3u);

    Refinement kill;
    kill.writes = {0, kDeadSlot, kDeadSlot, kDeadSlot};
    mesh.apply(kill);
    EXPECT_EQ(mesh.live_triangles(), 0u);
    EXPECT_EQ(mesh.slots().triangle_count(), 1u); // the slot stays, drawn as degenerate
}

} // namespace
} // namespace ddsimp::protocol
