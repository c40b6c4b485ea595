// analyze_topology on every builder of test_surfaces.h, against counts derived by hand from each
// construction (the derivations are next to the builders and in the table below).
#include "test_surfaces.h"

namespace ddsimp::test {
namespace {

// --- The builders themselves (these tests do not touch the library) ------------------------

TEST(TestSurfaces, ClosedBuildersAreOutwardWithTheirKnownVolume) {
    // regular tetrahedron with edge a = 2 sqrt 2: a^3 / (6 sqrt 2) = 16 sqrt 2 / (6 sqrt 2) = 8/3
    EXPECT_NEAR(signed_volume(tetrahedron()), 8.0 / 3.0, 1e-6);
    EXPECT_NEAR(signed_volume(corner_tetrahedron()), 1.0 / 6.0, 1e-7);
    EXPECT_NEAR(signed_volume(octahedron()), 4.0 / 3.0, 1e-6);
    EXPECT_NEAR(signed_volume(cube(3)), 8.0, 1e-5);
    // inscribed polyhedra: below the smooth volume, and close to it
    double sphere = 4.0 / 3.0 * kPi;
    EXPECT_LT(signed_volume(icosphere(3)), sphere);
    EXPECT_GT(signed_volume(icosphere(3)), 0.95 * sphere);
    double torus_volume = 2 * kPi * kPi * 2.0 * 0.75 * 0.75; // 2 pi^2 R r^2
    EXPECT_LT(signed_volume(torus(48, 24)), torus_volume);
    EXPECT_GT(signed_volume(torus(48, 24)), 0.95 * torus_volume);
}

TEST(TestSurfaces, FlatBuildersFaceUp) {
    for (const Surface& s : {single_triangle(), square(), fan(8), grid(5, 3),
                             grid_with_hole(6, 2, 4), bowtie(), corner_touching_grids(3)})
        for (size_t t = 0; t < s.triangle_count(); ++t) EXPECT_GT(triangle_normal(s, t)[2], 0) << t;
}

TEST(TestSurfaces, IndependentNonmanifoldVertexFinder) {
    EXPECT_EQ(nonmanifold_vertex_positions(grid(4, 4)).size(), 0u);
    EXPECT_EQ(nonmanifold_vertex_positions(torus(8, 6)).size(), 0u);
    EXPECT_EQ(nonmanifold_vertex_positions(bowtie()).size(), 1u);
    EXPECT_EQ(nonmanifold_vertex_positions(fin()).size(), 2u);
    EXPECT_EQ(nonmanifold_vertex_positions(corner_touching_grids(3)).size(), 1u);
    EXPECT_EQ(nonmanifold_vertex_positions(fin_on_grid(4)).size(), 2u);
}

// --- analyze_topology -----------------------------------------------------------------------

struct Expected {
    const char* name;
    std::function<Surface()> build;
    size_t vertices, edges, triangles, boundary_edges, nonmanifold_edges, nonmanifold_vertices;
    long long boundary_loops; // -1: not asserted (see AmbiguousLoops below)
    size_t components;
    long long euler;
};
void PrintTo(const Expected& e, std::ostream* os) {
    *os << e.name;
}

std::vector<Expected> expectations() {
    return {
        // name, builder, V, E, F, boundary edges, nm edges, nm vertices, loops, components, V-E+F
        {"SingleTriangle", single_triangle, 3, 3, 1, 3, 0, 0, 1, 1, 1},
        {"Square", square, 4, 5, 2, 4, 0, 0, 1, 1, 1},
        // hexagon fan: 6 spokes + 6 rim edges
        {"HexagonFan", [] { return fan(6); }, 7, 12, 6, 6, 0, 0, 1, 1, 1},
        {"Tetrahedron", tetrahedron, 4, 6, 4, 0, 0, 0, 0, 1, 2},
        {"Octahedron", octahedron, 6, 12, 8, 0, 0, 0, 0, 1, 2},
        // level 1: 10*4+2 = 42 vertices, 30*4 = 120 edges, 20*4 = 80 triangles
        {"Icosphere1", [] { return icosphere(1); }, 42, 120, 80, 0, 0, 0, 0, 1, 2},
        // 4x3 grid: 5*4 = 20 vertices; 4*4 horizontal + 3*5 vertical + 12 diagonal = 43 edges;
        // 24 triangles; boundary 2*(4+3) = 14
        {"Grid4x3", [] { return grid(4, 3); }, 20, 43, 24, 14, 0, 0, 1, 1, 1},
        // cube n=3: 6*9+2 = 56, 18*9 = 162, 12*9 = 108
        {"Cube3", [] { return cube(3); }, 56, 162, 108, 0, 0, 0, 0, 1, 2},
        // torus 8x6: 48, 144, 96
        {"Torus8x6", [] { return torus(8, 6); }, 48, 144, 96, 0, 0, 0, 0, 1, 0},
        // two 2x2 grids: 2*9, 2*16, 2*8, boundary 2*8
        {"TwoComponents", [] { return two_components(2); }, 18, 32, 16, 16, 0, 0, 2, 2, 2},
        // 6x6 grid minus the 2x2 centre: 48 used vertices (the centre (3,3) is unused), 64
        // triangles; edges: horizontal 42-2, vertical 42-2, diagonal 32 = 112; boundary
        // 24 outer + 8 inner; Euler 48 - 112 + 64 = 0
        {"GridWithHole", [] { return grid_with_hole(6, 2, 4); }, 48, 112, 64, 32, 0, 0, 2, 1, 0},
        {"Bowtie", bowtie, 7, 10, 4, 8, 0, 1, -1, 2, 1},
        {"Fin", fin, 5, 7, 3, 6, 1, 2, -1, 1, 1},
        // 4x4 grid (25, 56, 32, boundary 16) + apex, 2 edges, 1 triangle on an interior edge: the
        // two new edges are boundary edges
        {"FinOnGrid", [] { return fin_on_grid(4); }, 26, 58, 33, 18, 1, 2, -1, 1, 1},
        // 4x4 grid + a tetrahedron on an interior edge: 2 vertices, 5 edges (all inner) and 4
        // triangles more; that edge has 4 triangles
        {"TetrahedronOnGrid", [] { return tetrahedron_on_grid(4); }, 27, 61, 36, 16, 1, 2, -1, 1,
         2},
        // two 3x3 grids (16, 33, 18, boundary 12 each) sharing one vertex
        {"CornerTouchingGrids", [] { return corner_touching_grids(3); }, 31, 66, 36, 24, 0, 1, -1,
         2, 1},
        // Moebius n=8: 16, 32, 16, boundary 16 in one loop (the strip's edge goes round twice)
        {"Moebius", [] { return moebius(8); }, 16, 32, 16, 16, 0, 0, 1, 1, 0},
    };
}

class TopologyOf : public ::testing::TestWithParam<Expected> {};

TEST_P(TopologyOf, MatchesHandCount) {
    const Expected& e = GetParam();
    Topology t = analyze_topology(e.build());
    EXPECT_EQ(t.vertices, e.vertices);
    EXPECT_EQ(t.edges, e.edges);
    EXPECT_EQ(t.triangles, e.triangles);
    EXPECT_EQ(t.boundary_edges, e.boundary_edges);
    EXPECT_EQ(t.nonmanifold_edges, e.nonmanifold_edges);
    EXPECT_EQ(t.nonmanifold_vertices, e.nonmanifold_vertices);
    if (e.boundary_loops >= 0) {
        EXPECT_EQ(t.boundary_loops, size_t(e.boundary_loops));
    }
    EXPECT_EQ(t.components, e.components);
    EXPECT_EQ(t.euler_characteristic, e.euler);
    // V - E + F as documented, from the struct's own counts
    EXPECT_EQ(t.euler_characteristic,
              (long long)t.vertices - (long long)t.edges + (long long)t.triangles);
}

INSTANTIATE_TEST_SUITE_P(Builders, TopologyOf, ::testing::ValuesIn(expectations()),
                         [](const ::testing::TestParamInfo<Expected>& i) {
                             return std::string(i.param.name);
                         });

// Boundary loops where boundary edges meet at a non-manifold vertex (bowtie centre, fin ends)
// are not defined by the header ("closed loops of boundary edges"): the bowtie's 8 boundary
// edges are one closed walk through the centre or two loops, one per fan. Only the manifold
// cases are pinned down in the table; here only 1 or 2 is accepted for the bowtie. (The fin's
// boundary has two vertices of degree 3, so it has no decomposition into closed loops at all;
// nothing is asserted for it.)
TEST(Topology, BowtieLoopsAreOneOrTwo) {
    Topology bow = analyze_topology(bowtie());
    EXPECT_GE(bow.boundary_loops, 1u);
    EXPECT_LE(bow.boundary_loops, 2u);
}

// Two tetrahedra sharing one vertex: 7 vertices, 12 edges, 8 triangles, Euler 3, 2 components
// (edge-connected), the shared vertex is non-manifold (two disks).
TEST(Topology, TwoTetrahedraTouchingAtAVertex) {
    Surface s = tetrahedron();
    Surface t = tetrahedron();
    // move t so that its vertex 0 (1,1,1) lands on s's vertex 0 mirrored: translate by (2,2,2)
    // and reflect, i.e. map p -> (2,2,2) - p; (1,1,1) -> (1,1,1).
    for (float& x : t.positions) x = 2.0f - x;
    for (size_t k = 0; k < t.triangle_count(); ++k)
        std::swap(t.triangles[3 * k + 1], t.triangles[3 * k + 2]);
    uint32_t offset = uint32_t(s.vertex_count()) - 1; // t's vertices 1..3 -> 4..6, t's 0 -> 0
    for (size_t v = 1; v < t.vertex_count(); ++v)
        s.positions.insert(s.positions.end(), t.positions.begin() + 3 * v,
                           t.positions.begin() + 3 * v + 3);
    for (uint32_t i : t.triangles) s.triangles.push_back(i == 0 ? 0 : i + offset);
    Topology topo = analyze_topology(s);
    EXPECT_EQ(topo.vertices, 7u);
    EXPECT_EQ(topo.edges, 12u);
    EXPECT_EQ(topo.triangles, 8u);
    EXPECT_EQ(topo.boundary_edges, 0u);
    EXPECT_EQ(topo.nonmanifold_edges, 0u);
    EXPECT_EQ(topo.nonmanifold_vertices, 1u);
    EXPECT_EQ(topo.components, 2u);
    EXPECT_EQ(topo.euler_characteristic, 3);
}

// Four triangles on one edge: still one non-manifold edge (three or more triangles).
TEST(Topology, FourTrianglesOnOneEdge) {
    Surface s = fin();
    uint32_t apex = add_vertex(s, 0.5, 0, -1);
    add_triangle(s, 1, 0, apex);
    Topology t = analyze_topology(s);
    EXPECT_EQ(t.nonmanifold_edges, 1u);
    EXPECT_EQ(t.edges, 9u); // 7 + 2
    EXPECT_EQ(t.boundary_edges, 8u);
    EXPECT_EQ(t.euler_characteristic, 6 - 9 + 4);
}

// Orientation plays no part in the counts: a sphere with every other triangle flipped has the
// same topology.
TEST(Topology, IndependentOfOrientation) {
    Topology a = analyze_topology(icosphere(2));
    Topology b = analyze_topology(flipped(icosphere(2), [](size_t t) { return t % 2 == 1; }));
    EXPECT_EQ(b.edges, a.edges);
    EXPECT_EQ(b.boundary_edges, 0u);
    EXPECT_EQ(b.nonmanifold_edges, 0u);
    EXPECT_EQ(b.nonmanifold_vertices, 0u);
    EXPECT_EQ(b.components, 1u);
    EXPECT_EQ(b.euler_characteristic, 2);
}

// Unused vertices do not count, also in the Euler characteristic.
TEST(Topology, UnusedVerticesAreNotCounted) {
    Surface s = tetrahedron();
    add_vertex(s, 5, 5, 5);
    add_vertex(s, 6, 6, 6);
    Topology t = analyze_topology(s);
    EXPECT_EQ(t.vertices, 4u);
    EXPECT_EQ(t.euler_characteristic, 2);
    EXPECT_EQ(t.components, 1u);
}

} // namespace
} // namespace ddsimp::test
