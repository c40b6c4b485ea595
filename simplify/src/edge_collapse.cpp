// Edge collapse: the edge's two vertices become one new vertex, placed at the midpoint, at a
// volume-preserving point, or on the end that a boundary or feature line pins down. Its data is
// interpolated at the point's position along the edge.
#include "simplifier.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace ddsimp {

using namespace detail;

namespace {
// How far (in edge lengths) the least-error point may leave its edge sideways.
constexpr double kMaxSideways = 0.5;
// Bytes per cache line (x86-64, ARMv8), for prefetch_key's steps through a quadric.
constexpr size_t kCacheLine = 64;

// How far a smooth surface with unit normals na and nb at the ends of an edge of length 1 can
// bulge from the edge: the apex of its ends' tangent lines, tan(theta / 2) / 2 for normals
// theta apart.
double bulge(const Vec3& na, const Vec3& nb) {
    const double c = dot(na, nb);
    return c > -0.9 ? 0.5 * norm(cross(na, nb)) / (1 + c) : kMaxSideways;
}

bool on_line(VertexKind k) {
    return k == VertexKind::Line || k == VertexKind::Corner;
}

// Whether a fan's ring (WorkingMesh::ring: consecutive neighbours span a triangle; `closed`: the
// last and the first too) has a triangle on vertices p and q.
bool spans(const uint32_t* ring, size_t n, bool closed, uint32_t p, uint32_t q) {
    for (size_t i = 0; i + 1 < n + (closed ? 1 : 0); ++i) {
        const uint32_t u = ring[i], w = ring[(i + 1) % n];
        if ((u == p && w == q) || (u == q && w == p)) return true;
    }
    return false;
}

// Area x squared distance to its plane, for a triangle whose normal n is twice its area long, of
// a point `offset` from one of its corners (star_error's measure).
double plane_error(const Vec3& n, double twice_area, const Vec3& offset) {
    const double d = dot(n, offset); // twice_area x the distance to the plane
    return d * d / (2 * twice_area);
}

} // namespace

bool Simplifier::kinds_allow_collapse(uint32_t h, uint32_t a, uint32_t b) const {
    const VertexKind ka = mesh_.kind[a], kb = mesh_.kind[b];
    if (ka == VertexKind::Complex || kb == VertexKind::Complex) return false;
    if (ka == VertexKind::Dead || kb == VertexKind::Dead) return false;
    if (ka == VertexKind::Corner && kb == VertexKind::Corner) return false;
    if (size_t(mesh_.valence[a]) + mesh_.valence[b] > kMaxNewValence + 4) return false;
    if (!on_line(ka) || !on_line(kb)) return true; // a boundary vertex is always on a line
    // Two line vertices may only merge along their common line, and an inner edge between two
    // boundary vertices would pinch the surface.
    if (!mesh_.line[h]) return false;
    return mesh_.twin[h] == kNone || !mesh_.is_boundary_vertex(a) || !mesh_.is_boundary_vertex(b);
}

bool Simplifier::collapsible(uint32_t h, uint32_t a, uint32_t b) const {
    if (!kinds_allow_collapse(h, a, b)) return false;
    const uint32_t failed = fail_[h];
    if (failed == 0) return true;
    const uint32_t t = mesh_.twin[h];
    for (uint32_t v :
         {a, b, mesh_.origin[prev(h)], t != kNone ? mesh_.origin[prev(t)] : mesh_.origin[h]})
        if (epoch_[v] >= failed) return true;
    return false;
}

float Simplifier::collapse_weight(uint32_t h) const {
    if (quadric_terms_) {
        CollapsePlan plan;
        place(h, plan, Pricing::Key);
        return float(plan.error);
    }
    return weight_[mesh_.origin[h]] + weight_[mesh_.dest(h)];
}

void Simplifier::prefetch_key(uint32_t a, uint32_t b) const {
    for (const uint32_t v : {a, b}) {
        __builtin_prefetch(mesh_.position_of(v));
        if (quadrics_.values.empty()) continue;
        const char* q = reinterpret_cast<const char*>(quadrics_.of(v));
        for (size_t line = 0; line < quadrics_.size * sizeof(double); line += kCacheLine)
            __builtin_prefetch(q + line);
    }
}

float Simplifier::edge_length(uint32_t h) const {
    return float(norm(sub(mesh_.point(mesh_.origin[h]), mesh_.point(mesh_.dest(h)))));
}

bool Simplifier::plan_collapse(uint32_t h, CollapsePlan& plan, double taken_within) const {
    const uint32_t a = mesh_.origin[h], b = mesh_.dest(h), ht = mesh_.twin[h];
    plan.refused_at = kNone;
    if (!kinds_allow_collapse(h, a, b)) return false;
    const uint32_t x = mesh_.origin[prev(h)], y = ht != kNone ? mesh_.origin[prev(ht)] : kNone;

    // A removed triangle must keep at least one neighbour, or it would leave a dangling edge.
    if (mesh_.twin[next(h)] == kNone && mesh_.twin[prev(h)] == kNone) return false;
    if (ht != kNone && mesh_.twin[next(ht)] == kNone && mesh_.twin[prev(ht)] == kNone) return false;

    // A refusal for a folding triangle that is still there and still folds stands: test that
    // triangle first (the checks are a conjunction, so the answer is the same, only sooner).
    bool placed = false;
    if (const uint32_t g = fold_from_hint(h, fail_at_[h]); g != kNone) {
        const uint32_t v = mesh_.origin[g], t = g / 3;
        if ((v == a || v == b) && t != h / 3 && (ht == kNone || t != ht / 3)) {
            place(h, plan);
            placed = true;
            if (!keeps_facing(g, plan.point, ref_of(a, b))) {
                plan.refused_at = g;
                return false;
            }
        }
    }

    // Link condition: a and b share exactly the apexes of the edge's triangles as neighbours.
    uint32_t ring_a[kMaxValence], ring_b[kMaxValence];
    const size_t na = mesh_.ring(a, ring_a, kMaxValence), nb = mesh_.ring(b, ring_b, kMaxValence);
    if (na == 0 || nb == 0) return false;
    // The fold checks below read every ring vertex's record, scattered over the surface: fetch
    // them while the link condition runs (a prefetch changes no result).
    for (size_t i = 0; i < na; ++i) __builtin_prefetch(mesh_.position_of(ring_a[i]));
    for (size_t i = 0; i < nb; ++i) __builtin_prefetch(mesh_.position_of(ring_b[i]));
    size_t common = 0;
    for (size_t i = 0; i < na; ++i)
        for (size_t j = 0; j < nb; ++j)
            if (ring_a[i] == ring_b[j]) {
                if (ring_a[i] != x && ring_a[i] != y) return false;
                ++common;
            }
    if (common != (y == kNone ? 1u : 2u)) return false;
    // If both ends have a triangle on the two apexes, those two would become the same triangle:
    // an apex of valence 3, or a tetrahedron hanging on a non-manifold edge x-y.
    if (y != kNone && spans(ring_a, na, !mesh_.is_boundary_vertex(a), x, y) &&
        spans(ring_b, nb, !mesh_.is_boundary_vertex(b), x, y))
        return false;

    if (!placed) place(h, plan);
    // No remaining triangle may flip, fold or turn its normal by more than the limit. The same
    // walk prices the new point against the planes of the triangles it replaces (see star_error).
    const Vec3 ref = ref_of(a, b);
    const double retraction = retraction_scale();
    double star = 0;
    bool ok = true;
    auto check_star = [&](uint32_t v) {
        mesh_.for_each_outgoing(v, [&](uint32_t g) {
            const uint32_t t = g / 3;
            const bool removed = t == h / 3 || (ht != kNone && t == ht / 3);
            if (!ok || (removed && v != a)) return; // the removed ones once, from a's star
            if (removed) {
                if (retraction > 0) star += star_error(g, plan.point);
            } else if (!keeps_facing(g, plan.point, ref, retraction > 0 ? &star : nullptr)) {
                ok = false, plan.refused_at = g;
            }
        });
    };
    check_star(a);
    check_star(b);
    plan.retraction = 0;
    if (!ok || !(retraction > 0)) return ok;
    // How close the new triangles come to each end (see retraction_scale): the least distance
    // over them, measured until the plan is known to be taken whatever the rest would find (the
    // full key only falls as they are measured). No other triangle left (a closed tetrahedron's
    // last collapse): none.
    const double inv2 = quadrics_.inv_diagonal * quadrics_.inv_diagonal;
    const double present = geometry_weight() * star * inv2 * inv2;
    const Vec3 pa = mesh_.point(a), pb = mesh_.point(b);
    double near_a = INFINITY, near_b = INFINITY;
    auto full = [&] { return retraction * (near_a + near_b) + present; };
    bool settled = false;
    auto measure = [&](uint32_t v) {
        mesh_.for_each_outgoing(v, [&](uint32_t g) {
            const uint32_t t = g / 3;
            if (settled || t == h / 3 || (ht != kNone && t == ht / 3)) return;
            const Vec3 q = mesh_.point(mesh_.dest(g)), r = mesh_.point(mesh_.origin[prev(g)]);
            auto distance2 = [&](const Vec3& x) {
                const Vec3 d = sub(x, closest_on_triangle(x, plan.point, q, r).point);
                return dot(d, d);
            };
            near_a = std::min(near_a, distance2(pa));
            near_b = std::min(near_b, distance2(pb));
            settled = double(float(plan.error + full())) <= taken_within;
        });
    };
    measure(a);
    measure(b);
    plan.retraction = std::isinf(near_a) ? present : full();
    return true;
}

// The accumulated quadrics measure a new point against the input triangles its two ends stand
// for. Where those are few and small (the corner of a rim, the tip of a crease, once coarsened)
// they leave a direction almost free, and a collapse can pull the corner far along it although the
// triangles around it now are large and move with it. This measures what the error quadrics
// measure, area x squared distance to the plane (raw units), against the present triangle g / 3
// instead of the input's: for the planned collapses, what the surface as it is would lose.
double Simplifier::star_error(uint32_t g, const Vec3& p) const {
    const Vec3 pv = mesh_.point(mesh_.origin[g]);
    const Vec3 n =
        cross(sub(mesh_.point(mesh_.dest(g)), pv), sub(mesh_.point(mesh_.origin[prev(g)]), pv));
    const double twice_area = norm(n);
    return twice_area > 0 ? plane_error(n, twice_area, sub(p, pv)) : 0;
}

// Triangle g / 3 of the star of origin[g], with origin[g] moved to p: it must not degenerate,
// turn its normal by more than the limit, or stop facing the way of the input surface.
bool Simplifier::keeps_facing(uint32_t g, const Vec3& p, const Vec3& ref, double* star) const {
    const uint32_t v = mesh_.origin[g], qi = mesh_.dest(g), ri = mesh_.origin[prev(g)];
    const Vec3 pv = mesh_.point(v), q = mesh_.point(qi), r = mesh_.point(ri);
    const Vec3 before = cross(sub(q, pv), sub(r, pv));
    const Vec3 after = cross(sub(q, p), sub(r, p));
    const double la = norm(after), lb = norm(before);
    if (star && lb > 0) *star += plane_error(before, lb, sub(p, pv)); // star_error(g, p)
    const Vec3 qp = sub(q, p), rp = sub(r, p);
    if (la <= 1e-12 * (dot(qp, qp) + dot(rp, rp))) return false;
    if (lb > 0 && dot(after, before) < mesh_.limits.normal_turn_cos * la * lb) return false;
    // It faced the way of the input surface and would no longer: at each corner, or, once
    // nothing is removable so (relaxed_facing_), on the sum of its corners' reference normals.
    if (relaxed_facing_) {
        const double lr = norm(ref); // the new vertex's reference, as apply_collapse sets it
        const Vec3 sum = add(lr > 0 ? scale(ref, 1 / lr) : ref,
                             add(mesh_.reference_normal(qi), mesh_.reference_normal(ri)));
        return dot(after, sum) > 0 || dot(before, sum) <= 0;
    }
    if ((dot(after, ref) <= 0 || !mesh_.faces_along(after, qi, ri)) &&
        mesh_.faces_along(before, v, qi, ri))
        return false;
    return true;
}

Vec3 Simplifier::ref_of(uint32_t a, uint32_t b) const {
    return add(mesh_.reference_normal(a), mesh_.reference_normal(b));
}

// The data's error reads the input's field off each input triangle's plane, and where the planes
// bend it can pull the sideways step `d` off the surface to fit the data a little better: smooth
// curved surfaces then come out uneven, a sphere's points scattered in and out of its radius. So
// off the surface, along the ends' reference
// normals, the step goes no farther than the surface can bulge between them (bulge), and across
// it to where the error is then least. Without data (alpha = 1) the geometry alone decides.
Vec3 Simplifier::near_surface(const SegmentSlope& slope, double t, uint32_t a, uint32_t b,
                              const Vec3& axis, double length, const Vec3& d) const {
    const Vec3 na = mesh_.reference_normal(a), nb = mesh_.reference_normal(b);
    const double la = norm(na), lb = norm(nb);
    Vec3 normal = add(na, nb);
    normal = sub(normal, scale(axis, dot(normal, axis)));
    const double ln = norm(normal);
    if (!(la > 0 && lb > 0 && ln > 0)) return d;
    normal = scale(normal, 1 / ln);
    const double height = dot(d, normal);
    const double most = bulge(scale(na, 1 / la), scale(nb, 1 / lb)) * length;
    if (std::abs(height) <= most) return d;
    const Vec3 held = quadrics_.sideways_at(slope, t, axis, normal, std::copysign(most, height));
    const double l = norm(held);
    return l > kMaxSideways * length ? scale(held, kMaxSideways * length / l) : held;
}

// Where the new point of collapsing h goes, and its position along the edge.
void Simplifier::place(uint32_t h, CollapsePlan& plan, Pricing pricing) const {
    const uint32_t a = mesh_.origin[h], b = mesh_.dest(h), ht = mesh_.twin[h];
    const VertexKind ka = mesh_.kind[a], kb = mesh_.kind[b];
    const Vec3 pa = mesh_.point(a), pb = mesh_.point(b);
    Vec3 p = scale(add(pa, pb), 0.5);
    // The least-error placement: the error of both ends along the edge, from a at t = 0 to b at
    // t = 1 (the other placements need the error at their point only).
    SegmentError error;
    // Between two free ends the least-error point may also leave the edge sideways, to where the
    // error is least, keeping its projection on the edge (and so its data): the quadrics' geometry
    // (kMinGeometryWeight) says where the surface is. A key with data in the quadrics prices the
    // point on the edge: the step holds the data and trims only the geometric part of the error,
    // and it is most of a key's work.
    const bool may_leave_edge = least_error_ && ka == VertexKind::Free && kb == VertexKind::Free &&
                                (pricing == Pricing::Plan || quadrics_.components == 0);
    SegmentSlope slope;
    double t = 0.5, sideways_change = 0;
    bool off_edge = false;
    const float *fa = mesh_.data_of(a), *fb = mesh_.data_of(b);
    if (least_error_)
        error = quadrics_.along(a, b, pa, pb, fa, fb, may_leave_edge ? &slope : nullptr);
    if (ka == VertexKind::Corner || (ka == VertexKind::Line && kb == VertexKind::Free))
        p = pa;
    else if (kb == VertexKind::Corner || (kb == VertexKind::Line && ka == VertexKind::Free))
        p = pb;
    else if (least_error_) {
        t = error.least();
        p = add(pa, scale(sub(pb, pa), t));
        if (may_leave_edge) {
            const Vec3 edge = sub(pb, pa);
            const double length = norm(edge);
            const Vec3 axis = scale(edge, 1 / length);
            Vec3 d = quadrics_.sideways(slope, t, axis);
            const double l = norm(d);
            if (l > kMaxSideways * length) d = scale(d, kMaxSideways * length / l);
            if (quadrics_.components > 0) d = near_surface(slope, t, a, b, axis, length, d);
            if (l > 0)
                p = add(p, d), off_edge = true, sideways_change = quadrics_.change(slope, t, d);
        }
    } else if (ka == VertexKind::Free && kb == VertexKind::Free &&
               options_.placement == Placement::VolumePreserving) {
        // Volume between the star and the new star is linear in p: n . p = d (a plane); take
        // the point of that plane nearest the midpoint. Coordinates relative to the midpoint.
        const Vec3 mid = p;
        Vec3 normal{0, 0, 0};
        double before = 0;
        auto add_star = [&](uint32_t v) {
            mesh_.for_each_outgoing(v, [&](uint32_t g) {
                const Vec3 q = sub(mesh_.point(mesh_.dest(g)), mid);
                const Vec3 r = sub(mesh_.point(mesh_.origin[prev(g)]), mid);
                const Vec3 qr = cross(q, r);
                before += dot(qr, sub(mesh_.point(v), mid));
                const uint32_t t = g / 3;
                if (t != h / 3 && (ht == kNone || t != ht / 3)) normal = add(normal, qr);
            });
        };
        add_star(a);
        // b's star without the two shared triangles (already counted from a).
        mesh_.for_each_outgoing(b, [&](uint32_t g) {
            const uint32_t t = g / 3;
            if (t == h / 3 || (ht != kNone && t == ht / 3)) return;
            const Vec3 q = sub(mesh_.point(mesh_.dest(g)), mid);
            const Vec3 r = sub(mesh_.point(mesh_.origin[prev(g)]), mid);
            const Vec3 qr = cross(q, r);
            before += dot(qr, sub(pb, mid));
            normal = add(normal, qr);
        });
        const double nn = dot(normal, normal);
        const double length = norm(sub(pb, pa));
        if (nn > 0) {
            const Vec3 shift = scale(normal, before / nn);
            // A nearly flat star puts the plane far away; keep the point near the edge.
            if (norm(shift) <= 0.5 * length) p = add(mid, shift);
        }
    }
    const Vec3 edge = sub(pb, pa);
    const double ee = dot(edge, edge);
    plan.along = ee > 0 ? std::clamp(dot(sub(p, pa), edge) / ee, 0.0, 1.0) : 0.5;
    plan.point = p;
    plan.halfedge = h;
    plan.error = 0;
    if (quadric_terms_) {
        if (!least_error_) // the midpoint, an end or the volume point, with the data it gets
            plan.error = quadrics_.at(a, b, p, fa, fb, plan.along);
        else if (off_edge) // sideways: the error at t, and what the step changed, exactly
            plan.error = std::max(0.0, error.at(t) + sideways_change);
        else
            plan.error = error.at(plan.along);
    }
}

Simplifier::Apexes Simplifier::apply_collapse(const CollapsePlan& plan, size_t index) {
    WorkingMesh& m = mesh_;
    const uint32_t h = plan.halfedge, ht = m.twin[h];
    const uint32_t a = m.origin[h], b = m.dest(h);
    const uint32_t x = m.origin[prev(h)], y = ht != kNone ? m.origin[prev(ht)] : kNone;
    const uint32_t n = a; // the new vertex takes a's slot (see id_)
    const uint32_t t0 = h / 3, t1 = ht != kNone ? ht / 3 : kNone;

    // Half-edges that leave a or b and survive; they will leave n.
    uint32_t leaving[2 * kMaxValence];
    size_t count = 0;
    for (uint32_t v : {a, b})
        m.for_each_outgoing(v, [&](uint32_t g) {
            if (g / 3 != t0 && g / 3 != t1) leaving[count++] = g;
        });

    // A way into the fans of the apexes that survives the collapse.
    auto apex_entry = [&](uint32_t e) { // e: the removed triangle's half-edge into the apex
        const uint32_t from_apex = m.twin[e];
        return from_apex != kNone ? from_apex : next(m.twin[next(e)]);
    };
    const uint32_t entry_x = apex_entry(next(h));
    const uint32_t entry_y = ht != kNone ? apex_entry(next(ht)) : kNone;

    // The two outer edges of each removed triangle become one edge.
    // Either half of the merged edge may have been an edge's id, and the lower one is now: it is
    // keyed again, and the other's place, if it had one, goes.
    auto merge = [&](uint32_t e1, uint32_t e2) {
        const uint32_t o1 = m.twin[e1], o2 = m.twin[e2];
        const uint8_t l = m.line[e1] | m.line[e2];
        if (o1 != kNone) m.twin[o1] = o2, m.line[o1] = l;
        if (o2 != kNone) m.twin[o2] = o1, m.line[o2] = l;
        auto mark = [&](uint32_t o, uint32_t other) {
            if (o == kNone) return;
            if (other == kNone || o < other)
                mark_rekey(o);
            else if (placed_[o] != kUnplaced)
                mark_stale(o);
        };
        mark(o1, o2), mark(o2, o1);
    };
    merge(next(h), prev(h));
    if (ht != kNone) merge(next(ht), prev(ht));
    for (size_t i = 0; i < count; ++i) m.origin[leaving[i]] = n;
    for (uint32_t t : {t0, t1}) {
        if (t == kNone) continue;
        for (uint32_t c = 0; c < 3; ++c) {
            m.origin[3 * t + c] = kNone, m.twin[3 * t + c] = kNone;
            // Its place in the order goes, with no visit: it is no id again (drop_stale).
            if (placed_[3 * t + c] != kUnplaced) placed_[3 * t + c] = kDropped;
        }
    }

    // The new vertex. Its data of least error is written into its record first: a's data, which
    // it needs, is n's and gets the blend. A locked end keeps its data too (it is placed there).
    float* made = &made_[index * (3 + m.stride)];
    for (int c = 0; c < 3; ++c) m.position_of(n)[c] = float(plan.point[c]);
    const bool fit = least_data() && (m.locked.empty() || !(m.locked[a] | m.locked[b]));
    if (fit)
        quadrics_.least_data(a, b, plan.point, m.data_of(a), m.data_of(b), plan.along, made + 3);
    m.blend_data(a, b, plan.along, n);
    if (fit)
        for (size_t j = 0; j < quadrics_.components; ++j)
            if (quadrics_.continuous[j])
                m.data_of(n)[quadrics_.offset[j]] = made[3 + quadrics_.offset[j]];
    if (quadric_terms_ || least_error_) quadrics_.add(n, b, 1.0); // n is a's slot
    refusal_near_[n] |= refusal_near_[b];
    // n is on a boundary if an end was: until it is classified (refresh_changed), its kind says
    // which for reset_out.
    const bool interior = m.kind[a] == VertexKind::Free && m.kind[b] == VertexKind::Free;
    m.kind[a] = m.kind[b] = VertexKind::Dead;
    m.out[a] = m.out[b] = kNone;
    for (size_t i = 0; i < count; ++i) m.update_angles(leaving[i] / 3);
    const Vec3 ref = add(m.reference_normal(a), m.reference_normal(b));
    const double lr = norm(ref);
    for (int c = 0; c < 3; ++c)
        m.reference_of(n)[c] = lr > 0 ? float(ref[c] / lr) : m.reference_of(a)[c];
    m.kind[n] = interior ? VertexKind::Free : VertexKind::Corner;
    if (!m.locked.empty()) m.locked[n] = m.locked[a] | m.locked[b]; // placed on the locked end
    if (!m.zigzag.empty()) m.zigzag[n] = m.zigzag[a] | m.zigzag[b];
    m.reset_out(n, leaving[0]);
    // An apex that another collapse of the pass shares waits for them all (refresh_rings): its
    // out[] is set again by the collapse that removed it.
    Apexes deferred{n, {kNone, kNone}, {kNone, kNone}, false};
    const uint32_t apexes[2] = {x, y}, entries[2] = {entry_x, entry_y};
    for (int k = 0; k < 2; ++k) {
        const uint32_t v = apexes[k];
        if (v == kNone) continue;
        if (!shared(v)) {
            m.reset_out(v, entries[k]);
            continue;
        }
        deferred.apex[k] = v;
        if (m.out[v] / 3 == t0 || m.out[v] / 3 == t1) deferred.entry[k] = entries[k];
    }

    record_.collapse_[2 * index] = id_[a];
    record_.collapse_[2 * index + 1] = id_[b];
    id_[n] = uint32_t(record_.input_vertices_ + index);
    std::copy_n(m.position_of(n), 3, made);
    std::copy_n(m.data_of(n), m.stride, made + 3);

    // n, its apexes (which lost a neighbour and may have merged line flags) and the rest of its
    // ring: each one now unless another collapse of the pass shares it.
    epoch_[n] = pass_;
    refresh_changed(n, true, true);
    forgive_around(n);
    uint32_t ring[2 * kMaxValence + 2];
    const size_t k = m.ring(n, ring, 2 * kMaxValence + 2);
    for (size_t i = 0; i < k; ++i) {
        const uint32_t v = ring[i];
        std::atomic_ref<uint32_t>(epoch_[v]).store(pass_, std::memory_order_relaxed);
        if (v == x || v == y) {
            if (!shared(v)) refresh_changed(v, false, true), forgive_around(v);
        } else if (shared(v)) {
            deferred.ring |= ring_refreshes(v) || refusal_near_[v];
        } else {
            if (ring_refreshes(v)) refresh_changed(v, false, false);
            forgive_around(v);
        }
    }
    return deferred;
}

void Simplifier::refresh_rings(const Apexes* collapses, size_t count) {
    // Each shared apex's out[], where its collapse removed it (one collapse each), then each
    // shared apex's record and then those of the rest of the rings: every vertex once, by the
    // collapse that claims it, from the surface after them all.
    parallel_.for_each(count, [&](size_t j) {
        for (int k = 0; k < 2; ++k)
            if (collapses[j].entry[k] != kNone)
                mesh_.reset_out(collapses[j].apex[k], collapses[j].entry[k]);
    });
    parallel_.for_range(count, [&](size_t begin, size_t end) {
        for (size_t j = begin; j < end; ++j) {
            constexpr size_t kAhead = 4; // the apexes are scattered: their fans fetched ahead
            if (j + 2 * kAhead < end)
                for (uint32_t v : collapses[j + 2 * kAhead].apex)
                    if (v != kNone)
                        __builtin_prefetch(&mesh_.out[v]), __builtin_prefetch(&busy_[v]);
            if (j + kAhead < end)
                for (uint32_t v : collapses[j + kAhead].apex)
                    if (v != kNone) __builtin_prefetch(&mesh_.twin[mesh_.out[v]]);
            for (uint32_t v : collapses[j].apex)
                if (v != kNone && claim_shared(v))
                    refresh_changed(v, false, true), forgive_around(v);
        }
    });
    parallel_.for_each(count, [&](size_t j) {
        if (!collapses[j].ring) return;
        uint32_t ring[2 * kMaxValence + 2];
        const size_t k = mesh_.ring(collapses[j].made, ring, 2 * kMaxValence + 2);
        for (size_t i = 0; i < k; ++i) {
            if (!claim_shared(ring[i])) continue;
            if (ring_refreshes(ring[i])) refresh_changed(ring[i], false, false);
            forgive_around(ring[i]);
        }
    });
}

void Simplifier::forgive_around(uint32_t v) {
    if (!refusal_near_[v]) return;
    refusal_near_[v] = 0;
    // Each triangle of the star once, by its half-edge from v: its two edges at v and the one
    // across. Either half may carry an edge's refusal (a merged edge's halves come from two).
    mesh_.for_each_outgoing(v, [&](uint32_t g) {
        for (const uint32_t e : {g, next(g), prev(g)}) {
            const uint32_t t = mesh_.twin[e];
            if (fail_[e] != 0 || (t != kNone && fail_[t] != 0)) mark_stale(edge_id(e));
        }
    });
}

Simplifier::Check Simplifier::check_collapse(uint32_t h, float weight, CollapsePlan& plan) {
    if (plan_collapse(h, plan, taken_within(h, weight))) {
        // Its key left the retraction out (too costly for every key): if that makes it heavier
        // than the share the pass goes through, it waits for the next pass with its full key
        // (once: the retraction grows a little as the surface coarsens), and always if it makes
        // it heavier than Options::max_weight.
        const float full = float(plan.error + plan.retraction);
        if (waits(h, weight, full)) {
            edge_weight_[h] = full, placed_[h] = kMoved;
            mark_stale(h); // ranked again with that key
            return Check::Waits;
        }
        return Check::Taken;
    }
    // Refused: it is no candidate until a change around it.
    fail_[h] = pass_;
    mark_stale(h);
    fail_at_[h] = fold_hint(h, plan.refused_at);
    if (const uint32_t t = mesh_.twin[h]; t != kNone)
        fail_[t] = fail_[h], fail_at_[t] = fold_hint(t, plan.refused_at);
    return Check::Refused;
}

uint8_t Simplifier::fold_hint(uint32_t h, uint32_t g) const {
    if (g == kNone) return kNoFold;
    const uint32_t v = mesh_.origin[g];
    const uint8_t end = v == mesh_.origin[h] ? 0 : 0x40;
    uint32_t step = 0;
    for (uint32_t e = mesh_.out[v]; e != g; ++step) {
        e = mesh_.twin[prev(e)];
        if (e == kNone || step == 0x3f) return kNoFold;
    }
    return uint8_t(end | step);
}

uint32_t Simplifier::fold_from_hint(uint32_t h, uint8_t hint) const {
    if (hint == kNoFold) return kNone;
    const uint32_t v = hint & 0x40 ? mesh_.dest(h) : mesh_.origin[h];
    uint32_t g = mesh_.out[v];
    for (uint32_t step = hint & 0x3f; step > 0 && g != kNone; --step) g = mesh_.twin[prev(g)];
    return g;
}

} // namespace ddsimp
