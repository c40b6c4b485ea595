// Vertex removal: the vertex goes, the polygon of its star is projected to the plane of the
// star's mean normal and re-triangulated by clipping ears: with the error quadrics first those
// whose new edges leave the star's surface and data least, with the paper's terms the
// best-shaped. The remaining vertices keep their data exactly.
#include "simplifier.h"

#include <algorithm>
#include <cmath>

namespace ddsimp {

using namespace detail;

namespace {

double orient(const double* p, const double* q, const double* r) {
    return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
}

// A new triangle with 2 x area below this times the sum of its squared sides is a needle (shape
// below ~3e-6 of an equilateral one's): refused.
constexpr double kNeedle = 1e-5;

// 1 for an equilateral triangle, towards 0 for a sliver.
double shape(const double* p, const double* q, const double* r) {
    auto d2 = [](const double* a, const double* b) {
        return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
    };
    const double sum = d2(p, q) + d2(q, r) + d2(r, p);
    return sum > 0 ? 2 * std::sqrt(3.0) * orient(p, q, r) / sum : 0;
}

} // namespace

// Free or on a line, and not refused since its star last changed.
bool Simplifier::removable(uint32_t v) const {
    const VertexKind k = mesh_.kind[v];
    if (k != VertexKind::Free && k != VertexKind::Line) return false;
    return fail_[v] == 0 || epoch_[v] >= fail_[v];
}

// The key: its weight, ties broken by its shortest edge (kept up to date by refresh_vertex).
Key Simplifier::removal_key(uint32_t v) const {
    return {weight_[v], shortest_[v]};
}

void Simplifier::key_removal(uint32_t v) {
    double shortest = INFINITY;
    const Vec3 p = mesh_.point(v);
    uint32_t ring[kMaxValence];
    size_t count = 0;
    mesh_.for_each_edge(v, [&](uint32_t, uint32_t u, bool outgoing) {
        if (outgoing) shortest = std::min(shortest, norm(sub(mesh_.point(u), p)));
        if (count < kMaxValence) ring[count] = u;
        ++count;
    });
    shortest_[v] = float(shortest);
    const VertexKind k = mesh_.kind[v];
    if (quadric_terms_ && (k == VertexKind::Free || k == VertexKind::Line))
        weight_[v] = float(removal_error(v, ring, count));
}

double Simplifier::removal_error(uint32_t v, const uint32_t* ring, size_t count) const {
    if (count > kMaxValence) return INFINITY;
    if (mesh_.is_boundary_vertex(v)) { // the removal joins the fan's first and last neighbours
        const uint32_t ends[2] = {ring[0], ring[count - 1]};
        return quadrics_.at_blend(v, mesh_, ends, nullptr, 2);
    }
    // Where a flat re-triangulation passes, or where the fan from a ring vertex (the half-edge
    // collapse into it) puts v, whichever is lighter: plan_removal tries both kinds. With the
    // centre alone, a vertex on a crease or at the tip of a fan of slivers, whose ring's centre
    // lies off the surface, ranked far heavier than its removal along the crease costs.
    return std::min(quadrics_.at_blend(v, mesh_, ring, nullptr, count),
                    quadrics_.least_at(v, mesh_, ring, count));
}

// Ear clipping of polygon[0..n) (indices into the ring) in the plane; appends to out.
bool Simplifier::triangulate(const RemovalPlan& plan, const double (*xyh)[3],
                             const uint8_t* polygon, size_t n, const uint64_t* adjacent,
                             RemovalPlan& out) const {
    uint8_t left[kMaxValence];
    std::copy(polygon, polygon + n, left);
    double extent = 0;
    for (size_t i = 0; i < plan.ring_size; ++i)
        extent = std::max({extent, std::abs(xyh[i][0]), std::abs(xyh[i][1])});
    // Twice the area below which an ear counts as flat, relative to the ring's size: points
    // collinear on paper, such as three grid points on a diagonal, are off their line by float
    // rounding (about 1e-8 of the size there).
    const double eps = 1e-7 * extent * extent;
    // Ears found good, by their middle vertex, with their shape. An ear stays good while its
    // two neighbours stay: clipping only removes points that could lie inside it. A bad one is
    // tested again (a clipped point may have been what spoilt it).
    uint64_t good = 0;
    // With the error quadrics, the ear whose new edge changes the star least goes first (its
    // change at the edge's midpoint times the edge's squared length, the size of the region it
    // spans), the best-shaped among equals.
    double good_shape[kMaxValence], good_change[kMaxValence];
    auto better = [&](double change, double s, double best_change, double best_shape) {
        if (!quadric_terms_) return s > best_shape;
        const double tie = 1e-12 * (change + best_change);
        return change < best_change - tie || (change <= best_change + tie && s > best_shape);
    };
    while (n >= 3) {
        size_t best = n;
        double best_shape = -1, best_change = INFINITY;
        for (size_t i = 0; i < n; ++i) {
            const uint8_t p = left[(i + n - 1) % n], c = left[i], q = left[(i + 1) % n];
            if (good >> c & 1) {
                if (better(good_change[c], good_shape[c], best_change, best_shape))
                    best_shape = good_shape[c], best_change = good_change[c], best = i;
                continue;
            }
            if (orient(xyh[p], xyh[c], xyh[q]) <= eps) continue; // reflex or flat
            // The new edge p-q must not exist already (it would be non-manifold), unless this is
            // the last triangle, whose edges are all there by construction.
            if (n > 3 && (adjacent[p] >> q & 1)) continue;
            bool empty = true;
            for (size_t j = 0; j < n && empty; ++j) {
                const uint8_t o = left[j];
                if (o == p || o == c || o == q) continue;
                empty = orient(xyh[p], xyh[c], xyh[o]) < -eps ||
                        orient(xyh[c], xyh[q], xyh[o]) < -eps ||
                        orient(xyh[q], xyh[p], xyh[o]) < -eps;
            }
            if (!empty) continue;
            const double s = shape(xyh[p], xyh[c], xyh[q]);
            double change = 0;
            if (quadric_terms_ && n > 3) {
                const double dx = xyh[p][0] - xyh[q][0], dy = xyh[p][1] - xyh[q][1];
                change = midpoint_change(plan, xyh, p, q) * (dx * dx + dy * dy);
            }
            good |= uint64_t(1) << c, good_shape[c] = s, good_change[c] = change;
            if (better(change, s, best_change, best_shape))
                best_shape = s, best_change = change, best = i;
        }
        if (best == n) return false;
        if (out.new_count == kMaxValence) return false;
        uint8_t* t = out.triangles[out.new_count++];
        t[0] = left[(best + n - 1) % n], t[1] = left[best], t[2] = left[(best + 1) % n];
        good &= ~(uint64_t(1) << t[0] | uint64_t(1) << t[2]); // their ears change
        std::copy(left + best + 1, left + n, left + best);
        --n;
    }
    return true;
}

double Simplifier::new_midpoint_change(const RemovalPlan& plan, const double (*xyh)[3], uint8_t lo,
                                       uint8_t hi) const {
    double change = 0; // outside the star: a boundary's new edge, priced by its planes
    const size_t n = plan.ring_size;
    const double mid[2] = {(xyh[lo][0] + xyh[hi][0]) / 2, (xyh[lo][1] + xyh[hi][1]) / 2};
    // The star triangle (v, ring[i], ring[i + 1]) under the midpoint: for an edge inside the
    // polygon, one of those between its ends. Searched from the lower end, so that the edge's
    // change does not depend on which way round it is asked for (on a spoke both sides agree,
    // to rounding). side: the midpoint's side of the spoke to ring[i] (> 0: ahead of it).
    auto side = [&](size_t i) { return xyh[i][0] * mid[1] - xyh[i][1] * mid[0]; };
    double side_i = side(lo);
    for (size_t k = 0; k < n; ++k) {
        const size_t i = (lo + k) % n, i1 = (i + 1) % n;
        const double side_i1 = side(i1), side_at = side_i;
        side_i = side_i1;
        if (plan.boundary && i == n - 1) continue; // no star triangle between the ends
        const double d = xyh[i][0] * xyh[i1][1] - xyh[i][1] * xyh[i1][0]; // twice its area
        constexpr double kInside = 1e-9; // on a spoke, either side will do
        if (!(d > 0) || side_at < -kInside * d || side_i1 > kInside * d) continue;
        const double wi = -side_i1 / d, wi1 = side_at / d, wv = 1 - wi - wi1;
        if (wv < -kInside) continue;
        const double height =
            (xyh[lo][2] + xyh[hi][2]) / 2 - (wi * xyh[i][2] + wi1 * xyh[i1][2]); // v's is 0
        change =
            geometry_weight() * height * height * quadrics_.inv_diagonal * quadrics_.inv_diagonal;
        const float *fp = mesh_.data_of(plan.ring[lo]), *fq = mesh_.data_of(plan.ring[hi]);
        const float *fv = mesh_.data_of(plan.vertex), *fi = mesh_.data_of(plan.ring[i]),
                    *fi1 = mesh_.data_of(plan.ring[i1]);
        for (size_t j = 0; j < quadrics_.components; ++j) {
            const uint32_t o = quadrics_.offset[j];
            const double before = wv * fv[o] + wi * fi[o] + wi1 * fi1[o];
            const double s = ((double(fp[o]) + fq[o]) / 2 - before) * quadrics_.inv_range[j];
            change += (1 - options_.alpha) * s * s;
        }
        break;
    }
    if (hi < RemovalPlan::kChangeMemo)
        plan.edge_change[lo][hi] = change, plan.edge_change_known[lo] |= uint16_t(1u << hi);
    return change;
}

double Simplifier::triangulation_change(const RemovalPlan& plan, const double (*xyh)[3],
                                        const uint8_t (*triangles)[3], size_t count) const {
    // Over a new triangle the change is near linear and 0 on the ring's own edges: the
    // quadrature at the sides' midpoints (area / 3 each, exact for the square of a linear
    // change) integrates its square.
    const size_t n = plan.ring_size;
    const double unit = quadrics_.inv_diagonal * quadrics_.inv_diagonal;
    double sum = 0;
    for (size_t t = 0; t < count; ++t) {
        const uint8_t* c = triangles[t];
        const double area = std::abs(orient(xyh[c[0]], xyh[c[1]], xyh[c[2]])) / 2 * unit;
        for (int k = 0; k < 3; ++k) {
            const uint8_t a = c[k], b = c[(k + 1) % 3];
            const size_t gap = (b + n - a) % n;
            if (gap == 1 || gap == n - 1) continue; // the ring's own edge
            sum += area / 3 * midpoint_change(plan, xyh, a, b);
        }
    }
    return sum;
}

bool Simplifier::plan_removal(uint32_t v, RemovalPlan& plan) const {
    const VertexKind k = mesh_.kind[v];
    if (k != VertexKind::Free && k != VertexKind::Line) return false;
    plan.vertex = v;
    plan.boundary = mesh_.is_boundary_vertex(v);
    plan.new_count = 0;
    plan.feature_a = plan.feature_b = -1;

    size_t fan = 0;
    uint32_t last = kNone;
    Vec3 normal{0, 0, 0};
    bool fits = true;
    mesh_.for_each_outgoing(v, [&](uint32_t h) {
        if (fan + 1 >= kMaxValence) {
            fits = false;
            return;
        }
        plan.ring[fan] = mesh_.dest(h);
        plan.star[fan] = h / 3;
        plan.outer_twin[fan] = mesh_.twin[next(h)];
        plan.outer_line[fan] = mesh_.line[next(h)];
        if (!plan.boundary && mesh_.line[h]) // a feature line through v
            (plan.feature_a < 0 ? plan.feature_a : plan.feature_b) = int(fan);
        last = h;
        ++fan;
    });
    if (!fits) return false;
    size_t n = fan;
    if (plan.boundary) plan.ring[n++] = mesh_.origin[prev(last)];
    // The ring's records lie scattered over the surface: fetch them all before the star's normals
    // read them one by one (a prefetch changes no result).
    for (size_t i = 0; i < n; ++i) __builtin_prefetch(mesh_.position_of(plan.ring[i]));
    for (size_t i = 0; i < fan; ++i) {
        plan.star_normal[i] = mesh_.triangle_normal(plan.star[i]);
        normal = add(normal, plan.star_normal[i]);
    }
    plan.ring_size = n;
    std::fill_n(plan.edge_change_known, RemovalPlan::kChangeMemo, uint16_t(0));
    plan.star_faces_along = true;
    for (size_t i = 0; i < fan; ++i)
        plan.star_faces_along =
            plan.star_faces_along &&
            mesh_.faces_along(plan.star_normal[i], v, plan.ring[i], plan.ring[(i + 1) % n]);
    if (n < (plan.boundary ? 2u : 3u)) return false;

    // Which ring vertices are already joined by an edge (outside the star). A complex vertex's
    // neighbours cannot all be listed, but the other end of an edge can list it; between two
    // complex vertices an edge is assumed, so no new edge is made there.
    uint64_t adjacent[kMaxValence] = {};
    uint64_t complex = 0;
    bool listed = true;
    uint32_t walked[kMaxValence], neighbours[kMaxValence][kMaxValence];
    size_t walks = 0, counts[kMaxValence];
    for (size_t i = 0; i < n; ++i)
        if (mesh_.kind[plan.ring[i]] == VertexKind::Complex)
            complex |= uint64_t(1) << i;
        else
            walked[walks++] = plan.ring[i];
    mesh_.rings(walked, walks, neighbours[0], kMaxValence, counts);
    for (size_t i = 0, w = 0; i < n && listed; ++i) {
        if (complex >> i & 1) continue;
        const size_t m = counts[w];
        const uint32_t* neighbour = neighbours[w++];
        listed = m != 0;
        for (size_t j = 0; j < m; ++j)
            for (size_t r = 0; r < n; ++r)
                if (plan.ring[r] == neighbour[j]) adjacent[i] |= uint64_t(1) << r;
    }
    if (!listed) return false;
    for (size_t i = 0; i < n; ++i)
        if (complex >> i & 1) {
            adjacent[i] = complex;
            for (size_t j = 0; j < n; ++j)
                if (adjacent[j] >> i & 1) adjacent[i] |= uint64_t(1) << j;
        }

    if (plan.boundary) {
        if (n == 2) { // an ear: its inner edge stays
            plan.cover = Cover::ear(n);
            return plan.outer_twin[0] != kNone;
        }
        if (adjacent[n - 1] >> 0 & 1) return false; // the new boundary edge exists already
    } else if (n == 3) {
        if (complex) return false; // the far side of a complex edge cannot be seen
        // The one new triangle must not already exist on the far side (a tetrahedron).
        const uint32_t far = plan.outer_twin[0];
        if (far != kNone && mesh_.origin[prev(far)] == plan.ring[2]) return false;
    }

    // Project the ring to the plane of the star's mean normal; keep each point's height above it.
    const double nn = norm(normal);
    if (!(nn > 0)) return false;
    const Vec3 axis = scale(normal, 1 / nn);
    const auto [e1, e2] = plane_across(axis);
    double xyh[kMaxValence][3];
    const Vec3 centre = mesh_.point(v);
    for (size_t i = 0; i < n; ++i) {
        const Vec3 d = sub(mesh_.point(plan.ring[i]), centre);
        xyh[i][0] = dot(d, e1), xyh[i][1] = dot(d, e2), xyh[i][2] = dot(d, axis);
    }

    if (planar_triangulation(plan, xyh, adjacent, axis)) {
        if (!quadric_terms_) return true;
        plan.error = triangulation_error(plan, plan.triangles, plan.new_count, xyh, plan.cover) +
                     triangulation_change(plan, xyh, plan.triangles, plan.new_count);
        if (plan.error <= quadrics_.noise(v)) return true;
        // The flattest triangulation may cut across a crease that a fan from one of its ends
        // follows: the one with less error wins.
        RemovalPlan fan = plan;
        fan.new_count = 0;
        if (fan_triangulation(fan, adjacent, xyh, plan.error) &&
            fan.error + quadrics_.noise(v) < plan.error)
            plan = fan;
        return true;
    }
    // A star too curved to project flat may still be closed by a fan from one of its vertices
    // (the half-edge collapse of v into it), checked in 3D instead.
    plan.new_count = 0;
    return fan_triangulation(plan, adjacent, xyh);
}

double Simplifier::triangulation_error(const RemovalPlan& plan, const uint8_t (*triangles)[3],
                                       size_t count, const double (*xyh)[3], Cover& cover) const {
    // Barycentric coordinates of the origin (v) in each new triangle: the one that holds it, or
    // whose least coordinate is largest, clamped into it.
    const double origin[2] = {0, 0};
    double best[3] = {1, 0, 0}, best_least = -INFINITY;
    size_t at = 0;
    for (size_t t = 0; t < count; ++t) {
        const double *a = xyh[triangles[t][0]], *b = xyh[triangles[t][1]],
                     *c = xyh[triangles[t][2]];
        const double d = orient(a, b, c);
        if (d == 0) continue;
        const double w[3] = {orient(origin, b, c) / d, orient(a, origin, c) / d,
                             orient(a, b, origin) / d};
        const double least = std::min({w[0], w[1], w[2]});
        if (least > best_least) best_least = least, at = t, std::copy(w, w + 3, best);
    }
    double sum = 0;
    for (double& w : best) sum += (w = std::max(w, 0.0));
    for (double& w : best) w = sum > 0 ? w / sum : 1.0 / 3;
    const uint32_t corners[3] = {plan.ring[triangles[at][0]], plan.ring[triangles[at][1]],
                                 plan.ring[triangles[at][2]]};
    cover.count = 3;
    for (int k = 0; k < 3; ++k) cover.corner[k] = triangles[at][k], cover.weight[k] = best[k];
    Vec3 x{0, 0, 0};
    const double error = quadrics_.at_blend(plan.vertex, mesh_, corners, best, 3, &x);
    // On a boundary, the planes through its edges already price pulling it in.
    if (plan.boundary) return error;
    const Vec3 d = sub(x, mesh_.point(plan.vertex));
    // At three times a collapse's price: a collapse pays for both ends and puts its new vertex
    // where the error is least, a removal can only drop the vertex; a lower price lets corners
    // and tips go early (docs/algorithm.md). One within rounding (a flat star's) is none: it
    // would break the ties of 0.
    const double retraction = 3 * retraction_scale() * dot(d, d);
    return retraction > quadrics_.noise(plan.vertex) ? error + retraction : error;
}

bool Simplifier::planar_triangulation(RemovalPlan& plan, const double (*xyh)[3],
                                      const uint64_t* adjacent, const Vec3& axis) const {
    const size_t n = plan.ring_size;
    uint8_t polygon[kMaxValence];
    const int fa = plan.feature_a, fb = plan.feature_b;
    const bool split = fa >= 0 && fb >= 0 && fb - fa >= 2 && size_t(fa + int(n) - fb) >= 2;
    if (split) { // the feature line must go on as the edge between its two ends
        if (adjacent[fa] >> fb & 1) return false;
        size_t m = 0;
        for (int i = fa; i <= fb; ++i) polygon[m++] = uint8_t(i);
        if (!triangulate(plan, xyh, polygon, m, adjacent, plan)) return false;
        m = 0;
        for (int i = fb; i != fa + int(n); ++i) polygon[m++] = uint8_t(i % int(n));
        polygon[m++] = uint8_t(fa);
        if (!triangulate(plan, xyh, polygon, m, adjacent, plan)) return false;
    } else {
        for (size_t i = 0; i < n; ++i) polygon[i] = uint8_t(i);
        if (!triangulate(plan, xyh, polygon, n, adjacent, plan)) return false;
    }

    // The new triangles must face the same way as the star in 3D too, and turn no more than
    // the limit from the star triangles at their corners.
    const size_t fan = plan.boundary ? n - 1 : n;
    const double turn_cos = mesh_.limits.normal_turn_cos;
    for (size_t t = 0; t < plan.new_count; ++t) {
        const uint8_t* c = plan.triangles[t];
        const Vec3 p0 = mesh_.point(plan.ring[c[0]]);
        const Vec3 p1 = mesh_.point(plan.ring[c[1]]), p2 = mesh_.point(plan.ring[c[2]]);
        const Vec3 tn = cross(sub(p1, p0), sub(p2, p0));
        // Nor be a needle on (nearly) collinear ring vertices, which the projection can miss.
        const double sum = dot(sub(p1, p0), sub(p1, p0)) + dot(sub(p2, p1), sub(p2, p1)) +
                           dot(sub(p0, p2), sub(p0, p2));
        if (norm(tn) <= kNeedle * sum) return false;
        for (int k = 0; k < 3; ++k) {
            if (c[k] >= fan) continue;
            const Vec3& old = plan.star_normal[c[k]];
            if (dot(tn, old) < turn_cos * norm(tn) * norm(old)) return false;
        }
        if (dot(tn, axis) <= 0 || (plan.star_faces_along &&
                                   !faces_the_surface(tn, mesh_.reference_normal(plan.ring[c[0]]),
                                                      mesh_.reference_normal(plan.ring[c[1]]),
                                                      mesh_.reference_normal(plan.ring[c[2]]))))
            return false;
    }
    return true;
}

bool Simplifier::fan_triangulation(RemovalPlan& plan, const uint64_t* adjacent,
                                   const double (*xyh)[3], double beat) const {
    const size_t n = plan.ring_size;
    const Vec3 centre = mesh_.point(plan.vertex);
    const double turn_cos = mesh_.limits.normal_turn_cos;
    double best_shape = -1, best_error = INFINITY, chosen_error = 0;
    size_t best = n;
    // With the error quadrics the fan of least error wins (the best shape among equals).
    const double noise = quadric_terms_ ? quadrics_.noise(plan.vertex) : 0;
    Cover cover, best_cover;
    auto fan_error = [&](size_t j) {
        uint8_t triangles[kMaxValence][3];
        size_t count = 0;
        for (size_t k = 1; k + 1 < n; ++k) {
            const size_t i = (j + k) % n, i1 = (i + 1) % n;
            if (plan.boundary && i == n - 1) break;
            triangles[count][0] = uint8_t(j), triangles[count][1] = uint8_t(i);
            triangles[count++][2] = uint8_t(i1);
        }
        const double error = triangulation_error(plan, triangles, count, xyh, cover);
        // The change only adds: a fan already heavier than the best so far, or than `beat`,
        // cannot win, and its change is left out.
        if (error > std::min(best_error + noise, beat)) return error;
        return error + triangulation_change(plan, xyh, triangles, count);
    };
    // What does not depend on the fan's apex, once: the ring's points and reference normals,
    // and per star triangle (v, i, i + 1) its normal, that normal's length and the squared
    // length of its outer edge.
    Vec3 point[kMaxValence], reference[kMaxValence], before[kMaxValence];
    double before_length[kMaxValence], outer[kMaxValence];
    for (size_t i = 0; i < n; ++i)
        point[i] = mesh_.point(plan.ring[i]), reference[i] = mesh_.reference_normal(plan.ring[i]);
    for (size_t i = 0; i < n; ++i) {
        const Vec3 &q = point[i], &r = point[(i + 1) % n];
        before[i] = cross(sub(q, centre), sub(r, centre));
        before_length[i] = norm(before[i]);
        outer[i] = dot(sub(q, r), sub(q, r));
    }
    for (size_t j = 0; j < n; ++j) {
        // On a boundary the fan must keep the new boundary edge; on a feature line, its edge.
        if (plan.boundary && j != 0 && j != n - 1) continue;
        if (plan.feature_a >= 0 && int(j) != plan.feature_a && int(j) != plan.feature_b) continue;
        const Vec3 apex = point[j];
        double worst = 1;
        bool ok = true;
        // Triangle (j, i, i + 1) replaces the star's (v, i, i + 1): v moves onto ring[j].
        // worst only falls, so j cannot win once it is no better than the best so far (by
        // shape alone: the paper's terms).
        for (size_t k = 1; k + 1 < n && ok && (quadric_terms_ || worst > best_shape); ++k) {
            const size_t i = (j + k) % n, i1 = (i + 1) % n;
            if (plan.boundary && i == n - 1) break;
            if (k >= 2 && (adjacent[j] >> i & 1)) ok = false; // the diagonal j-i exists
            const Vec3 &q = point[i], &r = point[i1];
            const Vec3 after = cross(sub(q, apex), sub(r, apex));
            const double la = norm(after), lb = before_length[i];
            const double sum =
                dot(sub(q, apex), sub(q, apex)) + dot(sub(r, apex), sub(r, apex)) + outer[i];
            if (la <= kNeedle * sum || (lb > 0 && dot(after, before[i]) < turn_cos * la * lb) ||
                (plan.star_faces_along &&
                 !faces_the_surface(after, reference[j], reference[i], reference[i1])))
                ok = false;
            else
                worst = std::min(worst, 2 * std::sqrt(3.0) * la / sum);
        }
        if (!ok) continue;
        if (quadric_terms_) {
            const double error = fan_error(j);
            if (error < best_error - noise || (error <= best_error + noise && worst > best_shape))
                best_error = std::min(error, best_error), best_shape = worst, best = j,
                chosen_error = error, best_cover = cover;
        } else if (worst > best_shape)
            best_shape = worst, best = j;
    }
    if (best == n) return false;
    plan.error = chosen_error; // the best fan's (0 with the paper's terms)
    plan.cover = best_cover;
    for (size_t k = 1; k + 1 < n; ++k) {
        const size_t i = (best + k) % n, i1 = (i + 1) % n;
        if (plan.boundary && i == n - 1) break;
        uint8_t* t = plan.triangles[plan.new_count++];
        t[0] = uint8_t(best), t[1] = uint8_t(i), t[2] = uint8_t(i1);
    }
    return plan.new_count == n - 2;
}

void Simplifier::apply_removal(const Removal& plan, size_t index, size_t write_at) {
    WorkingMesh& m = mesh_;
    const size_t n = plan.ring_size, fan = plan.boundary ? n - 1 : n;
    const bool consecutive_feature =
        plan.feature_a >= 0 && plan.feature_b >= 0 &&
        (plan.feature_b - plan.feature_a == 1 || plan.feature_a + int(n) - plan.feature_b == 1);
    auto is_feature_pair = [&](int p, int q) {
        return (p == plan.feature_a && q == plan.feature_b) ||
               (q == plan.feature_a && p == plan.feature_b);
    };

    // Rewrite the first new_count star slots with the new triangles, retire the others.
    for (size_t t = 0; t < plan.new_count; ++t) {
        const uint32_t slot = plan.star[t];
        for (int c = 0; c < 3; ++c) m.origin[3 * slot + c] = plan.ring[plan.triangles[t][c]];
        m.update_angles(slot);
    }
    for (size_t t = plan.new_count; t < fan; ++t) {
        const uint32_t slot = plan.star[t];
        for (int c = 0; c < 3; ++c) m.origin[3 * slot + c] = kNone, m.twin[3 * slot + c] = kNone;
    }
    // Twins and line flags of the new half-edges.
    for (size_t t = 0; t < plan.new_count; ++t)
        for (int c = 0; c < 3; ++c) {
            const uint32_t h = 3 * plan.star[t] + uint32_t(c);
            const int p = plan.triangles[t][c], q = plan.triangles[t][(c + 1) % 3];
            if (q == (p + 1) % int(n) && !(plan.boundary && p == int(n) - 1)) {
                const uint32_t o = plan.outer_twin[p];
                m.twin[h] = o;
                m.line[h] = plan.outer_line[p] || (consecutive_feature && is_feature_pair(p, q));
                if (o != kNone) m.twin[o] = h, m.line[o] = m.line[h];
            } else if (plan.boundary && p == int(n) - 1 && q == 0) {
                m.twin[h] = kNone, m.line[h] = 1; // the new stretch of boundary
            } else {
                m.line[h] = is_feature_pair(p, q);
                for (size_t s = 0; s < plan.new_count; ++s)
                    for (int d = 0; d < 3; ++d)
                        if (plan.triangles[s][d] == q && plan.triangles[s][(d + 1) % 3] == p)
                            m.twin[h] = 3 * plan.star[s] + uint32_t(d);
            }
        }
    if (plan.boundary && n == 2) { // the removed ear's inner edge becomes boundary
        const uint32_t o = plan.outer_twin[0];
        m.twin[o] = kNone, m.line[o] = 1;
    }
    m.kind[plan.vertex] = VertexKind::Dead;
    m.out[plan.vertex] = kNone;
    mark_stale(plan.vertex); // its place in the order goes

    // Every ring vertex needs a surviving way into its fan.
    for (size_t i = 0; i < n; ++i) {
        uint32_t entry = kNone;
        for (size_t t = 0; t < plan.new_count && entry == kNone; ++t)
            for (int c = 0; c < 3; ++c)
                if (plan.triangles[t][c] == i) entry = 3 * plan.star[t] + uint32_t(c);
        if (entry == kNone) { // only for the ear: use the far side of its inner edge
            const uint32_t o = plan.outer_twin[0];
            entry = i == 1 ? o : next(o);
        }
        m.reset_out(plan.ring[i], entry);
    }

    // The record: {slot, a, b, c} per rewritten slot, {slot, kNone, kNone, kNone} per retired.
    uint32_t* write = &record_.writes_[write_at];
    for (size_t t = 0; t < fan; ++t) {
        const uint32_t slot = plan.star[t];
        *write++ = slot;
        for (int c = 0; c < 3; ++c) {
            const uint32_t v = m.origin[3 * slot + c];
            *write++ = v == kNone ? kNone : id_[v];
        }
    }
    (void)index; // the record's write_begin_ already holds where operation `index` ends
    // The input surface v stood for is now spanned by the new triangle that passes it: its error
    // quadric goes to that triangle's corners by v's barycentric weights there, as a collapse's
    // goes to the vertex that replaces it. (Shared equally among the ring, the error of v's input
    // would spread to ring vertices far from it.)
    if (quadric_terms_)
        for (size_t k = 0; k < plan.cover.count; ++k)
            quadrics_.add(plan.ring[plan.cover.corner[k]], plan.vertex, plan.cover.weight[k]);
    refresh_around(plan.ring, n);
}

Simplifier::Check Simplifier::check_removal(uint32_t v, size_t slot) {
    RemovalPlan plan;
    if (!plan_removal(v, plan)) {
        fail_[v] = pass_; // no candidate until its star changes
        mark_stale(v);
        return Check::Refused;
    }
    // Its key was an estimate (see weight_): a re-triangulation that makes it wait (see waits,
    // as a collapse's retraction does) becomes its key.
    const float error = float(plan.error);
    if (quadric_terms_ && waits(v, weight_[v], error)) {
        weight_[v] = error, placed_[v] = kMoved;
        mark_stale(v); // ranked again with that key
        return Check::Waits;
    }
    removals_.put(slot, plan);
    return Check::Taken;
}

} // namespace ddsimp
