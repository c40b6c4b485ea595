// Edge collapse on CAD-like parts (flat faces, sharp rims): at 10 %, with the geometry alone
// (alpha = 1), within twice the Hausdorff distance of OpenMesh's quadric decimater (the classic
// set-up the fidelity report runs), and the topology kept. The parts are generated here.
#include "tools_test_support.h"

#include <ddsimp/io/compare.h>
#include <ddsimp/openmesh.h>

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <cmath>
#include <string>

using namespace ddsimp;

namespace {

constexpr double kPi = 3.14159265358979323846;

void add_quad(Surface& s, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    s.triangles.insert(s.triangles.end(), {a, b, c, a, c, d});
}

// A closed tube (outer radius 1, inner `inner`, height `height`, `segments` around, `rings`
// rows of quads along its sides) tilted by `tilt` radians: two cylinders and two flat annular
// ends meeting them at sharp rims; genus 1.
Surface tilted_tube(uint32_t segments, double inner, double height, uint32_t rings, double tilt) {
    Surface s;
    const double c = std::cos(tilt), sn = std::sin(tilt);
    auto index = [&](uint32_t wall, uint32_t row, uint32_t i) {
        return (wall * (rings + 1) + row) * segments + i % segments;
    };
    for (const double r : {1.0, inner})
        for (uint32_t row = 0; row <= rings; ++row)
            for (uint32_t i = 0; i < segments; ++i) {
                const double t = 2 * kPi * i / segments, z = height * row / rings;
                const double x = r * std::cos(t), y = r * std::sin(t);
                s.positions.insert(s.positions.end(),
                                   {float(x * c + z * sn), float(y), float(-x * sn + z * c)});
            }
    for (uint32_t i = 0; i < segments; ++i) {
        for (uint32_t row = 0; row < rings; ++row) {
            add_quad(s, index(0, row, i), index(0, row, i + 1), index(0, row + 1, i + 1),
                     index(0, row + 1, i));
            add_quad(s, index(1, row, i), index(1, row + 1, i), index(1, row + 1, i + 1),
                     index(1, row, i + 1));
        }
        add_quad(s, index(0, 0, i), index(1, 0, i), index(1, 0, i + 1), index(0, 0, i + 1));
        add_quad(s, index(0, rings, i), index(0, rings, i + 1), index(1, rings, i + 1),
                 index(1, rings, i));
    }
    return s;
}

// A flat body with a curved outline (a guitar-like waist and lobes, `segments` around)
// extruded by `height` in `rings` rows: two flat faces fanned from their centres and a side
// wall meeting them at sharp rims.
Surface extruded_body(uint32_t segments, double height, uint32_t rings) {
    Surface s;
    for (uint32_t row = 0; row <= rings; ++row)
        for (uint32_t i = 0; i < segments; ++i) {
            const double t = 2 * kPi * i / segments;
            const double r =
                1 + 0.25 * std::cos(2 * t) - 0.15 * std::cos(4 * t) + 0.1 * std::sin(3 * t);
            s.positions.insert(s.positions.end(),
                               {float(1.3 * r * std::cos(t)), float(r * std::sin(t)),
                                float(height * row / rings)});
        }
    const uint32_t bottom = uint32_t(s.vertex_count()), top = bottom + 1;
    double cx = 0, cy = 0;
    for (uint32_t i = 0; i < segments; ++i) cx += s.positions[3 * i], cy += s.positions[3 * i + 1];
    cx /= segments, cy /= segments;
    s.positions.insert(s.positions.end(), {float(cx), float(cy), 0.0f});
    s.positions.insert(s.positions.end(), {float(cx), float(cy), float(height)});
    for (uint32_t i = 0; i < segments; ++i) {
        const uint32_t j = (i + 1) % segments;
        s.triangles.insert(s.triangles.end(), {bottom, j, i});
        s.triangles.insert(s.triangles.end(), {top, rings * segments + i, rings * segments + j});
        for (uint32_t row = 0; row < rings; ++row)
            add_quad(s, row * segments + i, row * segments + j, (row + 1) * segments + j,
                     (row + 1) * segments + i);
    }
    return s;
}

// OpenMesh's Decimater with a quadric priority and a normal-flip guard, to `target` triangles.
Surface openmesh_reduction(const Surface& input, size_t target) {
    TriMesh mesh = to_openmesh(input);
    using Decimater = OpenMesh::Decimater::DecimaterT<TriMesh>;
    mesh.request_face_normals();
    mesh.update_face_normals();
    Decimater decimater(mesh);
    OpenMesh::Decimater::ModQuadricT<TriMesh>::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<TriMesh>::Handle flipping;
    decimater.add(quadric);
    decimater.add(flipping);
    decimater.module(quadric).unset_max_err();
    decimater.initialize();
    decimater.decimate_to_faces(0, target);
    mesh.garbage_collection();
    return from_openmesh(mesh);
}

long euler(const Surface& s) {
    std::vector<uint8_t> used(s.vertex_count(), 0);
    for (uint32_t v : s.triangles) used[v] = 1;
    long vertices = 0;
    for (uint8_t u : used) vertices += u;
    // Closed: every edge in two triangles, E = 3F / 2.
    return vertices - long(3 * s.triangle_count() / 2) + long(s.triangle_count());
}

void expect_within_twice_openmesh(const Surface& part, long genus) {
    ASSERT_EQ(euler(part), 2 - 2 * genus);
    Options options;
    options.strategy = Strategy::EdgeCollapse;
    options.alpha = 1;
    options.keep_fraction = 0.1;
    const Result ours = simplify(part, options);
    const size_t target = target_triangles(options, part.triangle_count());
    ASSERT_LE(ours.triangles_out, target);
    EXPECT_EQ(euler(ours.surface), euler(part)); // the topology kept
    const Surface theirs = openmesh_reduction(part, target);
    ASSERT_LE(theirs.triangle_count(), target);
    const double d_ours = tools::compare_surfaces(part, ours.surface, {}).distance.symmetric.max;
    const double d_theirs = tools::compare_surfaces(part, theirs, {}).distance.symmetric.max;
    ASSERT_GT(d_theirs, 0);
    EXPECT_LE(d_ours, 2 * d_theirs) << "Hausdorff distance " << d_ours << " against OpenMesh's "
                                    << d_theirs << " at " << ours.triangles_out << " triangles";
}

} // namespace

TEST(CadShapes, TiltedTubeWithinTwiceOpenMesh) {
    for (const uint32_t segments : {24u, 48u, 64u})
        for (const double tilt : {0.3, 0.9}) {
            SCOPED_TRACE("segments " + std::to_string(segments) + ", tilt " + std::to_string(tilt));
            expect_within_twice_openmesh(tilted_tube(segments, 0.5, 1.5, 2, tilt), 1);
        }
}

TEST(CadShapes, ExtrudedBodyWithinTwiceOpenMesh) {
    for (const uint32_t segments : {24u, 48u, 96u})
        for (const double height : {0.1, 0.3}) {
            SCOPED_TRACE("segments " + std::to_string(segments) + ", height " +
                         std::to_string(height));
            expect_within_twice_openmesh(extruded_body(segments, height, 4), 0);
        }
}
