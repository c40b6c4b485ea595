// compare_surfaces and the closest-point BVH behind it.
#include "tools_test_support.h"

#include "ddsimp/io/compare.h"
#include "ddsimp/io/surface_io.h"
#include "ddsimp/io/triangle_bvh.h"

#include <algorithm>
#include <cmath>
#include <random>

using namespace ddsimp;
using namespace ddsimp::tools_test;

namespace {

double diagonal_of(const Surface& s) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < s.vertex_count(); ++v)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], double(s.positions[3 * v + a]));
            hi[a] = std::max(hi[a], double(s.positions[3 * v + a]));
        }
    return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

void expect_all(const tools::TwoWayError& e, double value, double tolerance) {
    for (const tools::ErrorStats* s :
         {&e.original_to_reduced, &e.reduced_to_original, &e.symmetric}) {
        EXPECT_NEAR(s->rms, value, tolerance);
        EXPECT_NEAR(s->max, value, tolerance);
    }
}

// Brute force: the smallest distance from p to any triangle, by sampling nothing but the exact
// point-triangle distance computed independently (projection + edges).
double point_segment_distance(const double p[3], const double a[3], const double b[3]) {
    double ab[3], ap[3];
    for (int i = 0; i < 3; ++i) ab[i] = b[i] - a[i], ap[i] = p[i] - a[i];
    const double len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    double t = len2 > 0 ? (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(p[0] - a[0] - t * ab[0], p[1] - a[1] - t * ab[1], p[2] - a[2] - t * ab[2]);
}

double point_triangle_distance(const double p[3], const double a[3], const double b[3],
                               const double c[3]) {
    double u[3], v[3], n[3];
    for (int i = 0; i < 3; ++i) u[i] = b[i] - a[i], v[i] = c[i] - a[i];
    n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2],
    n[2] = u[0] * v[1] - u[1] * v[0];
    const double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (nn > 0) {
        const double h = ((p[0] - a[0]) * n[0] + (p[1] - a[1]) * n[1] + (p[2] - a[2]) * n[2]) / nn;
        const double q[3] = {p[0] - h * n[0], p[1] - h * n[1], p[2] - h * n[2]};
        // Inside test with the signs of the three sub-triangle normals along n.
        auto side = [&](const double* x, const double* y) {
            const double e[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]};
            const double w[3] = {q[0] - x[0], q[1] - x[1], q[2] - x[2]};
            const double cr[3] = {e[1] * w[2] - e[2] * w[1], e[2] * w[0] - e[0] * w[2],
                                  e[0] * w[1] - e[1] * w[0]};
            return cr[0] * n[0] + cr[1] * n[1] + cr[2] * n[2];
        };
        if (side(a, b) >= 0 && side(b, c) >= 0 && side(c, a) >= 0)
            return std::fabs(h) * std::sqrt(nn);
    }
    return std::min({point_segment_distance(p, a, b), point_segment_distance(p, b, c),
                     point_segment_distance(p, c, a)});
}

} // namespace

TEST(Compare, IdenticalSurfacesGiveZero) {
    const Surface s = io::read_surface(sample_surface());
    const tools::CompareReport r = tools::compare_surfaces(s, s, {});
    expect_all(r.distance, 0.0, 0.0);
    ASSERT_EQ(r.fields.size(), 7u);
    for (const tools::FieldError& f : r.fields) expect_all(f.error, 0.0, 0.0);
    EXPECT_EQ(r.original_samples, 434u);
    EXPECT_EQ(r.reduced_samples, 434u);
    EXPECT_NEAR(r.diagonal, diagonal_of(s), 1e-9 * diagonal_of(s));
}

// The sample is the plane x = 0; moving it by d along x puts every vertex at distance d from the
// other copy, both ways.
TEST(Compare, PlaneShiftedByDGivesDOverTheDiagonal) {
    const Surface s = io::read_surface(sample_surface());
    for (size_t v = 0; v < s.vertex_count(); ++v) ASSERT_EQ(s.positions[3 * v], 0.0f);
    Surface shifted = s;
    const float d = 0.25f;
    for (size_t v = 0; v < s.vertex_count(); ++v) shifted.positions[3 * v] += d;
    const tools::CompareReport r = tools::compare_surfaces(s, shifted, {"Temp"});
    expect_all(r.distance, d / diagonal_of(s), 1e-7);
    ASSERT_EQ(r.fields.size(), 1u);
    expect_all(r.fields[0].error, 0.0, 1e-6); // same data at the corresponding points
}

TEST(Compare, ScalarOffsetIsRelativeToTheRange) {
    const Surface s = io::read_surface(sample_surface());
    Surface changed = s;
    Field& temp = changed.fields[1];
    ASSERT_EQ(temp.name, "Temp");
    const auto [lo, hi] = std::minmax_element(s.fields[1].values.begin(), s.fields[1].values.end());
    const double range = double(*hi) - double(*lo);
    for (float& x : temp.values) x += 10.0f;
    const tools::CompareReport r = tools::compare_surfaces(s, changed, {"Temp"});
    expect_all(r.distance, 0.0, 0.0);
    EXPECT_NEAR(r.fields[0].range, range, 1e-9 * range);
    expect_all(r.fields[0].error, 10.0 / range, 1e-4);
}

TEST(Compare, VectorErrorIsTheL2Norm) {
    Surface s = square_with_fields();
    s.fields[1].values = {1, 2, 3, -4, 5.5f, 6, 0.1f, 0.2f, 0.3f, 2, -1, 0.5f};
    // Component ranges 6 (-4..2), 6.5 (-1..5.5) and 5.7 (0.3..6): the scale is that box diagonal.
    const double expected_range = std::sqrt(6.0 * 6.0 + 6.5 * 6.5 + 5.7 * 5.7);
    Surface changed = s;
    for (size_t v = 0; v < s.vertex_count(); ++v) {
        changed.fields[1].values[3 * v] += 3.0f;
        changed.fields[1].values[3 * v + 1] += 4.0f;
    }
    const tools::CompareReport r = tools::compare_surfaces(s, changed, {"V"});
    EXPECT_NEAR(r.fields[0].range, expected_range, 1e-5);
    expect_all(r.fields[0].error, 5.0 / expected_range, 1e-5);
}

TEST(Compare, UnknownOrMismatchedFieldIsAnError) {
    const Surface s = square_with_fields();
    EXPECT_THROW(tools::compare_surfaces(s, s, {"Nope"}), InputError);
    Surface other = s;
    other.fields[0].components = 2;
    other.fields[0].values.resize(8);
    EXPECT_THROW(tools::compare_surfaces(s, other, {"Temp"}), InputError);
}

TEST(Compare, WithoutNamesOnlyFieldsBothHaveAlikeAreCompared) {
    const Surface s = square_with_fields(); // Temp, V(3), uv(2)
    Surface other = s;
    other.fields[0].components = 2; // Temp now differs in shape
    other.fields[0].values.resize(8);
    other.fields.pop_back(); // uv is gone
    const tools::CompareReport r = tools::compare_surfaces(s, other, {});
    ASSERT_EQ(r.fields.size(), 1u);
    EXPECT_EQ(r.fields[0].name, "V");
}

TEST(TriangleBvh, AgreesWithBruteForceOnARealSurface) {
    const std::string path = shared_data("geometry/fandisk.off");
    DDSIMP_REQUIRE_SHARED(path);
    const Surface s = io::read_surface(path);
    const tools::TriangleBvh bvh(s.positions, s.triangles);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> coordinate(-1.5, 1.5);
    for (int i = 0; i < 200; ++i) {
        // Around the surface: near a random vertex, plus noise of the model's size.
        const size_t v = random() % s.vertex_count();
        const double p[3] = {s.positions[3 * v] + 0.3 * coordinate(random),
                             s.positions[3 * v + 1] + 0.3 * coordinate(random),
                             s.positions[3 * v + 2] + 0.3 * coordinate(random)};
        double best = INFINITY;
        for (size_t t = 0; t < s.triangle_count(); ++t) {
            double c[3][3];
            for (int k = 0; k < 3; ++k)
                for (int a = 0; a < 3; ++a) c[k][a] = s.positions[3 * s.triangles[3 * t + k] + a];
            best = std::min(best, point_triangle_distance(p, c[0], c[1], c[2]));
        }
        const tools::ClosestPoint hit = bvh.closest(p);
        EXPECT_NEAR(std::sqrt(hit.distance_squared), best, 1e-9 + 1e-7 * best) << "query " << i;
        EXPECT_NEAR(hit.barycentric[0] + hit.barycentric[1] + hit.barycentric[2], 1.0, 1e-12);
    }
}
