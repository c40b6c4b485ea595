// Shared by the service tests: comparing meshes that travelled, whose vertices may be numbered
// differently (progressive refinements) or whose triangles may start at another corner (meshopt).
#pragma once

#include <ddsimp/ddsimp.h>

#include <algorithm>
#include <set>
#include <vector>

namespace ddsimp::test {

// A triangle as the positions and field values of its corners, starting at its smallest
// corner (orientation kept), so meshes with different vertex numbering compare equal.
using Corner = std::vector<float>;
using CornerTriangle = std::vector<Corner>;

inline std::multiset<CornerTriangle> triangles_by_content(const Surface& s) {
    std::multiset<CornerTriangle> out;
    for (size_t t = 0; t + 2 < s.triangles.size(); t += 3) {
        CornerTriangle tri;
        for (int c = 0; c < 3; ++c) {
            const uint32_t v = s.triangles[t + c];
            Corner corner(&s.positions[3 * v], &s.positions[3 * v + 3]);
            for (const Field& f : s.fields)
                corner.insert(corner.end(), &f.values[size_t(v) * f.components],
                              &f.values[size_t(v + 1) * f.components]);
            tri.push_back(corner);
        }
        std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
        out.insert(tri);
    }
    return out;
}

// Turns each triangle of `s` to start at the corner the same triangle of `like` starts at, if it
// is the same triangle (meshopt's index codec may rotate a triangle; orientation is kept).
// Vertices and the order of triangles are left alone, so same_bytes still checks them.
inline void rotate_to_match(Surface& s, const Surface& like) {
    if (s.triangles.size() != like.triangles.size()) return;
    for (size_t t = 0; t < s.triangles.size(); t += 3)
        for (int r = 0; r < 2 && s.triangles[t] != like.triangles[t]; ++r)
            std::rotate(&s.triangles[t], &s.triangles[t + 1], &s.triangles[t + 3]);
}

} // namespace ddsimp::test
