// Edge collapse: placement (midpoint, volume-preserving) and the data of the new point
// ("interpolated at its position along the edge, never extrapolated"; or of least error,
// within the two values it replaces).
//
// The trick used throughout: the field "velocity" of with_test_fields equals the vertex position.
// Interpolating it at parameter t along an edge (a, b) gives a + t (b - a), the point at t on
// the edge. So for the midpoint placement the carried "velocity" of every output vertex must equal
// its position.
#include "test_surfaces.h"

namespace ddsimp::test {
namespace {

// The paper's data: interpolated along the edge (what the tests of this file check).
Options edge(Placement p) {
    Options o;
    o.strategy = Strategy::EdgeCollapse;
    o.placement = p;
    o.data_placement = DataPlacement::Interpolated;
    return o;
}

// max |velocity - position| over the output's vertices.
double data_position_mismatch(const Surface& s) {
    const Field* v = s.find_field("velocity");
    if (!v || v->values.size() != 3 * s.vertex_count()) return INFINITY;
    double worst = 0;
    for (size_t i = 0; i < s.positions.size(); ++i)
        worst = std::max(worst, std::abs(double(v->values[i]) - double(s.positions[i])));
    return worst;
}

// Midpoint: t = 1/2 on every collapse (or t = 0 / 1 where an end is pinned by a boundary or
// feature line and the point stays there), so the data follows the point (to float rounding:
// the coordinates are at most 1, 1e-6 is about 8 ulps).
TEST(EdgeCollapse, MidpointDataFollowsThePoint) {
    for (const Surface& in : {with_test_fields(icosphere(3)), with_test_fields(grid(30, 30))}) {
        Options o = edge(Placement::Midpoint);
        o.keep_fraction = 0.1;
        Result r = simplify(in, o);
        ASSERT_TRUE(r.target_reached);
        EXPECT_LT(data_position_mismatch(r.surface), 1e-6);
    }
}

// Midpoints of chords of the unit sphere lie inside it: no output vertex is outside the sphere,
// and at least one new point is strictly inside (a midpoint placement really happened).
TEST(EdgeCollapse, MidpointPointsLieInsideTheSphere) {
    Options o = edge(Placement::Midpoint);
    o.keep_fraction = 0.1;
    Result r = simplify(with_test_fields(icosphere(3)), o);
    double smallest = 2;
    for (size_t v = 0; v < r.surface.vertex_count(); ++v) {
        double len = norm(position(r.surface, v));
        EXPECT_LE(len, 1.0 + 1e-6);
        smallest = std::min(smallest, len);
    }
    EXPECT_LT(smallest, 1.0 - 1e-3);
}

// On a flat surface every point of the plane keeps the (zero) volume change of a planar star: the
// volume change is linear in the new point with gradient (sum of area * normal)/3 = (0, 0, A/3),
// so the constraint is z = 0 and the nearest point to the midpoint is the midpoint itself. The
// volume-preserving placement therefore behaves like the midpoint on a flat grid.
TEST(EdgeCollapse, VolumePreservingIsTheMidpointOnAPlane) {
    Options o = edge(Placement::VolumePreserving);
    o.keep_fraction = 0.1;
    Result r = simplify(with_test_fields(grid(30, 30)), o);
    ASSERT_TRUE(r.target_reached);
    EXPECT_LT(data_position_mismatch(r.surface), 1e-6);
    for (size_t v = 0; v < r.surface.vertex_count(); ++v)
        EXPECT_NEAR(r.surface.positions[3 * v + 2], 0, 1e-6);
}

double relative_volume_change(const Surface& in, const Surface& out) {
    double before = signed_volume(in);
    return std::abs(signed_volume(out) - before) / before;
}

// Guéziec: each collapse keeps the enclosed volume, so the reduced sphere and torus enclose the
// input's volume (1e-3 covers float rounding over hundreds of collapses). Midpoint placement cuts
// chords on a convex surface and loses volume, so it does strictly worse.
TEST(EdgeCollapse, VolumePreservingKeepsTheVolume) {
    for (const Surface& in : {with_test_fields(icosphere(4)), with_test_fields(torus(48, 24))}) {
        Options o = edge(Placement::VolumePreserving);
        o.keep_fraction = 0.1;
        Result vol = simplify(in, o);
        ASSERT_TRUE(well_formed(vol.surface));
        EXPECT_TRUE(vol.target_reached);
        EXPECT_LT(relative_volume_change(in, vol.surface), 1e-3);
        o.placement = Placement::Midpoint;
        Result mid = simplify(in, o);
        EXPECT_GT(relative_volume_change(in, mid.surface), relative_volume_change(in, vol.surface));
    }
}

// The two placements are different algorithms: on a curved surface their outputs differ.
TEST(EdgeCollapse, PlacementsDifferOnACurvedSurface) {
    Surface in = with_test_fields(icosphere(3));
    Options o = edge(Placement::Midpoint);
    Result mid = simplify(in, o);
    o.placement = Placement::VolumePreserving;
    Result vol = simplify(in, o);
    EXPECT_FALSE(same_bytes(mid.surface, vol.surface));
}

// Never extrapolated: every new data value is a convex combination of two earlier ones. With
// "velocity" = position on the unit sphere, all data lies in the unit ball (the convex hull of
// the sphere's points); a parameter beyond an end of a chord of the sphere leaves the ball. Also
// holds for the volume-preserving placement, whose point is off the edge but whose data is
// interpolated at its position along it (clamped to the edge).
TEST(EdgeCollapse, DataIsNeverExtrapolated) {
    for (Placement p : {Placement::Midpoint, Placement::VolumePreserving}) {
        Options o = edge(p);
        o.keep_fraction = 0.05;
        Surface in = with_test_fields(icosphere(4));
        Result r = simplify(in, o);
        const Field* v = r.surface.find_field("velocity");
        ASSERT_NE(v, nullptr);
        for (size_t i = 0; i < r.surface.vertex_count(); ++i) {
            Vec3 d{v->values[3 * i], v->values[3 * i + 1], v->values[3 * i + 2]};
            EXPECT_LE(norm(d), 1.0 + 1e-6) << "vertex " << i;
        }
        EXPECT_TRUE(fields_carried(in, r.surface));
    }
}

// A step field (0 | 1): every carried value stays in [0, 1] exactly-ish, for both placements.
TEST(EdgeCollapse, StepDataStaysInRange) {
    Surface in = grid(30, 30);
    add_field(in, "step", 1,
              [](const Vec3& p) { return std::vector<double>{p[0] < 0.5 ? 0.0 : 1.0}; });
    add_field(in, "vec", 2, [](const Vec3& p) {
        return std::vector<double>{p[1] < 0.3 ? -5.0 : 5.0, p[0] * p[1]};
    });
    for (Placement p : {Placement::Midpoint, Placement::VolumePreserving})
        for (double alpha : {0.0, 1.0}) {
            Options o = edge(p);
            o.alpha = alpha;
            o.keep_fraction = 0.05;
            Result r = simplify(in, o);
            EXPECT_TRUE(fields_carried(in, r.surface));
            const Field* s = r.surface.find_field("step");
            ASSERT_NE(s, nullptr);
            for (float x : s->values) {
                EXPECT_GE(x, 0.0f);
                EXPECT_LE(x, 1.0f);
            }
        }
}

// Euler on a closed manifold: a collapse removes 1 vertex, 3 edges and 2 triangles.
TEST(EdgeCollapse, EachCollapseRemovesTwoTrianglesOnAClosedSurface) {
    for (Placement p : {Placement::Midpoint, Placement::VolumePreserving}) {
        Options o = edge(p);
        o.keep_fraction = 0.2;
        Result r = simplify(with_test_fields(torus(32, 16)), o);
        EXPECT_EQ(r.triangles_out + 2 * r.operations, r.triangles_in);
        EXPECT_EQ(r.surface.vertex_count() + r.operations, size_t(32 * 16));
    }
}

// A flat octagon fan: every rim vertex is a boundary corner (turn 45 degrees > 20). Reduced to
// the 6 triangles that the centre's collapse leaves, whatever collapses happen (the header's
// midpoint would move a corner, so none; a collapse of the centre onto a pinned rim vertex would
// keep it), the 8 corners stay exactly and the octagon keeps its area 8 * 1/2 sin 45 = 2 sqrt 2.
TEST(EdgeCollapse, OctagonFanKeepsItsCorners) {
    for (Placement p : {Placement::Midpoint, Placement::VolumePreserving}) {
        Options o = edge(p);
        o.target_triangles = 6;
        Surface in = with_test_fields(fan(8));
        Result r = simplify(in, o);
        EXPECT_EQ(r.stop, StopReason::TargetReached);
        EXPECT_EQ(r.triangles_out, 6u);
        for (size_t v = 1; v <= 8; ++v) EXPECT_TRUE(has_vertex_at(r.surface, position(in, v))) << v;
        EXPECT_NEAR(total_area(r.surface), 2 * std::sqrt(2.0), 1e-5);
        EXPECT_TRUE(well_formed(r.surface));
        for (size_t t = 0; t < r.surface.triangle_count(); ++t) {
            EXPECT_GT(triangle_normal(r.surface, t)[2], 0);
        }
    }
}

// A thin blade: the planes of the triangles around its rim are nearly parallel to the blade, so
// they hardly price pulling the rim inwards, which the surface then no longer reaches. Collapses
// also price how far the new triangles retract from their ends, so at 10% of the triangles every
// input vertex stays within a tenth of the blade's thickness of the reduction, for every
// placement. (Without that price, 0.009 to 0.019 of its 8.25 diagonal.)
TEST(EdgeCollapse, ThinBladeKeepsItsRim) {
    const Surface in = thin_blade();
    for (Placement p : {Placement::LeastError, Placement::Midpoint, Placement::VolumePreserving})
        EXPECT_LT(farthest_after_reduction(in, edge(p), 1, 0.1), 0.1 * kThinBladeThickness)
            << "placement " << int(p);
}

// DataPlacement::LeastError on a flat grid with a curved field f = x^2 + y^2: the new points'
// values differ from the interpolated ones but stay within the input's range (they never overshoot
// the values they replace). At alpha = 1 the data takes no part: both give the same surface.
// (That they lower the data error is checked on a real surface: tests/tools/test_isosurface.cpp.)
TEST(EdgeCollapse, LeastErrorDataStaysWithinTheInputsRange) {
    Surface in = grid(40, 40);
    add_field(in, "f", 1,
              [](const Vec3& p) { return std::vector<double>{p[0] * p[0] + p[1] * p[1]}; });
    const auto [lo, hi] =
        std::minmax_element(in.fields[0].values.begin(), in.fields[0].values.end());
    auto reduce = [&](DataPlacement d, double alpha) {
        Options o;
        o.alpha = alpha;
        o.keep_fraction = 0.1;
        o.data_placement = d;
        const Result r = simplify(in, o);
        EXPECT_TRUE(r.target_reached);
        return r.surface;
    };
    const Surface least = reduce(DataPlacement::LeastError, 0.0);
    for (float value : least.fields[0].values) {
        EXPECT_GE(value, *lo);
        EXPECT_LE(value, *hi);
    }
    EXPECT_NE(least.fields[0].values, reduce(DataPlacement::Interpolated, 0.0).fields[0].values);
    const Surface plain = reduce(DataPlacement::LeastError, 1.0);
    const Surface paper = reduce(DataPlacement::Interpolated, 1.0);
    EXPECT_EQ(plain.positions, paper.positions);
    EXPECT_EQ(plain.triangles, paper.triangles);
    EXPECT_EQ(plain.fields[0].values, paper.fields[0].values);
}

} // namespace
} // namespace ddsimp::test
