#include "error_quadric.h"

#include <cmath>

namespace ddsimp::detail {

double SegmentError::least() const {
    double t = 0.5;
    if (g > 0)
        t = std::clamp(-h / g, 0.0, 1.0);
    else if (2 * h + g != 0)
        t = 2 * h + g < 0 ? 1.0 : 0.0; // E(1) - E(0) = 2h + g
    // A gain within rounding is no gain: keep the midpoint, which shapes triangles best.
    return at(0.5) <= at(t) + noise ? 0.5 : t;
}

void add_plane(double* q, const Vec3& n, double e, double w) {
    q[0] += w * n[0] * n[0], q[1] += w * n[0] * n[1], q[2] += w * n[0] * n[2];
    q[3] += w * n[1] * n[1], q[4] += w * n[1] * n[2], q[5] += w * n[2] * n[2];
    for (int k = 0; k < 3; ++k) q[6 + k] += w * e * n[k];
    q[9] += w * e * e;
}

void ErrorQuadrics::setup(const WorkingMesh& mesh, const GradientTerms& gradient, double geometry,
                          double data, size_t capacity, Parallel& parallel) {
    // Scales: the bounding box of the live vertices, each counted component's range.
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const size_t m_all = data > 0 ? gradient.components.size() : 0;
    offset.assign(m_all, 0), low.assign(m_all, INFINITY), inv_range.assign(m_all, 0);
    for (size_t j = 0; j < m_all; ++j)
        offset[j] = gradient.components[j].first, inv_range[j] = gradient.components[j].second;
    continuous.assign(m_all, 0);
    for (size_t j = 0, start = 0, field = 0; j < m_all; ++j) {
        while (field < mesh.fields.size() && offset[j] >= start + size_t(mesh.fields[field].second))
            start += size_t(mesh.fields[field++].second);
        continuous[j] =
            field < mesh.fields.size() && mesh.fields[field].first == FieldKind::Continuous;
    }
    for (uint32_t v = 0; v < mesh.vertex_count; ++v) {
        if (mesh.kind[v] == VertexKind::Dead) continue;
        const float* p = mesh.position_of(v);
        for (int k = 0; k < 3; ++k)
            lo[k] = std::min(lo[k], double(p[k])), hi[k] = std::max(hi[k], double(p[k]));
        const float* f = mesh.data_of(v);
        for (size_t j = 0; j < m_all; ++j) low[j] = std::min(low[j], double(f[offset[j]]));
    }
    const Vec3 extent{hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    const double diagonal = norm(extent);
    inv_diagonal = diagonal > 0 ? 1 / diagonal : 0;
    centre = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    components = inv_diagonal > 0 ? m_all : 0;
    size = kSharedTerms + 4 * components;
    assign_on_threads(values, capacity * size, 0.0, parallel);
    area = 0;
    if (inv_diagonal == 0) return; // a single point: nothing can move

    auto position = [&](uint32_t v) { return scale(sub(mesh.point(v), centre), inv_diagonal); };
    auto datum = [&](uint32_t v, size_t j) {
        return (double(mesh.data_of(v)[offset[j]]) - low[j]) * inv_range[j];
    };
    // The data's linear interpolation on triangle v (edges e1, e2 from v[0], normal e1 x e2 of
    // squared length nn): s(x) = g.x + d, g in its plane. Writes each component's g and returns
    // sum_j |g_j|^2.
    auto steepness_of = [&](const uint32_t v[3], const Vec3& e1, const Vec3& e2, const Vec3& normal,
                            double nn, Vec3* gradients) {
        const Vec3 across1 = scale(cross(e2, normal), 1 / nn),
                   across2 = scale(cross(normal, e1), 1 / nn);
        double steepness = 0;
        for (size_t j = 0; j < components; ++j) {
            const double s0 = datum(v[0], j);
            gradients[j] = detail::add(scale(across1, datum(v[1], j) - s0),
                                       scale(across2, datum(v[2], j) - s0));
            steepness += dot(gradients[j], gradients[j]);
        }
        return steepness;
    };
    const size_t halfedges = mesh.origin.size();
    // Each triangle's terms go to its three corners: one piece of the vertices per thread, each
    // taking the triangles in order, so that a vertex sums its terms in triangle order.
    parallel.for_pieces(mesh.vertex_count, [&](size_t lo, size_t hi, size_t) {
        auto mine = [&](uint32_t v) { return v >= lo && v < hi; };
        std::vector<double> face(size);
        std::vector<Vec3> gradients(components);
        // A piece is a thread's whole share: the watch on the threads (stage_watch.h) is checked
        // every few milliseconds of it.
        constexpr uint32_t kTrianglesPerCheck = 8192;
        for (uint32_t t = 0; 3 * t < halfedges; ++t) {
            if (t % kTrianglesPerCheck == kTrianglesPerCheck - 1 && !parallel.check()) return;
            const uint32_t v[3] = {mesh.origin[3 * t], mesh.origin[3 * t + 1],
                                   mesh.origin[3 * t + 2]};
            if (v[0] == kNone || !(mine(v[0]) || mine(v[1]) || mine(v[2]))) continue;
            const Vec3 x0 = position(v[0]), e1 = sub(position(v[1]), x0),
                       e2 = sub(position(v[2]), x0);
            const Vec3 normal = cross(e1, e2);
            const double nn = dot(normal, normal);
            if (!(nn > 0)) continue; // no plane, no gradient
            const double area = 0.5 * std::sqrt(nn);
            // The terms that are summed into; the per-component G and D below are assigned.
            std::fill_n(face.begin(), kSharedTerms, 0.0);
            const Vec3 unit = scale(normal, 1 / std::sqrt(nn));
            const double w = data * area;
            if (components > 0) face[10] = w;
            const double steepness = steepness_of(v, e1, e2, normal, nn, gradients.data());
            const double plane = geometry + kShiftWeight * data * steepness;
            if (plane > 0) add_plane(face.data(), unit, -dot(unit, x0), plane * area);
            for (size_t j = 0; j < components; ++j) {
                const double s0 = datum(v[0], j);
                const Vec3& g = gradients[j];
                const double d = s0 - dot(g, x0);
                double* q = face.data();
                q[0] += w * g[0] * g[0], q[1] += w * g[0] * g[1], q[2] += w * g[0] * g[2];
                q[3] += w * g[1] * g[1], q[4] += w * g[1] * g[2], q[5] += w * g[2] * g[2];
                for (int k = 0; k < 3; ++k)
                    q[6 + k] += w * d * g[k], q[kSharedTerms + 4 * j + k] = w * g[k];
                q[9] += w * d * d;
                q[kSharedTerms + 3 + 4 * j] = w * d;
            }
            for (uint32_t c : v)
                if (mine(c))
                    for (size_t i = 0; i < size; ++i) of(c)[i] += face[i];
        }
        if (geometry == 0) return;
        // Boundary edges: the plane through the edge perpendicular to its triangle, weighted like
        // a triangle on the edge, so that sliding a boundary vertex off its line costs what it
        // does: in geometry, and where the data is steep in data too (the input beyond a boundary
        // that moves in is read at the boundary: a shift, as above).
        for (uint32_t h = 0; h < halfedges; ++h) {
            if (mesh.origin[h] == kNone || mesh.twin[h] != kNone) continue;
            const uint32_t a = mesh.origin[h], b = mesh.dest(h);
            if (!mine(a) && !mine(b)) continue;
            const uint32_t t = h / 3;
            const uint32_t v[3] = {mesh.origin[3 * t], mesh.origin[3 * t + 1],
                                   mesh.origin[3 * t + 2]};
            const Vec3 x0 = position(v[0]), e1 = sub(position(v[1]), x0),
                       e2 = sub(position(v[2]), x0);
            const Vec3 triangle = cross(e1, e2);
            const double tt = dot(triangle, triangle);
            const Vec3 xa = position(a), edge = sub(position(b), xa);
            const Vec3 normal = cross(edge, mesh.triangle_normal(t));
            const double nn = norm(normal);
            if (!(nn > 0)) continue;
            const Vec3 unit = scale(normal, 1 / nn);
            const double steepness =
                tt > 0 ? steepness_of(v, e1, e2, triangle, tt, gradients.data()) : 0;
            std::fill(face.begin(), face.end(), 0.0);
            add_plane(face.data(), unit, -dot(unit, xa),
                      (geometry + kShiftWeight * data * steepness) * dot(edge, edge));
            for (uint32_t c : {a, b})
                if (mine(c))
                    for (size_t i = 0; i < 10; ++i) of(c)[i] += face[i];
        }
    });
    if (parallel.stopped()) return;
    // The surface's area, summed in triangle order.
    for (uint32_t t = 0; 3 * t < halfedges; ++t) {
        if (mesh.origin[3 * t] == kNone) continue;
        const Vec3 x0 = position(mesh.origin[3 * t]);
        const double nn = norm(cross(sub(position(mesh.origin[3 * t + 1]), x0),
                                     sub(position(mesh.origin[3 * t + 2]), x0)));
        if (nn > 0) area += 0.5 * nn;
    }
}

void ErrorQuadrics::add(uint32_t to, uint32_t from, double scale) {
    double* q = of(to);
    const double* r = of(from);
    for (size_t i = 0; i < size; ++i) q[i] += scale * r[i];
}

namespace {

// Two doubles in one SSE register (GCC and Clang vector extension, which the build needs):
// lane 0 for one quadric, lane 1 for the other. Each lane does exactly the scalar operations,
// in the same order, so the results are the same bits as two scalar evaluations.
using Pair = double __attribute__((vector_size(16)));

} // namespace

SegmentError ErrorQuadrics::along(uint32_t v, uint32_t w, const Vec3& xa, const Vec3& xb,
                                  const float* fa, const float* fb, SegmentSlope* slope) const {
    const double *qv = of(v), *qw = of(w);
    const Vec3 x = scale(sub(xa, centre), inv_diagonal), dx = scale(sub(xb, xa), inv_diagonal);
    // Each quadric's terms are summed as for one quadric on its own (v in lane 0, w in lane 1),
    // then the two added: the segment's terms are computed once and both quadrics at once.
    auto q = [&](size_t i) { return Pair{qv[i], qw[i]}; };
    auto dot_q = [&](const Vec3& y, size_t i) { // (q[i], q[i + 1], q[i + 2]) . y per lane
        return q(i) * y[0] + q(i + 1) * y[1] + q(i + 2) * y[2];
    };
    auto times_a = [&](const Vec3& y, Pair* out) { // the symmetric A (q[0..6)) times y
        out[0] = q(0) * y[0] + q(1) * y[1] + q(2) * y[2];
        out[1] = q(1) * y[0] + q(3) * y[1] + q(4) * y[2];
        out[2] = q(2) * y[0] + q(4) * y[1] + q(5) * y[2];
    };
    Pair ax[3], adx[3];
    times_a(x, ax), times_a(dx, adx);
    Pair e0 = x[0] * ax[0] + x[1] * ax[1] + x[2] * ax[2] + 2 * dot_q(x, 6) + q(9);
    Pair h = dx[0] * ax[0] + dx[1] * ax[1] + dx[2] * ax[2] + dot_q(dx, 6);
    Pair g = dx[0] * adx[0] + dx[1] * adx[1] + dx[2] * adx[2];
    const Pair wt = q(10);
    // The half gradient at t: (A x + b - sum sa G) + t (A dx - sum ds G), per lane.
    Pair slope0[3] = {ax[0] + q(6), ax[1] + q(7), ax[2] + q(8)};
    Pair slope1[3] = {adx[0], adx[1], adx[2]};
    for (size_t j = 0; j < components; ++j) {
        const double a = double(fa[offset[j]]), b = double(fb[offset[j]]);
        const double sa = (a - low[j]) * inv_range[j], ds = (b - a) * inv_range[j];
        const size_t gj = kSharedTerms + 4 * j;
        const Pair gx = dot_q(x, gj) + q(gj + 3), gd = dot_q(dx, gj);
        e0 += wt * sa * sa - 2 * sa * gx;
        h += wt * sa * ds - ds * gx - sa * gd;
        g += wt * ds * ds - 2 * ds * gd;
        if (slope)
            for (size_t k = 0; k < 3; ++k) slope0[k] -= sa * q(gj + k), slope1[k] -= ds * q(gj + k);
    }
    if (slope) {
        for (size_t k = 0; k < 6; ++k) slope->a[k] = qv[k] + qw[k];
        for (size_t k = 0; k < 3; ++k)
            slope->slope0[k] = slope0[k][0] + slope0[k][1],
            slope->slope1[k] = slope1[k][0] + slope1[k][1];
    }
    // E is a sum of squares of terms of size up to ~1 (coordinates in diagonals, data in ranges)
    // weighted by A's trace and W: rounding leaves about 1e-12 of that.
    auto noise = [](const double* r) {
        return 1e-12 * (r[0] + r[3] + r[5] + r[10] + std::abs(r[9]));
    };
    SegmentError e;
    e.e0 = e0[0] + e0[1], e.h = h[0] + h[1], e.g = g[0] + g[1];
    e.noise = noise(qv) + noise(qw);
    return e;
}

namespace {

// A quadric's error at the normalised position y with normalised data datum(j), unclamped; q(i)
// is its i-th number, a double, or a Pair for two quadrics or two points at once (y's coordinates
// then Pairs too; the same operations per lane).
template <class T, class Q, class Y, class Datum>
T quadric_error(Q q, const Y& y, size_t components, Datum datum) {
    auto dot_q = [&](size_t i) { return q(i) * y[0] + q(i + 1) * y[1] + q(i + 2) * y[2]; };
    const T ay[3] = {q(0) * y[0] + q(1) * y[1] + q(2) * y[2],
                     q(1) * y[0] + q(3) * y[1] + q(4) * y[2],
                     q(2) * y[0] + q(4) * y[1] + q(5) * y[2]};
    T e = y[0] * ay[0] + y[1] * ay[1] + y[2] * ay[2] + 2 * dot_q(6) + q(9);
    for (size_t j = 0; j < components; ++j) {
        const auto s = datum(j); // a double, or a Pair with two points
        const size_t gj = ErrorQuadrics::kSharedTerms + 4 * j;
        e += q(10) * s * s - 2 * s * (dot_q(gj) + q(gj + 3));
    }
    return e;
}

} // namespace

double ErrorQuadrics::at(uint32_t v, uint32_t w, const Vec3& x, const float* fa, const float* fb,
                         double t) const {
    const double *qv = of(v), *qw = of(w);
    auto q = [&](size_t i) { return Pair{qv[i], qw[i]}; }; // v in lane 0, w in lane 1, as along
    const Pair e =
        quadric_error<Pair>(q, scale(sub(x, centre), inv_diagonal), components, [&](size_t j) {
            return ((1 - t) * double(fa[offset[j]]) + t * double(fb[offset[j]]) - low[j]) *
                   inv_range[j];
        });
    return std::max(0.0, e[0] + e[1]);
}

double ErrorQuadrics::least_data(uint32_t v, uint32_t w, const Vec3& x, const float* fa,
                                 const float* fb, double t, float* out) const {
    const double *qv = of(v), *qw = of(w);
    const double weight = qv[10] + qw[10];
    if (!(weight > 0)) return 0;
    const Vec3 y = scale(sub(x, centre), inv_diagonal);
    double change = 0;
    for (size_t j = 0; j < components; ++j) {
        if (!continuous[j]) continue;
        const size_t gj = kSharedTerms + 4 * j;
        // E(s) = W s^2 - 2 r s + (terms without s), least at r / W.
        const double r = qv[gj] * y[0] + qv[gj + 1] * y[1] + qv[gj + 2] * y[2] + qv[gj + 3] +
                         (qw[gj] * y[0] + qw[gj + 1] * y[1] + qw[gj + 2] * y[2] + qw[gj + 3]);
        const double a = double(fa[offset[j]]), b = double(fb[offset[j]]);
        const double sa = (a - low[j]) * inv_range[j], sb = (b - low[j]) * inv_range[j];
        const double blend = (1 - t) * sa + t * sb;
        const double least = std::clamp(r / weight, std::min(sa, sb), std::max(sa, sb));
        change += (least - blend) * (weight * (least + blend) - 2 * r);
        if (out)
            out[offset[j]] = std::clamp(float(low[j] + least / inv_range[j]),
                                        std::min(fa[offset[j]], fb[offset[j]]),
                                        std::max(fa[offset[j]], fb[offset[j]]));
    }
    return std::min(0.0, change);
}

double ErrorQuadrics::at_blend(uint32_t v, const WorkingMesh& mesh, const uint32_t* points,
                               const double* weights, size_t count, Vec3* position) const {
    if (count == 0) return 0;
    const double mean = 1.0 / double(count);
    auto weight = [&](size_t i) { return weights ? weights[i] : mean; };
    Vec3 x{0, 0, 0};
    for (size_t i = 0; i < count; ++i) x = detail::add(x, scale(mesh.point(points[i]), weight(i)));
    if (position) *position = x;
    const double* qv = of(v);
    auto datum = [&](size_t j) {
        double s = 0;
        for (size_t i = 0; i < count; ++i)
            s += weight(i) * double(mesh.data_of(points[i])[offset[j]]);
        return (s - low[j]) * inv_range[j];
    };
    return std::max(0.0,
                    quadric_error<double>([&](size_t i) { return qv[i]; },
                                          scale(sub(x, centre), inv_diagonal), components, datum));
}

double ErrorQuadrics::least_at(uint32_t v, const WorkingMesh& mesh, const uint32_t* points,
                               size_t count) const {
    const double* qv = of(v);
    auto q = [&](size_t i) { return Pair{qv[i], qv[i]}; };
    double least = INFINITY;
    for (size_t i = 0; i < count; i += 2) { // two points side by side (an odd last one twice)
        const uint32_t a = points[i], b = points[std::min(i + 1, count - 1)];
        const Vec3 ya = scale(sub(mesh.point(a), centre), inv_diagonal),
                   yb = scale(sub(mesh.point(b), centre), inv_diagonal);
        const Pair y[3] = {{ya[0], yb[0]}, {ya[1], yb[1]}, {ya[2], yb[2]}};
        const float *fa = mesh.data_of(a), *fb = mesh.data_of(b);
        const Pair e = quadric_error<Pair>(q, y, components, [&](size_t j) {
            return Pair{(double(fa[offset[j]]) - low[j]) * inv_range[j],
                        (double(fb[offset[j]]) - low[j]) * inv_range[j]};
        });
        least = std::min({least, std::max(0.0, e[0]), std::max(0.0, e[1])});
    }
    return least;
}

namespace {

// The symmetric 3x3 matrix a (6 numbers: xx, xy, xz, yy, yz, zz) times z.
Vec3 symmetric_times(const double* a, const Vec3& z) {
    return {a[0] * z[0] + a[1] * z[1] + a[2] * z[2], a[1] * z[0] + a[3] * z[1] + a[4] * z[2],
            a[2] * z[0] + a[4] * z[1] + a[5] * z[2]};
}

} // namespace

Vec3 ErrorQuadrics::sideways(const SegmentSlope& slope, double t, const Vec3& axis) const {
    if (inv_diagonal == 0) return {0, 0, 0};
    const Vec3 g = detail::add(slope.slope0, scale(slope.slope1, t));
    // Two directions across the axis; the 2x2 problem in them, solved by its eigenvectors.
    const auto [u1, u2] = detail::plane_across(axis);
    const Vec3 au1 = symmetric_times(slope.a, u1), au2 = symmetric_times(slope.a, u2);
    const double h11 = dot(u1, au1), h12 = dot(u1, au2), h22 = dot(u2, au2);
    const double r[2] = {-dot(u1, g), -dot(u2, g)};
    const double half = 0.5 * (h11 + h22);
    const double spread = std::sqrt(0.25 * (h11 - h22) * (h11 - h22) + h12 * h12);
    const double l1 = half + spread, l2 = half - spread;
    if (!(l1 > 0)) return {0, 0, 0};
    double e1[2] = {1, 0};
    if (h12 != 0) {
        e1[0] = l1 - h22, e1[1] = h12;
        const double l = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1]);
        e1[0] /= l, e1[1] /= l;
    } else if (h22 > h11)
        e1[0] = 0, e1[1] = 1;
    const double e2[2] = {-e1[1], e1[0]};
    double d[2] = {0, 0};
    const double c1 = (r[0] * e1[0] + r[1] * e1[1]) / l1;
    d[0] += c1 * e1[0], d[1] += c1 * e1[1];
    if (l2 > 1e-3 * l1) {
        const double c2 = (r[0] * e2[0] + r[1] * e2[1]) / l2;
        d[0] += c2 * e2[0], d[1] += c2 * e2[1];
    }
    return scale(detail::add(scale(u1, d[0]), scale(u2, d[1])), 1 / inv_diagonal);
}

Vec3 ErrorQuadrics::sideways_at(const SegmentSlope& slope, double t, const Vec3& axis,
                                const Vec3& normal, double height) const {
    if (inv_diagonal == 0) return {0, 0, 0};
    const Vec3 g = detail::add(slope.slope0, scale(slope.slope1, t));
    const Vec3 across = cross(axis, normal);
    const Vec3 a_across = symmetric_times(slope.a, across);
    const double h11 = dot(normal, symmetric_times(slope.a, normal)), h12 = dot(normal, a_across),
                 h22 = dot(across, a_across);
    const double d1 = height * inv_diagonal;
    // The 1D problem in `across` with d1 fixed, left out like sideways' weak direction.
    const double d2 = h22 > 1e-3 * (h11 + h22) ? (-dot(across, g) - h12 * d1) / h22 : 0;
    return scale(detail::add(scale(normal, d1), scale(across, d2)), 1 / inv_diagonal);
}

double ErrorQuadrics::change(const SegmentSlope& slope, double t, const Vec3& offset) const {
    const Vec3 d = scale(offset, inv_diagonal);
    const Vec3 ad = symmetric_times(slope.a, d);
    return 2 * dot(detail::add(slope.slope0, scale(slope.slope1, t)), d) + dot(d, ad);
}

} // namespace ddsimp::detail
