// Vertex removal's record replayed removal by removal, with the triangle that covers each removed
// input vertex (docs/algorithm.md, "The error of a level").
#pragma once

#include "working_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace ddsimp::detail {

// The record's triangle slots as the removals rewrite them, and where each removed input vertex
// lies: on the closest of the triangles that replaced its star, and when a later removal
// rewrites that triangle, on the closest of the new ones. Triangles equally near (within `tie`:
// the point is on their shared edge or corner) go by their corners' ids, so that which one
// covers a point is part of the definition, not of the order of the record's writes.
// `point(v)` gives vertex v's position, in the units of `tie`.
template <class Point>
class RemovalCover {
public:
    static constexpr uint32_t kDead = 0xffffffffu;

    RemovalCover(std::vector<uint32_t> triangles, size_t vertices, Point point, double tie)
        : slots_(std::move(triangles)), head_(slots_.size() / 3, kDead), next_(vertices, kDead),
          cover_(vertices, kDead), weights_(vertices), point_(std::move(point)), tie_(tie) {}

    // Applies one removal's writes [w, end), each {slot, a, b, c} (a == kDead retires the slot),
    // then lands anew the removed vertex and the points on the rewritten triangles, calling
    // landed(p, distance) for each, in order.
    template <class Landed>
    void apply(const uint32_t* w, const uint32_t* end, Landed&& landed) {
        before_.clear(), after_.clear(), points_.clear();
        for (; w < end; w += 4) {
            const size_t at = 3 * size_t(w[0]);
            if (at >= slots_.size()) slots_.resize(at + 3, kDead), head_.resize(at / 3 + 1, kDead);
            if (slots_[at] != kDead) before_.insert(before_.end(), &slots_[at], &slots_[at] + 3);
            for (uint32_t p = head_[w[0]]; p != kDead; p = next_[p])
                points_.push_back(p), cover_[p] = kDead;
            head_[w[0]] = kDead;
            if (w[1] != kDead) after_.push_back(w[0]);
            std::copy(w + 1, w + 4, &slots_[at]);
        }
        // The removed vertex: named by the star's old triangles, not by the new ones.
        std::sort(before_.begin(), before_.end());
        before_.erase(std::unique(before_.begin(), before_.end()), before_.end());
        for (uint32_t v : before_) {
            bool kept = false;
            for (uint32_t t : after_) {
                const uint32_t* c = &slots_[3 * size_t(t)];
                kept = kept || c[0] == v || c[1] == v || c[2] == v;
            }
            if (!kept) points_.push_back(v);
        }
        if (after_.empty()) return; // the star's triangles are gone, and so are their points'
        for (uint32_t p : points_) {
            const Vec3 x = point_(p);
            double best = std::numeric_limits<double>::infinity();
            uint32_t cover = kDead;
            std::array<double, 3> weights{};
            for (uint32_t t : after_) {
                const uint32_t* c = &slots_[3 * size_t(t)];
                const Vec3 a = point_(c[0]), b = point_(c[1]), d = point_(c[2]);
                const std::array<double, 3> w = closest_on_triangle(x, a, b, d).weights;
                const Vec3 q = add(add(scale(a, w[0]), scale(b, w[1])), scale(d, w[2]));
                const double distance = norm(sub(q, x));
                const bool tie = std::abs(distance - best) <= tie_;
                if (tie ? sorted_corners(t) < sorted_corners(cover) : distance < best)
                    best = distance, cover = t, weights = w;
            }
            next_[p] = head_[cover], head_[cover] = p;
            cover_[p] = cover, weights_[p] = weights;
            landed(p, best);
        }
    }

    const std::vector<uint32_t>& slots() const { return slots_; }
    // The slot whose triangle covers input vertex p (kDead: none, p is kept or its triangles
    // are gone), and p's weights on that triangle's corners.
    uint32_t cover(uint32_t p) const { return cover_[p]; }
    const std::array<double, 3>& weights(uint32_t p) const { return weights_[p]; }

private:
    std::array<uint32_t, 3> sorted_corners(uint32_t t) const {
        std::array<uint32_t, 3> c{slots_[3 * size_t(t)], slots_[3 * size_t(t) + 1],
                                  slots_[3 * size_t(t) + 2]};
        std::sort(c.begin(), c.end());
        return c;
    }

    std::vector<uint32_t> slots_;
    // Per slot, the points it covers: a list through next_.
    std::vector<uint32_t> head_, next_;
    std::vector<uint32_t> cover_;
    std::vector<std::array<double, 3>> weights_;
    Point point_;
    double tie_;
    std::vector<uint32_t> before_, after_, points_; // one removal's scratch
};

} // namespace ddsimp::detail
