// Edge flips of a level by the error of the samples landed on each quad.
#include "data_flips.h"

#include "working_mesh.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace ddsimp::detail {
namespace {

uint64_t edge_key(uint32_t a, uint32_t b) {
    return a < b ? uint64_t(a) << 32 | b : uint64_t(b) << 32 | a;
}

// An edge a-b with the triangles t1 = (a, b, c) and t2 = (b, a, d) beside it; flipped, they
// become t1 = (a, d, c) and t2 = (d, b, c).
struct Quad {
    uint32_t a, b, c, d, t1, t2;
};

// The level, the samples on each of its triangles, and its edges, as the flips change them.
class LevelFlips {
public:
    LevelFlips(const RefitInput& input, std::vector<Landing>& forward, Surface& level)
        : input_(input), in_(*input.surface), forward_(forward), level_(level),
          triangles_(level.triangles) {
        const size_t nt = level.triangle_count();
        // Each triangle's samples as a list through next_, in input order.
        head_.assign(nt, kNoOwner), next_.assign(forward.size(), kNoOwner);
        for (size_t i = forward.size(); i-- > 0;)
            if (const uint32_t t = forward[i].triangle; t != kNoOwner)
                next_[i] = head_[t], head_[t] = uint32_t(i);
        flipped_in_.assign(nt, 0);
        // Each edge's triangles; a third one marks the edge crowded (never flipped).
        edges_.reserve(3 * nt / 2 + 1);
        for (uint32_t t = 0; t < nt; ++t)
            for (int c = 0; c < 3; ++c) {
                auto [it, fresh] = edges_.try_emplace(edge_key(corner(t, c), corner(t, c + 1)),
                                                      std::array<uint32_t, 2>{t, kNoOwner});
                if (!fresh) it->second[1] = it->second[1] == kNoOwner ? t : kCrowded;
            }
    }

    std::vector<uint64_t> all_edges() const {
        std::vector<uint64_t> keys;
        keys.reserve(edges_.size());
        for (const auto& [key, pair] : edges_) keys.push_back(key);
        std::sort(keys.begin(), keys.end());
        return keys;
    }
    // The edges of the triangles at the vertices `near` (sorted) marks.
    std::vector<uint64_t> edges_at(const std::vector<uint32_t>& near) const {
        std::vector<uint8_t> marked(level_.vertex_count(), 0);
        for (uint32_t v : near) marked[v] = 1;
        std::vector<uint64_t> keys;
        for (uint32_t t = 0; t < head_.size(); ++t)
            if (marked[corner(t, 0)] || marked[corner(t, 1)] || marked[corner(t, 2)])
                for (int c = 0; c < 3; ++c)
                    keys.push_back(edge_key(corner(t, c), corner(t, c + 1)));
        std::sort(keys.begin(), keys.end());
        keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
        return keys;
    }

    // The corners of the quads flipped so far, sorted, each once.
    std::vector<uint32_t> flipped_corners() const {
        std::vector<uint32_t> at = flipped_at_;
        std::sort(at.begin(), at.end());
        at.erase(std::unique(at.begin(), at.end()), at.end());
        return at;
    }

    // Whether a flip marked with `stamp` changed triangle t.
    bool touched(uint32_t t, uint32_t stamp) const { return flipped_in_[t] == stamp; }

    // How much flipping the edge lowers its samples' error (0 if it may not be flipped).
    double gain(uint64_t key, Quad& q) const {
        if (!quad_of(key, q) || !flippable(q)) return 0;
        double before = 0, after = 0;
        size_t samples = 0;
        const Corners flipped[2] = {{q.a, q.d, q.c}, {q.d, q.b, q.c}};
        for (uint32_t t : {q.t1, q.t2})
            for (uint32_t i = head_[t]; i != kNoOwner; i = next_[i]) {
                before += cost(i, corners(t), forward_[i].weights);
                const Landing n = nearer(i, q);
                after += cost(i, flipped[n.triangle == q.t1 ? 0 : 1], n.weights);
                ++samples;
            }
        // Lower by more than rounding: by a part in 1e9 (so that a flip back never gains), and by
        // more than differences of a millionth of the data's range (or the diagonal) per sample,
        // which the data's floats cannot tell apart.
        const double noise = std::max(1e-9 * before, kNoise * double(samples));
        return after < before - noise ? before - after : 0;
    }

    // Flips q's edge and moves its samples; the quad's four rim edges go to `around`, for the
    // next sweep.
    void flip(const Quad& q, std::vector<uint64_t>& around, uint32_t stamp) {
        flipped_at_.insert(flipped_at_.end(), {q.a, q.b, q.c, q.d});
        flipped_in_[q.t1] = flipped_in_[q.t2] = stamp;
        uint32_t moved = head_[q.t1];
        if (moved == kNoOwner) {
            moved = head_[q.t2];
        } else {
            uint32_t last = moved;
            while (next_[last] != kNoOwner) last = next_[last];
            next_[last] = head_[q.t2];
        }
        set(q.t1, q.a, q.d, q.c), set(q.t2, q.d, q.b, q.c);
        edges_.erase(edge_key(q.a, q.b));
        swap_triangle(edge_key(q.a, q.d), q.t2, q.t1);
        swap_triangle(edge_key(q.b, q.c), q.t1, q.t2);
        edges_[edge_key(q.c, q.d)] = {q.t1, q.t2};
        // The moved samples, each to the nearer new triangle, kept in input order.
        std::vector<uint32_t> samples;
        for (uint32_t i = moved; i != kNoOwner; i = next_[i]) samples.push_back(i);
        std::sort(samples.begin(), samples.end());
        head_[q.t1] = head_[q.t2] = kNoOwner;
        for (size_t k = samples.size(); k-- > 0;) {
            const uint32_t i = samples[k];
            forward_[i] = nearer(i, q);
            next_[i] = head_[forward_[i].triangle], head_[forward_[i].triangle] = i;
        }
        for (uint64_t key :
             {edge_key(q.a, q.d), edge_key(q.d, q.b), edge_key(q.b, q.c), edge_key(q.c, q.a)})
            around.push_back(key);
    }

    // Whether q's edge may be flipped: its other diagonal is no edge, and both pairs of
    // triangles are flat, unfolded and no sliver.
    bool flippable(const Quad& q) const {
        if (q.c == q.d || edges_.count(edge_key(q.c, q.d))) return false;
        auto flat = [&](const Vec3& n, const Vec3& m) {
            return dot(n, m) >= input_.flat_cos * std::sqrt(dot(n, n) * dot(m, m));
        };
        const Vec3 n1 = normal(q.a, q.b, q.c), n2 = normal(q.b, q.a, q.d);
        const Vec3 m1 = normal(q.a, q.d, q.c), m2 = normal(q.d, q.b, q.c);
        // No sliver: each new triangle keeps a part of the quad's area that rounding cannot undo.
        const double area = std::sqrt(dot(n1, n1)) + std::sqrt(dot(n2, n2));
        if (!(std::sqrt(dot(m1, m1)) > 1e-6 * area && std::sqrt(dot(m2, m2)) > 1e-6 * area))
            return false;
        const Vec3 facing = add(n1, n2);
        return flat(n1, n2) && flat(m1, m2) && dot(m1, facing) > 0 && dot(m2, facing) > 0;
    }

private:
    static constexpr uint32_t kCrowded = kNoOwner - 1;
    static constexpr double kNoise = 1e-12;

    using Corners = std::array<uint32_t, 3>;
    uint32_t corner(uint32_t t, int c) const { return triangles_[3 * size_t(t) + size_t(c % 3)]; }
    Corners corners(uint32_t t) const { return {corner(t, 0), corner(t, 1), corner(t, 2)}; }
    Vec3 point(uint32_t v) const { return point_of(level_.positions, v); }
    Vec3 normal(uint32_t a, uint32_t b, uint32_t c) const {
        const Vec3 pa = point(a);
        return cross(sub(point(b), pa), sub(point(c), pa));
    }
    void set(uint32_t t, uint32_t a, uint32_t b, uint32_t c) {
        triangles_[3 * size_t(t)] = a, triangles_[3 * size_t(t) + 1] = b;
        triangles_[3 * size_t(t) + 2] = c;
    }
    // The rim edge `key` of a flipped quad now lies on triangle `to` instead of `from` (a crowded
    // edge stays crowded).
    void swap_triangle(uint64_t key, uint32_t from, uint32_t to) {
        std::array<uint32_t, 2>& pair = edges_.at(key);
        if (pair[0] == from)
            pair[0] = to;
        else if (pair[1] == from)
            pair[1] = to;
    }

    bool quad_of(uint64_t key, Quad& q) const {
        const auto it = edges_.find(key);
        if (it == edges_.end() || it->second[1] == kNoOwner || it->second[1] == kCrowded)
            return false;
        q.t1 = it->second[0], q.t2 = it->second[1];
        int at = 0; // the corner of t1 where the edge starts
        while (at < 3 && edge_key(corner(q.t1, at), corner(q.t1, at + 1)) != key) ++at;
        q.a = corner(q.t1, at), q.b = corner(q.t1, at + 1), q.c = corner(q.t1, at + 2);
        for (int k = 0; k < 3; ++k)
            if (corner(q.t2, k) == q.b) { // t2 must run b -> a: the same orientation as t1
                if (corner(q.t2, k + 1) != q.a) return false;
                q.d = corner(q.t2, k + 2);
                return true;
            }
        return false;
    }

    // Sample i on the nearer of a quad's two flipped triangles (the first on a tie).
    Landing nearer(uint32_t i, const Quad& q) const {
        const Vec3 p = point_of(in_.positions, i);
        const ClosestPoint c1 = closest_on_triangle(p, point(q.a), point(q.d), point(q.c));
        const ClosestPoint c2 = closest_on_triangle(p, point(q.d), point(q.b), point(q.c));
        const Vec3 e1 = sub(c1.point, p), e2 = sub(c2.point, p);
        return dot(e1, e1) <= dot(e2, e2) ? Landing{q.t1, c1.weights} : Landing{q.t2, c2.weights};
    }

    // Sample i's error where it lands on the triangle of corners k with weights w.
    double cost(uint32_t i, const Corners& k, const std::array<double, 3>& w) const {
        return landed_sample_error(input_, level_, i, k, {point(k[0]), point(k[1]), point(k[2])},
                                   w);
    }

    const RefitInput& input_;
    const Surface& in_;
    std::vector<Landing>& forward_;
    Surface& level_;
    std::vector<uint32_t>& triangles_;
    std::vector<uint32_t> head_, next_;
    std::vector<uint32_t> flipped_in_; // per triangle: the stamp of the last flip that changed it
    std::unordered_map<uint64_t, std::array<uint32_t, 2>> edges_;
    std::vector<uint32_t> flipped_at_; // the corners of every flipped quad
};

} // namespace

std::vector<uint32_t> flip_edges_for_data(const RefitInput& input, std::vector<Landing>& forward,
                                          Surface& level, Parallel& parallel,
                                          const std::vector<uint32_t>* near) {
    if (!(input.flat_cos <= 1) || level.triangle_count() < 2) return {};
    LevelFlips flips(input, forward, level);
    std::vector<uint64_t> sweep = near ? flips.edges_at(*near) : flips.all_edges();
    std::vector<uint8_t> worth;
    std::vector<Quad> quads;
    // Every flip lowers the samples' error, so the sweeps end; the cap bounds their time on a
    // level whose flips keep making room for more.
    constexpr int kMaxSweeps = 32;
    constexpr size_t kEdgesPerCheck = 4096; // a few milliseconds of the serial walk
    for (int round = 0; round < kMaxSweeps && !sweep.empty(); ++round) {
        // Which edges gain, as the level stands at the sweep's start (on the threads); each is
        // flipped in its turn if it still gains, as the flips before it may have changed its
        // quad.
        worth.assign(sweep.size(), 0), quads.resize(sweep.size());
        parallel.for_each(sweep.size(),
                          [&](size_t k) { worth[k] = flips.gain(sweep[k], quads[k]) > 0; });
        if (parallel.stopped()) return {};
        std::vector<uint64_t> around;
        const uint32_t stamp = uint32_t(round) + 1;
        for (size_t k = 0; k < sweep.size(); ++k) {
            if (k % kEdgesPerCheck == kEdgesPerCheck - 1 && !parallel.check()) return {};
            if (!worth[k]) continue;
            // A quad no flip of this sweep has touched gains what it gained at the start, unless
            // a flip has made its other diagonal an edge since.
            Quad& q = quads[k];
            const bool as_found = !flips.touched(q.t1, stamp) && !flips.touched(q.t2, stamp);
            if (as_found ? flips.flippable(q) : flips.gain(sweep[k], q) > 0)
                flips.flip(q, around, stamp);
        }
        std::sort(around.begin(), around.end());
        around.erase(std::unique(around.begin(), around.end()), around.end());
        sweep.swap(around);
    }
    return flips.flipped_corners();
}

} // namespace ddsimp::detail
