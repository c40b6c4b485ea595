// ErrorQuadrics (simplify/src/error_quadric.h, internal): the sideways step of the least-error
// placement (free, or at a held height) and the error change it reports, and the error at one
// point, against the quadrics evaluated along a segment; the least error over points, against
// each point alone; the data of least error at a point, against the closed form. The quadrics are
// built by hand from planes and a linear field, so that E(x, s) = sum (n.x + e)^2 + w (s - g.x -
// d)^2 is known in closed form. And setup's plane weights, a triangle's and a boundary edge's,
// which grow with the data's steepness.
#include "error_quadric.h"
#include "parallel.h"
#include "working_mesh.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace ddsimp::detail {
namespace {

// w (s - g.x - d)^2 for one data component, added to quadric q.
void add_field(double* q, const Vec3& g, double d, double w) {
    add_plane(q, g, d, w); // (g.x + d)^2 expands like a plane's
    q[10] += w;
    for (int k = 0; k < 3; ++k) q[ErrorQuadrics::kSharedTerms + k] += w * g[k];
    q[ErrorQuadrics::kSharedTerms + 3] += w * d;
}

Vec3 unit(Vec3 v) {
    return scale(v, 1 / norm(v));
}

// Two vertices' quadrics: curved geometry (planes of different directions) and one data component,
// in normalised units (centre 0, diagonal 1, data range 1).
ErrorQuadrics two_quadrics() {
    ErrorQuadrics q;
    q.components = 1;
    q.size = ErrorQuadrics::kSharedTerms + 4;
    q.values.assign(2 * q.size, 0.0);
    q.inv_diagonal = 1;
    q.offset = {0};
    q.low = {0};
    q.inv_range = {1};
    q.continuous = {1};
    add_plane(q.of(0), unit({0.1, 0.2, 1.0}), -0.05, 0.7);
    add_plane(q.of(0), unit({0.9, -0.1, 0.4}), 0.02, 0.3);
    add_field(q.of(0), {0.5, -0.3, 0.2}, 0.1, 0.4);
    add_plane(q.of(1), unit({-0.2, 0.1, 1.0}), -0.04, 0.5);
    add_plane(q.of(1), unit({0.0, 1.0, 0.3}), 0.01, 0.6);
    add_field(q.of(1), {0.4, -0.2, 0.1}, 0.12, 0.5);
    return q;
}

TEST(ErrorQuadrics, SidewaysChangeEqualsTheErrorAtTheMovedPoint) {
    const ErrorQuadrics q = two_quadrics();
    const Vec3 xa{0.10, -0.05, 0.02}, xb{0.16, 0.03, -0.01};
    const float fa[1] = {0.25f}, fb[1] = {0.40f};
    SegmentSlope slope;
    const SegmentError edge = q.along(0, 1, xa, xb, fa, fb, &slope);
    // The slope does not change the segment's error.
    const SegmentError plain = q.along(0, 1, xa, xb, fa, fb);
    EXPECT_EQ(edge.e0, plain.e0);
    EXPECT_EQ(edge.h, plain.h);
    EXPECT_EQ(edge.g, plain.g);

    const Vec3 axis = unit(sub(xb, xa));
    for (double t : {0.0, 0.3, 0.5, 1.0}) {
        const Vec3 p = add(xa, scale(sub(xb, xa), t));
        const Vec3 d = q.sideways(slope, t, axis);
        EXPECT_NEAR(dot(d, axis), 0.0, 1e-12) << "t = " << t << ": the step leaves the edge square";
        // The error at the moved point, its data held at the blend of t, evaluated afresh.
        const Vec3 moved = add(p, d);
        const double fresh = q.along(0, 1, moved, moved, fa, fb).at(t);
        const double on_edge = q.along(0, 1, p, p, fa, fb).at(t);
        EXPECT_NEAR(on_edge + q.change(slope, t, d), fresh, 1e-12 * (1 + on_edge)) << "t = " << t;
        EXPECT_LT(fresh, on_edge) << "t = " << t << ": the step lowers the error";
        // Any other offset across the edge is an exact change too, and no better than the step.
        const Vec3 other = scale(unit(cross(axis, {0.3, -0.7, 0.2})), 0.01);
        const Vec3 elsewhere = add(p, other);
        const double other_fresh = q.along(0, 1, elsewhere, elsewhere, fa, fb).at(t);
        EXPECT_NEAR(on_edge + q.change(slope, t, other), other_fresh, 1e-12 * (1 + on_edge));
        EXPECT_LE(fresh, other_fresh + 1e-15) << "t = " << t;
    }
}

// With its height along a normal held, the step goes across to the least error at that height:
// the offset's height is the one asked for, it stays square to the edge, any other offset at the
// same height has at least its error, and held at the free step's own height it is the free step.
TEST(ErrorQuadrics, SidewaysAtAHeightIsTheLeastErrorThere) {
    const ErrorQuadrics q = two_quadrics();
    const Vec3 xa{0.10, -0.05, 0.02}, xb{0.16, 0.03, -0.01};
    const float fa[1] = {0.25f}, fb[1] = {0.40f};
    SegmentSlope slope;
    q.along(0, 1, xa, xb, fa, fb, &slope);
    const Vec3 axis = unit(sub(xb, xa));
    const Vec3 normal = unit(cross(axis, cross({0.1, 0.1, 1.0}, axis))); // square to the axis
    const Vec3 across = cross(axis, normal);
    for (double t : {0.0, 0.4, 1.0})
        for (double height : {-0.02, 0.0, 0.005}) {
            const Vec3 d = q.sideways_at(slope, t, axis, normal, height);
            EXPECT_NEAR(dot(d, normal), height, 1e-15) << "t = " << t;
            EXPECT_NEAR(dot(d, axis), 0.0, 1e-15) << "t = " << t;
            const double least = q.change(slope, t, d);
            for (double s : {-0.01, -1e-4, 1e-4, 0.01})
                EXPECT_LE(least, q.change(slope, t, add(d, scale(across, s))) + 1e-15)
                    << "t = " << t << ", height " << height << ", moved across by " << s;
        }
    const Vec3 free = q.sideways(slope, 0.4, axis);
    const Vec3 held = q.sideways_at(slope, 0.4, axis, normal, dot(free, normal));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(held[k], free[k], 1e-12);
}

TEST(ErrorQuadrics, ErrorAtAPointEqualsTheSegmentsErrorThere) {
    const ErrorQuadrics q = two_quadrics();
    const Vec3 xa{0.10, -0.05, 0.02}, xb{0.16, 0.03, -0.01};
    const float fa[1] = {0.25f}, fb[1] = {0.40f};
    const SegmentError edge = q.along(0, 1, xa, xb, fa, fb);
    for (double t : {0.0, 0.25, 0.5, 1.0}) {
        const Vec3 p = add(xa, scale(sub(xb, xa), t));
        EXPECT_NEAR(q.at(0, 1, p, fa, fb, t), edge.at(t), 1e-12 * (1 + edge.at(t))) << "t = " << t;
        // Off the edge: the segment from the point to itself, its data still blended at t.
        const Vec3 off = add(p, {0.01, -0.02, 0.015});
        EXPECT_NEAR(q.at(0, 1, off, fa, fb, t), q.along(0, 1, off, off, fa, fb).at(t), 1e-12)
            << "t = " << t;
    }
    EXPECT_GT(q.at(0, 1, xa, fa, fb, 0.5), 0.0); // curved geometry: no point is free
}

// least_at takes the points two at a time, side by side: for every count, odd ones included, it
// is the least of at_blend at each point alone, bit for bit (vertex removal's keys depend on it).
TEST(ErrorQuadrics, LeastAtPointsIsTheLeastOfEachPointAlone) {
    const ErrorQuadrics q = two_quadrics();
    // A fan of 7 points around a centre, each with its own datum.
    Surface s;
    s.positions = {0, 0, 0};
    for (int i = 0; i < 7; ++i) {
        const double a = 0.9 * i;
        s.positions.insert(s.positions.end(),
                           {float(0.2 * std::cos(a)), float(0.15 * std::sin(a)), float(0.03 * i)});
    }
    for (uint32_t i = 1; i <= 7; ++i) s.triangles.insert(s.triangles.end(), {0, i, i % 7 + 1});
    s.fields.push_back({"f", 1, {0.3f, 0.1f, 0.9f, 0.4f, 0.05f, 0.7f, 0.2f, 0.6f}});
    WorkingMesh mesh;
    mesh.build(s, s.vertex_count(), Limits{});
    const uint32_t ring[7] = {1, 2, 3, 4, 5, 6, 7};
    for (uint32_t v : {0u, 1u})
        for (size_t count = 1; count <= 7; ++count)
            for (size_t first = 0; first + count <= 7; ++first) {
                double least = INFINITY;
                for (size_t i = first; i < first + count; ++i)
                    least = std::min(least, q.at_blend(v, mesh, ring + i, nullptr, 1));
                EXPECT_EQ(q.least_at(v, mesh, ring + first, count), least)
                    << "quadric " << v << ", points " << first << ".." << first + count;
            }
}

} // namespace
} // namespace ddsimp::detail

namespace ddsimp::detail {
namespace {

TEST(ErrorQuadrics, LeastDataIsTheLeastSquaresValueClampedToTheEnds) {
    const ErrorQuadrics q = two_quadrics();
    const Vec3 x{0.12, -0.01, 0.01};
    // Closed form: sum w (g.x + d) / sum w over the two fields of two_quadrics.
    const double least =
        (0.4 * (dot({0.5, -0.3, 0.2}, x) + 0.1) + 0.5 * (dot({0.4, -0.2, 0.1}, x) + 0.12)) / 0.9;
    auto error_with = [&](float s) { // both quadrics at x with data s
        const float f[1] = {s};
        return q.at(0, 1, x, f, f, 0.0);
    };
    const double t = 0.3;
    struct Case {
        float a, b, expected;
    };
    for (const Case c : {Case{0.0f, 0.5f, float(least)}, // inside: the least-squares value
                         Case{0.5f, 0.0f, float(least)}, // the ends' order does not matter
                         Case{0.2f, 0.3f, least < 0.2 ? 0.2f : 0.3f}, // outside: the nearer end
                         Case{0.4f, 0.9f, 0.4f}}) {
        const float fa[1] = {c.a}, fb[1] = {c.b};
        float out[1] = {-1};
        const double change = q.least_data(0, 1, x, fa, fb, t, out);
        EXPECT_NEAR(out[0], c.expected, 1e-6) << c.a << ".." << c.b;
        EXPECT_GE(out[0], std::min(c.a, c.b));
        EXPECT_LE(out[0], std::max(c.a, c.b));
        // The change is the error with the new value less the error with the blend at t.
        const float blend = float((1 - t) * c.a + t * c.b);
        EXPECT_NEAR(change, error_with(out[0]) - error_with(blend), 1e-6) << c.a << ".." << c.b;
        EXPECT_LE(change, 0.0);
    }
    // A component that is not continuous (a label, a direction) is left alone.
    ErrorQuadrics label = q;
    label.continuous = {0};
    const float fa[1] = {0.0f}, fb[1] = {0.5f};
    float out[1] = {-1};
    EXPECT_EQ(label.least_data(0, 1, x, fa, fb, t, out), 0.0);
    EXPECT_EQ(out[0], -1.0f);
}

} // namespace
} // namespace ddsimp::detail

namespace ddsimp::detail {
namespace {

// E(x, s) of one vertex's quadric (the layout of error_quadric.h), normalised units.
double error_of(const ErrorQuadrics& q, uint32_t v, const Vec3& x, double s) {
    const double* a = q.of(v);
    const double xax = x[0] * (a[0] * x[0] + 2 * a[1] * x[1] + 2 * a[2] * x[2]) +
                       x[1] * (a[3] * x[1] + 2 * a[4] * x[2]) + x[2] * a[5] * x[2];
    double e = xax + 2 * dot({a[6], a[7], a[8]}, x) + a[9];
    for (size_t j = 0; j < q.components; ++j) {
        const double* g = a + ErrorQuadrics::kSharedTerms + 4 * j;
        e += a[10] * s * s - 2 * s * (dot({g[0], g[1], g[2]}, x) + g[3]);
    }
    return e;
}

// One right triangle in the plane z = 0 carrying a field f. The cost of stepping its corner at
// the origin by delta along the unit vector `step`, its datum held: off the plane (z), the
// plane's weight x area x delta^2.
double step_cost(const std::vector<float>& f, double geometry, double data, const Vec3& step) {
    Surface s;
    s.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    s.triangles = {0, 1, 2};
    s.fields.push_back({"f", 1, f});
    WorkingMesh mesh;
    mesh.build(s, s.vertex_count(), Limits{});
    GradientTerms gradient;
    gradient.setup(s, {});
    Parallel parallel(1);
    ErrorQuadrics q;
    q.setup(mesh, gradient, geometry, data, s.vertex_count(), parallel);
    const Vec3 corner = scale(sub({0, 0, 0}, q.centre), q.inv_diagonal);
    const double datum = q.components > 0 ? (f[0] - q.low[0]) * q.inv_range[0] : 0, delta = 0.01;
    return error_of(q, 0, add(corner, scale(step, delta)), datum) - error_of(q, 0, corner, datum);
}

double step_off_cost(const std::vector<float>& f, double geometry, double data) {
    return step_cost(f, geometry, data, {0, 0, 1});
}

// Where the data is steep, a point off the surface misplaces the data a reader sees: the plane
// weighs kShiftWeight x data x |g|^2 more. Where the data is flat, or does not count, it does not.
// Field f = x over a unit triangle: one range per unit length, so |g| = the diagonal, sqrt(2), in
// ranges per diagonal; area 1/4 in diagonals squared.
TEST(ErrorQuadrics, AStepOffTheSurfaceCostsMoreWhereTheDataIsSteep) {
    const double area = 0.25, delta2 = 1e-4, steepness = 2;
    const std::vector<float> ramp = {0, 1, 0};
    EXPECT_NEAR(step_off_cost(ramp, 0.2, 1.0),
                (0.2 + ErrorQuadrics::kShiftWeight * steepness) * area * delta2, 1e-12);
    // f = x + y: |g|^2 twice the ramp's.
    EXPECT_NEAR(step_off_cost({0, 1, 1}, 0.2, 1.0),
                (0.2 + ErrorQuadrics::kShiftWeight * 2 * steepness) * area * delta2, 1e-12);
    // Flat data: the geometric weight alone.
    EXPECT_NEAR(step_off_cost({0.5f, 0.5f, 0.5f}, 0.2, 1.0), 0.2 * area * delta2, 1e-12);
    EXPECT_GT(step_off_cost(ramp, 0.2, 1.0), step_off_cost({0.5f, 0.5f, 0.5f}, 0.2, 1.0));
    // With no data term (alpha = 1) the geometry weighs what it says, steep data or not.
    EXPECT_NEAR(step_off_cost(ramp, 1.0, 0.0), 1.0 * area * delta2, 1e-12);
}

// The same for a boundary that moves in: the input beyond it is read at the boundary. The corner
// at the origin steps across the boundary edge along x (length 1/sqrt 2 in diagonals), in the
// triangle's plane: only that edge's boundary plane sees it, weighing what the triangle's plane
// weighs per unit area, times the edge's squared length. The ramp f = x does not change along y,
// so the data term itself does not see the step.
TEST(ErrorQuadrics, ABoundaryThatMovesInCostsMoreWhereTheDataIsSteep) {
    const double length2 = 0.5, delta2 = 1e-4, steepness = 2;
    const std::vector<float> ramp = {0, 1, 0}, flat = {0.5f, 0.5f, 0.5f};
    const Vec3 in{0, 1, 0};
    EXPECT_NEAR(step_cost(ramp, 0.2, 1.0, in),
                (0.2 + ErrorQuadrics::kShiftWeight * steepness) * length2 * delta2, 1e-12);
    EXPECT_NEAR(step_cost(flat, 0.2, 1.0, in), 0.2 * length2 * delta2, 1e-12);
    EXPECT_NEAR(step_cost(ramp, 1.0, 0.0, in), 1.0 * length2 * delta2, 1e-12);
}

} // namespace
} // namespace ddsimp::detail
