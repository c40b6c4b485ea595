// Topological counts of an indexed triangle surface (what simplification must keep).
#include "ddsimp/ddsimp.h"

#include <algorithm>
#include <numeric>

namespace ddsimp {
namespace {

struct DisjointSets {
    std::vector<uint32_t> parent;
    explicit DisjointSets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    uint32_t find(uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(uint32_t a, uint32_t b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
    size_t roots(const std::vector<uint8_t>& member) {
        size_t n = 0;
        for (uint32_t i = 0; i < parent.size(); ++i) n += member[i] && find(i) == i;
        return n;
    }
};

// One undirected edge of one triangle.
struct EdgeUse {
    uint32_t a, b, triangle;
    bool operator<(const EdgeUse& o) const {
        return a != o.a ? a < o.a : b != o.b ? b < o.b : triangle < o.triangle;
    }
};

} // namespace

Topology analyze_topology(const Surface& s) {
    Topology topo;
    const size_t nv = s.vertex_count(), nt = s.triangle_count();
    topo.triangles = nt;

    std::vector<EdgeUse> uses;
    uses.reserve(3 * nt);
    std::vector<uint8_t> used(nv, 0);
    for (uint32_t t = 0; t < nt; ++t)
        for (int c = 0; c < 3; ++c) {
            uint32_t a = s.triangles[3 * t + c], b = s.triangles[3 * t + (c + 1) % 3];
            used[a] = 1;
            uses.push_back({std::min(a, b), std::max(a, b), t});
        }
    std::sort(uses.begin(), uses.end());
    topo.vertices = size_t(std::count(used.begin(), used.end(), 1));

    DisjointSets triangle_sets(nt), boundary_sets(nv);
    std::vector<uint8_t> on_boundary(nv, 0), all_triangles(nt, 1);
    // Vertices touching a non-manifold edge are non-manifold; the rest are checked by their link.
    std::vector<uint8_t> nonmanifold(nv, 0);
    for (size_t i = 0; i < uses.size();) {
        size_t j = i;
        while (j < uses.size() && uses[j].a == uses[i].a && uses[j].b == uses[i].b) ++j;
        const size_t multiplicity = j - i;
        ++topo.edges;
        for (size_t k = i + 1; k < j; ++k) triangle_sets.unite(uses[i].triangle, uses[k].triangle);
        if (multiplicity == 1) {
            ++topo.boundary_edges;
            boundary_sets.unite(uses[i].a, uses[i].b);
            on_boundary[uses[i].a] = on_boundary[uses[i].b] = 1;
        } else if (multiplicity > 2) {
            ++topo.nonmanifold_edges;
            nonmanifold[uses[i].a] = nonmanifold[uses[i].b] = 1;
        }
        i = j;
    }
    topo.components = triangle_sets.roots(all_triangles);
    topo.boundary_loops = boundary_sets.roots(on_boundary);

    // A vertex's star is a disk or half-disk iff its link (the opposite edges of its triangles)
    // is one connected cycle or path; several pieces mean a pinch (a "bowtie").
    std::vector<uint32_t> first(nv + 1, 0);
    for (uint32_t v : s.triangles) ++first[v + 1];
    std::partial_sum(first.begin(), first.end(), first.begin());
    std::vector<uint32_t> star(s.triangles.size()), fill(first.begin(), first.end() - 1);
    for (uint32_t t = 0; t < nt; ++t)
        for (int c = 0; c < 3; ++c) star[fill[s.triangles[3 * t + c]]++] = t;
    std::vector<uint32_t> link;
    for (uint32_t v = 0; v < nv; ++v) {
        if (!used[v] || nonmanifold[v]) continue;
        link.clear();
        for (uint32_t k = first[v]; k < first[v + 1]; ++k) {
            const uint32_t* tri = &s.triangles[3 * star[k]];
            for (int c = 0; c < 3; ++c)
                if (tri[c] != v) link.push_back(tri[c]);
        }
        // Merge link edges (pairs in `link`) into pieces with a tiny union-find on positions.
        const size_t m = link.size() / 2;
        std::vector<uint32_t> piece(m);
        std::iota(piece.begin(), piece.end(), 0u);
        auto root = [&](uint32_t x) {
            while (piece[x] != x) x = piece[x];
            return x;
        };
        for (size_t i = 0; i < m; ++i)
            for (size_t j = i + 1; j < m; ++j) {
                bool touch = link[2 * i] == link[2 * j] || link[2 * i] == link[2 * j + 1] ||
                             link[2 * i + 1] == link[2 * j] || link[2 * i + 1] == link[2 * j + 1];
                if (touch) piece[root(uint32_t(j))] = root(uint32_t(i));
            }
        size_t pieces = 0;
        for (size_t i = 0; i < m; ++i) pieces += root(uint32_t(i)) == i;
        if (pieces > 1) nonmanifold[v] = 1;
    }
    topo.nonmanifold_vertices = size_t(std::count(nonmanifold.begin(), nonmanifold.end(), 1));
    topo.euler_characteristic =
        (long long)topo.vertices - (long long)topo.edges + (long long)topo.triangles;
    return topo;
}

} // namespace ddsimp
