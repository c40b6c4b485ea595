#include "simplifier.h"

#include "data_flips.h"
#include "pass_counts.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>

namespace ddsimp {

using detail::kNone;
using detail::VertexKind;

namespace {

// The share of simplify()'s work the run does before the level's fit, for the progress it
// reports: about what the run takes on the benchmark surfaces (bench/README.md).
constexpr double kRunShareEdgeCollapse = 0.75, kRunShareVertexRemoval = 0.5;

detail::Limits limits_from(const Options& o) {
    auto cosine = [](double degrees) { return std::cos(degrees * std::numbers::pi / 180.0); };
    detail::Limits limits;
    limits.feature_cos = o.feature_angle >= 180 ? -2.0 : cosine(o.feature_angle);
    limits.straight_cos = cosine(o.line_tolerance);
    limits.normal_turn_cos = cosine(o.max_normal_turn);
    return limits;
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

// resize for an array that a run appends to, past what reserve_record expected: in steps of a
// quarter, not doubling, as the array is near its final size.
template <class T> void grow(std::vector<T>& v, size_t n) {
    if (n > v.capacity()) v.reserve(std::max(n, v.capacity() + v.capacity() / 4));
    v.resize(n);
}

} // namespace

Simplifier::Simplifier(const Surface& surface, const Options& options, const RepairReport& repairs)
    : options_(options), parallel_(options.threads), input_(surface) {
    check_options(options);
    if (!options.locked.empty() && options.locked.size() != surface.vertex_count())
        throw InputError("invalid option: locked has " + std::to_string(options.locked.size()) +
                         " entries, but the surface has " + std::to_string(surface.vertex_count()) +
                         " vertices");
    record_.strategy_ = options.strategy;
    record_.threads_ = options.threads;
    record_.triangles_in_ = surface.triangle_count();
    record_.input_vertices_ = surface.vertex_count();
    record_.repairs_ = repairs;
    if (options.strategy == Strategy::VertexRemoval) record_.write_begin_.push_back(0);
    detail::StageWatch watch(options.progress, 0, 0);
    {
        const detail::Parallel::Watching watching(parallel_, watch);
        set_up(surface, options);
    }
    cancelled_ = watch.stopped();
}

void Simplifier::set_up(const Surface& surface, const Options& options) {
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
    line_tolerance_ = options.line_tolerance;
    mesh_.build(surface, capacity, limits_from(options), id_, rank_, &parallel_); // locality order
    if (parallel_.stopped()) return;
    const bool collapse = options.strategy == Strategy::EdgeCollapse;
    // Edge collapse's ids are half-edges, vertex removal's vertices.
    const size_t ids = collapse ? surface.triangles.size() : capacity;
    using detail::assign_on_threads;
    assign_on_threads(fail_, ids, 0, parallel_);
    assign_on_threads(raised_, ids, 0, parallel_);
    assign_on_threads(stale_, ids, kStale | kKeyStale, parallel_); // the first ranking: every id
    // No block marked: the first ranking visits every id without listing them.
    stale_blocks_.assign((ids >> kStaleBlockShift) / 64 + 1, 0);
    assign_on_threads(placed_, ids, kUnplaced, parallel_);
    if (collapse) assign_on_threads(edge_weight_, ids, 0, parallel_);
    assign_on_threads(epoch_, capacity, 0, parallel_);
    assign_on_threads(busy_, capacity, {0, 0}, parallel_);
    if (collapse) assign_on_threads(fail_at_, surface.triangles.size(), kNoFold, parallel_);
    if (collapse) assign_on_threads(refusal_near_, capacity, 0, parallel_);

    const size_t n = surface.vertex_count();
    for (uint32_t v = 0; v < n; ++v) vertices_in_use_ += mesh_.kind[v] != VertexKind::Dead;
    quadric_terms_ = options.terms == Terms::ErrorQuadrics;
    least_error_ =
        options.strategy == Strategy::EdgeCollapse && options.placement == Placement::LeastError;
    if (quadric_terms_ || least_error_)
        quadrics_.setup(mesh_, gradient_, geometry_weight(), 1 - options.alpha, capacity,
                        parallel_);
    if (parallel_.stopped()) return;
    // Edge collapse's levels fit these components' least squares to their new points and flip
    // their edges where these components fit the input better. Vertex removal's levels move their
    // vertices and flip their edges where the input's samples fit better, in these components and
    // in distance: with no component (at α = 1, or with no data) in distance alone.
    if (collapse ? least_data() : quadric_terms_ && quadrics_.inv_diagonal > 0) {
        for (size_t j = 0; j < quadrics_.components; ++j) {
            if (!quadrics_.continuous[j]) continue;
            uint32_t field = 0, first = 0; // the field of data-record offset quadrics_.offset[j]
            while (first + uint32_t(surface.fields[field].components) <= quadrics_.offset[j])
                first += uint32_t(surface.fields[field++].components);
            record_.refit_components_.emplace_back(field, quadrics_.offset[j] - first);
            record_.refit_data_weight_.push_back((1 - options.alpha) * quadrics_.inv_range[j] *
                                                 quadrics_.inv_range[j]);
        }
        // A level's edges are flipped for its data (data_flips.h) only where the surface is
        // nearly flat, and never across a feature edge.
        record_.refit_distance_weight_ =
            geometry_weight() * quadrics_.inv_diagonal * quadrics_.inv_diagonal;
        record_.refit_diagonal_ = 1 / quadrics_.inv_diagonal; // > 0: the levels are refitted
        record_.refit_feature_cos_ = mesh_.limits.feature_cos;
        record_.refit_flat_cos_ = std::cos(
            std::min(detail::kFlipFlatDegrees, options.feature_angle) * std::numbers::pi / 180.0);
        record_.refit_turn_cos_ = mesh_.limits.normal_turn_cos;
        if (!collapse) { // the input vertices a level vertex may move to along the boundary
            record_.boundary_line_input_.resize(n);
            for (uint32_t v = 0; v < n; ++v)
                record_.boundary_line_input_[v] =
                    mesh_.kind[rank_[v]] == VertexKind::Line && mesh_.is_boundary_vertex(rank_[v]);
        }
        if (!mesh_.locked.empty()) {
            record_.locked_input_.resize(n);
            for (uint32_t v = 0; v < n; ++v) record_.locked_input_[v] = mesh_.locked[rank_[v]];
        }
    }
    if (!(collapse && quadric_terms_)) weight_.assign(capacity, 0);
    // The paper's terms, then their means over the vertices that can take part.
    std::vector<double> curvature(quadric_terms_ ? 0 : n), gradient(quadric_terms_ ? 0 : n);
    if (!quadric_terms_)
        parallel_.for_range(n, [&](size_t begin, size_t end) {
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
    if (!collapse) {
        shortest_.assign(capacity, 0);
        constexpr uint32_t kKeysPerCheck = 4096; // a few milliseconds of the serial keys
        for (uint32_t v = 0; v < n; ++v) {
            if (v % kKeysPerCheck == kKeysPerCheck - 1 && !parallel_.check()) return;
            if (mesh_.kind[v] != VertexKind::Dead) key_removal(v);
        }
    }
}

void Simplifier::refresh_vertex(uint32_t v) {
    // One fan walk: kind, valence, angle sum, steepest neighbour and, for vertex removal, the
    // shortest edge (the key's tie-break). Same values as classify, the constructor's weights
    // and key_removal.
    // With the error quadrics, a vertex removal's weight is its estimated error (removal_error),
    // and an edge's comes from its ends' quadrics (collapse_weight).
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
    if (quadric_terms_) {
        if (removal)
            weight_[v] = ring_error && (k == VertexKind::Free || k == VertexKind::Line)
                             ? float(removal_error(v, ring, ring_size))
                             : 0.0f;
    } else {
        weight_[v] =
            float(options_.alpha * mesh_.curvature_from(v, angles) * curvature_scale_ +
                  (1 - options_.alpha) * (counted ? steepest.value() : 0.0) * gradient_scale_);
    }
    if (removal) {
        shortest_[v] = float(shortest);
        raised_[v] = 0; // its key is an estimate again
    }
}

// After a removal: the `changed` vertices (its ring) have new neighbourhoods. Their kinds and
// weights are recomputed at once (a weight reads only the vertex's star and its neighbours, so no
// other weight changed). A collapse does the same for its new vertex and ring in apply_collapse.
void Simplifier::refresh_around(const uint32_t* changed, size_t count) {
    for (size_t i = 0; i < count; ++i) {
        epoch_[changed[i]] = pass_;
        refresh_changed(changed[i], false, true);
    }
}

bool Simplifier::claim_shared(uint32_t v) {
    return std::atomic_ref<uint32_t>(busy_[v].holder)
               .fetch_and(~kShared, std::memory_order_relaxed) &
           kShared;
}

bool Simplifier::ring_refreshes(uint32_t v) const {
    return !quadric_terms_ || options_.strategy != Strategy::EdgeCollapse ||
           options_.placement == Placement::VolumePreserving || mesh_.kind[v] != VertexKind::Free;
}

void Simplifier::refresh_changed(uint32_t v, bool made, bool apex) {
    // With the error quadrics, an edge's key reads only its ends' quadrics, positions, data and
    // kinds (and, for the volume-preserving point, their stars). A collapse changes these for the
    // new vertex and at most the kinds of the others: their edges keep their keys unless their
    // kind changed. A kind can change only at the apexes (they lost a neighbour and may have
    // merged line flags) and at ring vertices on a line; a Free vertex of the rest of the ring
    // keeps its kind and valence (and weight_ is not used).
    const bool collapse = options_.strategy == Strategy::EdgeCollapse;
    const bool collapse_quadrics = quadric_terms_ && collapse;
    const bool star_keys = options_.placement == Placement::VolumePreserving;
    const VertexKind kind = mesh_.kind[v];
    if (!collapse_quadrics || apex || kind != VertexKind::Free) refresh_vertex(v);
    if (!collapse) return mark_stale(v);
    // The edges at a ring vertex that kept its kind, valence and line read nothing that changed
    // (a refused one is marked by forgive_around): they keep their places. At an apex or a
    // line vertex that kept its kind only the valence can have fallen, which can only make an
    // edge without a place a candidate: mark_edges_at marks only those.
    const bool rekey = !collapse_quadrics || made || mesh_.kind[v] != kind || star_keys;
    if (rekey || apex || kind != VertexKind::Free) mark_edges_at(v, rekey);
}

void Simplifier::forgive_refusals() {
    const bool collapse = options_.strategy == Strategy::EdgeCollapse;
    for (uint32_t id = 0; id < fail_.size(); ++id)
        if (fail_[id] != 0 &&
            (collapse ? mesh_.origin[id] != kNone : mesh_.kind[id] != detail::VertexKind::Dead))
            mark_stale(collapse ? edge_id(id) : id);
    std::fill(fail_.begin(), fail_.end(), 0);
    if (collapse) {
        std::fill(refusal_near_.begin(), refusal_near_.end(), 0);
        std::fill(fail_at_.begin(), fail_at_.end(), kNoFold);
    }
}

bool Simplifier::widen_lines() {
    // Doubling keeps a tolerance of 0 (only straight lines thin out) as the caller set it.
    const double wider = std::min(2 * line_tolerance_, kWidestLine);
    if (wider <= line_tolerance_) return false;
    line_tolerance_ = wider;
    mesh_.limits.straight_cos = std::cos(wider * std::numbers::pi / 180.0);
    // Only a corner between exactly two line edges can become a line vertex; locked vertices
    // stay corners (classify).
    for (uint32_t v = 0; v < mesh_.vertex_count; ++v)
        if (mesh_.kind[v] == VertexKind::Corner) refresh_changed(v, false, true);
    return true;
}

void Simplifier::mark_edges_at(uint32_t v, bool rekey) {
    mesh_.for_each_edge(v, [&](uint32_t h, uint32_t, bool) {
        const uint32_t id = edge_id(h);
        if (rekey)
            mark_rekey(id);
        else if (placed_[id] == kUnplaced)
            mark_stale(id);
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

bool Simplifier::waits(uint32_t id, float key, float planned) {
    if (double(planned) > taken_within(id, key)) return raised_[id] = 1, true;
    return false;
}

double Simplifier::taken_within(uint32_t id, float key) const {
    // Heavier than its key and than the share, once (raised_), or than Options::max_weight.
    return raised_[id] ? options_.max_weight
                       : std::min(double(std::max(key, share_limit_)), options_.max_weight);
}

void Simplifier::publish_selected(bool over) {
    const bool collapse = options_.strategy == Strategy::EdgeCollapse;
    if (!over) {
        if (collapse)
            plans_.emplace_back();
        else
            removals_.add_slot();
        if (selected_.size() % kCheckBatch != 0) return;
    }
    published_.store(selected_.size() | (over ? kWalkOver : 0), std::memory_order_release);
    published_.notify_all();
}

size_t Simplifier::wait_published(size_t count) {
    uint64_t state = published_.load(std::memory_order_acquire);
    while (!(state & kWalkOver) && state < count) {
        published_.wait(state, std::memory_order_acquire);
        state = published_.load(std::memory_order_acquire);
    }
    return std::min<size_t>(count, state & ~kWalkOver);
}

void Simplifier::check_published(size_t first, std::atomic<size_t>& claimed,
                                 std::atomic<bool>& stopped, bool calling) {
    const bool collapse = options_.strategy == Strategy::EdgeCollapse;
    size_t since_progress = 0;
    for (;;) {
        const size_t begin = claimed.fetch_add(kCheckBatch, std::memory_order_relaxed);
        const size_t end = wait_published(begin + kCheckBatch);
        if (begin >= end || stopped.load(std::memory_order_relaxed)) return;
        for (size_t i = begin; i < end; ++i) {
            if (collapse)
                prefetch_ahead(i, end, [&](size_t k) { return ranked_[selected_[k]].id; });
            const detail::Candidate& c = ranked_[selected_[i]];
            checked_[first + i] = collapse ? check_collapse(c.id, c.weight(), plans_[first + i])
                                           : check_removal(c.id, first + i);
        }
        since_progress += end - begin;
        if (calling && since_progress >= kBlock) {
            since_progress = 0;
            if (!checkpoint()) return stopped.store(true, std::memory_order_relaxed);
        }
    }
}

bool Simplifier::checkpoint() {
    if (cancelled_) return false;
    if (!options_.progress) return true;
    const size_t in = record_.triangles_in_, live = mesh_.live_triangles;
    const double total = double(in - std::min(target_, in));
    const double done = double(in - live);
    cancelled_ = !options_.progress(total > 0 ? std::min(1.0, done / total) : 1.0);
    return !cancelled_;
}

void Simplifier::count_pass(size_t walked, size_t waited, size_t refused) const {
    detail::PassCounts& counts = detail::pass_counts();
    counts.passes.fetch_add(1, std::memory_order_relaxed);
    counts.walked.fetch_add(walked, std::memory_order_relaxed);
    counts.taken.fetch_add(taken_.size(), std::memory_order_relaxed);
    counts.waited.fetch_add(waited, std::memory_order_relaxed);
    counts.refused.fetch_add(refused, std::memory_order_relaxed);
}

bool Simplifier::run_pass(size_t target, StopReason& stop) {
    const bool collapse = options_.strategy == Strategy::EdgeCollapse;
    size_t share = 0;
    if (!rank_candidates(share)) return stop = StopReason::Cancelled, true;
    if (share == 0) {
        // The last resorts, in turn: a new triangle need only face along its corners' reference
        // normals together; then lines may bend more where a vertex goes (widen_lines). Each
        // time every refused edge or vertex is tried again.
        if (relaxed_facing_ && !widen_lines()) return stop = StopReason::NothingRemovable, true;
        relaxed_facing_ = true;
        forgive_refusals();
        return false;
    }
    if (ranked_.front().weight() > options_.max_weight) return stop = StopReason::WeightBound, true;
    share_limit_ = ranked_[share - 1].weight();
    ++pass_;
    if (collapse) {
        share_ends_.resize(share);
        parallel_.for_range(share, [&](size_t begin, size_t end) {
            constexpr size_t kAhead = 16; // the half-edges are scattered: fetched ahead
            for (size_t i = begin; i < end; ++i) {
                if (i + kAhead < end) __builtin_prefetch(&mesh_.origin[ranked_[i + kAhead].id]);
                const uint32_t h = ranked_[i].id;
                share_ends_[i] = {mesh_.origin[h], mesh_.dest(h)};
            }
        });
    }

    // Select, in rank order: a candidate whose neighbourhood no candidate selected before it
    // touches (selection.cpp). The checks run on the other threads while the walk goes on, each
    // on the surface as the pass found it; the calling thread joins them when its walk is done.
    // What is selected never depends on a check being done yet, so nothing depends on the
    // thread count. Rounds repeat this among the candidates that only a refused or waiting one
    // blocked: its neighbourhood is free again.
    taken_.clear();
    pending_.clear();
    // A candidate is selected once a pass at most: room for the share's plans (pages never
    // written cost nothing), so that neither a round's plans nor the walk's move those that
    // checks are writing.
    plans_.clear();
    if (collapse)
        plans_.reserve(share);
    else
        removals_.reset(share);
    for (uint32_t i = 0; i < share && ranked_[i].weight() <= options_.max_weight; ++i)
        pending_.push_back(i);
    checked_.clear();
    const uint32_t pass_stamp = stamp_ + 1; // the first round's
    size_t visited = 0, waited = 0, refused = 0;
    for (int round = 0; round < kSelectionRounds && !pending_.empty(); ++round) {
        visited += pending_.size();
        const uint32_t round_stamp = ++stamp_;
        // Each selected one's plan and check after the rounds' before it: the taken ones stay
        // where their check put them until they are applied, and hold their neighbourhoods for
        // the rest of the pass (see select).
        const size_t first = collapse ? plans_.size() : removals_.size();
        selected_.reserve(pending_.size());
        checked_.resize(first + pending_.size());
        published_.store(0, std::memory_order_relaxed);
        std::atomic<size_t> claimed{0};
        std::atomic<bool> stopped{false};
        bool walked = true;
        parallel_.beside([&] { walked = select(pass_stamp, round_stamp, first); },
                         [&](bool calling) { check_published(first, claimed, stopped, calling); });
        if (!walked || stopped.load(std::memory_order_relaxed))
            return stop = StopReason::Cancelled, true;
        hold_for_taken();
        // A round selects in rank order: its taken ones are one ordered run, merged in below.
        const size_t round_taken = taken_.size();
        bool freed = false;
        for (size_t i = 0; i < selected_.size(); ++i) {
            if (checked_[first + i] != Check::Taken) {
                ++(checked_[first + i] == Check::Waits ? waited : refused);
                freed = true;
                continue;
            }
            taken_.push_back({selected_[i], uint32_t(first + i)});
        }
        std::inplace_merge(taken_.begin(), taken_.begin() + round_taken, taken_.end());
        if (!freed) break; // nothing blocked now is free in another round
        pend_blocked();
    }
    count_pass(visited, waited, refused);

    // Apply in key order, as far as the target: a direct run to any target stops at the first
    // operation that reaches it, so every run is a prefix of the one record.
    size_t live = mesh_.live_triangles, count = taken_.size();
    write_at_.clear();
    size_t writes = record_.writes_.size();
    for (size_t j = 0; j < taken_.size(); ++j) {
        const uint32_t t = taken_[j].second;
        size_t removed;
        if (collapse) {
            removed = mesh_.twin[plans_[t].halfedge] != kNone ? 2 : 1;
        } else {
            const size_t slots = removals_.slots_of(t);
            removed = slots - removals_.new_count_of(t);
            write_at_.push_back(uint32_t(writes));
            writes += 4 * slots;
            record_.write_begin_.push_back(uint32_t(writes));
        }
        live -= removed;
        record_.triangles_after_.push_back(uint32_t(live));
        if (live <= target) {
            count = j + 1;
            break;
        }
    }
    if (collapse) {
        grow(record_.collapse_, 2 * (operations_ + count));
        grow(made_, (operations_ + count) * (3 + mesh_.stride));
    } else {
        grow(record_.writes_, writes);
    }
    if (collapse && apexes_.size() < count) apexes_.resize(count);
    const size_t applied = in_blocks(count, [&](size_t begin, size_t end) {
        for (size_t j = begin; j < end; ++j) {
            if (collapse) {
                prefetch_ahead(j, end, [&](size_t k) { return plans_[taken_[k].second].halfedge; });
                if (j + 2 < end) { // whether the apexes are shared (prefetch_ahead fetched h)
                    const uint32_t h = plans_[taken_[j + 2].second].halfedge;
                    __builtin_prefetch(&busy_[mesh_.origin[detail::prev(h)]]);
                }
            }
            const uint32_t t = taken_[j].second;
            if (collapse) {
                apexes_[j] = apply_collapse(plans_[t], operations_ + j);
            } else {
                Removal removal;
                removals_.get(t, removal);
                apply_removal(removal, operations_ + j, write_at_[j]);
            }
        }
    });
    if (collapse) refresh_rings(apexes_.data(), applied);
    if (pass_release_.due(share)) release_pass_arrays();
    // Cancelled in the middle: the record keeps the operations applied so far.
    const size_t recorded = record_.triangles_after_.size() - count;
    if (applied < count) {
        record_.triangles_after_.resize(recorded + applied);
        if (collapse) {
            record_.collapse_.resize(2 * (operations_ + applied));
            made_.resize((operations_ + applied) * (3 + mesh_.stride));
        } else {
            record_.write_begin_.resize(operations_ + applied + 1);
            record_.writes_.resize(record_.write_begin_.back());
        }
        live = applied > 0 ? record_.triangles_after_.back() : mesh_.live_triangles;
    }
    operations_ += applied;
    mesh_.live_triangles = live;
    if (applied < count) return stop = StopReason::Cancelled, true;
    if (live <= target) return stop = StopReason::TargetReached, true;
    if (!checkpoint()) return stop = StopReason::Cancelled, true;
    return false;
}

void Simplifier::release_pass_arrays() {
    using detail::clear_and_release;
    clear_and_release(plans_), clear_and_release(checked_), clear_and_release(taken_);
    clear_and_release(pending_), clear_and_release(selected_), clear_and_release(blocked_);
    clear_and_release(blocked_by_), clear_and_release(apexes_), clear_and_release(share_ends_);
    removals_.release();
}

void Simplifier::reserve_record(size_t target) {
    // Every operation removes a triangle at least (most remove two; a removal's star has six
    // triangles on average, by Euler). Reserved pages that are never written cost no memory, so
    // the bound is reserved rather than an estimate that a reallocation (old and new arrays at
    // once) would have to make good.
    const size_t in = record_.triangles_in_;
    const size_t operations = in - std::min(target, in);
    record_.triangles_after_.reserve(operations);
    if (options_.strategy == Strategy::EdgeCollapse) {
        record_.collapse_.reserve(2 * operations);
        made_.reserve(operations * (3 + mesh_.stride));
    } else {
        record_.write_begin_.reserve(operations + 1);
        record_.writes_.reserve(4 * 6 * operations);
    }
}

ProgressiveRecord Simplifier::run(std::vector<float>& made_points) {
    const size_t target = target_triangles(options_, record_.triangles_in_);
    target_ = target;
    // Pass after pass until the target. Nothing in a pass depends on the target but where it
    // stops applying, so a run to any target performs a prefix of the same operations.
    StopReason stop = StopReason::TargetReached;
    reserve_record(target);
    if (mesh_.live_triangles > target && checkpoint())
        while (!run_pass(target, stop)) continue;
    else if (cancelled_)
        stop = StopReason::Cancelled;
    record_.stop_ = stop;
    if (options_.progress && !cancelled_) options_.progress(1.0);

    made_points.swap(made_);
    return std::move(record_);
}

Result simplify(const Surface& input, const Options& options) {
    // Progress: the run reports up to its share of the work, the level's fit the rest. Once the
    // callback says stop, the level is the one reached, not fitted.
    const double run_share = options.strategy == Strategy::VertexRemoval ? kRunShareVertexRemoval
                                                                         : kRunShareEdgeCollapse;
    bool stopped = false;
    Options run_options = options;
    if (options.progress)
        run_options.progress = [&](double done) {
            stopped = stopped || !options.progress(done * run_share);
            return !stopped;
        };
    const ProgressiveRecord record = ProgressiveRecord::run(input, run_options, false);
    std::optional<Surface> fitted;
    if (!stopped) {
        std::function<bool(double)> fit_progress;
        if (options.progress)
            fit_progress = [&](double done) {
                return options.progress(run_share + done * (1 - run_share));
            };
        fitted = record.after(record.operations(), fit_progress);
        if (fitted && options.progress) options.progress(1.0);
    }
    Result result;
    result.surface = fitted ? std::move(*fitted) : record.after_as_recorded(record.operations());
    result.triangles_in = record.triangles_in();
    result.triangles_out = result.surface.triangle_count();
    result.operations = record.operations();
    result.stop = fitted ? record.stop() : StopReason::Cancelled;
    result.target_reached = result.stop == StopReason::TargetReached;
    result.repairs = record.repairs();
    return result;
}

} // namespace ddsimp
