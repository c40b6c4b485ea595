// The library's input checks: ddsimp::validate on surfaces built from the bytes must either
// throw InputError or leave a surface the rest of the library takes: indices in range, no
// degenerate or duplicate triangle, and a simplification that keeps the topology it promises.
#include "fuzz_check.h"
#include "fuzz_input.h"
#include "fuzz_surface.h"

#include <algorithm>
#include <array>
#include <set>

using namespace ddsimp;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz::FuzzInput in(data, size);
    Options options;
    options.alpha = double(in.take<uint8_t>() % 5) / 4;
    options.strategy = in.take<uint8_t>() & 1 ? Strategy::VertexRemoval : Strategy::EdgeCollapse;
    options.placement = in.take<uint8_t>() & 1 ? Placement::VolumePreserving : Placement::Midpoint;
    options.keep_fraction = double(in.take<uint8_t>() % 11) / 10;
    options.feature_angle = in.take<uint8_t>() & 1 ? 45.0 : 180.0;
    Surface surface = fuzz::surface_from(in);

    const Surface input = surface;
    RepairReport report;
    try {
        report = validate(surface);
    } catch (const InputError&) {
        return 0;
    }
    FUZZ_CHECK(surface.positions == input.positions);
    FUZZ_CHECK(!surface.triangles.empty());
    FUZZ_CHECK(surface.triangle_count() + report.degenerate_triangles_dropped +
                   report.duplicate_triangles_dropped ==
               input.triangle_count());
    std::set<std::array<uint32_t, 3>> seen;
    for (size_t t = 0; t < surface.triangles.size(); t += 3) {
        std::array<uint32_t, 3> k{surface.triangles[t], surface.triangles[t + 1],
                                  surface.triangles[t + 2]};
        for (uint32_t v : k) FUZZ_CHECK(v < surface.vertex_count());
        std::sort(k.begin(), k.end());
        FUZZ_CHECK(k[0] != k[1] && k[1] != k[2]);
        FUZZ_CHECK(seen.insert(k).second);
    }
    // A second pass finds nothing left to drop.
    Surface again = surface;
    const RepairReport second = validate(again);
    FUZZ_CHECK(second.degenerate_triangles_dropped + second.duplicate_triangles_dropped == 0);

    const Topology topology = analyze_topology(surface);
    FUZZ_CHECK(vertex_curvature(surface).size() == surface.vertex_count());
    FUZZ_CHECK(vertex_gradient(surface, {}).size() == surface.vertex_count());

    const Result result = simplify(input, options);
    FUZZ_CHECK(result.triangles_in == surface.triangle_count());
    FUZZ_CHECK(result.triangles_out == result.surface.triangle_count());
    FUZZ_CHECK(result.triangles_out <= result.triangles_in);
    const Topology after = analyze_topology(result.surface);
    FUZZ_CHECK(after.euler_characteristic == topology.euler_characteristic);
    FUZZ_CHECK(after.boundary_loops == topology.boundary_loops);
    FUZZ_CHECK(after.components == topology.components);
    FUZZ_CHECK(after.nonmanifold_edges <= topology.nonmanifold_edges);
    return 0;
}
