// Shared by the client tests: comparing meshes whose vertices are numbered differently.
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

// Byte-equal surfaces: same positions, triangles and fields in the same order.
inline bool identical(const Surface& a, const Surface& b) {
    if (a.positions != b.positions || a.triangles != b.triangles ||
        a.fields.size() != b.fields.size())
        return false;
    for (size_t f = 0; f < a.fields.size(); ++f)
        if (a.fields[f].name != b.fields[f].name ||
            a.fields[f].components != b.fields[f].components ||
            a.fields[f].values != b.fields[f].values)
            return false;
    return true;
}

} // namespace ddsimp::test
