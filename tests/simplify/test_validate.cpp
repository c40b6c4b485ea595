// validate(): every rejection of ddsimp.h throws InputError naming what and where; every repair
// drops what it should, keeps the first copy in order, and reports its counts.
//
// Decision (documented here because the header decides it): a triangle with the same three
// vertices in reversed orientation, e.g. (0,2,1) after (0,1,2), IS a duplicate — the header says
// "same three vertices as an earlier triangle", not "same oriented triangle". It is dropped.
#include "test_surfaces.h"

#include <limits>

namespace ddsimp::test {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// A 4x4 grid: 25 vertices (0..24), 32 triangles (0..31), with a scalar "pressure" and a 3-vector
// "velocity" (both finite).
Surface sample() {
    return with_test_fields(grid(4, 4));
}

// validate(s) throws InputError whose message contains every word (case-insensitive) and every
// number (as a whole number).
::testing::AssertionResult rejected(Surface s, const std::vector<std::string>& words,
                                    const std::vector<long long>& numbers) {
    try {
        validate(s);
    } catch (const InputError& e) {
        std::string msg = e.what();
        for (const std::string& w : words)
            if (!mentions(msg, w))
                return ::testing::AssertionFailure()
                       << "message \"" << msg << "\" does not mention " << w;
        for (long long n : numbers)
            if (!mentions_number(msg, n))
                return ::testing::AssertionFailure()
                       << "message \"" << msg << "\" does not name " << n;
        return ::testing::AssertionSuccess() << msg;
    } catch (const std::exception& e) {
        return ::testing::AssertionFailure()
               << "threw something other than InputError: " << e.what();
    }
    return ::testing::AssertionFailure() << "accepted";
}

// --- accepted unchanged ------------------------------------------------------------------------

TEST(Validate, AcceptsAValidSurfaceUnchanged) {
    Surface s = sample();
    const Surface original = s;
    RepairReport r = validate(s);
    EXPECT_EQ(r.degenerate_triangles_dropped, 0u);
    EXPECT_EQ(r.duplicate_triangles_dropped, 0u);
    EXPECT_EQ(r.unused_vertices, 0u);
    EXPECT_EQ(r.triangles_flipped, 0u);
    EXPECT_TRUE(same_bytes(s, original));
}

// A triangle that shares an edge in opposite direction with another is normal; one that shares
// two of three vertices is not a duplicate.
TEST(Validate, NeighbouringTrianglesAreNotDuplicates) {
    Surface s = square();
    RepairReport r = validate(s);
    EXPECT_EQ(r.duplicate_triangles_dropped, 0u);
    EXPECT_EQ(s.triangle_count(), 2u);
}

// --- rejections ----------------------------------------------------------------------------------

TEST(Validate, RejectsAnEmptySurface) {
    EXPECT_TRUE(rejected(Surface{}, {}, {}));
}

TEST(Validate, RejectsVerticesWithoutTriangles) {
    Surface s = square();
    s.triangles.clear();
    EXPECT_TRUE(rejected(s, {"triangle"}, {}));
}

TEST(Validate, RejectsPositionsNotAMultipleOf3) {
    Surface s = square();
    s.positions.push_back(0.5f); // 13 floats
    EXPECT_TRUE(rejected(s, {"position"}, {}));
}

TEST(Validate, RejectsTriangleIndicesNotAMultipleOf3) {
    Surface s = square();
    s.triangles.push_back(1); // 7 indices
    EXPECT_TRUE(rejected(s, {"triangle"}, {}));
}

TEST(Validate, RejectsANaNCoordinateNamingTheVertex) {
    Surface s = sample();
    s.positions[3 * 17 + 1] = kNaN; // y of vertex 17
    EXPECT_TRUE(rejected(s, {}, {17}));
}

TEST(Validate, RejectsAnInfiniteCoordinateNamingTheVertex) {
    Surface s = sample();
    s.positions[3 * 9 + 2] = kInf;
    EXPECT_TRUE(rejected(s, {}, {9}));
    Surface t = sample();
    t.positions[3 * 13] = -kInf;
    EXPECT_TRUE(rejected(t, {}, {13}));
}

// An unused vertex with a NaN coordinate is still a non-finite coordinate (the header does not
// restrict the check to used vertices).
TEST(Validate, RejectsANaNCoordinateOfAnUnusedVertex) {
    Surface s = square();
    add_vertex(s, 0, 0, 0);
    s.positions[3 * 4] = kNaN;
    EXPECT_TRUE(rejected(s, {}, {4}));
}

TEST(Validate, RejectsAnIndexOutOfRangeNamingTriangleAndIndex) {
    Surface s = sample();
    s.triangles[3 * 13 + 2] = 999; // triangle 13 refers to vertex 999 of 25
    EXPECT_TRUE(rejected(s, {}, {13, 999}));
}

TEST(Validate, RejectsTheFirstIndexPastTheEnd) {
    Surface s = sample();
    s.triangles[3 * 6] = 25; // one past the last vertex (24)
    EXPECT_TRUE(rejected(s, {}, {6}));
}

TEST(Validate, RejectsTheLargestIndex) {
    Surface s = sample();
    s.triangles[3 * 30 + 1] = 0xFFFFFFFFu;
    EXPECT_TRUE(rejected(s, {}, {30}));
}

TEST(Validate, RejectsAScalarFieldOfTheWrongLength) {
    Surface s = sample();
    s.fields[0].name = "pressure";
    s.fields[0].values.pop_back(); // 24 values for 25 vertices
    EXPECT_TRUE(rejected(s, {"pressure"}, {}));
    Surface t = sample();
    t.fields[0].values.push_back(1.0f); // 26
    EXPECT_TRUE(rejected(t, {"pressure"}, {}));
}

TEST(Validate, RejectsAVectorFieldOfTheWrongLength) {
    Surface s = sample();
    s.fields[1].values.pop_back(); // 74 values for 25 x 3
    EXPECT_TRUE(rejected(s, {"velocity"}, {}));
    // 75 values, but declared as 2 components: 75 is not 25 x 2
    Surface t = sample();
    t.fields[1].components = 2;
    EXPECT_TRUE(rejected(t, {"velocity"}, {}));
}

TEST(Validate, RejectsComponentsBelowOne) {
    Surface s = sample();
    s.fields[1].components = 0;
    s.fields[1].values.clear(); // 0 x 25 = 0 values: the length alone would look right
    EXPECT_TRUE(rejected(s, {"velocity"}, {}));
    Surface t = sample();
    t.fields[1].components = -3;
    EXPECT_TRUE(rejected(t, {"velocity"}, {}));
}

TEST(Validate, RejectsAnEmptyFieldName) {
    Surface s = sample();
    s.fields[1].name = "";
    EXPECT_TRUE(rejected(s, {"field"}, {}));
}

TEST(Validate, RejectsARepeatedFieldName) {
    Surface s = sample();
    s.fields[1] = s.fields[0]; // two "pressure"
    EXPECT_TRUE(rejected(s, {"pressure"}, {}));
}

TEST(Validate, RejectsANonFiniteScalarValueNamingFieldAndVertex) {
    Surface s = sample();
    s.fields[0].values[11] = kNaN;
    EXPECT_TRUE(rejected(s, {"pressure"}, {11}));
}

TEST(Validate, RejectsANonFiniteVectorValueNamingFieldAndVertex) {
    Surface s = sample();
    s.fields[1].values[3 * 7 + 2] = -kInf; // vertex 7, component 2
    EXPECT_TRUE(rejected(s, {"velocity"}, {7}));
}

// After dropping its degenerate triangles a surface with no proper triangle has nothing left;
// the header rejects "no triangles". A silently empty surface would be a wrong answer.
TEST(Validate, RejectsASurfaceWhoseTrianglesAreAllDegenerate) {
    Surface s = square();
    s.triangles = {0, 0, 1, 2, 3, 3};
    EXPECT_TRUE(rejected(s, {}, {}));
}

// simplify validates a copy first: the same rejections.
TEST(Validate, SimplifyRejectsInvalidInput) {
    Surface s = sample();
    s.positions[3 * 17 + 1] = kNaN;
    EXPECT_THROW(simplify(s, Options{}), InputError);
    Surface t = sample();
    t.triangles[3 * 13 + 2] = 999;
    EXPECT_THROW(simplify(t, Options{}), InputError);
    EXPECT_THROW(simplify(Surface{}, Options{}), InputError);
    EXPECT_THROW(ProgressiveRecord::build(t, Options{}), InputError);
}

// --- repairs -------------------------------------------------------------------------------------

TEST(Validate, DropsDegenerateTriangles) {
    Surface s = square();
    // (0,1,2) (1,1,3) (0,2,3) (2,2,2): two degenerate ones
    s.triangles = {0, 1, 2, 1, 1, 3, 0, 2, 3, 2, 2, 2};
    RepairReport r = validate(s);
    EXPECT_EQ(r.degenerate_triangles_dropped, 2u);
    EXPECT_EQ(r.duplicate_triangles_dropped, 0u);
    EXPECT_EQ(r.unused_vertices, 0u);
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST(Validate, DropsAnExactDuplicateKeepingTheFirst) {
    Surface s = square();
    s.triangles = {0, 1, 2, 0, 2, 3, 0, 1, 2};
    RepairReport r = validate(s);
    EXPECT_EQ(r.duplicate_triangles_dropped, 1u);
    EXPECT_EQ(r.degenerate_triangles_dropped, 0u);
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST(Validate, DropsARotatedDuplicate) {
    Surface s = square();
    s.triangles = {0, 1, 2, 1, 2, 0, 0, 2, 3, 2, 0, 1};
    RepairReport r = validate(s);
    EXPECT_EQ(r.duplicate_triangles_dropped, 2u);
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

// See the decision at the top of this file.
TEST(Validate, DropsAReversedDuplicate) {
    Surface s = square();
    s.triangles = {0, 1, 2, 0, 2, 3, 0, 2, 1, 3, 2, 0};
    RepairReport r = validate(s);
    EXPECT_EQ(r.duplicate_triangles_dropped, 2u);
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

// "the first copy is kept": as written, not canonicalised, and the others keep their order.
// (2,0,1) and (3,0,2) are rotations of the square's (0,1,2) and (0,2,3): both face +z and agree
// along their shared edge 0-2, so no orientation repair is involved.
TEST(Validate, KeepsTheFirstCopyAsWrittenAndTheOrder) {
    Surface s = square();
    s.triangles = {2, 0, 1, 3, 0, 2, 0, 1, 2, 2, 3, 0};
    RepairReport r = validate(s);
    EXPECT_EQ(r.duplicate_triangles_dropped, 2u);
    EXPECT_EQ(r.triangles_flipped, 0u);
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{2, 0, 1, 3, 0, 2}));
}

TEST(Validate, CountsDegenerateAndDuplicateTogether) {
    Surface s = grid(2, 2); // 8 triangles
    std::vector<uint32_t> orig = s.triangles;
    // append: copies of triangles 0, 3, 5 (one rotated, one reversed) and two degenerate ones
    auto tri = [&](int t, int k) { return orig[size_t(3 * t + k)]; };
    s.triangles.insert(s.triangles.end(),
                       {tri(0, 0), tri(0, 1), tri(0, 2), 4, 4, 5, tri(3, 1), tri(3, 2), tri(3, 0),
                        tri(5, 0), tri(5, 2), tri(5, 1), 7, 8, 7});
    RepairReport r = validate(s);
    EXPECT_EQ(r.degenerate_triangles_dropped, 2u);
    EXPECT_EQ(r.duplicate_triangles_dropped, 3u);
    EXPECT_EQ(s.triangles, orig);
}

// A duplicate of a degenerate triangle is counted once, as degenerate (it names a vertex twice
// and is dropped as such before any duplicate test could apply) — only the total is pinned.
TEST(Validate, RepeatedDegenerateTrianglesAreAllDropped) {
    Surface s = square();
    s.triangles = {0, 1, 2, 0, 0, 1, 0, 0, 1, 0, 2, 3};
    RepairReport r = validate(s);
    EXPECT_EQ(r.degenerate_triangles_dropped + r.duplicate_triangles_dropped, 2u);
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST(Validate, CountsUnusedVertices) {
    Surface s = square();
    add_vertex(s, 2, 2, 0);
    add_vertex(s, 3, 3, 0);
    RepairReport r = validate(s);
    EXPECT_EQ(r.unused_vertices, 2u);
}

// A vertex only a dropped triangle used is unused after the repair.
TEST(Validate, VerticesOfDroppedTrianglesBecomeUnused) {
    Surface s = square();
    uint32_t a = add_vertex(s, 2, 2, 0);
    uint32_t b = add_vertex(s, 3, 3, 0);
    add_triangle(s, a, b, a);
    RepairReport r = validate(s);
    EXPECT_EQ(r.degenerate_triangles_dropped, 1u);
    EXPECT_EQ(r.unused_vertices, 2u);
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

// The hole's centre vertex of grid_with_hole is unused.
TEST(Validate, UnusedVertexInsideAHole) {
    Surface s = grid_with_hole(6, 2, 4);
    EXPECT_EQ(validate(s).unused_vertices, 1u);
}

// Repairing keeps the fields consistent with the vertices (whatever validate does with unused
// vertices, each remaining vertex keeps its own values).
TEST(Validate, RepairKeepsEachVertexItsFieldValues) {
    Surface s = with_test_fields(grid(3, 3));
    add_vertex(s, 9, 9, 9);
    for (Field& f : s.fields)
        for (int c = 0; c < f.components; ++c) f.values.push_back(42.0f);
    s.triangles.insert(s.triangles.end(), {0, 0, 5, 0, 1, 5});
    Surface before = s;
    validate(s);
    for (const Field& f : s.fields)
        ASSERT_EQ(f.values.size(), s.vertex_count() * size_t(f.components));
    auto lookup = vertex_lookup(before);
    for (size_t v = 0; v < s.vertex_count(); ++v) {
        uint32_t w =
            lookup.at({s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]});
        for (size_t i = 0; i < s.fields.size(); ++i)
            for (int c = 0; c < s.fields[i].components; ++c)
                EXPECT_EQ(s.fields[i].values[v * s.fields[i].components + c],
                          before.fields[i].values[w * before.fields[i].components + c]);
    }
}

// Orientation: "every edge-connected component is consistently oriented like its first
// triangle". An outward icosphere with every odd triangle flipped: the 160 odd ones of 320 are
// turned back, the surface is the original one again (up to how a flip orders the corners).
TEST(Validate, FlipsTrianglesToAgreeWithTheFirst) {
    Surface original = icosphere(2);
    Surface s = flipped(original, [](size_t t) { return t % 2 == 1; });
    RepairReport r = validate(s);
    EXPECT_EQ(r.triangles_flipped, 160u);
    EXPECT_EQ(canonical_triangles(s), canonical_triangles(original));
    EXPECT_GT(signed_volume(s), 0);
}

// Only the first triangle flipped: the component follows it, so the other 319 turn and the
// sphere ends inward (negative volume).
TEST(Validate, TheFirstTriangleSetsTheOrientation) {
    Surface s = flipped(icosphere(2), [](size_t t) { return t == 0; });
    RepairReport r = validate(s);
    EXPECT_EQ(r.triangles_flipped, 319u);
    EXPECT_LT(signed_volume(s), 0);
    for (size_t t = 0; t < s.triangle_count(); ++t)
        EXPECT_LT(dot(triangle_normal(s, t), triangle_centroid(s, t)), 0) << t;
}

// Each component follows its own first triangle: two 4x4 grids (32 triangles each); the second is
// entirely flipped (consistent, facing -z) except its 6th triangle. Only that one is turned.
TEST(Validate, EachComponentFollowsItsOwnFirstTriangle) {
    Surface s = flipped(two_components(4), [](size_t t) { return t >= 32 && t != 37; });
    RepairReport r = validate(s);
    EXPECT_EQ(r.triangles_flipped, 1u);
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        if (t < 32) {
            EXPECT_GT(triangle_normal(s, t)[2], 0) << t;
        } else {
            EXPECT_LT(triangle_normal(s, t)[2], 0) << t;
        }
    }
}

// A Moebius strip cannot be oriented: validate accepts it without changing its topology.
TEST(Validate, NonOrientableSurfaceIsAccepted) {
    Surface s = moebius(12);
    Topology before = analyze_topology(s);
    validate(s);
    EXPECT_EQ(s.triangle_count(), 24u);
    Topology after = analyze_topology(s);
    EXPECT_EQ(after.euler_characteristic, before.euler_characteristic);
    EXPECT_EQ(after.boundary_loops, before.boundary_loops);
    EXPECT_EQ(after.edges, before.edges);
}

// simplify and ProgressiveRecord report the same repairs as validate.
TEST(Validate, SimplifyReportsTheRepairs) {
    Surface s = with_test_fields(grid(6, 6));
    s.triangles.insert(s.triangles.end(), {0, 0, 1, 1, 8, 0}); // degenerate, duplicate of (0,1,8)
    add_vertex(s, 5, 5, 5);                                    // unused
    for (Field& f : s.fields) f.values.insert(f.values.end(), size_t(f.components), 0.0f);
    Surface copy = s;
    RepairReport expected = validate(copy);
    EXPECT_EQ(expected.degenerate_triangles_dropped, 1u);
    EXPECT_EQ(expected.duplicate_triangles_dropped, 1u);
    EXPECT_EQ(expected.unused_vertices, 1u);
    Options o;
    o.keep_fraction = 0.5;
    Result r = simplify(s, o);
    EXPECT_EQ(r.repairs.degenerate_triangles_dropped, 1u);
    EXPECT_EQ(r.repairs.duplicate_triangles_dropped, 1u);
    EXPECT_EQ(r.repairs.unused_vertices, 1u);
    EXPECT_EQ(r.repairs.triangles_flipped, 0u);
    EXPECT_TRUE(well_formed(r.surface));
    ProgressiveRecord rec = ProgressiveRecord::build(s, o);
    EXPECT_EQ(rec.repairs().degenerate_triangles_dropped, 1u);
    EXPECT_EQ(rec.repairs().duplicate_triangles_dropped, 1u);
    EXPECT_EQ(rec.repairs().unused_vertices, 1u);
}

} // namespace
} // namespace ddsimp::test
