// Property tests on the real surfaces of the shared data set (DDSIMP_SHARED_DATA): the topology of
// the repaired input is kept, every field is carried within its range, and the 10% target is
// reached on the clean surfaces.
//
// motorBike's cutting plane is the messy one: 36,421 duplicated triangles (dropped by validate),
// 2 zero-area triangles and 144 non-manifold edges that stay after de-duplication, a hole where
// the bike is. For it the target is not required; the test records what happens (stop reason,
// triangles reached) as test properties and on stdout, and still requires the topology and the
// fields to be kept.
#include "test_surfaces.h"

#include "ddsimp/io/surface_io.h"

#include <oneapi/tbb/global_control.h>

#include <cstdio>
#include <filesystem>

namespace ddsimp::test {
namespace {

struct RealSurface {
    const char* name;
    const char* path; // relative to DDSIMP_SHARED_DATA
    bool clean;       // target required, no zero-area triangles in the input
    bool closed;      // closed and outward: the signed volume keeps its sign
};
void PrintTo(const RealSurface& s, std::ostream* os) {
    *os << s.name;
}

std::vector<RealSurface> real_surfaces() {
    return {
        {"SurfaceVectors", "surfaces/SurfaceVectors.vtk", true, false},
        {"earth", "surfaces/earth.vtp", true, true},
        {"fandisk", "geometry/fandisk.off", true, true},
        {"bunny", "geometry/bunny.ply", true, false},
        {"motorBike_p", "surfaces/motorBike_cuttingPlane_500/p_yNormal.vtk", false, false},
    };
}

// Each file is read and repaired once for the whole run.
struct Loaded {
    Surface input;
    Surface repaired;
    RepairReport repairs;
    Topology topology;
};
const Loaded& load(const RealSurface& s) {
    static std::map<std::string, Loaded> cache;
    auto it = cache.find(s.name);
    if (it != cache.end()) return it->second;
    Loaded l;
    l.input = io::read_surface(std::string(DDSIMP_SHARED_DATA) + "/" + s.path);
    l.repaired = l.input;
    l.repairs = validate(l.repaired);
    l.topology = analyze_topology(l.repaired);
    return cache.emplace(s.name, std::move(l)).first->second;
}

class RealSurfaces : public ::testing::TestWithParam<std::tuple<Config, RealSurface>> {};

TEST_P(RealSurfaces, TenPercentKeepsTopologyAndFields) {
    const Config& c = std::get<0>(GetParam());
    const RealSurface& rs = std::get<1>(GetParam());
    if (!std::filesystem::exists(std::string(DDSIMP_SHARED_DATA) + "/" + rs.path))
        GTEST_SKIP() << rs.path << " not found under " << DDSIMP_SHARED_DATA;
    const Loaded& l = load(rs);

    Options o = options_for(c);
    o.keep_fraction = 0.1;
    Result r = simplify(l.input, o);

    const size_t target = size_t(0.1 * double(l.repaired.triangle_count()));
    std::printf(
        "[ %s / %s ] %zu -> %zu triangles (target %zu of the repaired input, %zu of the "
        "file), %zu operations, stop: %s; repairs: %zu degenerate, %zu duplicate, %zu unused, "
        "%zu flipped; "
        "input: %zu nm-edges, %zu nm-vertices, %zu loops, %zu components, euler %lld\n",
        rs.name, c.name, r.triangles_in, r.triangles_out, target,
        size_t(0.1 * double(l.input.triangle_count())), r.operations, describe(r.stop),
        r.repairs.degenerate_triangles_dropped, r.repairs.duplicate_triangles_dropped,
        r.repairs.unused_vertices, r.repairs.triangles_flipped, l.topology.nonmanifold_edges,
        l.topology.nonmanifold_vertices, l.topology.boundary_loops, l.topology.components,
        l.topology.euler_characteristic);
    RecordProperty("triangles_out", std::to_string(r.triangles_out));
    RecordProperty("stop", describe(r.stop));

    EXPECT_TRUE(well_formed(r.surface, rs.clean));
    EXPECT_TRUE(topology_kept(l.topology, analyze_topology(r.surface)));
    EXPECT_TRUE(fields_carried(l.repaired, r.surface));
    EXPECT_EQ(r.triangles_out, r.surface.triangle_count());
    EXPECT_EQ(r.repairs.duplicate_triangles_dropped, l.repairs.duplicate_triangles_dropped);
    EXPECT_EQ(r.repairs.degenerate_triangles_dropped, l.repairs.degenerate_triangles_dropped);
    if (rs.clean) {
        EXPECT_TRUE(r.target_reached) << describe(r.stop);
        EXPECT_EQ(r.stop, StopReason::TargetReached);
        // "at or below this fraction of the input's triangles"
        EXPECT_LE(double(r.triangles_out), 0.1 * double(l.input.triangle_count()));
    } else {
        // whatever happened is reported truthfully
        EXPECT_EQ(r.target_reached, r.stop == StopReason::TargetReached);
    }
    if (rs.closed) {
        EXPECT_GT(signed_volume(r.surface) * signed_volume(l.repaired), 0);
    }
}

// Real surfaces, with their ties and repairs, give the same bytes on one thread and on many. The
// thread counts are allowed beyond the machine's cores, so that they really run that wide.
TEST_P(RealSurfaces, ThreadCountDoesNotMatter) {
    const Config& c = std::get<0>(GetParam());
    const RealSurface& rs = std::get<1>(GetParam());
    if (!std::filesystem::exists(std::string(DDSIMP_SHARED_DATA) + "/" + rs.path))
        GTEST_SKIP() << rs.path << " not found under " << DDSIMP_SHARED_DATA;
    oneapi::tbb::global_control allow(oneapi::tbb::global_control::max_allowed_parallelism, 13);
    Options o = options_for(c);
    o.keep_fraction = 0.25;
    o.threads = 1;
    const Result one = simplify(load(rs).input, o);
    for (int threads : {3, 12}) {
        o.threads = threads;
        const Result many = simplify(load(rs).input, o);
        EXPECT_TRUE(same_bytes(one.surface, many.surface)) << threads << " threads";
        EXPECT_EQ(one.operations, many.operations) << threads << " threads";
    }
}

// Every field of the file reaches the reader (a check of the test's own premise).
TEST(RealSurfaceFiles, FieldsAsDocumented) {
    if (!std::filesystem::exists(std::string(DDSIMP_SHARED_DATA) + "/surfaces/SurfaceVectors.vtk"))
        GTEST_SKIP();
    const Loaded& sv = load(real_surfaces()[0]);
    EXPECT_EQ(sv.input.vertex_count(), 434u);
    EXPECT_EQ(sv.input.triangle_count(), 756u);
    // V(3), Temp, Pres, AsH3, GaMe3, CH4, H2 (shared/data/README.md)
    for (const char* name : {"V", "Temp", "Pres", "AsH3", "GaMe3", "CH4", "H2"})
        EXPECT_NE(sv.input.find_field(name), nullptr) << name;
    const Loaded& earth = load(real_surfaces()[1]);
    EXPECT_EQ(earth.input.triangle_count(), 81920u);
    EXPECT_NE(earth.input.find_field("bottomDepth"), nullptr);
    EXPECT_EQ(earth.topology.boundary_edges, 0u);
    EXPECT_EQ(earth.topology.euler_characteristic, 2);
}

// The earth is a sphere carrying the ocean's depth, whose coastlines are steep. Below alpha = 1
// the data's error may pull edge collapse's least-error point off its edge, but not off the
// sphere by more than the sphere bulges between the edge's ends: at 10%, every output vertex
// stays within 2% of the radius. Version 12 left them up to 6.1% off at alpha = 0 and 3.8% at
// alpha = 0.5 (this version: 0.8% and 0.4%).
TEST(RealSurfaceFiles, EdgeCollapseKeepsTheEarthRound) {
    const Loaded& earth = load(real_surfaces()[1]);
    const double radius = norm(position(earth.repaired, 0));
    for (double alpha : {0.0, 0.5}) {
        Options o;
        o.strategy = Strategy::EdgeCollapse;
        o.alpha = alpha;
        o.keep_fraction = 0.1;
        const Result r = simplify(earth.input, o);
        ASSERT_TRUE(r.target_reached);
        double farthest = 0;
        for (size_t v = 0; v < r.surface.vertex_count(); ++v)
            farthest = std::max(farthest, std::abs(norm(position(r.surface, v)) / radius - 1));
        EXPECT_LT(farthest, 0.02) << "alpha " << alpha;
    }
}

INSTANTIATE_TEST_SUITE_P(All, RealSurfaces,
                         ::testing::Combine(::testing::ValuesIn(all_configs()),
                                            ::testing::ValuesIn(real_surfaces())),
                         [](const ::testing::TestParamInfo<std::tuple<Config, RealSurface>>& i) {
                             return std::string(std::get<0>(i.param).name) + "_" +
                                    std::get<1>(i.param).name;
                         });

} // namespace
} // namespace ddsimp::test
