// vertex_curvature and vertex_gradient against values computed by hand from ddsimp.h's
// definitions:
//   curv(v) = |2pi - sum theta| / pi, or |pi - sum theta| / pi at a boundary vertex;
//   grad(v) = max_i ||f_i - f||_1 / ||x_i - x||_1, each field divided by its range (the largest
//             max - min of its components), lengths by the bounding-box diagonal.
// The bounding-box diagonal is taken as the Euclidean length of (max - min) — the usual meaning;
// the header does not say which norm measures it.
#include "test_surfaces.h"

namespace ddsimp::test {
namespace {

constexpr double kTol = 1e-5;
const double kSqrt2 = std::sqrt(2.0);
const double kSqrt3 = std::sqrt(3.0);

void expect_values(const std::vector<float>& got, const std::vector<double>& want,
                   double tol = kTol) {
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(got[i], want[i], tol) << "vertex " << i;
}

// --- curvature -----------------------------------------------------------------------------------

// Right triangle: vertex 0 has pi/2 -> |pi - pi/2|/pi = 1/2; vertices 1, 2 have pi/4 ->
// |pi - pi/4|/pi = 3/4. All three are boundary vertices.
TEST(Curvature, SingleTriangle) {
    expect_values(vertex_curvature(single_triangle()), {0.5, 0.75, 0.75});
}

// Square: each corner's angles sum to pi/2 (vertex 0 and 2: pi/4 + pi/4; 1 and 3: pi/2) -> 1/2.
TEST(Curvature, SquareCorners) {
    expect_values(vertex_curvature(square()), {0.5, 0.5, 0.5, 0.5});
}

// Flat regular hexagon fan: the centre is interior with 6 * pi/3 = 2pi -> 0; each rim vertex is
// on the boundary with two angles of pi/3 -> |pi - 2pi/3|/pi = 1/3.
TEST(Curvature, FlatHexagonFan) {
    expect_values(vertex_curvature(fan(6)), {0, 1. / 3, 1. / 3, 1. / 3, 1. / 3, 1. / 3, 1. / 3});
}

// Square pyramid: fan(4) with the centre raised to height 1. Spokes (0,0,1)-(1,0,0) have length
// sqrt 2, rim edges (1,0,0)-(0,1,0) also sqrt 2: four equilateral triangles. Apex: 4 * pi/3 ->
// |2pi - 4pi/3|/pi = 2/3. Rim (boundary): 2 * pi/3 -> |pi - 2pi/3|/pi = 1/3.
TEST(Curvature, SquarePyramidApex) {
    expect_values(vertex_curvature(fan(4, 1.0)), {2. / 3, 1. / 3, 1. / 3, 1. / 3, 1. / 3});
}

// Regular tetrahedron: three angles of pi/3 at each vertex -> |2pi - pi|/pi = 1.
TEST(Curvature, RegularTetrahedron) {
    expect_values(vertex_curvature(tetrahedron()), {1, 1, 1, 1});
}

// Corner tetrahedron: at O three right angles -> |2pi - 3pi/2|/pi = 1/2. At X: pi/4 in OXY, pi/4
// in OXZ, pi/3 in the equilateral XYZ -> 5pi/6 -> |2pi - 5pi/6|/pi = 7/6 (same for Y, Z).
// Check: the deficits sum to (1/2 + 3 * 7/6) pi = 4pi (Gauss-Bonnet).
TEST(Curvature, CornerTetrahedron) {
    expect_values(vertex_curvature(corner_tetrahedron()), {0.5, 7. / 6, 7. / 6, 7. / 6});
}

// Regular octahedron: four equilateral angles -> |2pi - 4pi/3|/pi = 2/3 at every vertex.
TEST(Curvature, RegularOctahedron) {
    expect_values(vertex_curvature(octahedron()), std::vector<double>(6, 2. / 3));
}

// Cube with 2x2 faces: a corner has three right angles -> 1/2; a vertex in the middle of a cube
// edge has pi from each of its two faces -> 2pi -> 0 (an edge has no angle deficit); a face centre
// is flat -> 0.
TEST(Curvature, CubeCornersEdgesAndFaces) {
    Surface s = cube(2);
    std::vector<float> c = vertex_curvature(s);
    ASSERT_EQ(c.size(), s.vertex_count());
    for (size_t v = 0; v < s.vertex_count(); ++v) {
        Vec3 p = position(s, v);
        int on_planes = 0;
        for (double x : p) on_planes += std::abs(std::abs(x) - 1) < 1e-6;
        EXPECT_NEAR(c[v], on_planes == 3 ? 0.5 : 0.0, kTol) << "vertex " << v;
    }
}

// Flat grid: interior 2pi -> 0; straight boundary pi -> 0; corners pi/2 -> 1/2.
TEST(Curvature, FlatGrid) {
    Surface s = grid(4, 4);
    std::vector<float> c = vertex_curvature(s);
    ASSERT_EQ(c.size(), 25u);
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 4; ++i) {
            bool corner = (i == 0 || i == 4) && (j == 0 || j == 4);
            EXPECT_NEAR(c[grid_index(4, i, j)], corner ? 0.5 : 0.0, kTol) << i << "," << j;
        }
}

// Gauss-Bonnet: on a convex closed surface every deficit is positive and they sum to 2pi * 2, so
// the unit-free curvatures sum to 4.
TEST(Curvature, IcosphereSumsToFour) {
    std::vector<float> c = vertex_curvature(icosphere(2));
    double sum = 0;
    for (float x : c) {
        EXPECT_GT(x, 0);
        sum += x;
    }
    EXPECT_NEAR(sum, 4.0, 1e-3);
}

// Angles do not depend on the order of a triangle's corners: flipping triangles changes nothing
// (a regular octahedron with half its triangles flipped still has 2/3 everywhere).
TEST(Curvature, IndependentOfOrientation) {
    expect_values(vertex_curvature(flipped(octahedron(), [](size_t t) { return t % 2 == 0; })),
                  std::vector<double>(6, 2. / 3));
    std::vector<float> a = vertex_curvature(icosphere(2));
    std::vector<float> b =
        vertex_curvature(flipped(icosphere(2), [](size_t t) { return t % 3 == 1; }));
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], kTol) << i;
}

TEST(Curvature, UnreferencedVerticesGetZero) {
    Surface s = tetrahedron();
    add_vertex(s, 3, 3, 3);
    expect_values(vertex_curvature(s), {1, 1, 1, 1, 0});
}

// Angles do not change with scale or translation.
TEST(Curvature, IsScaleFree) {
    Surface s = corner_tetrahedron();
    for (size_t i = 0; i < s.positions.size(); ++i)
        s.positions[i] = s.positions[i] * 1000.0f + 7.0f;
    expect_values(vertex_curvature(s), {0.5, 7. / 6, 7. / 6, 7. / 6});
}

// --- gradient ------------------------------------------------------------------------------------

// The right triangle (0,0,0) (1,0,0) (0,1,0) with
//   "s" (scalar): 0, 1, 2             range 2 -> normalised 0, 0.5, 1
//   "v" (2 comp): (0,0) (2,0) (0,4)   range max(2, 4) = 4 -> (0,0) (0.5,0) (0,1)
// Bounding box [0,1]x[0,1]x[0,0], diagonal sqrt 2. L1 edge lengths: 0-1: 1, 0-2: 1, 1-2: 2,
// normalised 1/sqrt2, 1/sqrt2, sqrt2.
Surface gradient_triangle() {
    Surface s = single_triangle();
    s.fields.push_back({"s", 1, {0, 1, 2}});
    s.fields.push_back({"v", 2, {0, 0, 2, 0, 0, 4}});
    return s;
}

// "s" only. v0: to 1: 0.5/(1/sqrt2) = sqrt2/2; to 2: 1/(1/sqrt2) = sqrt2 -> sqrt2.
// v1: to 0: sqrt2/2; to 2: 0.5/sqrt2 = sqrt2/4 -> sqrt2/2. v2: to 0: sqrt2; to 1: sqrt2/4 -> sqrt2.
TEST(Gradient, ScalarFieldOnATriangle) {
    expect_values(vertex_gradient(gradient_triangle(), {"s"}), {kSqrt2, kSqrt2 / 2, kSqrt2});
}

// "v" only. Differences: 0-1: 0.5; 0-2: 1; 1-2: 0.5 + 1 = 1.5.
// v0: max(0.5 sqrt2, sqrt2) = sqrt2; v1: max(0.5 sqrt2, 1.5/sqrt2) = 1.5/sqrt2; v2: sqrt2.
TEST(Gradient, VectorFieldUsesTheLargestComponentRangeAndL1) {
    expect_values(vertex_gradient(gradient_triangle(), {"v"}), {kSqrt2, 1.5 / kSqrt2, kSqrt2});
}

// Both fields (L1 over all components of all fields): 0-1: 0.5 + 0.5 = 1; 0-2: 1 + 1 = 2;
// 1-2: 0.5 + 1.5 = 2. v0: max(1 sqrt2, 2 sqrt2) = 2 sqrt2; v1: max(sqrt2, 2/sqrt2) = sqrt2;
// v2: max(2 sqrt2, sqrt2) = 2 sqrt2.
TEST(Gradient, AllFieldsByDefault) {
    std::vector<double> both{2 * kSqrt2, kSqrt2, 2 * kSqrt2};
    expect_values(vertex_gradient(gradient_triangle(), {}), both);
    expect_values(vertex_gradient(gradient_triangle(), {"s", "v"}), both);
    expect_values(vertex_gradient(gradient_triangle(), {"v", "s"}), both);
}

TEST(Gradient, UnknownFieldIsAnInputErrorNamingIt) {
    try {
        vertex_gradient(gradient_triangle(), {"s", "nonexistent_field"});
        FAIL() << "accepted an unknown field";
    } catch (const InputError& e) {
        EXPECT_TRUE(mentions(e.what(), "nonexistent_field")) << e.what();
    }
}

// Corner tetrahedron with f(O) = 0, f(X) = 1, f(Y) = f(Z) = 0: range 1; bounding box [0,1]^3,
// diagonal sqrt3 (so the box is 3-D, not the xy extent). L1 lengths: O-X, O-Y, O-Z 1; X-Y, X-Z,
// Y-Z 2. O: to X 1/(1/sqrt3) = sqrt3 -> sqrt3. X: to O sqrt3 -> sqrt3. Y: to X 1/(2/sqrt3) =
// sqrt3/2, to O, Z 0 -> sqrt3/2. Z: likewise sqrt3/2.
TEST(Gradient, ThreeDimensionalBoundingBox) {
    Surface s = corner_tetrahedron();
    s.fields.push_back({"f", 1, {0, 1, 0, 0}});
    expect_values(vertex_gradient(s, {}), {kSqrt3, kSqrt3, kSqrt3 / 2, kSqrt3 / 2});
}

// f = x on a flat 8x8 grid over [0,1]^2 (spacing h = 1/8), range 1, diagonal sqrt2. Every vertex
// has a horizontal neighbour: h / (h/sqrt2) = sqrt2; diagonal neighbours h / (2h/sqrt2) = sqrt2/2;
// vertical 0. The maximum is sqrt2 everywhere (a mean instead of a max, or L2 lengths instead of
// L1, would give other values).
TEST(Gradient, LinearFieldOnAGridIsUniform) {
    Surface s = grid(8, 8);
    add_field(s, "f", 1, [](const Vec3& p) { return std::vector<double>{p[0]}; });
    expect_values(vertex_gradient(s, {}), std::vector<double>(81, kSqrt2));
}

// Unit-free: an affine change of the data (f -> 1e5 f + 7) and a scale + shift of the geometry
// leave the gradient unchanged.
TEST(Gradient, IsUnitFree) {
    Surface s = grid(8, 8);
    add_field(s, "f", 1, [](const Vec3& p) { return std::vector<double>{1e5 * p[0] * p[0] + 7}; });
    Surface t = grid(8, 8);
    add_field(t, "f", 1, [](const Vec3& p) { return std::vector<double>{p[0] * p[0]}; });
    for (float& x : t.positions) x = x * 250.0f - 3.0f;
    std::vector<float> a = vertex_gradient(s, {}), b = vertex_gradient(t, {});
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-4 * std::max(1.0f, a[i])) << i;
}

// A field that is constant has range 0: it contributes nothing (never NaN or inf).
TEST(Gradient, ConstantFieldGivesZero) {
    Surface s = grid(4, 4);
    add_field(s, "c", 1, [](const Vec3&) { return std::vector<double>{3.5}; });
    expect_values(vertex_gradient(s, {}), std::vector<double>(25, 0.0), 0.0);
}

// ... and does not disturb the others: "c" constant plus f = x gives the f = x result.
TEST(Gradient, ConstantFieldNextToAVaryingOne) {
    Surface s = grid(8, 8);
    add_field(s, "c", 1, [](const Vec3&) { return std::vector<double>{3.5}; });
    add_field(s, "f", 1, [](const Vec3& p) { return std::vector<double>{p[0]}; });
    expect_values(vertex_gradient(s, {}), std::vector<double>(81, kSqrt2));
}

// Neighbours do not depend on orientation either.
TEST(Gradient, IndependentOfOrientation) {
    Surface s = grid(8, 8);
    add_field(s, "f", 1, [](const Vec3& p) { return std::vector<double>{p[0]}; });
    expect_values(vertex_gradient(flipped(s, [](size_t t) { return t % 2 == 1; }), {}),
                  std::vector<double>(81, kSqrt2));
}

TEST(Gradient, NoFieldsGivesZero) {
    expect_values(vertex_gradient(grid(3, 3), {}), std::vector<double>(16, 0.0), 0.0);
}

} // namespace
} // namespace ddsimp::test
