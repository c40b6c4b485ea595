#include "simplifier.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <thread>

namespace ddsimp {

using detail::kNone;
using detail::VertexKind;

namespace {

detail::Limits limits_from(const Options& o) {
    auto cosine = [](double degrees) { return std::cos(degrees * std::numbers::pi / 180.0); };
    detail::Limits limits;
    limits.feature_cos = o.feature_angle >= 180 ? -2.0 : cosine(o.feature_angle);
    limits.straight_cos = cosine(o.line_tolerance);
    limits.normal_turn_cos = cosine(o.max_normal_turn);
    return limits;
}

// Runs f(begin, end) over [0, n) on `threads` threads; each index is touched by one thread only.
template <class F> void parallel_for(size_t n, int threads, F&& f) {
    if (threads <= 1 || n < 4096) return f(size_t(0), n);
    std::vector<std::thread> pool;
    const size_t chunk = (n + size_t(threads) - 1) / size_t(threads);
    for (size_t begin = 0; begin < n; begin += chunk)
        pool.emplace_back([&, begin] { f(begin, std::min(n, begin + chunk)); });
    for (std::thread& t : pool) t.join();
}

// Vertices renumbered in the order the triangles first use them: a mesher writes triangles in
// spatial order, so a fan's vertices then sit close together in memory. Unused vertices go last.
// Returns the input id of each internal id.
std::vector<uint32_t> locality_order(const Surface& s) {
    const uint32_t n = uint32_t(s.vertex_count());
    std::vector<uint32_t> order, rank(n, kNone);
    order.reserve(n);
    for (uint32_t v : s.triangles)
        if (rank[v] == kNone) rank[v] = uint32_t(order.size()), order.push_back(v);
    for (uint32_t v = 0; v < n; ++v)
        if (rank[v] == kNone) order.push_back(v);
    return order;
}

} // namespace

Simplifier::Simplifier(const Surface& surface, const Options& options, const RepairReport& repairs)
    : options_(options), input_(surface) {
    check_options(options);
    if (!options.locked.empty() && options.locked.size() != surface.vertex_count())
        throw InputError("invalid option: locked has " + std::to_string(options.locked.size()) +
                         " entries, but the surface has " + std::to_string(surface.vertex_count()) +
                         " vertices");
    gradient_.setup(surface, options.gradient_fields);
    // A collapse puts its new vertex in the slot of one of its ends, so the live vertices stay
    // where the locality order put them and the capacity is the input's.
    const size_t capacity = surface.vertex_count();
    id_ = locality_order(surface);
    rank_.assign(capacity, kNone);
    for (uint32_t v = 0; v < capacity; ++v) rank_[id_[v]] = v;
    if (!options.locked.empty()) { // before build: its classification reads the locks
        mesh_.locked.assign(capacity, 0);
        for (uint32_t v = 0; v < capacity; ++v) mesh_.locked[rank_[v]] = options.locked[v] != 0;
    }
    mesh_.track_angles = options.terms == Terms::AngleDeficitGradient; // for the curvature
    mesh_.build(surface, capacity, limits_from(options), id_, rank_);  // in locality order
    const bool collapse = options.strategy == Strategy::EdgeCollapse;
    // Edge collapse's ids are half-edges, vertex removal's vertices.
    const size_t ids = collapse ? surface.triangles.size() : capacity;
    fail_.assign(ids, 0);
    listed_.assign(ids, 0);
    raised_.assign(ids, 0);
    epoch_.assign(capacity, 0);
    busy_.assign(capacity, 0);
    rekey_.assign(capacity, 0);
    if (collapse) {
        fail_at_.assign(surface.triangles.size(), kNone);
        seen_.assign(capacity, 0);
    }

    record_.strategy_ = options.strategy;
    record_.base_triangles_ = surface.triangles;
    record_.triangles_in_ = surface.triangle_count();
    record_.input_vertices_ = surface.vertex_count();
    record_.repairs_ = repairs;
    if (options.strategy == Strategy::VertexRemoval) {
        record_.write_begin_.push_back(0);
        ring_at_.assign(capacity, kNotInRing);
    }

    const size_t n = surface.vertex_count();
    for (uint32_t v = 0; v < n; ++v) vertices_in_use_ += mesh_.kind[v] != VertexKind::Dead;
    quadric_terms_ = options.terms == Terms::ErrorQuadrics;
    least_error_ =
        options.strategy == Strategy::EdgeCollapse && options.placement == Placement::LeastError;
    if (quadric_terms_ || least_error_)
        quadrics_.setup(mesh_, gradient_, geometry_weight(), 1 - options.alpha, capacity);
    weight_.assign(capacity, 0);
    // The paper's terms, then their means over the vertices that can take part.
    std::vector<double> curvature(quadric_terms_ ? 0 : n), gradient(quadric_terms_ ? 0 : n);
    if (!quadric_terms_)
        parallel_for(n, options.threads, [&](size_t begin, size_t end) {
            for (size_t v = begin; v < end; ++v) {
                curvature[v] = mesh_.curvature(uint32_t(v));
                gradient[v] = gradient_.at(mesh_, uint32_t(v));
            }
        });
    double sum_c = 0, sum_g = 0;
    size_t counted = 0;
    for (uint32_t i = 0; i < n && !quadric_terms_; ++i) { // in input order: the same sums as
        const uint32_t v = rank_[i];                      // without the reorder
        if (mesh_.kind[v] != VertexKind::Complex && mesh_.kind[v] != VertexKind::Dead)
            sum_c += curvature[v], sum_g += gradient[v], ++counted;
    }
    curvature_scale_ = sum_c > 0 ? double(counted) / sum_c : 0;
    gradient_scale_ = sum_g > 0 ? double(counted) / sum_g : 0;
    for (uint32_t v = 0; v < n && !quadric_terms_; ++v)
        weight_[v] = float(options.alpha * curvature[v] * curvature_scale_ +
                           (1 - options.alpha) * gradient[v] * gradient_scale_);
    if (collapse) {
        length_.resize(surface.triangles.size());
        for (uint32_t h = 0; h < surface.triangles.size(); ++h) {
            const uint32_t t = mesh_.twin[h];
            if (t == kNone || h < t) {
                update_length(h);
                pool_.push_back({h, kNever, {}}), listed_[h] = 1;
            } else {
                length_[h] = length_[t]; // the same edge's length, the same bits
            }
        }
    } else {
        shortest_.assign(capacity, 0);
        for (uint32_t v = 0; v < n; ++v)
            if (mesh_.kind[v] != VertexKind::Dead)
                key_removal(v), pool_.push_back({v, kNever, {}}), listed_[v] = 1;
    }
}

void Simplifier::refresh_vertex(uint32_t v) {
    // One fan walk: kind, valence, angle sum, steepest neighbour and, for vertex removal, the
    // shortest edge (the key's tie-break). Same values as classify, the constructor's weights
    // and key_removal.
    // With the error quadrics, a vertex removal's weight is its estimated error (removal_error),
    // and an edge's comes from its ends' quadrics (collapse_key).
    detail::GradientTerms::Steepest steepest(gradient_, mesh_, v);
    const bool removal = options_.strategy == Strategy::VertexRemoval;
    const bool ring_error = removal && quadric_terms_;
    const detail::Vec3 p = mesh_.point(v);
    double shortest = INFINITY;
    uint32_t ring[kMaxValence];
    size_t ring_size = 0;
    const double angles = mesh_.classify(v, [&](uint32_t u, bool closing) {
        if (ring_error) {
            if (ring_size < kMaxValence) ring[ring_size] = u;
            ++ring_size;
        } else if (!quadric_terms_)
            steepest.consider(u);
        if (removal && !closing)
            shortest = std::min(shortest, detail::norm(detail::sub(mesh_.point(u), p)));
    });
    const VertexKind k = mesh_.kind[v];
    const bool counted = k != VertexKind::Complex && k != VertexKind::Dead;
    if (quadric_terms_)
        weight_[v] = ring_error && (k == VertexKind::Free || k == VertexKind::Line)
                         ? float(removal_error(v, ring, ring_size))
                         : 0.0f;
    else
        weight_[v] =
            float(options_.alpha * mesh_.curvature_from(v, angles) * curvature_scale_ +
                  (1 - options_.alpha) * (counted ? steepest.value() : 0.0) * gradient_scale_);
    if (removal) {
        shortest_[v] = float(shortest);
        raised_[v] = 0; // its key is an estimate again
    }
}

// After an operation: `changed` vertices have new neighbourhoods. Their kinds and weights are
// recomputed at once (a weight reads only the vertex's star and its neighbours, so no other
// weight changed), and the rest of the pass leaves them alone. changed[0] is a collapse's new
// vertex: its edges are new and join the pool.
void Simplifier::refresh_around(const uint32_t* changed, size_t count, size_t kept_from) {
    const uint32_t epoch = uint32_t(operations_ + 1);
    // With the error quadrics, an edge's key reads only its ends' quadrics, positions, data and
    // kinds (and, for the volume-preserving point, their stars). A collapse changes these for the
    // new vertex, changed[0], and at most the kinds of the others: their edges keep their keys
    // unless their kind changed. A kind can change only at the apexes (they lost a neighbour and
    // may have merged line flags), changed[1..kept_from), and at ring vertices on a line; a Free
    // vertex from kept_from on keeps its kind and valence (and weight_ is not used).
    const bool collapse_quadrics = quadric_terms_ && options_.strategy == Strategy::EdgeCollapse;
    const bool star_keys = options_.placement == Placement::VolumePreserving;
    for (size_t i = 0; i < count; ++i) {
        const uint32_t v = changed[i];
        epoch_[v] = epoch;
        busy_[v] = pass_;
        const VertexKind kind = mesh_.kind[v];
        if (!collapse_quadrics || i < kept_from || kind != VertexKind::Free) refresh_vertex(v);
        if (!collapse_quadrics || i == 0 || mesh_.kind[v] != kind || star_keys) rekey_[v] = pass_;
    }
    if (options_.strategy != Strategy::EdgeCollapse) return;
    const uint32_t n = changed[0];
    mesh_.for_each_edge(n, [&](uint32_t h, uint32_t, bool) {
        const uint32_t t = mesh_.twin[h];
        const uint32_t id = t != kNone && t < h ? t : h;
        if (!listed_[id]) listed_[id] = 1, born_.push_back(id);
    });
}

double Simplifier::geometry_weight() const {
    return std::max(options_.alpha, kMinGeometryWeight);
}

double Simplifier::retraction_scale() const {
    if (!quadric_terms_) return 0;
    // Each input triangle's plane is in the quadrics of its three corners; an operation removes
    // one vertex.
    const double live = std::max(1.0, double(vertices_in_use_) - double(operations_));
    return geometry_weight() * 3 * quadrics_.area / live * quadrics_.inv_diagonal *
           quadrics_.inv_diagonal;
}

void Simplifier::rank_candidates(size_t& share) {
    const bool collapse = options_.strategy == Strategy::EdgeCollapse;
    // The pool without what died, merged with what was born, in id order; every candidate with
    // its key, in the same order. A key is computed again only if an end's star changed since
    // (nothing else it reads can change), so a pass costs a sweep, not a key per candidate.
    if (!born_.empty()) {
        std::sort(born_.begin(), born_.end());
        const size_t old = pool_.size();
        for (uint32_t id : born_) pool_.push_back({id, kNever, {}});
        std::inplace_merge(pool_.begin(), pool_.begin() + std::ptrdiff_t(old), pool_.end(),
                           [](const Member& a, const Member& b) { return a.id < b.id; });
        born_.clear();
    }
    scratch_.clear();
    // Edge collapse's keys (placing the new point: most of its work) may be computed on several
    // threads, after the sweep; a key reads the surface and writes only its own member, so the
    // keys are the same whatever the thread count. Vertex removal's are at hand.
    const bool threaded = collapse && options_.threads > 1;
    auto rekey = [&](Member& m, uint32_t id) {
        m.key = collapse ? collapse_key(id) : removal_key(id), m.keyed = pass_;
        if (collapse) raised_[id] = 0;
    };
    auto add_candidate = [&](const Member& m, size_t i) {
        if (!std::isinf(m.key.weight))
            scratch_.push_back(detail::Candidate::make(m.key, uint32_t(i)));
    };
    // On one thread a stale key is computed kKeysAhead candidates after the sweep lists it, its
    // memory fetched meanwhile (prefetch_key), while what the sweep read for it is still at hand;
    // the candidates still join in pool order.
    uint32_t ahead[kKeysAhead];
    size_t queued = 0, keyed = 0;
    auto key_and_add = [&](uint32_t i) {
        if (pool_[i].keyed == kStale) rekey(pool_[i], pool_[i].id);
        add_candidate(pool_[i], i);
    };
    size_t kept = 0;
    for (const Member& member : pool_) {
        const uint32_t id = member.id;
        const uint32_t a = collapse ? mesh_.origin[id] : id;
        const bool live = collapse ? a != kNone && (mesh_.twin[id] == kNone || id < mesh_.twin[id])
                                   : mesh_.kind[id] != VertexKind::Dead;
        if (!live) {
            listed_[id] = 0;
            continue;
        }
        Member& m = pool_[kept++];
        m = member;
        const uint32_t b = collapse ? mesh_.dest(id) : kNone;
        if (collapse ? !collapsible(id, a, b) : !removable(id)) continue;
        const uint32_t changed = std::max(rekey_[a], collapse ? rekey_[b] : uint32_t(0));
        if (m.keyed == kNever || changed > m.keyed) m.keyed = kStale;
        if (threaded) {
            candidates_.push_back(uint32_t(kept - 1));
            continue;
        }
        if (collapse && m.keyed == kStale) prefetch_key(a, b);
        ahead[queued++ % kKeysAhead] = uint32_t(kept - 1);
        if (queued - keyed == kKeysAhead) key_and_add(ahead[keyed++ % kKeysAhead]);
    }
    while (keyed < queued) key_and_add(ahead[keyed++ % kKeysAhead]);
    pool_.resize(kept);
    if (threaded) {
        parallel_for(candidates_.size(), options_.threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i)
                if (Member& m = pool_[candidates_[i]]; m.keyed == kStale) rekey(m, m.id);
        });
        for (const uint32_t i : candidates_) add_candidate(pool_[i], i);
        candidates_.clear();
    }
    share = scratch_.empty()
                ? 0
                : std::max<size_t>(1, size_t(std::ceil(kPassShare * double(scratch_.size()))));
    detail::lightest_sorted(scratch_, share, order_);
}

void Simplifier::prefetch_collapses_after(size_t i, size_t share) const {
    if (i + 16 < share) __builtin_prefetch(&pool_[order_[i + 16].id]);
    if (i + 8 < share) {
        const uint32_t h = pool_[order_[i + 8].id].id;
        __builtin_prefetch(&mesh_.origin[h]), __builtin_prefetch(&mesh_.twin[h]);
    }
    if (i + 4 >= share) return;
    const uint32_t h = pool_[order_[i + 4].id].id, a = mesh_.origin[h];
    if (a == kNone) return;
    for (const uint32_t v : {a, mesh_.dest(h)}) {
        __builtin_prefetch(&busy_[v]), __builtin_prefetch(&mesh_.out[v]);
        __builtin_prefetch(mesh_.position_of(v));
    }
}

bool Simplifier::waits(uint32_t id, float key, float planned) {
    if ((planned > std::max(key, share_limit_) && !raised_[id]) || planned > options_.max_weight)
        return raised_[id] = 1, true;
    return false;
}

bool Simplifier::report_progress(size_t live, size_t target) {
    if (!options_.progress || operations_ % 1024 != 0) return true;
    const double total = double(record_.triangles_in_ - std::min(target, record_.triangles_in_));
    const double done = double(record_.triangles_in_ - live);
    return options_.progress(total > 0 ? std::min(1.0, done / total) : 1.0);
}

ProgressiveRecord Simplifier::run() {
    const size_t target = target_triangles(options_, record_.triangles_in_);
    // Pass after pass: rank every candidate by its key on the current surface, then go through
    // the lightest share of them in that order. A candidate next to an operation of this pass
    // waits for the next pass, where it is ranked again with its new key. Nothing here depends on
    // the target, so a run to any target performs a prefix of the same operations.
    const auto run_passes = [&]() {
        for (;;) {
            if (mesh_.live_triangles <= target) return StopReason::TargetReached;
            size_t share = 0;
            rank_candidates(share);
            if (share == 0) {
                // Edge collapse's last resort: a triangle need only face along its corners'
                // reference normals together, and every refused edge is tried again.
                if (options_.strategy != Strategy::EdgeCollapse || relaxed_facing_)
                    return StopReason::NothingRemovable;
                relaxed_facing_ = true;
                std::fill(fail_.begin(), fail_.end(), 0);
                std::fill(fail_at_.begin(), fail_at_.end(), kNone);
                continue;
            }
            if (order_.front().weight() > options_.max_weight) return StopReason::WeightBound;
            share_limit_ = order_[share - 1].weight();
            if (options_.strategy == Strategy::EdgeCollapse)
                detail::runs_in_id_order(order_, share, kPassRuns, scratch_);
            ++pass_;
            for (size_t i = 0; i < share; ++i) {
                const detail::Candidate c = order_[i];
                if (options_.strategy == Strategy::EdgeCollapse) // no gain measured for removal
                    prefetch_collapses_after(i, share);
                if (c.weight() > options_.max_weight) continue; // heavier ones may follow
                const size_t before = operations_;
                if (options_.strategy == Strategy::EdgeCollapse)
                    step_collapse(pool_[c.id]);
                else
                    step_removal(pool_[c.id].id);
                if (operations_ == before) continue;
                record_.triangles_after_.push_back(uint32_t(mesh_.live_triangles));
                if (!report_progress(mesh_.live_triangles, target)) return StopReason::Cancelled;
                if (mesh_.live_triangles <= target) return StopReason::TargetReached;
            }
        }
    };
    record_.stop_ = run_passes();
    if (options_.progress && record_.stop_ != StopReason::Cancelled) options_.progress(1.0);

    // Hand the vertices (the input's, then those the collapses made) to the record.
    const size_t made = 3 + mesh_.stride;
    const size_t ni = input_.vertex_count(), nv = ni + made_.size() / made;
    Surface& vertices = record_.vertices_;
    vertices.positions.resize(3 * nv);
    std::copy(input_.positions.begin(), input_.positions.end(), vertices.positions.begin());
    for (size_t v = ni; v < nv; ++v)
        std::copy_n(&made_[(v - ni) * made], 3, &vertices.positions[3 * v]);
    size_t offset = 3;
    for (const Field& in : input_.fields) {
        Field f{in.name, in.components, {}};
        const size_t nc = size_t(f.components);
        f.values.resize(nv * nc);
        std::copy(in.values.begin(), in.values.end(), f.values.begin());
        for (size_t v = ni; v < nv; ++v)
            std::copy_n(&made_[(v - ni) * made + offset], nc, &f.values[v * nc]);
        offset += nc;
        vertices.fields.push_back(std::move(f));
    }
    return std::move(record_);
}

Result simplify(const Surface& input, const Options& options) {
    const ProgressiveRecord record = ProgressiveRecord::run(input, options, false);
    Result result;
    result.surface = record.after(record.operations());
    result.triangles_in = record.triangles_in();
    result.triangles_out = result.surface.triangle_count();
    result.operations = record.operations();
    result.stop = record.stop();
    result.target_reached = record.stop() == StopReason::TargetReached;
    result.repairs = record.repairs();
    return result;
}

} // namespace ddsimp
