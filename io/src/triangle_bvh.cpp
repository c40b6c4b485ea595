#include "ddsimp/io/triangle_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ddsimp::tools {

namespace {

constexpr uint32_t kLeafSize = 4;

struct Vec {
    double x, y, z;
};
Vec operator-(Vec a, Vec b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
double dot(Vec a, Vec b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// Closest point on triangle abc to p, as barycentric weights (Ericson, Real-Time Collision
// Detection, 5.1.5): find the Voronoi region of p, then project.
void closest_on_triangle(Vec p, Vec a, Vec b, Vec c, double w[3]) {
    const Vec ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) {
        w[0] = 1, w[1] = 0, w[2] = 0;
        return;
    }
    const Vec bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) {
        w[0] = 0, w[1] = 1, w[2] = 0;
        return;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        w[0] = 1 - v, w[1] = v, w[2] = 0;
        return;
    }
    const Vec cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) {
        w[0] = 0, w[1] = 0, w[2] = 1;
        return;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double v = d2 / (d2 - d6);
        w[0] = 1 - v, w[1] = 0, w[2] = v;
        return;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double v = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        w[0] = 0, w[1] = 1 - v, w[2] = v;
        return;
    }
    const double sum = va + vb + vc;
    if (!(sum > 0)) {
        w[0] = 1, w[1] = 0, w[2] = 0;
        return;
    } // degenerate triangle
    const double v = vb / sum, u = vc / sum;
    w[0] = 1 - v - u, w[1] = v, w[2] = u;
}

} // namespace

// A triangle while the tree is built: its box and centroid, sorted in place.
struct TriangleBvh::Item {
    float lo[3], hi[3], centroid[3];
    uint32_t triangle;
};

TriangleBvh::TriangleBvh(const std::vector<float>& positions,
                         const std::vector<uint32_t>& triangles) {
    const uint32_t n = uint32_t(triangles.size() / 3);
    std::vector<Item> items(n);
    for (uint32_t t = 0; t < n; ++t) {
        Item& item = items[t];
        item.triangle = t;
        for (int a = 0; a < 3; ++a) {
            const float x0 = positions[3 * size_t(triangles[3 * size_t(t)]) + a];
            const float x1 = positions[3 * size_t(triangles[3 * size_t(t) + 1]) + a];
            const float x2 = positions[3 * size_t(triangles[3 * size_t(t) + 2]) + a];
            item.lo[a] = std::min({x0, x1, x2});
            item.hi[a] = std::max({x0, x1, x2});
            item.centroid[a] = (x0 + x1 + x2) / 3.0f;
        }
    }
    nodes_.reserve(2 * size_t(n / kLeafSize + 1));
    if (n > 0) build(items, 0, n);

    // Leaf order: triangle numbers and corner coordinates side by side for the queries.
    order_.resize(n);
    corners_.resize(9 * size_t(n));
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t t = items[i].triangle;
        order_[i] = t;
        for (int c = 0; c < 3; ++c)
            for (int a = 0; a < 3; ++a)
                corners_[9 * size_t(i) + 3 * c + a] =
                    positions[3 * size_t(triangles[3 * size_t(t) + c]) + a];
    }
    // The hint names a triangle; find its corners through this inverse.
    slot_of_.resize(n);
    for (uint32_t i = 0; i < n; ++i) slot_of_[order_[i]] = i;
}

uint32_t TriangleBvh::build(std::vector<Item>& items, uint32_t begin, uint32_t end) {
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.push_back({});
    Node node;
    for (int a = 0; a < 3; ++a) {
        node.lo[a] = std::numeric_limits<float>::infinity();
        node.hi[a] = -std::numeric_limits<float>::infinity();
    }
    for (uint32_t i = begin; i < end; ++i)
        for (int a = 0; a < 3; ++a) {
            node.lo[a] = std::min(node.lo[a], items[i].lo[a]);
            node.hi[a] = std::max(node.hi[a], items[i].hi[a]);
        }
    if (end - begin <= kLeafSize) {
        node.first = begin;
        node.right = 0;
        node.count = end - begin;
        nodes_[index] = node;
        return index;
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (node.hi[a] - node.lo[a] > node.hi[axis] - node.lo[axis]) axis = a;
    const uint32_t mid = begin + (end - begin) / 2;
    // Ties broken by triangle number so the tree depends only on the surface.
    std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end,
                     [axis](const Item& s, const Item& t) {
                         return s.centroid[axis] < t.centroid[axis] ||
                                (s.centroid[axis] == t.centroid[axis] && s.triangle < t.triangle);
                     });
    node.count = 0;
    nodes_[index] = node;
    const uint32_t left = build(items, begin, mid);
    const uint32_t right = build(items, mid, end);
    nodes_[index].first = left;
    nodes_[index].right = right;
    return index;
}

double TriangleBvh::box_distance_squared(const Node& node, const double q[3]) const {
    double d = 0;
    for (int a = 0; a < 3; ++a) {
        const double below = node.lo[a] - q[a], above = q[a] - node.hi[a];
        const double gap = std::max({below, above, 0.0});
        d += gap * gap;
    }
    return d;
}

void TriangleBvh::test_slot(uint32_t slot, const double q[3], ClosestPoint& best) const {
    const float* x = &corners_[9 * size_t(slot)];
    const Vec p{q[0], q[1], q[2]};
    const Vec a{x[0], x[1], x[2]}, b{x[3], x[4], x[5]}, c{x[6], x[7], x[8]};
    double w[3];
    closest_on_triangle(p, a, b, c, w);
    const Vec y{w[0] * a.x + w[1] * b.x + w[2] * c.x, w[0] * a.y + w[1] * b.y + w[2] * c.y,
                w[0] * a.z + w[1] * b.z + w[2] * c.z};
    const Vec d = p - y;
    const double d2 = dot(d, d);
    if (d2 < best.distance_squared) {
        best.distance_squared = d2;
        best.triangle = order_[slot];
        std::copy(w, w + 3, best.barycentric);
        best.point[0] = y.x, best.point[1] = y.y, best.point[2] = y.z;
    }
}

ClosestPoint TriangleBvh::closest(const double query[3]) const {
    return closest(query, UINT32_MAX);
}

ClosestPoint TriangleBvh::closest(const double query[3], uint32_t hint) const {
    ClosestPoint best;
    best.distance_squared = std::numeric_limits<double>::infinity();
    if (nodes_.empty()) return best;
    if (hint < order_.size()) test_slot(slot_of_[hint], query, best);

    // Depth-first, nearer child first; a box farther than the best so far is skipped. (Equal
    // distances keep the first found, so a hint can change which of two equally close
    // triangles is reported, never the distance.)
    struct Entry {
        uint32_t node;
        double distance_squared;
    };
    Entry stack[128];
    int top = 0;
    stack[top++] = {0, box_distance_squared(nodes_[0], query)};
    while (top > 0) {
        const Entry entry = stack[--top];
        if (entry.distance_squared >= best.distance_squared) continue;
        const Node& node = nodes_[entry.node];
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i)
                test_slot(i, query, best);
            continue;
        }
        const uint32_t left = node.first;
        const uint32_t right = node.right;
        const double dl = box_distance_squared(nodes_[left], query);
        const double dr = box_distance_squared(nodes_[right], query);
        // Push the farther child first so the nearer one is searched first.
        if (dl <= dr) {
            stack[top++] = {right, dr};
            stack[top++] = {left, dl};
        } else {
            stack[top++] = {left, dl};
            stack[top++] = {right, dr};
        }
    }
    return best;
}

} // namespace ddsimp::tools
