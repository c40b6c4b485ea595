// Small surfaces and checks shared by the libddsimp tests.
//
// Every builder states the counts the topology tests expect from it; those counts are derived by
// hand from the construction (see test_topology.cpp), never read back from the library.
#pragma once

#include <ddsimp/ddsimp.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <ostream>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace ddsimp::test {

inline constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// Small vector maths (double precision, independent of the library)
// ---------------------------------------------------------------------------------------------

using Vec3 = std::array<double, 3>;

inline Vec3 operator+(const Vec3& a, const Vec3& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Vec3 operator-(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Vec3 operator*(double s, const Vec3& a) {
    return {s * a[0], s * a[1], s * a[2]};
}
inline double dot(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) {
    return std::sqrt(dot(a, a));
}

inline Vec3 position(const Surface& s, size_t v) {
    return {s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]};
}
inline std::array<uint32_t, 3> corners(const Surface& s, size_t t) {
    return {s.triangles[3 * t], s.triangles[3 * t + 1], s.triangles[3 * t + 2]};
}
// (b - a) x (c - a): twice the area times the unit normal (right-hand rule).
inline Vec3 triangle_normal(const Surface& s, size_t t) {
    auto [a, b, c] = corners(s, t);
    Vec3 pa = position(s, a);
    return cross(position(s, b) - pa, position(s, c) - pa);
}
inline double triangle_area(const Surface& s, size_t t) {
    return 0.5 * norm(triangle_normal(s, t));
}
inline Vec3 triangle_centroid(const Surface& s, size_t t) {
    auto [a, b, c] = corners(s, t);
    return (1.0 / 3.0) * (position(s, a) + position(s, b) + position(s, c));
}
inline double total_area(const Surface& s) {
    double area = 0;
    for (size_t t = 0; t < s.triangle_count(); ++t) area += triangle_area(s, t);
    return area;
}
// Sum of the signed volumes of the tetrahedra (origin, a, b, c): the enclosed volume of a closed,
// outward-oriented surface (divergence theorem), negative if it is oriented inward.
inline double signed_volume(const Surface& s) {
    double volume = 0;
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        auto [a, b, c] = corners(s, t);
        volume += dot(position(s, a), cross(position(s, b), position(s, c))) / 6.0;
    }
    return volume;
}
inline double bbox_diagonal(const Surface& s) {
    if (s.positions.empty()) return 0;
    Vec3 lo = position(s, 0), hi = lo;
    for (size_t v = 0; v < s.vertex_count(); ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], double(s.positions[3 * v + k]));
            hi[k] = std::max(hi[k], double(s.positions[3 * v + k]));
        }
    return norm(hi - lo);
}

// ---------------------------------------------------------------------------------------------
// Builders
// ---------------------------------------------------------------------------------------------

inline uint32_t add_vertex(Surface& s, double x, double y, double z) {
    s.positions.push_back(float(x));
    s.positions.push_back(float(y));
    s.positions.push_back(float(z));
    return uint32_t(s.vertex_count() - 1);
}
inline void add_triangle(Surface& s, uint32_t a, uint32_t b, uint32_t c) {
    s.triangles.insert(s.triangles.end(), {a, b, c});
}
// Flips every triangle whose normal points towards `centre` (valid for convex shapes only).
inline void orient_outward(Surface& s, const Vec3& centre) {
    for (size_t t = 0; t < s.triangle_count(); ++t)
        if (dot(triangle_normal(s, t), triangle_centroid(s, t) - centre) < 0)
            std::swap(s.triangles[3 * t + 1], s.triangles[3 * t + 2]);
}

// One right triangle (0,0,0) (1,0,0) (0,1,0), normal +z.
// V 3, E 3, F 1, boundary edges 3, 1 loop, 1 component, Euler 1.
inline Surface single_triangle() {
    Surface s;
    add_vertex(s, 0, 0, 0);
    add_vertex(s, 1, 0, 0);
    add_vertex(s, 0, 1, 0);
    add_triangle(s, 0, 1, 2);
    return s;
}

// The unit square as two triangles (0,1,2) (0,2,3), normal +z.
// V 4, E 5, F 2, boundary edges 4, 1 loop, 1 component, Euler 1.
inline Surface square() {
    Surface s;
    add_vertex(s, 0, 0, 0);
    add_vertex(s, 1, 0, 0);
    add_vertex(s, 1, 1, 0);
    add_vertex(s, 0, 1, 0);
    add_triangle(s, 0, 1, 2);
    add_triangle(s, 0, 2, 3);
    return s;
}

// A regular n-gon fan: centre 0 at (0,0,height), rim vertex i+1 at angle 2*pi*i/n on the unit
// circle in z = 0; triangles (0, i+1, (i+1)%n + 1), normal +z side.
// V n+1, E 2n, F n, boundary edges n, 1 loop, 1 component, Euler 1.
inline Surface fan(int n, double height = 0.0) {
    Surface s;
    add_vertex(s, 0, 0, height);
    for (int i = 0; i < n; ++i)
        add_vertex(s, std::cos(2 * kPi * i / n), std::sin(2 * kPi * i / n), 0);
    for (int i = 0; i < n; ++i) add_triangle(s, 0, uint32_t(1 + i), uint32_t(1 + (i + 1) % n));
    return s;
}

// Regular tetrahedron (1,1,1) (1,-1,-1) (-1,1,-1) (-1,-1,1), outward; edge 2*sqrt(2), volume 8/3.
// V 4, E 6, F 4, closed, 1 component, Euler 2.
inline Surface tetrahedron() {
    Surface s;
    add_vertex(s, 1, 1, 1);
    add_vertex(s, 1, -1, -1);
    add_vertex(s, -1, 1, -1);
    add_vertex(s, -1, -1, 1);
    add_triangle(s, 0, 1, 2);
    add_triangle(s, 0, 1, 3);
    add_triangle(s, 0, 2, 3);
    add_triangle(s, 1, 2, 3);
    orient_outward(s, {0, 0, 0});
    return s;
}

// The corner tetrahedron O(0,0,0) X(1,0,0) Y(0,1,0) Z(0,0,1), outward; volume 1/6.
inline Surface corner_tetrahedron() {
    Surface s;
    add_vertex(s, 0, 0, 0);
    add_vertex(s, 1, 0, 0);
    add_vertex(s, 0, 1, 0);
    add_vertex(s, 0, 0, 1);
    add_triangle(s, 0, 1, 2);
    add_triangle(s, 0, 1, 3);
    add_triangle(s, 0, 2, 3);
    add_triangle(s, 1, 2, 3);
    orient_outward(s, {0.25, 0.25, 0.25});
    return s;
}

// Regular octahedron, vertices +-e_k, outward; volume 4/3 (|x|+|y|+|z| <= 1 is 8 * 1/6).
// V 6, E 12, F 8, closed, Euler 2.
inline Surface octahedron() {
    Surface s;
    for (int k = 0; k < 3; ++k)
        for (double sign : {1.0, -1.0}) {
            Vec3 p{0, 0, 0};
            p[k] = sign;
            add_vertex(s, p[0], p[1], p[2]);
        }
    // vertex 2k is +e_k, 2k+1 is -e_k
    for (uint32_t sx : {0u, 1u})
        for (uint32_t sy : {0u, 1u})
            for (uint32_t sz : {0u, 1u}) add_triangle(s, sx, 2 + sy, 4 + sz);
    orient_outward(s, {0, 0, 0});
    return s;
}

// Icosahedron subdivided `level` times, vertices on the unit sphere, outward.
// V 10*4^level + 2, F 20*4^level, E 30*4^level, closed, Euler 2.
inline Surface icosphere(int level) {
    const double t = (1 + std::sqrt(5.0)) / 2;
    std::vector<Vec3> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                           {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                           {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::array<uint32_t, 3>> f = {
        {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (Vec3& q : p) q = (1.0 / norm(q)) * q;
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            Vec3 m = 0.5 * (p[a] + p[b]);
            p.push_back((1.0 / norm(m)) * m);
            return mid[key] = uint32_t(p.size() - 1);
        };
        std::vector<std::array<uint32_t, 3>> g;
        for (auto [a, b, c] : f) {
            uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            g.push_back({a, ab, ca});
            g.push_back({b, bc, ab});
            g.push_back({c, ca, bc});
            g.push_back({ab, bc, ca});
        }
        f = std::move(g);
    }
    Surface s;
    for (const Vec3& q : p) add_vertex(s, q[0], q[1], q[2]);
    for (auto [a, b, c] : f) add_triangle(s, a, b, c);
    orient_outward(s, {0, 0, 0});
    return s;
}

// A thin blade: icosphere(4) scaled to 8 x 2 x kThinBladeThickness. The planes of the triangles
// around its rim are nearly parallel to the blade, so they hardly price pulling the rim inwards.
inline constexpr double kThinBladeThickness = 0.06;
inline Surface thin_blade() {
    Surface s = icosphere(4);
    for (size_t v = 0; v < s.vertex_count(); ++v) {
        s.positions[3 * v] *= 4.0f;
        s.positions[3 * v + 2] *= float(kThinBladeThickness / 2);
    }
    return s;
}

// Distance from p to the triangle (a, b, c), by its three edges and, where p projects inside, its
// plane (brute force, independent of the library's closest-point code).
inline double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    auto to_segment = [&](const Vec3& u, const Vec3& w) {
        const Vec3 d = w - u;
        const double t = std::clamp(dot(p - u, d) / dot(d, d), 0.0, 1.0);
        return norm(p - (u + t * d));
    };
    double best = std::min({to_segment(a, b), to_segment(b, c), to_segment(c, a)});
    const Vec3 n = cross(b - a, c - a);
    const double nn = dot(n, n);
    if (nn == 0) return best;
    const Vec3 q = p - (dot(p - a, n) / nn) * n; // p's projection on the plane
    if (dot(cross(b - a, q - a), n) >= 0 && dot(cross(c - b, q - b), n) >= 0 &&
        dot(cross(a - c, q - c), n) >= 0)
        best = std::min(best, std::abs(dot(p - a, n)) / std::sqrt(nn));
    return best;
}

// The largest distance from an input vertex to the reduction (brute force over its triangles).
inline double farthest_input_vertex(const Surface& in, const Surface& out) {
    double farthest = 0;
    for (size_t v = 0; v < in.vertex_count(); ++v) {
        double nearest = INFINITY;
        for (size_t t = 0; t < out.triangle_count(); ++t) {
            const auto [a, b, c] = corners(out, t);
            nearest = std::min(nearest, distance_to_triangle(position(in, v), position(out, a),
                                                             position(out, b), position(out, c)));
        }
        farthest = std::max(farthest, nearest);
    }
    return farthest;
}

// farthest_input_vertex of `in` and its reduction with `o` at `alpha` to `keep` of its triangles
// (a failure is recorded if the reduction stops short of its target).
inline double farthest_after_reduction(const Surface& in, Options o, double alpha, double keep) {
    o.alpha = alpha;
    o.keep_fraction = keep;
    const Result r = simplify(in, o);
    EXPECT_TRUE(r.target_reached) << describe(r.stop);
    return farthest_input_vertex(in, r.surface);
}

// Flat grid over [0,1]^2 in z = 0: vertex (i, j) = (i/nx, j/ny, 0) has index j*(nx+1) + i; each
// cell is split along its (i,j)-(i+1,j+1) diagonal into (a,b,c) and (a,c,d), normal +z.
// V (nx+1)(ny+1), F 2 nx ny, E nx(ny+1) + ny(nx+1) + nx ny, boundary edges 2(nx+ny), 1 loop,
// Euler 1.
inline uint32_t grid_index(int nx, int i, int j) {
    return uint32_t(j * (nx + 1) + i);
}
inline Surface grid(int nx, int ny, const std::function<bool(int, int)>& keep_cell = {}) {
    Surface s;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) add_vertex(s, double(i) / nx, double(j) / ny, 0);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            if (keep_cell && !keep_cell(i, j)) continue;
            uint32_t a = grid_index(nx, i, j), b = grid_index(nx, i + 1, j),
                     c = grid_index(nx, i + 1, j + 1), d = grid_index(nx, i, j + 1);
            add_triangle(s, a, b, c);
            add_triangle(s, a, c, d);
        }
    return s;
}

// An n x n grid without the cells lo <= i,j < hi: an annulus. Vertices strictly inside the hole
// stay in `positions` but no triangle uses them. For n = 6, lo = 2, hi = 4: 49 positions, 48 used
// (only (3,3) is strictly inside), F 64, E 112, boundary edges 24 + 8 = 32, 2 loops, Euler 0.
inline Surface grid_with_hole(int n, int lo, int hi) {
    return grid(n, n, [=](int i, int j) { return !(i >= lo && i < hi && j >= lo && j < hi); });
}

// The surface of the cube [-1,1]^3, each face an n x n grid (lattice points shared between
// faces), outward. V (n+1)^3 - (n-1)^3 = 6n^2 + 2, F 12 n^2, E 18 n^2, closed, Euler 2.
inline Surface cube(int n) {
    Surface s;
    std::map<std::array<int, 3>, uint32_t> index;
    auto vertex = [&](std::array<int, 3> ijk) {
        auto it = index.find(ijk);
        if (it != index.end()) return it->second;
        return index[ijk] = add_vertex(s, -1 + 2.0 * ijk[0] / n, -1 + 2.0 * ijk[1] / n,
                                       -1 + 2.0 * ijk[2] / n);
    };
    for (int axis = 0; axis < 3; ++axis)
        for (int side : {0, n})
            for (int a = 0; a < n; ++a)
                for (int b = 0; b < n; ++b) {
                    auto at = [&](int u, int v) {
                        std::array<int, 3> ijk{};
                        ijk[axis] = side;
                        ijk[(axis + 1) % 3] = u;
                        ijk[(axis + 2) % 3] = v;
                        return vertex(ijk);
                    };
                    uint32_t p = at(a, b), q = at(a + 1, b), r = at(a + 1, b + 1), w = at(a, b + 1);
                    add_triangle(s, p, q, r);
                    add_triangle(s, p, r, w);
                }
    orient_outward(s, {0, 0, 0});
    return s;
}

// Torus around the z axis, ring radius R, tube radius r; vertex (u, v) at
// ((R + r cos v) cos u, (R + r cos v) sin u, r sin v). Quads (u,v) (u+1,v) (u+1,v+1) (u,v+1):
// d/du x d/dv points away from the tube centre, so the triangles are outward.
// V nu nv, E 3 nu nv, F 2 nu nv, closed, Euler 0.
inline Surface torus(int nu, int nv, double R = 2.0, double r = 0.75) {
    Surface s;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
            add_vertex(s, (R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                       r * std::sin(v));
        }
    auto id = [&](int i, int j) { return uint32_t((i % nu) * nv + (j % nv)); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            add_triangle(s, id(i, j), id(i + 1, j), id(i + 1, j + 1));
            add_triangle(s, id(i, j), id(i + 1, j + 1), id(i, j + 1));
        }
    return s;
}

// Appends `b` to `a` (indices shifted; fields are not merged, build them afterwards).
inline void append(Surface& a, const Surface& b) {
    uint32_t offset = uint32_t(a.vertex_count());
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    for (uint32_t i : b.triangles) a.triangles.push_back(i + offset);
}

// Two n x n grids, [0,1]^2 and [2,3]x[0,1]: two components, 2 loops, Euler 2.
inline Surface two_components(int n) {
    Surface s = grid(n, n);
    Surface t = grid(n, n);
    for (size_t v = 0; v < t.vertex_count(); ++v) t.positions[3 * v] += 2.0f;
    append(s, t);
    return s;
}

// Two flat fans sharing only vertex 0 (the origin): fan A (0,1,2) (0,2,3) with rim at angles
// -45, 0, 45 degrees, fan B (0,4,5) (0,5,6) with rim at 135, 180, 225 degrees.
// V 7, E 10 (5 per fan), F 4, boundary edges 8, 1 non-manifold vertex (0: its star is two
// half-disks), 2 (edge-connected) components, Euler 7 - 10 + 4 = 1.
inline Surface bowtie() {
    Surface s;
    add_vertex(s, 0, 0, 0);
    for (double deg : {-45.0, 0.0, 45.0, 135.0, 180.0, 225.0})
        add_vertex(s, std::cos(deg * kPi / 180), std::sin(deg * kPi / 180), 0);
    add_triangle(s, 0, 1, 2);
    add_triangle(s, 0, 2, 3);
    add_triangle(s, 0, 4, 5);
    add_triangle(s, 0, 5, 6);
    return s;
}

// Three triangles on the edge 0-1 (a "fin"): apexes 2 (0.5,1,0), 3 (0.5,-1,0), 4 (0.5,0,1).
// V 5, E 1 + 3*2 = 7, F 3, boundary edges 6, 1 non-manifold edge (0-1), 2 non-manifold vertices
// (0 and 1: their stars are three triangles around one edge, not a disk or half-disk),
// 1 component, Euler 5 - 7 + 3 = 1.
inline Surface fin() {
    Surface s;
    add_vertex(s, 0, 0, 0);
    add_vertex(s, 1, 0, 0);
    add_vertex(s, 0.5, 1, 0);
    add_vertex(s, 0.5, -1, 0);
    add_vertex(s, 0.5, 0, 1);
    add_triangle(s, 0, 1, 2);
    add_triangle(s, 1, 0, 3);
    add_triangle(s, 0, 1, 4);
    return s;
}

// An n x n grid with one extra triangle standing on the interior edge (n/2, n/2)-(n/2+1, n/2):
// that edge has three triangles (1 non-manifold edge, its 2 end points are non-manifold).
// Euler stays 1 (one more vertex, two more edges, one more triangle).
inline Surface fin_on_grid(int n) {
    Surface s = grid(n, n);
    int i = n / 2, j = n / 2;
    uint32_t apex = add_vertex(s, (i + 0.5) / n, double(j) / n, 1.0 / n);
    add_triangle(s, grid_index(n, i, j), grid_index(n, i + 1, j), apex);
    return s;
}

// An n x n grid with a closed tetrahedron x, y, a, b standing on its interior edge
// x = (n/2, n/2), y = (n/2+1, n/2): that edge has four triangles (1 non-manifold edge, x and y
// non-manifold). a and b have valence 3 and share exactly x and y as neighbours, so collapsing
// a-b passes the link condition but would fold the tetrahedron into two triangles on x, y and
// the new point. Euler 2 (two more vertices, five more edges, four more triangles).
inline Surface tetrahedron_on_grid(int n) {
    Surface s = grid(n, n);
    const int i = n / 2, j = n / 2;
    const uint32_t x = grid_index(n, i, j), y = grid_index(n, i + 1, j);
    const uint32_t a = add_vertex(s, double(i) / n, (j - 0.25) / n, 1.0 / n);
    const uint32_t b = add_vertex(s, (i - 0.026) / n, (j + 0.114) / n, 1.143 / n);
    add_triangle(s, x, y, a);
    add_triangle(s, y, x, b);
    add_triangle(s, x, a, b);
    add_triangle(s, y, b, a);
    return s;
}

// Two n x n grids, [0,1]^2 and [-1,0]^2, sharing only the vertex at the origin (index 0):
// 1 non-manifold vertex, 2 components, Euler 2*1 - 1 = 1.
inline Surface corner_touching_grids(int n) {
    Surface s = grid(n, n);
    std::vector<uint32_t> map((n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            map[grid_index(n, i, j)] =
                (i == n && j == n) ? 0u : add_vertex(s, -1 + double(i) / n, -1 + double(j) / n, 0);
    Surface b = grid(n, n);
    for (uint32_t idx : b.triangles) s.triangles.push_back(map[idx]);
    return s;
}

// A Moebius strip of n quads around the z axis (ring radius 2, width 0.5): vertex 2i on the
// "top" rail, 2i+1 on the "bottom" one; after a half turn the top rail arrives on the bottom,
// so the last quad joins top(n-1), bottom(n-1) to top(0)'s partner bottom(0) and vice versa.
// Not orientable. V 2n, E 4n (2n rail + n rung + n diagonal), F 2n, boundary edges 2n forming
// one loop, 1 component, Euler 0.
inline Surface moebius(int n) {
    Surface s;
    for (int i = 0; i < n; ++i) {
        double u = 2 * kPi * i / n;
        for (double w : {0.25, -0.25})
            add_vertex(s, (2 + w * std::cos(u / 2)) * std::cos(u),
                       (2 + w * std::cos(u / 2)) * std::sin(u), w * std::sin(u / 2));
    }
    for (int i = 0; i < n; ++i) {
        uint32_t top = uint32_t(2 * i), bottom = top + 1;
        uint32_t next_top = uint32_t(2 * (i + 1)), next_bottom = next_top + 1;
        if (i == n - 1) next_top = 1, next_bottom = 0; // the half twist
        add_triangle(s, top, bottom, next_bottom);
        add_triangle(s, top, next_bottom, next_top);
    }
    return s;
}

// Flips (a,b,c) -> (a,c,b) every triangle for which `which(t)` holds.
inline Surface flipped(Surface s, const std::function<bool(size_t)>& which) {
    for (size_t t = 0; t < s.triangle_count(); ++t)
        if (which(t)) std::swap(s.triangles[3 * t + 1], s.triangles[3 * t + 2]);
    return s;
}

// ---------------------------------------------------------------------------------------------
// Fields
// ---------------------------------------------------------------------------------------------

using FieldFunction = std::function<std::vector<double>(const Vec3&)>;

// Adds a field whose value at each vertex is `f(position)`.
inline void add_field(Surface& s, const std::string& name, int components, const FieldFunction& f) {
    Field field{name, components, {}};
    for (size_t v = 0; v < s.vertex_count(); ++v)
        for (double value : f(position(s, v))) field.values.push_back(float(value));
    s.fields.push_back(std::move(field));
}

// The two fields most tests carry: a smooth scalar "pressure" and a 3-vector "velocity" that
// equals the vertex position (so data interpolated along an edge can be checked against the
// point's position).
inline Surface with_test_fields(Surface s) {
    add_field(s, "pressure", 1, [](const Vec3& p) {
        return std::vector<double>{std::sin(3 * p[0]) + std::cos(2 * p[1]) + p[2]};
    });
    add_field(s, "velocity", 3, [](const Vec3& p) {
        return std::vector<double>{p[0], p[1], p[2]};
    });
    return s;
}

// ---------------------------------------------------------------------------------------------
// Comparisons and checks
// ---------------------------------------------------------------------------------------------

// The surface without the vertices no triangle uses, the others in their old order.
inline Surface compact(const Surface& s) {
    std::vector<uint32_t> map(s.vertex_count(), UINT32_MAX);
    for (uint32_t i : s.triangles) map[i] = 0;
    Surface out;
    uint32_t next = 0;
    for (size_t v = 0; v < s.vertex_count(); ++v)
        if (map[v] == 0) {
            map[v] = next++;
            out.positions.insert(out.positions.end(), s.positions.begin() + 3 * v,
                                 s.positions.begin() + 3 * v + 3);
        }
    for (uint32_t i : s.triangles) out.triangles.push_back(map[i]);
    for (const Field& f : s.fields) {
        Field g{f.name, f.components, {}};
        for (size_t v = 0; v < s.vertex_count(); ++v)
            if (map[v] != UINT32_MAX)
                g.values.insert(g.values.end(), f.values.begin() + v * f.components,
                                f.values.begin() + (v + 1) * f.components);
        out.fields.push_back(std::move(g));
    }
    return out;
}

// Each triangle as the floats of its corners (position, then every field's values, in field
// order), rotated so that the smallest corner comes first (orientation kept); sorted. Two
// surfaces with equal canonical forms are the same surface up to vertex numbering.
inline std::vector<std::vector<float>> canonical_triangles(const Surface& s) {
    auto corner = [&](uint32_t v) {
        std::vector<float> c(s.positions.begin() + 3 * v, s.positions.begin() + 3 * v + 3);
        for (const Field& f : s.fields)
            c.insert(c.end(), f.values.begin() + v * f.components,
                     f.values.begin() + (v + 1) * f.components);
        return c;
    };
    std::vector<std::vector<float>> out;
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        std::array<std::vector<float>, 3> c{corner(s.triangles[3 * t]),
                                            corner(s.triangles[3 * t + 1]),
                                            corner(s.triangles[3 * t + 2])};
        size_t first = size_t(std::min_element(c.begin(), c.end()) - c.begin());
        std::vector<float> key;
        for (size_t k = 0; k < 3; ++k)
            key.insert(key.end(), c[(first + k) % 3].begin(), c[(first + k) % 3].end());
        out.push_back(std::move(key));
    }
    std::sort(out.begin(), out.end());
    return out;
}

inline bool same_floats(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

// A progress callback's fractions: each in [0, 1], none below the one before.
inline ::testing::AssertionResult progress_in_order(const std::vector<double>& seen) {
    for (size_t i = 0; i < seen.size(); ++i) {
        if (!(seen[i] >= 0.0 && seen[i] <= 1.0))
            return ::testing::AssertionFailure() << "call " << i << ": " << seen[i];
        if (i > 0 && seen[i] < seen[i - 1])
            return ::testing::AssertionFailure()
                   << "call " << i << ": " << seen[i] << " after " << seen[i - 1];
    }
    return ::testing::AssertionSuccess();
}

// Byte-for-byte equality of positions, triangles and fields.
inline ::testing::AssertionResult same_bytes(const Surface& a, const Surface& b) {
    if (!same_floats(a.positions, b.positions))
        return ::testing::AssertionFailure() << "positions differ (" << a.vertex_count() << " vs "
                                             << b.vertex_count() << " vertices)";
    if (a.triangles != b.triangles)
        return ::testing::AssertionFailure()
               << "triangles differ (" << a.triangle_count() << " vs " << b.triangle_count() << ")";
    if (a.fields.size() != b.fields.size())
        return ::testing::AssertionFailure() << "field counts differ";
    for (size_t i = 0; i < a.fields.size(); ++i) {
        const Field &f = a.fields[i], &g = b.fields[i];
        if (f.name != g.name || f.components != g.components || !same_floats(f.values, g.values))
            return ::testing::AssertionFailure()
                   << "field " << i << " (" << f.name << "/" << g.name << ") differs";
    }
    return ::testing::AssertionSuccess();
}

// Structural soundness of an output surface: sizes, finite coordinates, indices in range, no
// triangle naming a vertex twice, no two triangles on the same three vertices, every vertex used,
// and (check_area) no triangle of (nearly) zero area relative to the bounding box.
inline ::testing::AssertionResult well_formed(const Surface& s, bool check_area = true) {
    if (s.positions.size() % 3 || s.triangles.size() % 3)
        return ::testing::AssertionFailure() << "array sizes are not multiples of 3";
    if (s.triangles.empty()) return ::testing::AssertionFailure() << "no triangles";
    for (size_t i = 0; i < s.positions.size(); ++i)
        if (!std::isfinite(s.positions[i]))
            return ::testing::AssertionFailure() << "vertex " << i / 3 << " is not finite";
    std::vector<bool> used(s.vertex_count(), false);
    std::set<std::array<uint32_t, 3>> seen;
    const double diag = bbox_diagonal(s);
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        auto c = corners(s, t);
        for (uint32_t v : c) {
            if (v >= s.vertex_count())
                return ::testing::AssertionFailure()
                       << "triangle " << t << " index " << v << " out of range";
            used[v] = true;
        }
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2])
            return ::testing::AssertionFailure() << "triangle " << t << " is degenerate";
        std::sort(c.begin(), c.end());
        if (!seen.insert(c).second)
            return ::testing::AssertionFailure()
                   << "triangle " << t << " duplicates an earlier one";
        if (check_area && triangle_area(s, t) <= 1e-10 * diag * diag)
            return ::testing::AssertionFailure() << "triangle " << t << " has zero area";
    }
    for (size_t v = 0; v < used.size(); ++v)
        if (!used[v]) return ::testing::AssertionFailure() << "vertex " << v << " is unused";
    for (const Field& f : s.fields)
        if (f.components < 1 || f.values.size() != s.vertex_count() * size_t(f.components))
            return ::testing::AssertionFailure() << "field " << f.name << " has the wrong size";
    return ::testing::AssertionSuccess();
}

struct ComponentRange {
    double lo = INFINITY, hi = -INFINITY;
};

// Per field, per component: min and max over the vertices that some triangle uses.
inline std::vector<std::vector<ComponentRange>> field_ranges(const Surface& s) {
    std::vector<bool> used(s.vertex_count(), false);
    for (uint32_t i : s.triangles) used[i] = true;
    std::vector<std::vector<ComponentRange>> out;
    for (const Field& f : s.fields) {
        std::vector<ComponentRange> r(size_t(f.components));
        for (size_t v = 0; v < s.vertex_count(); ++v)
            if (used[v])
                for (int c = 0; c < f.components; ++c) {
                    double x = f.values[v * f.components + c];
                    r[c].lo = std::min(r[c].lo, x);
                    r[c].hi = std::max(r[c].hi, x);
                }
        out.push_back(std::move(r));
    }
    return out;
}

// Every field of `in` is in `out` with the same name and components, one finite tuple per vertex,
// and each component within the input's range. The slack is float rounding only:
// 1e-6 * max(|lo|, |hi|, hi - lo) (a few ulps), so an interpolation weight outside [0,1] by more
// than about 1e-6 is caught.
inline ::testing::AssertionResult fields_carried(const Surface& in, const Surface& out) {
    if (out.fields.size() != in.fields.size())
        return ::testing::AssertionFailure()
               << "input has " << in.fields.size() << " fields, output " << out.fields.size();
    auto ranges = field_ranges(in);
    for (size_t i = 0; i < in.fields.size(); ++i) {
        const Field& f = in.fields[i];
        const Field* g = out.find_field(f.name);
        if (!g) return ::testing::AssertionFailure() << "field " << f.name << " is missing";
        if (g->components != f.components)
            return ::testing::AssertionFailure() << "field " << f.name << " has " << g->components
                                                 << " components, input " << f.components;
        if (g->values.size() != out.vertex_count() * size_t(f.components))
            return ::testing::AssertionFailure()
                   << "field " << f.name << " has " << g->values.size() << " values for "
                   << out.vertex_count() << " vertices";
        for (size_t k = 0; k < g->values.size(); ++k) {
            const ComponentRange& r = ranges[i][k % f.components];
            double slack = 1e-6 * std::max({std::abs(r.lo), std::abs(r.hi), r.hi - r.lo});
            double x = g->values[k];
            if (!std::isfinite(x) || x < r.lo - slack || x > r.hi + slack)
                return ::testing::AssertionFailure()
                       << "field " << f.name << " vertex " << k / f.components << " component "
                       << k % f.components << " = " << x << " outside the input's range [" << r.lo
                       << ", " << r.hi << "]";
        }
    }
    return ::testing::AssertionSuccess();
}

// What simplification must keep (ddsimp.h, `simplify`): Euler characteristic, boundary loops and
// components equal; non-manifold edges never more. Also: no new non-manifold (pinched) vertex.
inline ::testing::AssertionResult topology_kept(const Topology& before, const Topology& after) {
    auto fail = [&]() {
        return ::testing::AssertionFailure()
               << "before: euler " << before.euler_characteristic << " loops "
               << before.boundary_loops << " components " << before.components << " nm-edges "
               << before.nonmanifold_edges << " nm-vertices " << before.nonmanifold_vertices
               << "; after: euler " << after.euler_characteristic << " loops "
               << after.boundary_loops << " components " << after.components << " nm-edges "
               << after.nonmanifold_edges << " nm-vertices " << after.nonmanifold_vertices;
    };
    if (before.euler_characteristic != after.euler_characteristic ||
        before.boundary_loops != after.boundary_loops || before.components != after.components ||
        after.nonmanifold_edges > before.nonmanifold_edges ||
        after.nonmanifold_vertices > before.nonmanifold_vertices)
        return fail();
    return ::testing::AssertionSuccess();
}

// Whether some vertex of `s` sits exactly (bit for bit) at `p` (given in float).
inline bool has_vertex_at(const Surface& s, const Vec3& p) {
    for (size_t v = 0; v < s.vertex_count(); ++v)
        if (s.positions[3 * v] == float(p[0]) && s.positions[3 * v + 1] == float(p[1]) &&
            s.positions[3 * v + 2] == float(p[2]))
            return true;
    return false;
}

// Exact position -> vertex index (the test surfaces have distinct positions).
inline std::map<std::array<float, 3>, uint32_t> vertex_lookup(const Surface& s) {
    std::map<std::array<float, 3>, uint32_t> out;
    for (size_t v = 0; v < s.vertex_count(); ++v)
        out.emplace(std::array<float, 3>{s.positions[3 * v], s.positions[3 * v + 1],
                                         s.positions[3 * v + 2]},
                    uint32_t(v));
    return out;
}

// Positions of the non-manifold vertices of a surface, found independently of the library: a
// vertex is regular when its incident triangles, linked through the edges they share at the
// vertex (each shared by exactly two of them), form one chain or cycle.
inline std::vector<Vec3> nonmanifold_vertex_positions(const Surface& s) {
    std::map<std::pair<uint32_t, uint32_t>, int> edge_count;
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        auto c = corners(s, t);
        for (int k = 0; k < 3; ++k) edge_count[std::minmax(c[k], c[(k + 1) % 3])]++;
    }
    std::vector<std::vector<size_t>> star(s.vertex_count());
    for (size_t t = 0; t < s.triangle_count(); ++t)
        for (uint32_t v : corners(s, t)) star[v].push_back(t);
    std::vector<Vec3> out;
    for (size_t v = 0; v < s.vertex_count(); ++v) {
        if (star[v].empty()) continue;
        bool bad = false;
        // union-find over the star's triangles through edges (v, w) with exactly two triangles
        std::vector<size_t> parent(star[v].size());
        for (size_t i = 0; i < parent.size(); ++i) parent[i] = i;
        std::function<size_t(size_t)> root = [&](size_t i) {
            return parent[i] == i ? i : parent[i] = root(parent[i]);
        };
        std::map<uint32_t, std::vector<size_t>> by_other;
        for (size_t i = 0; i < star[v].size(); ++i)
            for (uint32_t w : corners(s, star[v][i]))
                if (w != v) by_other[w].push_back(i);
        for (auto& [w, list] : by_other) {
            if (edge_count[std::minmax(uint32_t(v), w)] > 2) bad = true;
            for (size_t k = 1; k < list.size(); ++k) parent[root(list[k])] = root(list[0]);
        }
        std::set<size_t> roots;
        for (size_t i = 0; i < parent.size(); ++i) roots.insert(root(i));
        if (bad || roots.size() > 1) out.push_back(position(s, v));
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// Error messages
// ---------------------------------------------------------------------------------------------

// Whether `text` contains the integer `n` as a whole number (not as part of a longer number).
inline bool mentions_number(const std::string& text, long long n) {
    const std::string needle = std::to_string(n);
    for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) {
        bool left = at == 0 || !std::isdigit(static_cast<unsigned char>(text[at - 1]));
        size_t end = at + needle.size();
        bool right = end == text.size() || !std::isdigit(static_cast<unsigned char>(text[end]));
        if (left && right) return true;
    }
    return false;
}

// Case-insensitive substring test.
inline bool mentions(const std::string& text, const std::string& word) {
    auto lower = [](std::string x) {
        for (char& c : x) c = char(std::tolower(static_cast<unsigned char>(c)));
        return x;
    };
    return lower(text).find(lower(word)) != std::string::npos;
}

// ---------------------------------------------------------------------------------------------
// Strategy / placement combinations
// ---------------------------------------------------------------------------------------------

struct Config {
    Strategy strategy;
    Placement placement;
    const char* name;
};
inline void PrintTo(const Config& c, std::ostream* os) {
    *os << c.name;
}

inline std::vector<Config> all_configs() {
    return {{Strategy::EdgeCollapse, Placement::LeastError, "EdgeLeastError"},
            {Strategy::EdgeCollapse, Placement::Midpoint, "EdgeMidpoint"},
            {Strategy::EdgeCollapse, Placement::VolumePreserving, "EdgeVolume"},
            {Strategy::VertexRemoval, Placement::Midpoint, "VertexRemoval"}};
}
inline Options options_for(const Config& c) {
    Options o;
    o.strategy = c.strategy;
    o.placement = c.placement;
    return o;
}
inline std::string config_name(const ::testing::TestParamInfo<Config>& info) {
    return info.param.name;
}

inline const char* stop_name(StopReason r) {
    switch (r) {
    case StopReason::TargetReached:
        return "TargetReached";
    case StopReason::WeightBound:
        return "WeightBound";
    case StopReason::NothingRemovable:
        return "NothingRemovable";
    case StopReason::Cancelled:
        return "Cancelled";
    }
    return "?";
}

} // namespace ddsimp::test

namespace ddsimp {
// Readable StopReason in gtest failure messages.
inline void PrintTo(StopReason r, std::ostream* os) {
    *os << test::stop_name(r);
}
} // namespace ddsimp
