// The data and distance errors of a reduction measured by brute force, independent of the
// library's level error: every vertex of each surface against the other surface at its closest
// point.
#pragma once

#include "test_surfaces.h"
#include "working_mesh.h"

#include <array>
#include <cmath>
#include <limits>

namespace ddsimp::test {

// A sphere with a field that varies faster than the reduced surface can follow.
inline Surface wavy_sphere() {
    Surface s = icosphere(4); // 5120 triangles
    add_field(s, "wave", 1, [](const Vec3& p) {
        return std::vector<double>{std::sin(4 * p[0]) * std::cos(3 * p[1]) + p[2] * p[2]};
    });
    return s;
}

// The point of `s` closest to p (every triangle tried): its triangle, its barycentric weights and
// its squared distance to p.
struct ClosestOn {
    size_t triangle = 0;
    std::array<double, 3> weights{};
    double squared_distance = std::numeric_limits<double>::infinity();
};
inline ClosestOn closest_on(const Surface& s, const Vec3& p) {
    ClosestOn best;
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        const auto c = corners(s, t);
        const detail::ClosestPoint q =
            detail::closest_on_triangle(p, position(s, c[0]), position(s, c[1]), position(s, c[2]));
        const Vec3 d = q.point - p;
        if (dot(d, d) < best.squared_distance) best = {t, q.weights, dot(d, d)};
    }
    return best;
}

// The field's value at the point of `s` closest to p.
inline double value_at_closest(const Surface& s, const Field& f, const Vec3& p) {
    const ClosestOn q = closest_on(s, p);
    const auto c = corners(s, q.triangle);
    double value = 0;
    for (int k = 0; k < 3; ++k) value += q.weights[size_t(k)] * f.values[c[size_t(k)]];
    return value;
}

// The RMS of the data differences over both sets of samples: every vertex of each surface
// against the other's data at its closest point.
inline double two_way_data_rms(const Surface& input, const Surface& level) {
    const Field& fi = input.fields[0];
    const Field& fl = level.fields[0];
    double sum = 0;
    for (size_t v = 0; v < input.vertex_count(); ++v)
        sum += std::pow(fi.values[v] - value_at_closest(level, fl, position(input, v)), 2);
    for (size_t v = 0; v < level.vertex_count(); ++v)
        sum += std::pow(fl.values[v] - value_at_closest(input, fi, position(level, v)), 2);
    return std::sqrt(sum / double(input.vertex_count() + level.vertex_count()));
}

// The RMS of the distances over both sets of samples: every vertex of each surface to the
// other surface.
inline double two_way_distance_rms(const Surface& input, const Surface& level) {
    double sum = 0;
    for (size_t v = 0; v < input.vertex_count(); ++v)
        sum += closest_on(level, position(input, v)).squared_distance;
    for (size_t v = 0; v < level.vertex_count(); ++v)
        sum += closest_on(input, position(level, v)).squared_distance;
    return std::sqrt(sum / double(input.vertex_count() + level.vertex_count()));
}

} // namespace ddsimp::test
