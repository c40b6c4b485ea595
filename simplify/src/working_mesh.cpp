#include "working_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace ddsimp::detail {

void WorkingMesh::build(const Surface& s, size_t capacity, const Limits& lim,
                        const std::vector<uint32_t>& order, const std::vector<uint32_t>& rank,
                        Parallel* threads) {
    Parallel one(1);
    Parallel& parallel = threads ? *threads : one;
    limits = lim;
    vertex_count = s.vertex_count();
    stride = 0;
    fields.clear();
    for (const Field& f : s.fields)
        stride += size_t(f.components), fields.emplace_back(f.kind, f.components);
    record = 6 + stride;
    assign_on_threads(records, record * capacity, 0.0f, parallel);
    const bool reorder = !order.empty();
    parallel.for_each(vertex_count, [&](size_t v) {
        const size_t u = reorder ? order[v] : v;
        std::copy_n(&s.positions[3 * u], 3, position_of(uint32_t(v)));
        float* d = data_of(uint32_t(v));
        for (const Field& f : s.fields)
            for (int c = 0; c < f.components; ++c)
                *d++ = f.values[u * size_t(f.components) + size_t(c)];
    });

    const size_t halfedges = s.triangles.size();
    if (reorder) {
        assign_on_threads(origin, halfedges, kNone, parallel);
        parallel.for_each(halfedges, [&](size_t h) { origin[h] = rank[s.triangles[h]]; });
    } else {
        origin.assign(s.triangles.begin(), s.triangles.end());
    }
    // Once a watch on the threads stops a loop (stage_watch.h), the serial steps between the
    // loops would read what it left undone: the build ends there.
    if (parallel.stopped()) return;
    if (limits.straight_cos < 1 && halfedges > 0) { // a line tolerance: Limits::zigzag
        // The input's mean edge length (each half-edge once), summed in blocks of triangles
        // fixed by the surface, so that the bits do not depend on the threads.
        constexpr size_t kBlock = 1 << 14;
        const size_t triangles = halfedges / 3, blocks = (triangles + kBlock - 1) / kBlock;
        std::vector<double> part(blocks, 0.0);
        parallel.for_each(
            blocks,
            [&](size_t b) {
                double sum = 0;
                for (size_t h = 3 * b * kBlock; h < 3 * std::min(triangles, (b + 1) * kBlock); ++h)
                    sum += norm(sub(point(dest(uint32_t(h))), point(origin[h])));
                part[b] = sum;
            },
            1);
        double sum = 0;
        for (double p : part) sum += p;
        limits.zigzag = kZigzagShare * sum / double(halfedges);
    }
    assign_on_threads(twin, halfedges, kNone, parallel);
    assign_on_threads(line, halfedges, 0, parallel);
    assign_on_threads(angle, track_angles ? halfedges : 0, 0.0f, parallel);
    parallel.for_each(halfedges / 3, [&](size_t t) { update_angles(uint32_t(t)); });
    live_triangles = s.triangle_count();
    assign_on_threads(kind, capacity, VertexKind::Dead, parallel);
    assign_on_threads(valence, capacity, 0, parallel);
    assign_on_threads(out, capacity, kNone, parallel);

    // Outgoing half-edges grouped by origin (counting sort), each with its destination, to find
    // twins without hashing. Each vertex's group is in half-edge order, so a sum over it adds in
    // the order of a loop over the triangles: gathering per vertex on the threads gives the bits
    // of that loop.
    Array<uint32_t> first(vertex_count + 1, 0);
    for (uint32_t v : origin) ++first[v + 1];
    std::partial_sum(first.begin(), first.end(), first.begin());
    if (!parallel.check()) return;
    Array<uint32_t> outgoing(halfedges), to(halfedges);
    Array<uint32_t> fill(first.begin(), first.end() - 1);
    constexpr uint32_t kHalfedgesPerCheck = 3 << 16; // a few milliseconds of the serial sort
    for (uint32_t h = 0; h < halfedges; h += 3) {    // a triangle's three half-edges
        if (h % kHalfedgesPerCheck == kHalfedgesPerCheck - 3 && !parallel.check()) return;
        for (uint32_t c = 0; c < 3; ++c) {
            const uint32_t k = fill[origin[h + c]]++;
            outgoing[k] = h + c, to[k] = origin[h + (c == 2 ? 0 : c + 1)];
        }
    }
    Array<uint32_t>().swap(fill);

    for (uint32_t v = 0; v < vertex_count; ++v)
        if (first[v + 1] > first[v]) kind[v] = VertexKind::Free;

    // A half-edge's twin is the one half-edge back along its edge, if the edge has exactly one
    // each way; otherwise it is a line, and an edge with more than two half-edges makes its ends
    // Complex (marked after the loop, as several edges may share an end).
    constexpr uint8_t kCrowded = 2; // in line[h] until the ends are marked
    parallel.for_each(halfedges, [&](size_t h) {
        const uint32_t a = origin[h], b = dest(uint32_t(h));
        uint32_t same = 0, opposite = 0, candidate = kNone;
        for (uint32_t k = first[a]; k < first[a + 1]; ++k) same += to[k] == b;
        for (uint32_t k = first[b]; k < first[b + 1]; ++k)
            if (to[k] == a) ++opposite, candidate = outgoing[k];
        if (same == 1 && opposite == 1)
            twin[h] = candidate;
        else
            line[h] = same + opposite > 1 ? 1 | kCrowded : 1;
    });
    if (parallel.stopped()) return;
    for (uint32_t h = 0; h < halfedges; ++h)
        if (line[h] & kCrowded) line[h] = 1, kind[origin[h]] = kind[dest(h)] = VertexKind::Complex;

    {
        Array<double> sum(3 * vertex_count, 0.0);
        parallel.for_each(vertex_count, [&](size_t v) {
            for (uint32_t k = first[v]; k < first[v + 1]; ++k) {
                const Vec3 n = triangle_normal(outgoing[k] / 3);
                for (int i = 0; i < 3; ++i) sum[3 * v + i] += n[i];
            }
        });
        // Vertex normals of sampled surfaces (marching-cubes staircases, slivers) are noisy;
        // a few rounds of averaging with the neighbours give the surface's broad direction.
        auto unit = [&](double* n) {
            const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int k = 0; k < 3; ++k) n[k] = l > 0 ? n[k] / l : 0;
        };
        Array<double> smoothed(sum.size());
        for (int round = 0; round < kReferenceSmoothing; ++round) {
            parallel.for_each(vertex_count, [&](size_t v) { unit(&sum[3 * v]); });
            parallel.for_each(vertex_count, [&](size_t v) { // each edge direction once per
                double* n = &smoothed[3 * v];               // half-edge
                for (int i = 0; i < 3; ++i) n[i] = sum[3 * v + i];
                for (uint32_t k = first[v]; k < first[v + 1]; ++k)
                    for (int i = 0; i < 3; ++i) n[i] += sum[3 * size_t(to[k]) + i];
            });
            sum.swap(smoothed);
        }
        parallel.for_each(vertex_count, [&](size_t v) {
            const double l = std::sqrt(sum[3 * v] * sum[3 * v] + sum[3 * v + 1] * sum[3 * v + 1] +
                                       sum[3 * v + 2] * sum[3 * v + 2]);
            if (l > 0)
                for (int k = 0; k < 3; ++k)
                    reference_of(uint32_t(v))[k] = float(sum[3 * v + k] / l);
        });
    }

    // Feature edges from the dihedral angle between twin triangles (none when the limit is
    // below every cosine: feature angle 180, the default), and folds of the input (see
    // kFoldCos): their vertices are locked (after the loop, as several folds may share one).
    // Each edge once, its normals computed there rather than kept for every triangle (which
    // would raise the peak memory).
    auto unit_normal = [&](uint32_t t) {
        const Vec3 n = triangle_normal(t);
        const double len = norm(n);
        return len > 0 ? scale(n, 1.0 / len) : Vec3{0, 0, 0};
    };
    constexpr uint8_t kFold = 2; // in line[h] until its ends are locked
    parallel.for_each(halfedges, [&](size_t h) {
        const uint32_t t = twin[h];
        if (t == kNone || t < h) return;
        const Vec3 n0 = unit_normal(uint32_t(h / 3)), n1 = unit_normal(t / 3);
        if (dot(n0, n0) > 0 && dot(n1, n1) > 0 && dot(n0, n1) < limits.feature_cos)
            line[h] = line[t] = 1;
        if (dot(n0, n1) < kFoldCos) line[h] |= kFold;
    });
    if (parallel.stopped()) return;
    for (uint32_t h = 0; h < halfedges; ++h) {
        if (!(line[h] & kFold)) continue;
        line[h] &= ~kFold;
        if (locked.empty()) locked.assign(capacity, 0);
        locked[origin[h]] = locked[dest(h)] = 1;
    }

    // Each vertex's fan must cover all its triangles and have at most one boundary gap.
    parallel.for_each(vertex_count, [&](size_t v) {
        if (kind[v] == VertexKind::Dead) return;
        uint32_t open = 0, start = outgoing[first[v]];
        for (uint32_t k = first[v]; k < first[v + 1]; ++k)
            if (twin[outgoing[k]] == kNone) ++open, start = outgoing[k];
        out[v] = start;
        if (kind[v] == VertexKind::Complex) return;
        size_t fan = 0;
        for_each_outgoing(uint32_t(v), [&](uint32_t) { ++fan; });
        if (open > 1 || fan != first[v + 1] - first[v]) kind[v] = VertexKind::Complex;
    });
    if (limits.zigzag > 0) {
        assign_on_threads(zigzag, capacity, 0, parallel);
        parallel.for_each(vertex_count, [&](size_t v) {
            if (kind[v] == VertexKind::Dead || kind[v] == VertexKind::Complex) return;
            uint32_t ends[2];
            if (line_neighbours(uint32_t(v), ends) == 2)
                zigzag[v] = turns_back(uint32_t(v), ends[0], ends[1]);
        });
    }
    parallel.for_each(vertex_count, [&](size_t v) { classify(uint32_t(v)); });
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
    if (kind[v] == VertexKind::Free) return void(out[v] = h);
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

bool WorkingMesh::turns_back(uint32_t v, uint32_t a, uint32_t b) const {
    const Vec3 p = point(v);
    const float* r = reference_of(v);
    const Vec3 normal{r[0], r[1], r[2]};
    // The turn from x to y to z: > 0 to the left of the normal, < 0 to the right.
    auto turn = [&](const Vec3& x, const Vec3& y, const Vec3& z) {
        return dot(cross(sub(y, x), sub(z, y)), normal);
    };
    const double here = turn(point(a), p, point(b));
    // The line's next vertex beyond `end` (away from v), if end is on one line only.
    auto beyond = [&](uint32_t end) {
        uint32_t ends[2];
        if (line_neighbours(end, ends) != 2) return kNone;
        return ends[1] != v ? ends[1] : ends[0] != v ? ends[0] : kNone; // both v: a sliver
    };
    const uint32_t before = beyond(a), after = beyond(b);
    return (before != kNone && turn(point(before), point(a), p) * here < 0) ||
           (after != kNone && turn(p, point(b), point(after)) * here < 0);
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
