// Closest-point queries on a triangle surface: a bounding-volume hierarchy over its triangles.
#pragma once

#include <cstdint>
#include <vector>

namespace ddsimp::tools {

// The point of a surface closest to a query point.
struct ClosestPoint {
    uint32_t triangle = 0;   // index into the surface's triangles
    double barycentric[3]{}; // weights of the triangle's corners at the point
    double point[3]{};
    double distance_squared = 0;
};

// A median-split BVH over triangles (leaves of up to 4), built once, queried many times from
// any number of threads. Keeps its own copy of the corners (36 bytes per triangle), in leaf order.
class TriangleBvh {
public:
    // `positions`: 3 floats per vertex; `triangles`: 3 in-range indices per triangle; at least one.
    TriangleBvh(const std::vector<float>& positions, const std::vector<uint32_t>& triangles);

    // The closest point of the surface to `query`; ties go to the first triangle found, which
    // depends only on the surface, so results are deterministic.
    ClosestPoint closest(const double query[3]) const;
    // The same, starting from the distance to triangle `hint` (e.g. the previous query's answer
    // for a nearby point), which lets the search skip most boxes at once.
    ClosestPoint closest(const double query[3], uint32_t hint) const;

private:
    struct Node {
        float lo[3], hi[3];
        uint32_t first; // leaf: first entry of order_; inner: the left child
        uint32_t right; // inner: the right child
        uint32_t count; // leaf: number of triangles; inner: 0
    };
    struct Item;
    uint32_t build(std::vector<Item>& items, uint32_t begin, uint32_t end);
    double box_distance_squared(const Node& node, const double q[3]) const;
    void test_slot(uint32_t slot, const double q[3], ClosestPoint& best) const;

    std::vector<Node> nodes_;
    std::vector<uint32_t> order_;   // slot (leaf order) -> triangle number
    std::vector<uint32_t> slot_of_; // triangle number -> slot
    std::vector<float> corners_;    // 9 floats per slot: the triangle's three corners
};

} // namespace ddsimp::tools
