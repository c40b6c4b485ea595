#include "simplifier.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <thread>

namespace ddsimp {

using detail::HeapKey;
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

void check_options(const Options& o) {
    auto fail = [](const std::string& what) { throw InputError("invalid option: " + what); };
    if (!(o.alpha >= 0 && o.alpha <= 1)) fail("alpha must be in [0, 1]");
    if (!(o.keep_fraction >= 0 && o.keep_fraction <= 1)) fail("keep fraction must be in [0, 1]");
    if (std::isnan(o.max_weight)) fail("max weight is NaN");
    if (!(o.feature_angle >= 0 && o.feature_angle <= 180))
        fail("feature angle must be in [0, 180] degrees");
    if (!(o.line_tolerance >= 0 && o.line_tolerance < 180))
        fail("line tolerance must be in [0, 180) degrees");
    if (!(o.max_normal_turn > 0 && o.max_normal_turn < 180))
        fail("max normal turn must be in (0, 180) degrees");
    if (o.threads < 1) fail("threads must be at least 1");
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

} // namespace

Simplifier::Simplifier(const Surface& surface, const Options& options, const RepairReport& repairs)
    : options_(options),
      heap_(options.strategy == Strategy::EdgeCollapse ? 2 * surface.vertex_count()
                                                       : surface.vertex_count()) {
    check_options(options);
    gradient_.setup(surface, options.gradient_fields);
    const size_t capacity = options.strategy == Strategy::EdgeCollapse ? 2 * surface.vertex_count()
                                                                       : surface.vertex_count();
    mesh_.build(surface, capacity, limits_from(options));
    stamp_.assign(capacity, 0);

    record_.strategy_ = options.strategy;
    record_.base_triangles_ = surface.triangles;
    record_.triangles_in_ = surface.triangle_count();
    record_.input_vertices_ = surface.vertex_count();
    record_.repairs_ = repairs;
    record_.vertices_.fields = surface.fields;
    for (Field& f : record_.vertices_.fields) f.values.clear();
    if (options.strategy == Strategy::VertexRemoval) record_.write_begin_.push_back(0);

    // Both terms, then their means over the vertices that can take part.
    const size_t n = surface.vertex_count();
    std::vector<double> curvature(n), gradient(n);
    parallel_for(n, options.threads, [&](size_t begin, size_t end) {
        for (size_t v = begin; v < end; ++v) {
            curvature[v] = mesh_.curvature(uint32_t(v));
            gradient[v] = gradient_.at(mesh_, uint32_t(v));
        }
    });
    double sum_c = 0, sum_g = 0;
    size_t counted = 0;
    for (uint32_t v = 0; v < n; ++v)
        if (mesh_.kind[v] != VertexKind::Complex && mesh_.kind[v] != VertexKind::Dead)
            sum_c += curvature[v], sum_g += gradient[v], ++counted;
    curvature_scale_ = sum_c > 0 ? double(counted) / sum_c : 0;
    gradient_scale_ = sum_g > 0 ? double(counted) / sum_g : 0;
    weight_.assign(capacity, 0);
    for (uint32_t v = 0; v < n; ++v)
        weight_[v] = float(options.alpha * curvature[v] * curvature_scale_ +
                           (1 - options.alpha) * gradient[v] * gradient_scale_);
    for (uint32_t v = 0; v < n; ++v) refresh_key(v);
}

double Simplifier::weight_of(uint32_t v) const {
    return options_.alpha * mesh_.curvature(v) * curvature_scale_ +
           (1 - options_.alpha) * gradient_.at(mesh_, v) * gradient_scale_;
}

void Simplifier::refresh_weight(uint32_t v) {
    weight_[v] = float(weight_of(v));
}

void Simplifier::refresh_key(uint32_t v) {
    const HeapKey key =
        options_.strategy == Strategy::EdgeCollapse ? best_collapse_key(v) : removal_key(v);
    if (std::isinf(key.weight))
        heap_.erase(v);
    else
        heap_.set(v, key);
}

// After an operation: `changed` vertices have new neighbourhoods. Their kinds, weights and keys
// are recomputed. For edge collapse their neighbours' keys (which add a changed weight) are only
// lowered where an edge to a changed vertex became lighter; a key left too low is corrected
// when its vertex is taken from the heap (step_collapse recomputes it), so the order is exact.
void Simplifier::refresh_around(const uint32_t* changed, size_t count) {
    for (size_t i = 0; i < count; ++i) mesh_.classify(changed[i]);
    for (size_t i = 0; i < count; ++i) refresh_weight(changed[i]);
    ++stamp_now_;
    for (size_t i = 0; i < count; ++i) stamp_[changed[i]] = stamp_now_;
    if (options_.strategy != Strategy::EdgeCollapse) {
        for (size_t i = 0; i < count; ++i) refresh_key(changed[i]);
        return;
    }
    for (size_t i = 0; i < count; ++i) {
        const uint32_t v = changed[i];
        HeapKey best;
        if (mesh_.kind[v] != VertexKind::Complex && mesh_.kind[v] != VertexKind::Dead) {
            // One pass over v's edges: v's own key, and lower keys of unchanged neighbours.
            auto consider = [&](uint32_t h, uint32_t other) {
                if (!kinds_allow_collapse(h)) return;
                const HeapKey key = collapse_key(h);
                if (key < best) best = key;
                if (stamp_[other] != stamp_now_ &&
                    (!heap_.contains(other) || key < heap_.key(other)))
                    heap_.set(other, key);
            };
            uint32_t last = kNone;
            mesh_.for_each_outgoing(v, [&](uint32_t h) {
                consider(h, mesh_.dest(h));
                last = h;
            });
            if (mesh_.twin[detail::prev(last)] == kNone)
                consider(detail::prev(last), mesh_.origin[detail::prev(last)]);
        }
        if (std::isinf(best.weight))
            heap_.erase(v);
        else
            heap_.set(v, best);
    }
}

bool Simplifier::report_progress(size_t live, size_t target) {
    if (!options_.progress || operations_ % 1024 != 0) return true;
    const double total = double(record_.triangles_in_ - std::min(target, record_.triangles_in_));
    const double done = double(record_.triangles_in_ - live);
    return options_.progress(total > 0 ? std::min(1.0, done / total) : 1.0);
}

ProgressiveRecord Simplifier::run() {
    const size_t in = record_.triangles_in_;
    const size_t target = options_.target_triangles > 0
                              ? options_.target_triangles
                              : size_t(std::floor(options_.keep_fraction * double(in) + 1e-9));
    for (;;) {
        if (mesh_.live_triangles <= target) {
            record_.stop_ = StopReason::TargetReached;
            break;
        }
        if (heap_.empty()) {
            record_.stop_ = StopReason::NothingRemovable;
            break;
        }
        const uint32_t v = heap_.top();
        if (heap_.key(v).weight > options_.max_weight) {
            record_.stop_ = StopReason::WeightBound;
            break;
        }
        const size_t before = operations_;
        if (options_.strategy == Strategy::EdgeCollapse)
            step_collapse(v);
        else
            step_removal(v);
        if (operations_ != before) {
            record_.triangles_after_.push_back(uint32_t(mesh_.live_triangles));
            if (!report_progress(mesh_.live_triangles, target)) {
                record_.stop_ = StopReason::Cancelled;
                break;
            }
        }
    }
    if (options_.progress) options_.progress(1.0);

    // Hand the vertices (the input's and those the collapses made) to the record.
    const size_t nv = mesh_.vertex_count;
    Surface& vertices = record_.vertices_;
    vertices.positions.assign(mesh_.position.begin(), mesh_.position.begin() + 3 * nv);
    size_t offset = 0;
    for (Field& f : vertices.fields) {
        const size_t nc = size_t(f.components);
        f.values.resize(nv * nc);
        for (size_t v = 0; v < nv; ++v)
            for (size_t c = 0; c < nc; ++c)
                f.values[v * nc + c] = mesh_.data[v * mesh_.stride + offset + c];
        offset += nc;
    }
    return std::move(record_);
}

Result simplify(const Surface& input, const Options& options) {
    const ProgressiveRecord record = ProgressiveRecord::build(input, options);
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
