// Field kinds (ddsimp::FieldKind): a label is never a mix of two values, a direction stays unit
// length, and only continuous fields drive the data term unless the options name others.
#include "test_surfaces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

using namespace ddsimp;
using namespace ddsimp::test;

namespace {

// A 24 x 24 grid bent into a bump, with a smooth scalar, an id per vertex (distinct integers),
// and the bump's unit normal.
Surface grid_with_kinds() {
    Surface s = grid(24, 24);
    for (size_t v = 0; v < s.vertex_count(); ++v) {
        const double x = s.positions[3 * v], y = s.positions[3 * v + 1];
        s.positions[3 * v + 2] = float(0.3 * std::sin(3 * x) * std::cos(2 * y));
    }
    add_field(s, "pressure", 1,
              [](const Vec3& p) { return std::vector<double>{std::sin(4 * p[0]) + p[1]}; });
    Field id{"GlobalNodeId", 1, {}, FieldKind::Label};
    for (size_t v = 0; v < s.vertex_count(); ++v) id.values.push_back(float(1000 + 7 * v));
    s.fields.push_back(id);
    add_field(s, "Normals", 3, [](const Vec3& p) {
        // The normal of z = 0.3 sin(3x) cos(2y).
        const double dx = 0.9 * std::cos(3 * p[0]) * std::cos(2 * p[1]);
        const double dy = -0.6 * std::sin(3 * p[0]) * std::sin(2 * p[1]);
        const double l = std::sqrt(dx * dx + dy * dy + 1);
        return std::vector<double>{-dx / l, -dy / l, 1 / l};
    });
    s.fields.back().kind = FieldKind::Direction;
    return s;
}

Result reduce(const Surface& s, Strategy strategy, double keep = 0.1) {
    Options o;
    o.strategy = strategy;
    o.keep_fraction = keep;
    return simplify(s, o);
}

std::set<float> values_of(const Field& f) {
    return {f.values.begin(), f.values.end()};
}

} // namespace

TEST(FieldKinds, DefaultGradientFieldsAreTheContinuousOnes) {
    const Surface s = grid_with_kinds();
    EXPECT_EQ(default_gradient_fields(s), std::vector<std::string>{"pressure"});
}

TEST(FieldKinds, EveryKindIsCarriedIntoTheOutput) {
    const Surface s = grid_with_kinds();
    for (Strategy strategy : {Strategy::EdgeCollapse, Strategy::VertexRemoval}) {
        const Result r = reduce(s, strategy);
        ASSERT_EQ(r.surface.fields.size(), 3u);
        for (size_t f = 0; f < 3; ++f) EXPECT_EQ(r.surface.fields[f].kind, s.fields[f].kind);
    }
}

TEST(FieldKinds, EdgeCollapseGivesALabelOneEndsValueNeverAMix) {
    const Surface s = grid_with_kinds();
    const Result r = reduce(s, Strategy::EdgeCollapse);
    ASSERT_LT(r.triangles_out, r.triangles_in / 5);
    const std::set<float> ids = values_of(s.fields[1]);
    for (float v : r.surface.fields[1].values) EXPECT_TRUE(ids.count(v)) << v;
    // The same values as a continuous field are interpolated: the check above can fail.
    Surface continuous = s;
    continuous.fields[1].kind = FieldKind::Continuous;
    Options o;
    o.gradient_fields = {"pressure"};
    const Result mixed = simplify(continuous, o);
    size_t new_values = 0;
    for (float v : mixed.surface.fields[1].values) new_values += ids.count(v) == 0;
    EXPECT_GT(new_values, 0u);
}

TEST(FieldKinds, VertexRemovalKeepsLabelsExactly) {
    const Surface s = grid_with_kinds();
    const Result r = reduce(s, Strategy::VertexRemoval);
    const std::set<float> ids = values_of(s.fields[1]);
    for (float v : r.surface.fields[1].values) EXPECT_TRUE(ids.count(v)) << v;
}

TEST(FieldKinds, EdgeCollapseKeepsDirectionsUnitLength) {
    const Surface s = grid_with_kinds();
    const Result r = reduce(s, Strategy::EdgeCollapse, 0.05);
    const Field& n = r.surface.fields[2];
    for (size_t v = 0; v < r.surface.vertex_count(); ++v) {
        const double l = std::sqrt(n.values[3 * v] * n.values[3 * v] +
                                   n.values[3 * v + 1] * n.values[3 * v + 1] +
                                   n.values[3 * v + 2] * n.values[3 * v + 2]);
        EXPECT_NEAR(l, 1.0, 1e-5) << "vertex " << v;
    }
    // As a continuous field, the averages of unit vectors come out shorter.
    Surface continuous = s;
    continuous.fields[2].kind = FieldKind::Continuous;
    Options o;
    o.keep_fraction = 0.05;
    o.gradient_fields = {"pressure"};
    const Result result = simplify(continuous, o);
    const Field& averaged = result.surface.fields[2];
    double shortest = 1;
    for (size_t v = 0; v < averaged.values.size() / 3; ++v)
        shortest = std::min(
            shortest, std::sqrt(double(averaged.values[3 * v]) * averaged.values[3 * v] +
                                double(averaged.values[3 * v + 1]) * averaged.values[3 * v + 1] +
                                double(averaged.values[3 * v + 2]) * averaged.values[3 * v + 2]));
    EXPECT_LT(shortest, 0.999);
}

TEST(FieldKinds, OnlyContinuousFieldsDriveByDefault) {
    const Surface s = grid_with_kinds();
    for (Strategy strategy : {Strategy::EdgeCollapse, Strategy::VertexRemoval}) {
        Options named;
        named.strategy = strategy;
        named.gradient_fields = {"pressure"};
        Options by_default = named;
        by_default.gradient_fields.clear();
        Options every = named;
        every.gradient_fields = {"pressure", "GlobalNodeId", "Normals"};
        const Surface a = simplify(s, by_default).surface, b = simplify(s, named).surface;
        EXPECT_EQ(a.positions, b.positions);
        EXPECT_EQ(a.triangles, b.triangles);
        // Naming the others makes them drive: a different reduction.
        const Surface c = simplify(s, every).surface;
        EXPECT_NE(a.positions, c.positions);
    }
    EXPECT_EQ(vertex_gradient(s, {}), vertex_gradient(s, {"pressure"}));
    EXPECT_NE(vertex_gradient(s, {}), vertex_gradient(s, {"pressure", "GlobalNodeId"}));
}

TEST(FieldKinds, ASurfaceWithoutContinuousFieldsIsReducedByGeometryAlone) {
    Surface s = grid_with_kinds();
    Surface geometry = s;
    geometry.fields.clear();
    s.fields.erase(s.fields.begin()); // the label and the normals only
    Options o;
    o.alpha = 0; // data alone, if any field drove
    const Result with_labels = simplify(s, o), without = simplify(geometry, o);
    EXPECT_EQ(with_labels.surface.positions, without.surface.positions);
    EXPECT_EQ(with_labels.surface.triangles, without.surface.triangles);
}
