// The mutable surface the simplifier works on: flat arrays, a half-edge structure over triangle
// slots, no per-element allocation. Half-edge h = 3t + c runs from corner c of slot t to corner
// c + 1; its twin is the half-edge of the neighbouring triangle on the same edge, or kNone on a
// boundary. Edges with three or more triangles, or whose triangles disagree on orientation, get
// no twin either, and their vertices are locked (kind Complex).
#pragma once

#include "ddsimp/ddsimp.h"
#include "huge_pages.h"
#include "parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

namespace ddsimp::detail {

inline constexpr uint32_t kNone = 0xffffffffu;
// Rounds of neighbour averaging that turn vertex normals into reference normals.
inline constexpr int kReferenceSmoothing = 4;
// Limits::zigzag, as a share of the input's mean edge length: a rim that crosses the cells
// wanders by about half a cell from its straight course.
inline constexpr double kZigzagShare = 0.5;
// Two neighbouring triangles whose normals are more than 175 degrees apart: the surface folds
// back over itself there (a cutting plane through a mesh's overlapping cells makes these). The
// error quadrics hardly see what moving such a fold costs, since its two sides lie in nearly one
// plane, yet it uncovers part of the surface; so the fold's vertices are locked.
inline constexpr double kFoldCos = -0.99619469809174553; // cos(175 degrees)

inline uint32_t next(uint32_t h) {
    return h % 3 == 2 ? h - 2 : h + 1;
}
inline uint32_t prev(uint32_t h) {
    return h % 3 == 0 ? h + 2 : h - 1;
}

// What a vertex may do. Line: on a boundary or feature line that continues straight. Corner: on
// a line, but where it bends, ends or branches; it stays where it is. Complex: its star is not
// a disk or half-disk; it is never touched.
enum class VertexKind : uint8_t { Free, Line, Corner, Complex, Dead };

using Vec3 = std::array<double, 3>;
inline Vec3 sub(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Vec3 add(const Vec3& a, const Vec3& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Vec3 scale(const Vec3& a, double s) {
    return {a[0] * s, a[1] * s, a[2] * s};
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
// Two unit vectors across the unit vector `axis`, perpendicular to each other, (u1, u2, axis)
// right-handed: a frame of the plane across an axis.
inline std::array<Vec3, 2> plane_across(const Vec3& axis) {
    Vec3 u1 = std::abs(axis[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    u1 = sub(u1, scale(axis, dot(u1, axis)));
    u1 = scale(u1, 1 / norm(u1));
    return {u1, cross(axis, u1)};
}
// Vertex v of a surface's positions (three floats per vertex).
inline Vec3 point_of(const std::vector<float>& positions, uint32_t v) {
    return {positions[3 * size_t(v)], positions[3 * size_t(v) + 1], positions[3 * size_t(v) + 2]};
}
// The distance from p to the segment from a to b.
inline double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = sub(b, a), ap = sub(p, a);
    const double length2 = dot(ab, ab);
    const double t = length2 > 0 ? std::clamp(dot(ap, ab) / length2, 0.0, 1.0) : 0.0;
    return norm(sub(ap, scale(ab, t)));
}
// The point of triangle (a, b, c) closest to p, and its barycentric weights.
struct ClosestPoint {
    Vec3 point;
    std::array<double, 3> weights;
};
// By the region of the triangle's plane that p projects into (Ericson, Real-Time Collision
// Detection, 5.1.5).
inline ClosestPoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                        const Vec3& c) {
    const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return {a, {1, 0, 0}};
    const Vec3 bp = sub(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return {b, {0, 1, 0}};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return {add(a, scale(ab, v)), {1 - v, v, 0}};
    }
    const Vec3 cp = sub(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return {c, {0, 0, 1}};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return {add(a, scale(ac, w)), {1 - w, 0, w}};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {add(b, scale(sub(c, b), w)), {0, 1 - w, w}};
    }
    const double denom = 1 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    return {add(a, add(scale(ab, v), scale(ac, w))), {1 - v - w, v, w}};
}

// Feature and tolerance settings, as cosines.
struct Limits {
    double feature_cos = -2; // twin normals with a smaller cosine make a feature edge
    double straight_cos = 1; // a line vertex's two edges must turn less than this
    double normal_turn_cos = 0.5;
    // A vertex whose line turns more than straight_cos allows is still a line vertex when it
    // lies within this distance of the segment between its two line neighbours and its input
    // line turned the other way at a neighbour (WorkingMesh::zigzag, turns_back): a zigzag of the
    // sampling (a cut or an isosurface's rim crossing the cells), not a bend of the line. Set by
    // build to kZigzagShare of the input's mean edge length when there is a line tolerance; 0: off.
    double zigzag = 0;
};

struct WorkingMesh {
    // Per vertex (capacity: input vertices + one new vertex per possible collapse).
    // One record of `record` floats per vertex: its position (3), its reference normal (3, see
    // reference_normal) and its data (`stride` values: every field's components, in field
    // order). One array rather than three, because an operation reads all three of the same few
    // vertices: one cache line per vertex instead of three.
    Array<float> records;
    size_t stride = 0, record = 6;
    std::vector<std::pair<FieldKind, int>> fields; // each field's kind and components, in order
    Array<uint32_t> out; // an outgoing half-edge; on a boundary the one without a twin
    Array<VertexKind> kind;
    Array<uint16_t> valence; // number of neighbours (kept up to date by classify)
    // Options::locked by vertex slot, and the vertices of the input's folds (see kFoldCos);
    // empty: none. classify makes a locked vertex a Corner, and a collapse into a locked vertex
    // passes the lock on to the slot of the new vertex.
    Array<uint8_t> locked;
    // Vertices on a line of the input that turn the other way from a line neighbour
    // (turns_back): where the line may be a zigzag of the sampling (Limits::zigzag); empty when
    // there is none. A collapse passes it on to the new vertex from either end.
    Array<uint8_t> zigzag;
    size_t vertex_count = 0; // vertices in use (ids below this)

    // Per half-edge.
    Array<uint32_t> origin; // kNone for a retired slot
    Array<uint32_t> twin;
    Array<uint8_t> line; // boundary or feature edge
    Array<float> angle;  // the triangle's angle at the half-edge's origin (see track_angles)

    size_t live_triangles = 0;
    Limits limits;
    // Set before build: keep the corner angles (angle, update_angles, classify's sum). Only the
    // angle deficit reads them; without them `angle` stays empty and classify returns 0.
    bool track_angles = true;

    // Builds the half-edges, twins, line flags and vertex kinds for a validated surface (part-way
    // if a watch on `threads` stops it, stage_watch.h).
    // `capacity` is the number of vertex slots to reserve. With `order` and `rank` (each the
    // other's inverse) vertex v is the surface's vertex order[v] and a triangle's index i becomes
    // rank[i], read in place rather than from a reordered copy; empty: the surface's ids.
    // Runs on `threads` (none: one thread); the same result for any number.
    void build(const Surface& surface, size_t capacity, const Limits& limits,
               const std::vector<uint32_t>& order = {}, const std::vector<uint32_t>& rank = {},
               Parallel* threads = nullptr);

    float* position_of(uint32_t v) { return &records[size_t(v) * record]; }
    const float* position_of(uint32_t v) const { return &records[size_t(v) * record]; }
    // Unit normal of the input surface around v (a new vertex averages its edge's two): no
    // operation may leave a triangle facing away from its corners' normals, so turns cannot add
    // up to a flip over many operations.
    float* reference_of(uint32_t v) { return &records[size_t(v) * record + 3]; }
    const float* reference_of(uint32_t v) const { return &records[size_t(v) * record + 3]; }
    float* data_of(uint32_t v) { return &records[size_t(v) * record + 6]; }
    const float* data_of(uint32_t v) const { return &records[size_t(v) * record + 6]; }
    // Sets the data of n (which may be a's slot) for a new vertex at `along` (0 at a, 1 at b) on
    // the edge a-b, each field as its kind says (see FieldKind).
    void blend_data(uint32_t a, uint32_t b, double along, uint32_t n);

    Vec3 reference_normal(uint32_t v) const {
        const float* n = reference_of(v);
        return {n[0], n[1], n[2]};
    }
    // Does a triangle with (unnormalised) normal n face the way of the surface at its corners
    // (less than 90 degrees from each corner's reference normal)?
    template <class... V> bool faces_along(const Vec3& n, V... corners) const {
        return faces_along_normals(n, reference_normal(corners)...);
    }
    // The same, from the corners' reference normals (for callers that hold them already).
    template <class... R> static bool faces_along_normals(const Vec3& n, const R&... references) {
        return ((dot(n, references) > 0) && ...);
    }
    Vec3 point(uint32_t v) const {
        const float* p = position_of(v);
        return {p[0], p[1], p[2]};
    }
    uint32_t dest(uint32_t h) const { return origin[next(h)]; }
    bool is_boundary_vertex(uint32_t v) const { return twin[out[v]] == kNone; }
    // Outgoing half-edges around v, counter-clockwise from out[v]; stops at a boundary.
    template <class F> void for_each_outgoing(uint32_t v, F&& f) const {
        const uint32_t start = out[v];
        uint32_t h = start;
        do {
            f(h);
            h = twin[prev(h)];
        } while (h != kNone && h != start);
    }
    // Every edge at v once: f(h, other, true) for each outgoing half-edge h (other = dest(h)),
    // then on a boundary f(p, other, false) for the incoming half-edge p that closes the fan
    // (other = its origin).
    template <class F> void for_each_edge(uint32_t v, F&& f) const {
        uint32_t last = kNone;
        for_each_outgoing(v, [&](uint32_t h) {
            f(h, dest(h), true);
            last = h;
        });
        const uint32_t closing = prev(last);
        if (twin[closing] == kNone) f(closing, origin[closing], false);
    }
    // Neighbours of v in counter-clockwise order (on a boundary from the fan's first to its last
    // neighbour) into ids[0..max); returns their number, or 0 if there are more than `max`.
    size_t ring(uint32_t v, uint32_t* ids, size_t max) const;
    // The rings of vs[0..k), k <= 64: vertex vs[i]'s into ids[i * max ..], its count (as ring's,
    // 0 if more than max) into counts[i]. The walks advance side by side: each step of a walk
    // waits on its own last load, so k walks together take about as long as the longest.
    void rings(const uint32_t* vs, size_t k, uint32_t* ids, size_t max, size_t* counts) const;
    // One step of a walk around a fan that began at half-edge `start`, now at `h`: lists the next
    // neighbour into ids[count++] (on a boundary also the one closing the fan) and moves h on.
    // True when the walk is over; then count is 0 if there were more than `max`.
    bool ring_step(uint32_t& h, uint32_t start, uint32_t* ids, size_t& count, size_t max) const {
        if (count == max) return count = 0, true;
        ids[count++] = dest(h);
        const uint32_t p = prev(h);
        h = twin[p];
        if (h == kNone) { // boundary: the fan ends with the origin of its incoming edge
            if (count == max) return count = 0, true;
            ids[count++] = origin[p];
            return true;
        }
        return h == start;
    }

    Vec3 triangle_normal(uint32_t t) const; // not normalised (length = 2 x area)
    // Recomputes the three corner angles of slot t (after its corners moved or changed).
    void update_angles(uint32_t t);
    // Points `out[v]` at the fan's first half-edge (the one without a twin, if any), starting
    // the search at outgoing half-edge `h`. A Free vertex is on no boundary, which no operation
    // changes: its fan has no first half-edge, and `h` is kept without a walk (kind[v] must say
    // whether v is on a boundary).
    void reset_out(uint32_t v, uint32_t h);
    // Recomputes the kind and valence of v from its fan, line edges and their straightness. The
    // same walk calls visit(u, closing) for every neighbour u in ring order (closing: u only
    // closes a boundary fan, no half-edge leaves v towards it) and returns the sum of v's angles
    // (0 for a complex or dead vertex), so that a weight needs no second walk.
    template <class F> double classify(uint32_t v, F&& visit);
    void classify(uint32_t v) {
        classify(v, [](uint32_t, bool) {});
    }
    // Unit-free curvature from the angle sum that classify returned.
    double curvature_from(uint32_t v, double angles) const {
        if (kind[v] == VertexKind::Complex || kind[v] == VertexKind::Dead) return 0;
        const double full = is_boundary_vertex(v) ? std::numbers::pi : 2 * std::numbers::pi;
        return std::abs(full - angles) / std::numbers::pi;
    }
    // Whether the edge that for_each_edge gives as (h, outgoing) is on a line: a line edge, or
    // the edge closing a boundary fan (a boundary edge).
    bool on_line(uint32_t h, bool outgoing) const { return !outgoing || line[h]; }
    // v's neighbours along its line edges: the first two into ends; returns the number of line
    // edges at v.
    int line_neighbours(uint32_t v, uint32_t ends[2]) const {
        int lines = 0;
        for_each_edge(v, [&](uint32_t h, uint32_t other, bool outgoing) {
            if (on_line(h, outgoing) && lines++ < 2) ends[lines - 1] = other;
        });
        return lines;
    }
    // Whether line vertex v, between its line neighbours a and b, turns the other way (about its
    // reference normal) from a or b, each seen along the line: the line may zigzag there. A
    // polygon's corners all turn one way. Reads the line beyond a and b: for the input only.
    bool turns_back(uint32_t v, uint32_t a, uint32_t b) const;
    // Unit-free curvature: |2pi - sum of angles| (|pi - ...| on a boundary) / pi.
    double curvature(uint32_t v) const;
};

template <class F> double WorkingMesh::classify(uint32_t v, F&& visit) {
    if (kind[v] == VertexKind::Dead) return 0;
    if (kind[v] == VertexKind::Complex) {
        valence[v] = 0xffff; // never part of an operation
        return 0;
    }
    uint32_t ends[2];
    int lines = 0;
    uint32_t neighbours = 0;
    double angles = 0;
    for_each_edge(v, [&](uint32_t h, uint32_t other, bool outgoing) {
        visit(other, !outgoing);
        if (outgoing && track_angles) angles += angle[h];
        if (on_line(h, outgoing)) {
            if (lines < 2) ends[lines] = other;
            ++lines;
        }
        ++neighbours;
    });
    valence[v] = uint16_t(std::min(neighbours, 0xffffu));
    kind[v] = VertexKind::Corner;
    if (lines == 0) {
        kind[v] = VertexKind::Free;
    } else if (lines == 2) {
        const Vec3 p = point(v), in = sub(p, point(ends[0])), on = sub(point(ends[1]), p);
        const double l = norm(in) * norm(on);
        if (l > 0 && dot(in, on) >= limits.straight_cos * l)
            kind[v] = VertexKind::Line;
        else if (!zigzag.empty() && zigzag[v] &&
                 distance_to_segment(p, point(ends[0]), point(ends[1])) <= limits.zigzag)
            kind[v] = VertexKind::Line;
    }
    if (!locked.empty() && locked[v]) kind[v] = VertexKind::Corner;
    return angles;
}

} // namespace ddsimp::detail
