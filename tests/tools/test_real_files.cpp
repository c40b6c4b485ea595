// Reading the real files of the shared data set; the expected counts are the data README's.
#include "tools_test_support.h"

#include "ddsimp/io/surface_io.h"

#include <fstream>

using namespace ddsimp;
using namespace ddsimp::tools_test;

namespace {

Topology topology_of(Surface s) {
    validate(s);
    return analyze_topology(s);
}

} // namespace

TEST(RealFiles, SurfaceVectorsLegacyUnstructuredGrid) {
    const std::string path = shared_data("surfaces/SurfaceVectors.vtk");
    DDSIMP_REQUIRE_SHARED(path);
    const Surface s = io::read_surface(path);
    EXPECT_EQ(s.vertex_count(), 434u);
    EXPECT_EQ(s.triangle_count(), 756u);
    ASSERT_EQ(s.fields.size(), 7u);
    for (const char* name : {"V", "Temp", "Pres", "AsH3", "GaMe3", "CH4", "H2"})
        EXPECT_NE(s.find_field(name), nullptr) << name;
    EXPECT_EQ(s.find_field("V")->components, 3);
    EXPECT_EQ(topology_of(s).boundary_edges, 110u);
}

TEST(RealFiles, SampleInTheRepositoryIsTheSameSurface) {
    const Surface s = io::read_surface(sample_surface());
    EXPECT_EQ(s.vertex_count(), 434u);
    EXPECT_EQ(s.triangle_count(), 756u);
    EXPECT_EQ(s.fields.size(), 7u);
}

TEST(RealFiles, EarthXmlPolyDataIsAClosedSphere) {
    const std::string path = shared_data("surfaces/earth.vtp");
    DDSIMP_REQUIRE_SHARED(path);
    const Surface s = io::read_surface(path);
    EXPECT_EQ(s.vertex_count(), 40962u);
    EXPECT_EQ(s.triangle_count(), 81920u);
    ASSERT_NE(s.find_field("bottomDepth"), nullptr);
    const Topology t = topology_of(s);
    EXPECT_EQ(t.boundary_edges, 0u);
    EXPECT_EQ(t.euler_characteristic, 2);
}

TEST(RealFiles, FandiskOff) {
    const std::string path = shared_data("geometry/fandisk.off");
    DDSIMP_REQUIRE_SHARED(path);
    const Surface s = io::read_surface(path);
    EXPECT_EQ(s.vertex_count(), 6475u);
    EXPECT_EQ(s.triangle_count(), 12946u);
    EXPECT_TRUE(s.fields.empty());
}

TEST(RealFiles, ArmadilloOffIsClosed) {
    const std::string path = shared_data("geometry/armadillo.off");
    DDSIMP_REQUIRE_SHARED(path);
    const Surface s = io::read_surface(path);
    EXPECT_EQ(s.vertex_count(), 26002u);
    EXPECT_EQ(s.triangle_count(), 52000u);
    EXPECT_EQ(topology_of(s).boundary_edges, 0u);
}

TEST(RealFiles, BunnyPlyWithItsVertexProperties) {
    const std::string path = shared_data("geometry/bunny.ply");
    DDSIMP_REQUIRE_SHARED(path);
    const Surface s = io::read_surface(path);
    EXPECT_EQ(s.vertex_count(), 35947u);
    EXPECT_EQ(s.triangle_count(), 69451u);
    // The header declares "property float confidence" and "property float intensity".
    EXPECT_NE(s.find_field("confidence"), nullptr);
    EXPECT_NE(s.find_field("intensity"), nullptr);
    EXPECT_EQ(topology_of(s).boundary_edges, 223u);
}

// The OpenFOAM cutting plane repeats 36,421 triangles and has non-manifold edges; OpenMesh's own
// importer would split or drop those faces. Every triangle must arrive.
TEST(RealFiles, MotorBikeCuttingPlaneKeepsItsNonManifoldTriangles) {
    const std::string path = shared_data("surfaces/motorBike_cuttingPlane_500/p_yNormal.vtk");
    DDSIMP_REQUIRE_SHARED(path);
    const Surface s = io::read_surface(path);
    EXPECT_EQ(s.vertex_count(), 28504u);
    EXPECT_EQ(s.triangle_count(), 89466u);
    ASSERT_NE(s.find_field("p"), nullptr);

    ScratchDir dir;
    for (const char* ext : {".ply", ".off", ".obj"}) {
        io::write_surface(s, dir.file(std::string("bike") + ext));
        const Surface back = io::read_surface(dir.file(std::string("bike") + ext));
        EXPECT_EQ(back.triangles, s.triangles) << ext;
    }
}

TEST(RealFiles, StlFromOurOwnPlyOfFandisk) {
    // No STL in the data set: write one by hand from fandisk (binary STL: 80-byte header, count,
    // 50 bytes per facet), then read it back through OpenMesh.
    const std::string path = shared_data("geometry/fandisk.off");
    DDSIMP_REQUIRE_SHARED(path);
    const Surface s = io::read_surface(path);
    ScratchDir dir;
    const std::string stl = dir.file("fandisk.stl");
    {
        std::ofstream out(stl, std::ios::binary);
        const char header[80] = "binary STL written by the ddsimp tests";
        out.write(header, 80);
        const uint32_t count = uint32_t(s.triangle_count());
        out.write(reinterpret_cast<const char*>(&count), 4);
        for (size_t t = 0; t < s.triangle_count(); ++t) {
            const float normal[3] = {0, 0, 0};
            out.write(reinterpret_cast<const char*>(normal), 12);
            for (int c = 0; c < 3; ++c)
                out.write(reinterpret_cast<const char*>(&s.positions[3 * s.triangles[3 * t + c]]),
                          12);
            const uint16_t attributes = 0;
            out.write(reinterpret_cast<const char*>(&attributes), 2);
        }
    }
    const Surface back = io::read_surface(stl);
    EXPECT_EQ(back.triangle_count(), 12946u);
    EXPECT_EQ(back.vertex_count(), 6475u); // STL repeats corners; equal points are merged
    EXPECT_EQ(topology_of(back).euler_characteristic, topology_of(s).euler_characteristic);
}
