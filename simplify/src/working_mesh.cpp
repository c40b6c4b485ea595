#include "working_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace ddsimp::detail {

void WorkingMesh::build(const Surface& s, size_t capacity, const Limits& lim,
                        const std::vector<uint32_t>& order, const std::vector<uint32_t>& rank) {
    limits = lim;
    vertex_count = s.vertex_count();
    stride = 0;
    fields.clear();
    for (const Field& f : s.fields)
        stride += size_t(f.components), fields.emplace_back(f.kind, f.components);
    record = 6 + stride;
    records.assign(record * capacity, 0.0f);
    const bool reorder = !order.empty();
    for (uint32_t v = 0; v < vertex_count; ++v) {
        const size_t u = reorder ? order[v] : v;
        std::copy_n(&s.positions[3 * u], 3, position_of(v));
        float* d = data_of(v);
        for (const Field& f : s.fields)
            for (int c = 0; c < f.components; ++c)
                *d++ = f.values[u * size_t(f.components) + size_t(c)];
    }

    const size_t halfedges = s.triangles.size();
    if (reorder) {
        origin.resize(halfedges);
        for (size_t h = 0; h < halfedges; ++h) origin[h] = rank[s.triangles[h]];
    } else {
        origin.assign(s.triangles.begin(), s.triangles.end());
    }
    twin.assign(halfedges, kNone);
    line.assign(halfedges, 0);
    angle.assign(track_angles ? halfedges : 0, 0.0f);
    for (uint32_t t = 0; t < halfedges / 3; ++t) update_angles(t);
    live_triangles = s.triangle_count();
    kind.assign(capacity, VertexKind::Dead);
    valence.assign(capacity, 0);
    out.assign(capacity, kNone);

    // Outgoing half-edges grouped by origin (counting sort), each with its destination, to find
    // twins without hashing.
    std::vector<uint32_t> first(vertex_count + 1, 0);
    for (uint32_t v : origin) ++first[v + 1];
    std::partial_sum(first.begin(), first.end(), first.begin());
    std::vector<uint32_t> outgoing(halfedges), to(halfedges), fill(first.begin(), first.end() - 1);
    for (uint32_t h = 0; h < halfedges; h += 3) // a triangle's three half-edges
        for (uint32_t c = 0; c < 3; ++c) {
            const uint32_t k = fill[origin[h + c]]++;
            outgoing[k] = h + c, to[k] = origin[h + (c == 2 ? 0 : c + 1)];
        }

    for (uint32_t v = 0; v < vertex_count; ++v)
        if (first[v + 1] > first[v]) kind[v] = VertexKind::Free;

    for (uint32_t h = 0; h < halfedges; ++h) {
        if (twin[h] != kNone) continue; // its twin found it: the same counts from the other side
        const uint32_t a = origin[h], b = dest(h);
        uint32_t same = 0, opposite = 0, candidate = kNone;
        for (uint32_t k = first[a]; k < first[a + 1]; ++k) same += to[k] == b;
        for (uint32_t k = first[b]; k < first[b + 1]; ++k)
            if (to[k] == a) ++opposite, candidate = outgoing[k];
        if (same == 1 && opposite == 1) {
            twin[h] = candidate, twin[candidate] = h;
        } else {
            line[h] = 1;
            if (same + opposite > 1) kind[a] = kind[b] = VertexKind::Complex;
        }
    }

    {
        std::vector<double> sum(3 * vertex_count, 0.0);
        for (uint32_t t = 0; t < live_triangles; ++t) {
            const Vec3 n = triangle_normal(t);
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 3; ++k) sum[3 * size_t(origin[3 * t + c]) + k] += n[k];
        }
        // Vertex normals of sampled surfaces (marching-cubes staircases, slivers) are noisy;
        // a few rounds of averaging with the neighbours give the surface's broad direction.
        std::vector<double> smoothed(sum.size());
        for (int round = 0; round < kReferenceSmoothing; ++round) {
            for (size_t v = 0; v < vertex_count; ++v) {
                const double l =
                    std::sqrt(sum[3 * v] * sum[3 * v] + sum[3 * v + 1] * sum[3 * v + 1] +
                              sum[3 * v + 2] * sum[3 * v + 2]);
                for (int k = 0; k < 3; ++k) sum[3 * v + k] = l > 0 ? sum[3 * v + k] / l : 0;
            }
            smoothed = sum;
            for (size_t h = 0; h < halfedges; h += 3) // each edge direction once per half-edge
                for (size_t c = 0; c < 3; ++c) {
                    double* to_origin = &smoothed[3 * size_t(origin[h + c])];
                    const double* at_dest = &sum[3 * size_t(origin[h + (c == 2 ? 0 : c + 1)])];
                    for (int k = 0; k < 3; ++k) to_origin[k] += at_dest[k];
                }
            sum.swap(smoothed);
        }
        for (size_t v = 0; v < vertex_count; ++v) {
            const double l = std::sqrt(sum[3 * v] * sum[3 * v] + sum[3 * v + 1] * sum[3 * v + 1] +
                                       sum[3 * v + 2] * sum[3 * v + 2]);
            if (l > 0)
                for (int k = 0; k < 3; ++k)
                    reference_of(uint32_t(v))[k] = float(sum[3 * v + k] / l);
        }
    }

    // Feature edges from the dihedral angle between twin triangles (none when the limit is
    // below every cosine: feature angle 180, the default), and folds of the input (see
    // kFoldCos): their vertices are locked. Each edge once, its normals computed there rather
    // than kept for every triangle (which would raise the peak memory).
    auto unit_normal = [&](uint32_t t) {
        const Vec3 n = triangle_normal(t);
        const double len = norm(n);
        return len > 0 ? scale(n, 1.0 / len) : Vec3{0, 0, 0};
    };
    for (uint32_t h = 0; h < halfedges; ++h) {
        const uint32_t t = twin[h];
        if (t == kNone || t < h) continue;
        const Vec3 n0 = unit_normal(h / 3), n1 = unit_normal(t / 3);
        if (dot(n0, n0) > 0 && dot(n1, n1) > 0 && dot(n0, n1) < limits.feature_cos)
            line[h] = line[t] = 1;
        if (dot(n0, n1) < kFoldCos) {
            if (locked.empty()) locked.assign(capacity, 0);
            locked[origin[h]] = locked[dest(h)] = 1;
        }
    }

    // Each vertex's fan must cover all its triangles and have at most one boundary gap.
    for (uint32_t v = 0; v < vertex_count; ++v) {
        if (kind[v] == VertexKind::Dead) continue;
        uint32_t open = 0, start = outgoing[first[v]];
        for (uint32_t k = first[v]; k < first[v + 1]; ++k)
            if (twin[outgoing[k]] == kNone) ++open, start = outgoing[k];
        out[v] = start;
        if (kind[v] == VertexKind::Complex) continue;
        size_t fan = 0;
        for_each_outgoing(v, [&](uint32_t) { ++fan; });
        if (open > 1 || fan != first[v + 1] - first[v]) kind[v] = VertexKind::Complex;
    }
    for (uint32_t v = 0; v < vertex_count; ++v) classify(v);
}

Vec3 WorkingMesh::triangle_normal(uint32_t t) const {
    const Vec3 a = point(origin[3 * t]), b = point(origin[3 * t + 1]), c = point(origin[3 * t + 2]);
    return cross(sub(b, a), sub(c, a));
}

namespace {

// atan2(y, x) for y >= 0: the angle in [0, pi] of a corner from the length of the cross product
// and the dot product of its two edges. Cephes' atanf reduction and polynomial, in double: within
// 1e-8 of the exact angle (finer than the float it is stored in), several times cheaper than
// the library's atan2f, and the same on every machine.
double corner_angle(double y, double x) {
    constexpr double pi = std::numbers::pi;
    const double ax = std::abs(x);
    if (y == 0 && ax == 0) return 0;
    double t, base;                 // atan(y / ax) = base + atan(t), |t| <= tan(pi / 8)
    if (y > 2.414213562373095 * ax) // beyond tan(3 pi / 8)
        t = -ax / y, base = pi / 2;
    else if (y > 0.4142135623730950 * ax) // beyond tan(pi / 8)
        t = (y - ax) / (y + ax), base = pi / 4;
    else
        t = y / ax, base = 0;
    const double z = t * t;
    const double a = base + t +
                     t * z *
                         (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z -
                          3.33329491539e-1);
    return x >= 0 ? a : pi - a;
}

} // namespace

void WorkingMesh::update_angles(uint32_t t) {
    if (!track_angles) return;
    const Vec3 p[3] = {point(origin[3 * t]), point(origin[3 * t + 1]), point(origin[3 * t + 2])};
    for (int c = 0; c < 3; ++c) {
        const Vec3 a = sub(p[(c + 1) % 3], p[c]), b = sub(p[(c + 2) % 3], p[c]);
        angle[3 * t + c] = float(corner_angle(norm(cross(a, b)), dot(a, b)));
    }
}

void WorkingMesh::reset_out(uint32_t v, uint32_t h) {
    const uint32_t start = h;
    for (;;) {
        const uint32_t t = twin[h];
        if (t == kNone) break;
        h = next(t);
        if (h == start) break;
    }
    out[v] = h;
}

void WorkingMesh::blend_data(uint32_t a, uint32_t b, double along, uint32_t n) {
    const float *da = data_of(a), *db = data_of(b);
    float* dn = data_of(n); // may be da: each component is read before it is written
    for (const auto& [kind, components] : fields) {
        const size_t nc = size_t(components);
        for (size_t c = 0; c < nc; ++c)
            dn[c] = kind == FieldKind::Label
                        ? (along <= 0.5 ? da[c] : db[c])
                        : float((1 - along) * double(da[c]) + along * double(db[c]));
        if (kind == FieldKind::Direction) {
            double length = 0;
            for (size_t c = 0; c < nc; ++c) length += double(dn[c]) * dn[c];
            length = std::sqrt(length);
            for (size_t c = 0; c < nc && length > 0; ++c) dn[c] = float(dn[c] / length);
        }
        da += nc, db += nc, dn += nc;
    }
}

double WorkingMesh::curvature(uint32_t v) const {
    if (kind[v] == VertexKind::Complex || kind[v] == VertexKind::Dead) return 0;
    double angles = 0;
    for_each_outgoing(v, [&](uint32_t h) { angles += angle[h]; });
    const double full = is_boundary_vertex(v) ? std::numbers::pi : 2 * std::numbers::pi;
    return std::abs(full - angles) / std::numbers::pi;
}

} // namespace ddsimp::detail

namespace ddsimp::detail {

size_t WorkingMesh::ring(uint32_t v, uint32_t* ids, size_t max) const {
    size_t count = 0;
    const uint32_t start = out[v];
    uint32_t h = start;
    while (!ring_step(h, start, ids, count, max)) continue;
    return count;
}

void WorkingMesh::rings(const uint32_t* vs, size_t k, uint32_t* ids, size_t max,
                        size_t* counts) const {
    uint32_t at[64], start[64];
    uint64_t walking = 0;
    for (size_t i = 0; i < k; ++i)
        start[i] = at[i] = out[vs[i]], counts[i] = 0, walking |= uint64_t(1) << i;
    while (walking != 0)
        for (uint64_t w = walking; w != 0; w &= w - 1) {
            const size_t i = size_t(__builtin_ctzll(w));
            if (ring_step(at[i], start[i], ids + i * max, counts[i], max))
                walking &= ~(uint64_t(1) << i);
        }
}

} // namespace ddsimp::detail
