#include "triangle_bvh.h"

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

TriangleBvh::TriangleBvh(const std::vector<float>& positions,
                         const std::vector<uint32_t>& triangles)
    : positions_(positions), triangles_(triangles) {
    const uint32_t n = uint32_t(triangles.size() / 3);
    order_.resize(n);
    std::vector<float> centroids(3 * size_t(n));
    for (uint32_t t = 0; t < n; ++t) {
        order_[t] = t;
        for (int a = 0; a < 3; ++a)
            centroids[3 * t + a] =
                (positions[3 * triangles[3 * t] + a] + positions[3 * triangles[3 * t + 1] + a] +
                 positions[3 * triangles[3 * t + 2] + a]) /
                3.0f;
    }
    nodes_.reserve(2 * size_t(n / kLeafSize + 1));
    if (n > 0) build(0, n, centroids);
}

uint32_t TriangleBvh::build(uint32_t begin, uint32_t end, std::vector<float>& centroids) {
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.push_back({});
    Node node;
    for (int a = 0; a < 3; ++a) {
        node.lo[a] = std::numeric_limits<float>::infinity();
        node.hi[a] = -std::numeric_limits<float>::infinity();
    }
    for (uint32_t i = begin; i < end; ++i)
        for (int corner = 0; corner < 3; ++corner)
            for (int a = 0; a < 3; ++a) {
                const float x = positions_[3 * triangles_[3 * order_[i] + corner] + a];
                node.lo[a] = std::min(node.lo[a], x);
                node.hi[a] = std::max(node.hi[a], x);
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
    // Ties broken by triangle index so the tree depends only on the surface.
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](uint32_t s, uint32_t t) {
                         const float cs = centroids[3 * s + axis], ct = centroids[3 * t + axis];
                         return cs < ct || (cs == ct && s < t);
                     });
    node.count = 0;
    nodes_[index] = node;
    const uint32_t left = build(begin, mid, centroids);
    const uint32_t right = build(mid, end, centroids);
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

ClosestPoint TriangleBvh::closest(const double query[3]) const {
    ClosestPoint best;
    best.distance_squared = std::numeric_limits<double>::infinity();
    if (nodes_.empty()) return best;
    const Vec p{query[0], query[1], query[2]};
    auto corner = [&](uint32_t t, int c) {
        const float* x = &positions_[3 * size_t(triangles_[3 * size_t(t) + c])];
        return Vec{x[0], x[1], x[2]};
    };

    // Depth-first, nearer child first; a box farther than the best so far is skipped.
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
            for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                const uint32_t t = order_[i];
                const Vec a = corner(t, 0), b = corner(t, 1), c = corner(t, 2);
                double w[3];
                closest_on_triangle(p, a, b, c, w);
                const Vec x{w[0] * a.x + w[1] * b.x + w[2] * c.x,
                            w[0] * a.y + w[1] * b.y + w[2] * c.y,
                            w[0] * a.z + w[1] * b.z + w[2] * c.z};
                const Vec d = p - x;
                const double d2 = dot(d, d);
                if (d2 < best.distance_squared) {
                    best.distance_squared = d2;
                    best.triangle = t;
                    std::copy(w, w + 3, best.barycentric);
                    best.point[0] = x.x, best.point[1] = x.y, best.point[2] = x.z;
                }
            }
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
