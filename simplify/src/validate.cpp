// Input checks: reject what has no obvious repair, drop degenerate and duplicate triangles.
#include "validate.h"

#include "huge_pages.h"

#include <atomic>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>
#include <utility>

namespace ddsimp {
namespace {

[[noreturn]] void reject(const std::string& message) {
    throw InputError(message);
}

void check_shape(const Surface& s) {
    if (s.positions.size() % 3 != 0)
        reject("positions hold " + std::to_string(s.positions.size()) +
               " floats, not a multiple of 3");
    if (s.triangles.size() % 3 != 0)
        reject("triangles hold " + std::to_string(s.triangles.size()) +
               " indices, not a multiple of 3");
    if (s.triangles.empty()) reject("the surface has no triangles");
}

// Whether bad(i) holds for any i in [0, n), looked for on the threads; the checks then find the
// first one alone, for their message.
template <class F> bool any_of(detail::Parallel& parallel, size_t n, F&& bad) {
    std::atomic<bool> found{false};
    parallel.for_range(
        n,
        [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end && !found.load(std::memory_order_relaxed); ++i)
                if (bad(i)) found.store(true, std::memory_order_relaxed);
        },
        4096);
    return found.load();
}

void check_positions(const Surface& s, detail::Parallel& parallel) {
    if (!any_of(parallel, s.positions.size(),
                [&](size_t i) { return !std::isfinite(s.positions[i]); }))
        return;
    for (size_t i = 0; i < s.positions.size(); ++i)
        if (!std::isfinite(s.positions[i]))
            reject("vertex " + std::to_string(i / 3) + " has a non-finite coordinate (" +
                   std::to_string(s.positions[i]) + ")");
}

void check_indices(const Surface& s, detail::Parallel& parallel) {
    const size_t n = s.vertex_count();
    if (!any_of(parallel, s.triangles.size(), [&](size_t i) { return s.triangles[i] >= n; }))
        return;
    for (size_t i = 0; i < s.triangles.size(); ++i)
        if (s.triangles[i] >= n)
            reject("triangle " + std::to_string(i / 3) + " refers to vertex " +
                   std::to_string(s.triangles[i]) + ", but the surface has " + std::to_string(n) +
                   " vertices");
}

void check_fields(const Surface& s, detail::Parallel& parallel) {
    std::set<std::string> names;
    for (const Field& f : s.fields) {
        if (f.name.empty()) reject("a field has an empty name");
        if (!names.insert(f.name).second) reject("field '" + f.name + "' appears twice");
        if (f.components < 1)
            reject("field '" + f.name + "' has " + std::to_string(f.components) + " components");
        const size_t expected = s.vertex_count() * size_t(f.components);
        if (f.values.size() != expected)
            reject("field '" + f.name + "' has " + std::to_string(f.values.size()) +
                   " values, expected " + std::to_string(expected) + " (" +
                   std::to_string(f.components) + " per vertex for " +
                   std::to_string(s.vertex_count()) + " vertices)");
        if (!any_of(parallel, f.values.size(),
                    [&](size_t i) { return !std::isfinite(f.values[i]); }))
            continue;
        for (size_t i = 0; i < f.values.size(); ++i)
            if (!std::isfinite(f.values[i]))
                reject("field '" + f.name + "' has a non-finite value at vertex " +
                       std::to_string(i / size_t(f.components)));
    }
}

// Keeps the first of every set of triangles naming the same three vertices (in any order) and
// drops triangles that name a vertex twice: the triangles kept into `out` if any is dropped
// (returns true), nothing written otherwise.
bool drop_bad_triangles(const Surface& s, std::vector<uint32_t>& out, RepairReport& report,
                        detail::Parallel& parallel) {
    const size_t count = s.triangle_count();
    // Each triangle's vertices sorted; triangles bucketed by their lowest vertex (counting sort,
    // in triangle order), so that a duplicate is found among the few earlier ones of its bucket.
    // Per triangle and per bucket on the threads: each writes only its own.
    detail::Array<std::array<uint32_t, 3>> keys(count);
    detail::Array<uint8_t> keep(count, 1);
    parallel.for_each(count, [&](size_t t) {
        std::array<uint32_t, 3> k{s.triangles[3 * t], s.triangles[3 * t + 1],
                                  s.triangles[3 * t + 2]};
        if (k[0] == k[1] || k[1] == k[2] || k[0] == k[2]) {
            keep[t] = 0;
            return;
        }
        std::sort(k.begin(), k.end());
        keys[t] = k;
    });
    detail::Array<uint32_t> first(s.vertex_count() + 1, 0);
    for (uint32_t t = 0; t < count; ++t) {
        if (keep[t])
            ++first[keys[t][0] + 1];
        else
            ++report.degenerate_triangles_dropped;
    }
    for (size_t v = 0; v + 1 < first.size(); ++v) first[v + 1] += first[v];
    detail::Array<uint32_t> bucket(first.back()), fill(first.begin(), first.end() - 1);
    for (uint32_t t = 0; t < count; ++t)
        if (keep[t]) bucket[fill[keys[t][0]]++] = t;
    detail::Array<uint32_t>().swap(fill);
    std::atomic<size_t> duplicates{0};
    parallel.for_range(s.vertex_count(), [&](size_t from, size_t to) {
        size_t dropped = 0;
        auto drop = [&](uint32_t t) { keep[t] = 0, ++dropped; };
        for (size_t v = from; v < to; ++v) {
            const uint32_t begin = first[v], end = first[v + 1];
            if (end - begin <= 16) { // the usual few: compare with the earlier ones
                for (uint32_t i = begin; i < end; ++i)
                    for (uint32_t j = begin; j < i; ++j)
                        if (keys[bucket[j]] == keys[bucket[i]]) {
                            drop(bucket[i]); // the first of equal triangles stays
                            break;
                        }
                continue;
            }
            // A hub: sort its bucket instead of comparing every pair.
            std::sort(bucket.begin() + begin, bucket.begin() + end, [&](uint32_t a, uint32_t b) {
                return keys[a] != keys[b] ? keys[a] < keys[b] : a < b;
            });
            for (uint32_t i = begin + 1; i < end; ++i)
                if (keys[bucket[i]] == keys[bucket[i - 1]]) drop(bucket[i]);
        }
        duplicates += dropped;
    });
    report.duplicate_triangles_dropped += duplicates.load();
    if (report.degenerate_triangles_dropped + report.duplicate_triangles_dropped == 0) return false;
    out.clear();
    for (size_t t = 0; t < count; ++t)
        if (keep[t])
            for (int c = 0; c < 3; ++c) out.push_back(s.triangles[3 * t + c]);
    if (out.empty())
        reject("no triangles left after dropping " +
               std::to_string(report.degenerate_triangles_dropped) + " degenerate and " +
               std::to_string(report.duplicate_triangles_dropped) + " duplicate triangles");
    return true;
}

// The triangles to flip so that neighbours across every two-triangle edge run it in opposite
// directions, walking each component breadth-first from its lowest-numbered triangle: per
// triangle of `triangles` (over nv vertices), 2 if it is to be flipped.
std::vector<uint8_t> orientation_flips(const std::vector<uint32_t>& triangles, size_t nv,
                                       RepairReport& report, detail::Parallel& parallel) {
    constexpr uint32_t kNone = 0xffffffffu;
    const size_t nt = triangles.size() / 3;
    // The triangle across each edge of each triangle (by half-edge 3t + c of the input's
    // orientation, the edge from corner c to corner c + 1), where exactly two triangles share
    // the edge: the half-edges grouped by their lower vertex (counting sort), each with its
    // higher one, and matched within their group. A flip changes no triangle's vertices, so
    // these stay right.
    auto ends = [&](uint32_t h) {
        const uint32_t a = triangles[h], b = triangles[h % 3 == 2 ? h - 2 : h + 1];
        return std::pair{std::min(a, b), std::max(a, b)};
    };
    const uint32_t halfedges = uint32_t(triangles.size());
    detail::Array<uint32_t> first(nv + 1, 0);
    for (uint32_t h = 0; h < halfedges; ++h) ++first[ends(h).first + 1];
    for (size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
    detail::Array<uint64_t> group(halfedges); // higher vertex << 32 | half-edge
    detail::Array<uint32_t> fill(first.begin(), first.end() - 1);
    for (uint32_t h = 0; h < halfedges; ++h) {
        const auto [low, high] = ends(h);
        group[fill[low]++] = uint64_t(high) << 32 | h;
    }
    detail::Array<uint32_t> across(halfedges, kNone);
    // Whether two triangles run an edge the same way: only then is there anything to flip.
    std::atomic<bool> opposed{false};
    parallel.for_each(nv, [&](size_t v) { // each group on its own
        const auto begin = group.begin() + first[v], end = group.begin() + first[v + 1];
        std::sort(begin, end); // by the higher vertex: each edge's half-edges together
        for (auto i = begin; i != end;) {
            auto j = i;
            while (j != end && *j >> 32 == *i >> 32) ++j;
            if (j - i == 2) {
                const uint32_t h0 = uint32_t(i[0]), h1 = uint32_t(i[1]);
                across[h0] = h1 / 3, across[h1] = h0 / 3;
                if ((triangles[h0] == v) == (triangles[h1] == v))
                    opposed.store(true, std::memory_order_relaxed);
            }
            i = j;
        }
    });
    // Consistent already (as most surfaces are): the walk below would flip nothing.
    if (!opposed.load(std::memory_order_relaxed)) return std::vector<uint8_t>(nt, 1);

    // Does triangle t, not flipped, run the edge a -> b?
    auto runs = [&](uint32_t t, uint32_t a, uint32_t b) {
        const uint32_t* c = &triangles[3 * size_t(t)];
        return (c[0] == a && c[1] == b) || (c[1] == a && c[2] == b) || (c[2] == a && c[0] == b);
    };
    // seen[t]: 1 once reached, 2 if it was also flipped (corners 1 and 2 swapped, so its corner
    // c is the input's corner (3 - c) % 3 and its edge from corner c the input's edge from
    // corner 2 - c).
    std::vector<uint8_t> seen(nt, 0);
    auto corner = [&](uint32_t t, uint32_t c) {
        return triangles[3 * size_t(t) + (seen[t] == 2 ? (3 - c) % 3 : c)];
    };
    std::vector<uint32_t> queue;
    for (uint32_t root = 0; root < nt; ++root) {
        if (seen[root]) continue;
        seen[root] = 1;
        queue.assign(1, root);
        for (size_t q = 0; q < queue.size(); ++q) {
            const uint32_t t = queue[q];
            for (uint32_t c = 0; c < 3; ++c) {
                const uint32_t a = corner(t, c), b = corner(t, (c + 1) % 3);
                const uint32_t other = across[3 * t + (seen[t] == 2 ? 2 - c : c)];
                if (other == kNone || seen[other]) continue; // boundary, non-manifold or done
                seen[other] = 1;
                if (runs(other, a, b)) {
                    seen[other] = 2;
                    ++report.triangles_flipped;
                }
                queue.push_back(other);
            }
        }
    }
    return seen;
}

} // namespace

namespace detail {

bool repair_triangles(const Surface& surface, std::vector<uint32_t>& repaired, RepairReport& report,
                      Parallel& parallel) {
    report = {};
    check_shape(surface);
    check_positions(surface, parallel);
    check_indices(surface, parallel);
    check_fields(surface, parallel);
    const bool dropped = drop_bad_triangles(surface, repaired, report, parallel);
    const std::vector<uint32_t>& triangles = dropped ? repaired : surface.triangles;
    const std::vector<uint8_t> flips =
        orientation_flips(triangles, surface.vertex_count(), report, parallel);
    if (report.triangles_flipped > 0) {
        if (!dropped) repaired = surface.triangles;
        for (size_t t = 0; t < flips.size(); ++t)
            if (flips[t] == 2) std::swap(repaired[3 * t + 1], repaired[3 * t + 2]);
    }
    detail::Array<uint8_t> used(surface.vertex_count(), 0);
    for (uint32_t v : dropped || report.triangles_flipped > 0 ? repaired : surface.triangles)
        used[v] = 1;
    report.unused_vertices = size_t(std::count(used.begin(), used.end(), 0));
    return dropped || report.triangles_flipped > 0;
}

const Surface& validated(const Surface& input, Surface& repaired, RepairReport& report,
                         Parallel& parallel) {
    std::vector<uint32_t> triangles;
    if (!repair_triangles(input, triangles, report, parallel)) return input;
    repaired.positions = input.positions;
    repaired.fields = input.fields;
    repaired.triangles = std::move(triangles);
    return repaired;
}

} // namespace detail

RepairReport validate(Surface& surface) {
    RepairReport report;
    std::vector<uint32_t> triangles;
    detail::Parallel one(1);
    if (detail::repair_triangles(surface, triangles, report, one))
        surface.triangles = std::move(triangles);
    return report;
}

} // namespace ddsimp
