// Vertex removal's record followed point by point: the triangle that covers each removed input
// vertex, removal after removal (docs/algorithm.md, "The error of a level").
#pragma once

#include "working_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace ddsimp::detail {

// Where each removed input vertex lies as the removals go on: on the closest of the triangles
// that replaced its star, and when a later removal rewrites that triangle, on the closest of the
// triangles that removal writes. Triangles equally near (within `tie`: the point is on their
// shared edge or corner) go by their corners' ids, so that which one covers a point is part of
// the definition, not of the order of the record's writes. Each point's path reads only the
// record, so points can be followed on any threads, in any order.
class RemovalCover {
public:
    static constexpr uint32_t kNone = 0xffffffffu;

    // The record's first `operations` removals: operation i wrote writes[write_begin[i] ..
    // write_begin[i + 1]), each write {slot, a, b, c} (a == kNone retires the slot), over the
    // input's `triangles` (one slot each) and `vertices` vertices.
    RemovalCover(const std::vector<uint32_t>& triangles, size_t vertices,
                 const std::vector<uint32_t>& write_begin, const std::vector<uint32_t>& writes,
                 size_t operations);

    // Follows input vertex p from its removal (nothing if the removals keep it), calling
    // landed(operation, write, weights, distance) each time it lands: on the triangle `write`
    // wrote (writes[write + 1 .. write + 4)), with `weights` on its corners, at `distance`.
    // Returns the write whose triangle covers p after the last removal, or kNone (p is kept, or
    // a removal left no triangle where it was). `point(v)` is vertex v's position, in the units
    // of `tie`.
    template <class Point, class Landed>
    uint32_t follow(uint32_t p, const Point& point, double tie, Landed&& landed) const {
        uint32_t operation = removed_at_[p];
        uint32_t cover = kNone;
        while (operation != kNone) {
            const Vec3 x = point(p);
            double best = std::numeric_limits<double>::infinity();
            std::array<double, 3> weights{};
            cover = kNone;
            for (uint32_t w = write_begin_[operation]; w < write_begin_[operation + 1]; w += 4) {
                if (writes_[w + 1] == kNone) continue;
                const Vec3 a = point(writes_[w + 1]), b = point(writes_[w + 2]),
                           c = point(writes_[w + 3]);
                const std::array<double, 3> l = closest_on_triangle(x, a, b, c).weights;
                const Vec3 q = add(add(scale(a, l[0]), scale(b, l[1])), scale(c, l[2]));
                const double distance = norm(sub(q, x));
                const bool tied = cover != kNone && std::abs(distance - best) <= tie;
                if (tied ? sorted_corners(w) < sorted_corners(cover) : distance < best)
                    best = distance, cover = w, weights = l;
            }
            if (cover == kNone) return kNone; // the star's triangles are gone, and so is p's
            landed(operation, cover, weights, best);
            const uint32_t next = next_write_[cover / 4];
            operation = next == kNone ? kNone : operation_[next / 4];
        }
        return cover;
    }

private:
    std::array<uint32_t, 3> sorted_corners(uint32_t w) const {
        std::array<uint32_t, 3> c{writes_[w + 1], writes_[w + 2], writes_[w + 3]};
        std::sort(c.begin(), c.end());
        return c;
    }

    const std::vector<uint32_t>& write_begin_;
    const std::vector<uint32_t>& writes_;
    // Per input vertex: the removal that took it (kNone: kept). Per write: the next write to the
    // same slot among the first `operations` removals (kNone: none), as a write's offset, and the
    // removal it belongs to.
    std::vector<uint32_t> removed_at_, next_write_, operation_;
};

} // namespace ddsimp::detail
