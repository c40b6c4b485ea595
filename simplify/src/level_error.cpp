// The error of every level of a progressive record against the repaired input (see LevelError
// and docs/algorithm.md, "The error of a level"), measured after the run from the record alone,
// so it is the same whatever terms ordered the operations.
// - Edge collapse moves vertices: each new vertex is measured with two error quadrics of its own
//   (geometry, data) built from the input, summed as collapses merge regions. The run's own
//   quadrics mix the two by alpha and cannot be split.
// - Vertex removal keeps the vertices and moves the surface over the removed ones: each removed
//   input vertex is measured against the triangle that covers it.
#include "error_quadric.h"
#include "removal_cover.h"
#include "working_mesh.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace ddsimp {

namespace {

using detail::cross;
using detail::dot;
using detail::norm;
using detail::scale;
using detail::sub;
using detail::Vec3;

// Vertex removal: distances (in diagonals) closer than this are equal, ties of rounding.
constexpr double kTie = 1e-12;

// Per vertex slot, over the normalised position x and data s:
//   geometry  G(x)    = x.A.x + 2 b.x + c                                    numbers 0..9
//   data      D(x, s) = x.A'.x + 2 b'.x + c' + sum_j W s_j^2 - 2 s_j (G_j.x + D_j)
//                       (A', b', c': 10..19, W: 20, then G_j and D_j, 4 per component)
// A is symmetric, stored as xx, xy, xz, yy, yz, zz.
constexpr size_t kDataPart = 10, kWeight = 20, kPerComponent = 21;

// x.A.x + 2 b.x + c of the 10 numbers at q.
double quadratic_at(const double* q, const Vec3& x) {
    const Vec3 ax{q[0] * x[0] + q[1] * x[1] + q[2] * x[2], q[1] * x[0] + q[3] * x[1] + q[4] * x[2],
                  q[2] * x[0] + q[4] * x[1] + q[5] * x[2]};
    return dot(x, ax) + 2 * (q[6] * x[0] + q[7] * x[1] + q[8] * x[2]) + q[9];
}

class ErrorMeasure {
public:
    // With `quadrics`, each input vertex's quadrics (of its triangles and boundary edges).
    ErrorMeasure(const Surface& vertices, const std::vector<uint32_t>& triangles,
                 size_t input_vertices, const std::vector<std::string>& fields, bool quadrics);

    size_t components() const { return component_.size(); }
    // x: normalised position of vertex `id` of the record.
    Vec3 point(uint32_t id) const {
        const float* p = &vertices_.positions[3 * size_t(id)];
        return scale(sub(Vec3{p[0], p[1], p[2]}, centre_), inv_diagonal_);
    }
    // s_j: normalised data of vertex `id`, into s.
    void data(uint32_t id, double* s) const {
        for (size_t j = 0; j < component_.size(); ++j) {
            const Component& c = component_[j];
            const Field& f = vertices_.fields[c.field];
            s[j] = (double(f.values[size_t(id) * size_t(f.components) + c.component]) - c.low) *
                   c.inv_range;
        }
    }
    double* of(uint32_t slot) { return &q_[size_t(slot) * size_]; }
    // q(to) += scale * q(from)
    void add(uint32_t to, uint32_t from, double scale) {
        double* a = of(to);
        const double* b = of(from);
        for (size_t i = 0; i < size_; ++i) a[i] += scale * b[i];
    }
    // The RMS geometric and data errors of slot's quadrics at (x, s).
    std::pair<double, double> error(uint32_t slot, const Vec3& x, const double* s) const;

private:
    struct Component {
        size_t field, component;
        double low, inv_range;
    };
    const Surface& vertices_;
    std::vector<Component> component_;
    Vec3 centre_{0, 0, 0};
    double inv_diagonal_ = 0;
    size_t size_ = kPerComponent;
    std::vector<double> q_;
};

ErrorMeasure::ErrorMeasure(const Surface& vertices, const std::vector<uint32_t>& triangles,
                           size_t input_vertices, const std::vector<std::string>& fields,
                           bool quadrics)
    : vertices_(vertices) {
    std::vector<uint8_t> used(input_vertices, 0);
    for (uint32_t v : triangles) used[v] = 1;
    // Scales, as the weights take them: the bounding box of the used vertices; each chosen
    // field's range (the largest of its components'), a field without one counting for nothing.
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < input_vertices; ++v)
        for (int k = 0; k < 3 && used[v]; ++k)
            lo[k] = std::min(lo[k], double(vertices.positions[3 * v + k])),
            hi[k] = std::max(hi[k], double(vertices.positions[3 * v + k]));
    const double diagonal = norm(Vec3{hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    if (!(diagonal > 0)) return; // a point: no error can be measured (or made)
    inv_diagonal_ = 1 / diagonal;
    centre_ = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    const std::vector<std::string> names =
        fields.empty() ? default_gradient_fields(vertices) : fields;
    const std::set<std::string> chosen(names.begin(), names.end());
    for (size_t f = 0; f < vertices.fields.size(); ++f) {
        const Field& field = vertices.fields[f];
        if (!chosen.count(field.name)) continue;
        const size_t nc = size_t(field.components);
        std::vector<double> low(nc, INFINITY);
        double range = 0;
        for (size_t c = 0; c < nc; ++c) {
            double high = -INFINITY;
            for (size_t v = 0; v < input_vertices; ++v)
                if (used[v])
                    low[c] = std::min(low[c], double(field.values[v * nc + c])),
                    high = std::max(high, double(field.values[v * nc + c]));
            range = std::max(range, high - low[c]);
        }
        if (range > 0)
            for (size_t c = 0; c < nc; ++c) component_.push_back({f, c, low[c], 1 / range});
    }
    const size_t m = component_.size();
    size_ = kPerComponent + 4 * m;
    if (!quadrics) return;
    q_.assign(input_vertices * size_, 0.0);

    std::vector<double> face(size_), s0(m), s1(m), s2(m);
    for (size_t t = 0; t < triangles.size(); t += 3) {
        const uint32_t v[3] = {triangles[t], triangles[t + 1], triangles[t + 2]};
        const Vec3 x0 = point(v[0]), e1 = sub(point(v[1]), x0), e2 = sub(point(v[2]), x0);
        const Vec3 normal = cross(e1, e2);
        const double nn = dot(normal, normal);
        if (!(nn > 0)) continue; // no plane, no interpolation
        const double area = 0.5 * std::sqrt(nn);
        std::fill(face.begin(), face.end(), 0.0);
        const Vec3 unit = scale(normal, 1 / std::sqrt(nn));
        detail::add_plane(face.data(), unit, -dot(unit, x0), area);
        // The data's linear interpolation on the triangle: s(x) = g.x + d, g in its plane.
        data(v[0], s0.data()), data(v[1], s1.data()), data(v[2], s2.data());
        const Vec3 across1 = scale(cross(e2, normal), 1 / nn),
                   across2 = scale(cross(normal, e1), 1 / nn);
        face[kWeight] = m > 0 ? area : 0.0;
        for (size_t j = 0; j < m; ++j) {
            const Vec3 g =
                detail::add(scale(across1, s1[j] - s0[j]), scale(across2, s2[j] - s0[j]));
            const double d = s0[j] - dot(g, x0);
            detail::add_plane(face.data() + kDataPart, g, d, area);
            double* gj = face.data() + kPerComponent + 4 * j;
            for (int k = 0; k < 3; ++k) gj[k] = area * g[k];
            gj[3] = area * d;
        }
        for (uint32_t c : v)
            for (size_t i = 0; i < size_; ++i) of(c)[i] += face[i];
    }
    // Boundary edges (used by one triangle): the plane through the edge perpendicular to its
    // triangle, weighted by the edge's squared length, as the weights take them.
    std::vector<uint64_t> edges;
    edges.reserve(triangles.size());
    for (size_t i = 0; i < triangles.size(); ++i) {
        const uint64_t a = triangles[i], b = triangles[i % 3 == 2 ? i - 2 : i + 1];
        edges.push_back(std::min(a, b) << 32 | std::max(a, b));
    }
    std::sort(edges.begin(), edges.end());
    for (size_t i = 0; i < triangles.size(); ++i) {
        const uint32_t a = triangles[i], b = triangles[i % 3 == 2 ? i - 2 : i + 1];
        const uint64_t key = uint64_t(std::min(a, b)) << 32 | std::max(a, b);
        const auto [first, last] = std::equal_range(edges.begin(), edges.end(), key);
        if (last - first != 1) continue;
        const size_t t = i - i % 3;
        const Vec3 x0 = point(triangles[t]);
        const Vec3 normal =
            cross(sub(point(triangles[t + 1]), x0), sub(point(triangles[t + 2]), x0));
        const Vec3 xa = point(a), edge = sub(point(b), xa);
        const Vec3 across = cross(edge, normal);
        const double length = norm(across);
        if (!(length > 0)) continue;
        const Vec3 unit = scale(across, 1 / length);
        std::fill(face.begin(), face.begin() + kDataPart, 0.0);
        detail::add_plane(face.data(), unit, -dot(unit, xa), dot(edge, edge));
        for (uint32_t c : {a, b})
            for (size_t k = 0; k < kDataPart; ++k) of(c)[k] += face[k];
    }
}

std::pair<double, double> ErrorMeasure::error(uint32_t slot, const Vec3& x, const double* s) const {
    const double* q = &q_[size_t(slot) * size_];
    // Errors within the rounding of the quadric's sums are 0 (a flat, linear region).
    const double weight = q[0] + q[3] + q[5];
    const double g = quadratic_at(q, x);
    const double geometric =
        weight > 0 && g > 1e-12 * (weight + std::abs(q[9])) ? std::sqrt(g / weight) : 0.0;
    const size_t m = component_.size();
    const double w = q[kWeight] * double(m);
    if (!(w > 0)) return {geometric, 0.0};
    const double* dq = q + kDataPart;
    double d = quadratic_at(dq, x);
    for (size_t j = 0; j < m; ++j) {
        const double* gj = q + kPerComponent + 4 * j;
        d += q[kWeight] * s[j] * s[j] -
             2 * s[j] * (gj[0] * x[0] + gj[1] * x[1] + gj[2] * x[2] + gj[3]);
    }
    const double scale_of_d = w + dq[0] + dq[3] + dq[5] + std::abs(dq[9]);
    return {geometric, d > 1e-12 * scale_of_d ? std::sqrt(d / w) : 0.0};
}

} // namespace

void ProgressiveRecord::measure_errors(const std::vector<std::string>& gradient_fields) {
    ErrorMeasure measure(vertices_, base_triangles_, input_vertices_, gradient_fields,
                         strategy_ == Strategy::EdgeCollapse);
    const size_t m = measure.components();
    error_components_ = m;
    level_error_.assign(2 * operations(), 0.0f);
    std::vector<double> s(m), corner(3 * m);
    double geometric = 0, data = 0; // the running maxima
    auto count = [&](const std::pair<double, double>& e) {
        geometric = std::max(geometric, e.first), data = std::max(data, e.second);
    };
    if (strategy_ == Strategy::EdgeCollapse) {
        // A collapse's new vertex takes the slot of its first end and the sum of both quadrics.
        std::vector<uint32_t> slot(input_vertices_ + operations());
        for (uint32_t v = 0; v < input_vertices_; ++v) slot[v] = v;
        for (size_t i = 0; i < operations(); ++i) {
            const uint32_t a = slot[collapse_[2 * i]], b = slot[collapse_[2 * i + 1]];
            const uint32_t made = uint32_t(input_vertices_ + i);
            measure.add(a, b, 1.0);
            slot[made] = a;
            measure.data(made, s.data());
            count(measure.error(a, measure.point(made), s.data()));
            level_error_[2 * i] = float(geometric), level_error_[2 * i + 1] = float(data);
        }
        return;
    }
    // Vertex removal keeps every other vertex in place: what moves is the surface over the
    // removed ones. Each removed input vertex is measured against the point nearest to it of the
    // triangle that covers it (removal_cover.h), again whenever a later removal rewrites that
    // triangle.
    const detail::RemovalCover cover(base_triangles_, input_vertices_, write_begin_, writes_,
                                     operations());
    std::vector<std::pair<double, double>> worst(operations()); // per removal, of its landings
    auto point = [&](uint32_t v) { return measure.point(v); };
    for (uint32_t p = 0; p < input_vertices_; ++p)
        cover.follow(
            p, point, kTie,
            [&](uint32_t i, uint32_t w, const std::array<double, 3>& weights, double distance) {
                const uint32_t* c = &writes_[w + 1];
                double squares = 0;
                if (m > 0) {
                    measure.data(p, s.data());
                    for (int k = 0; k < 3; ++k) measure.data(c[k], corner.data() + k * m);
                    for (size_t j = 0; j < m; ++j) {
                        const double d = s[j] - weights[0] * corner[j] -
                                         weights[1] * corner[m + j] -
                                         weights[2] * corner[2 * m + j];
                        squares += d * d;
                    }
                }
                // Below 1e-9 (far under a float's resolution): rounding of a point on
                // its plane.
                const double misfit = m > 0 ? std::sqrt(squares / double(m)) : 0.0;
                worst[i].first = std::max(worst[i].first, distance > 1e-9 ? distance : 0.0);
                worst[i].second = std::max(worst[i].second, misfit > 1e-9 ? misfit : 0.0);
            });
    for (size_t i = 0; i < operations(); ++i) {
        count(worst[i]);
        level_error_[2 * i] = float(geometric), level_error_[2 * i + 1] = float(data);
    }
}

LevelError ProgressiveRecord::error_after(size_t operations) const {
    LevelError e;
    e.data_components = error_components_;
    operations = std::min(operations, level_error_.size() / 2);
    if (operations == 0) return e;
    e.geometric = level_error_[2 * (operations - 1)];
    e.data = level_error_[2 * (operations - 1) + 1];
    return e;
}

} // namespace ddsimp
