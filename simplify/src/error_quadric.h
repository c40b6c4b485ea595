// Accumulated error quadrics: what moving a vertex (with its data) costs relative to the INPUT
// surface and data, the default terms of the weight (see Options::terms).
//
// Geometry after Garland & Heckbert (1997): the sum, over the input triangles a vertex stands for,
// of area x squared distance of the vertex to the triangle's plane. Data after Hoppe (1999): area x
// squared difference between the vertex's data and the triangle's linear interpolation of the
// input data at the vertex's position (projected into the triangle's plane). Positions are
// measured in bounding-box diagonals and every data component in its field's range, the scales
// `ddsimp compare` reports errors in, so both terms are unit-free in the same way and
// max(alpha, kMinGeometryWeight) * geometric + (1 - alpha) * data is one quadric (simplifier.h),
// the geometric term weighing more where the data is steep (kShiftWeight).
// Per vertex 11 + 4m numbers (m: the data components that count, 0 when alpha = 1): A (6,
// symmetric 3x3), b (3), c, W, then per component
// G (3) and D, with
//     E(x, s) = x.A.x + 2 b.x + c + W s.s - 2 sum_j s_j (G_j.x + D_j).
// A collapse adds its two ends' quadrics; a removal gives the vertex's to the corners of the new
// triangle that passes it, by its barycentric weights there.
#pragma once

#include "weights.h"
#include "working_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace ddsimp::detail {

// The error along a segment from (xa, sa) to (xb, sb), as a function of the position t in [0, 1]:
// E(t) = e0 + 2 h t + g t^2.
struct SegmentError {
    double e0 = 0, h = 0, g = 0;
    // Scale of the rounding noise in E (errors closer than this are equal).
    double noise = 0;

    double at(double t) const { return std::max(0.0, e0 + (2 * h + g * t) * t); }
    // The t of least error; the midpoint where the error does not tell (flat and linear).
    double least() const;
    SegmentError& operator+=(const SegmentError& o) {
        e0 += o.e0, h += o.h, g += o.g, noise += o.noise;
        return *this;
    }
};

// w (n.x + e)^2 as quadric terms (A, b, c of the layout above), added to q: a plane's squared
// distance for n of unit length.
void add_plane(double* q, const Vec3& n, double e, double w);

// What moving a point sideways off a segment needs of the two quadrics summed along it: A, and
// the half gradient of the error, A y + b - sum_j s_j G_j, at the segment's point of position t
// (data held at its blend there): slope0 + t slope1. Normalised units.
struct SegmentSlope {
    double a[6] = {0, 0, 0, 0, 0, 0};
    Vec3 slope0{0, 0, 0}, slope1{0, 0, 0};
};

struct ErrorQuadrics {
    // Where the data varies along the surface, a point off the surface also misplaces the data
    // a reader sees: the closest point on a coarse surface lies some way along it, a fraction of
    // the distance off. So each input triangle's plane weighs, on top of the geometric weight,
    // data x kShiftWeight x sum_j |g_j|^2 (g_j: the triangle's gradient of component j, in ranges
    // per diagonal): the data error of a shift of a third of the distance (0.1 ~ (1/3)^2).
    // Where the data is flat the geometry weighs what alpha says.
    static constexpr double kShiftWeight = 0.1;
    // A (6), b (3), c and W, which every data component shares; its G (3) and D follow.
    static constexpr size_t kSharedTerms = 11;
    size_t components = 0;      // m
    size_t size = kSharedTerms; // numbers per vertex
    Array<double> values;
    // The input surface's area (normalised units: diagonals squared).
    double area = 0;
    // Normalisation: x' = (x - centre) * inv_diagonal, s'_j = (f[offset_j] - low_j) * inv_range_j.
    Vec3 centre{0, 0, 0};
    double inv_diagonal = 0;
    std::vector<uint32_t> offset;
    std::vector<double> low, inv_range;
    // Per component: whether a new vertex may take its value of least error (a Continuous
    // field's; labels and directions keep their own rules, WorkingMesh::blend_data).
    std::vector<uint8_t> continuous;

    // The quadrics of every live vertex of `mesh` (slots up to `capacity`), from its input
    // triangles and, for the geometry, planes through its boundary edges perpendicular to the
    // surface, so that a boundary keeps its shape. `gradient` says which data components count;
    // the geometric error weighs `geometry` (a triangle's plane more where its data is steep,
    // kShiftWeight), the data error `data` (none: no data terms). The
    // same bits on any number of threads; part-way if a watch on `parallel` stops it
    // (stage_watch.h).
    void setup(const WorkingMesh& mesh, const GradientTerms& gradient, double geometry, double data,
               size_t capacity, Parallel& parallel);

    double* of(uint32_t v) { return &values[size_t(v) * size]; }
    const double* of(uint32_t v) const { return &values[size_t(v) * size]; }
    // q(to) += scale * q(from).
    void add(uint32_t to, uint32_t from, double scale);

    // The summed error of the quadrics of vertices v and w (an edge's two ends) along the segment
    // from position xa with data fa to xb with data fb (raw positions and data records of the
    // working mesh). One call for both: the segment's normalised terms are shared. With `slope`,
    // also what a sideways step off the segment needs (from the same terms).
    SegmentError along(uint32_t v, uint32_t w, const Vec3& xa, const Vec3& xb, const float* fa,
                       const float* fb, SegmentSlope* slope = nullptr) const;
    // The summed error of the quadrics of v and w at position x with the data blend
    // (1 - t) fa + t fb (raw position and data records): along's error at one point, for half
    // its work.
    double at(uint32_t v, uint32_t w, const Vec3& x, const float* fa, const float* fb,
              double t) const;
    // The data of least error of the quadrics of v and w summed, at position x, for every
    // continuous component: (G.x + D) / W, clamped to the range of the component's values fa and
    // fb (raw data records), so that it never leaves the values it replaces. Returns how much
    // lower the summed error is than with the blend (1 - t) fa + t fb (t in [0, 1]: a change
    // <= 0); with `out` (a data record), writes the values there (raw units, at their offsets).
    double least_data(uint32_t v, uint32_t w, const Vec3& x, const float* fa, const float* fb,
                      double t, float* out = nullptr) const;
    // The offset (raw units) from the segment's point of position t, perpendicular to the unit
    // vector `axis`, that lowers the summed error most (`slope` from along); directions the
    // quadrics hardly determine are left out (a truncated inverse).
    Vec3 sideways(const SegmentSlope& slope, double t, const Vec3& axis) const;
    // The same with the offset's component along the unit vector `normal` (perpendicular to
    // `axis`) held at `height` (raw units): the offset height * normal + s * (axis x normal) with
    // the s of least error (0 where the quadrics hardly determine it).
    Vec3 sideways_at(const SegmentSlope& slope, double t, const Vec3& axis, const Vec3& normal,
                     double height) const;
    // How the summed error changes when the segment's point of position t moves by `offset`
    // (raw units), its data held: 2 grad.d + d.A.d, exactly, as the error is quadratic.
    double change(const SegmentSlope& slope, double t, const Vec3& offset) const;
    // The error of vertex v's quadric at the blend sum_i weights[i] * points[i] of positions and
    // data (weights summing to 1; nullptr: the mean); the blended position (raw units) into
    // `position` if given.
    double at_blend(uint32_t v, const WorkingMesh& mesh, const uint32_t* points,
                    const double* weights, size_t count, Vec3* position = nullptr) const;
    // The least error of vertex v's quadric at any of points[0..count), each with its own data
    // (the same values as at_blend of that point alone).
    double least_at(uint32_t v, const WorkingMesh& mesh, const uint32_t* points,
                    size_t count) const;
    // Errors of v's quadric closer than this are equal (rounding).
    double noise(uint32_t v) const {
        const double* q = of(v);
        return 1e-12 * (q[0] + q[3] + q[5] + q[10] + std::abs(q[9]));
    }
};

} // namespace ddsimp::detail
