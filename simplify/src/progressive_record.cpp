// Replaying a prefix of the recorded operations: every level of one run, without re-running.
#include "level_relocation.h"
#include "removal_cover.h"
#include "simplifier.h"
#include "validate.h"

#include <algorithm>

namespace ddsimp {

namespace {

// Vertex removal: per input vertex, where it lies on the level after `operations` removals (none
// for a kept one): on the level's triangle that covers it (removal_cover.h), distances within
// `tie` of each other equal.
std::vector<detail::Landing>
covered_landings(const std::vector<float>& positions, size_t input_vertices,
                 const std::vector<uint32_t>& triangles, const std::vector<uint32_t>& write_begin,
                 const std::vector<uint32_t>& writes, size_t operations, double tie,
                 detail::Parallel& parallel) {
    const detail::RemovalCover cover(triangles, input_vertices, write_begin, writes, operations);
    if (!parallel.check()) return {};
    // The level's triangles are the live slots, in slot order; the write that covers a point is
    // the last to its slot.
    std::vector<uint32_t> triangle_of(triangles.size() / 3, 0);
    for (uint32_t w = 0; w < write_begin[operations]; w += 4)
        triangle_of[writes[w]] = writes[w + 1] == detail::RemovalCover::kNone;
    for (uint32_t t = 0, live = 0; t < triangle_of.size(); ++t)
        triangle_of[t] = triangle_of[t] ? detail::kNoOwner : live++;
    std::vector<detail::Landing> landed(input_vertices);
    auto point = [&](uint32_t v) { return detail::point_of(positions, v); };
    parallel.for_each(input_vertices, [&](size_t p) {
        std::array<double, 3> last{};
        const uint32_t w =
            cover.follow(uint32_t(p), point, tie,
                         [&](uint32_t, uint32_t, const std::array<double, 3>& weights, double) {
                             last = weights;
                         });
        if (w != detail::RemovalCover::kNone) landed[p] = {triangle_of[writes[w]], last};
    });
    return landed;
}

} // namespace

ProgressiveRecord ProgressiveRecord::build(const Surface& input, const Options& options) {
    return run(input, options, true);
}

ProgressiveRecord ProgressiveRecord::run(const Surface& input, const Options& options,
                                         bool measure) {
    RepairReport repairs;
    Surface repaired;
    detail::Parallel parallel(options.threads);
    // The repair is finished even if cancelled meanwhile: a cancelled run still has the repaired
    // input (its loops are short); the simplifier's set-up then stops at once.
    detail::StageWatch watch(options.progress, 0, 0, false);
    const Surface& surface = [&]() -> const Surface& {
        const detail::Parallel::Watching watching(parallel, watch);
        return detail::validated(input, repaired, repairs, parallel);
    }();
    std::vector<float> made;         // per collapse: the new point, then its data
    std::optional<Options> stopping; // cancelled during the repair: the set-up stops at once
    if (watch.stopped()) stopping = options, stopping->progress = [](double) { return false; };
    ProgressiveRecord record =
        Simplifier(surface, stopping ? *stopping : options, repairs).run(made);
    record.take_input(surface, made);
    // After the run, when the simplifier's memory is gone: the measurement's peak stays below it.
    if (measure) record.measure_errors(options.gradient_fields);
    return record;
}

void ProgressiveRecord::take_input(const Surface& input, std::vector<float>& made) {
    base_triangles_ = input.triangles;
    size_t record = 3;
    for (const Field& f : input.fields) record += size_t(f.components);
    const size_t ni = input.vertex_count(), nv = ni + made.size() / record;
    vertices_.positions.resize(3 * nv);
    std::copy(input.positions.begin(), input.positions.end(), vertices_.positions.begin());
    for (size_t v = ni; v < nv; ++v)
        std::copy_n(&made[(v - ni) * record], 3, &vertices_.positions[3 * v]);
    size_t offset = 3;
    for (const Field& in : input.fields) {
        Field f{in.name, in.components, {}, in.kind};
        const size_t nc = size_t(f.components);
        f.values.resize(nv * nc);
        std::copy(in.values.begin(), in.values.end(), f.values.begin());
        for (size_t v = ni; v < nv; ++v)
            std::copy_n(&made[(v - ni) * record + offset], nc, &f.values[v * nc]);
        offset += nc;
        vertices_.fields.push_back(std::move(f));
    }
    std::vector<float>().swap(made);
}

size_t ProgressiveRecord::operations_for(size_t triangles) const {
    if (triangles >= triangles_in_) return 0;
    // triangles_after_ never grows, so the first operation at or below the count is a bound.
    const auto at = std::find_if(triangles_after_.begin(), triangles_after_.end(),
                                 [&](uint32_t t) { return t <= triangles; });
    return at == triangles_after_.end() ? triangles_after_.size()
                                        : size_t(at - triangles_after_.begin()) + 1;
}

Surface ProgressiveRecord::level(size_t triangles) const {
    return after(operations_for(triangles));
}

std::vector<uint32_t> ProgressiveRecord::collapse_map(size_t operations) const {
    // Each collapse maps its two vertices to a vertex made later, so resolving the map from the
    // newest vertex down settles every chain in one pass.
    std::vector<uint32_t> map(input_vertices_ + operations);
    for (uint32_t v = 0; v < map.size(); ++v) map[v] = v;
    for (size_t i = 0; i < operations; ++i)
        map[collapse_[2 * i]] = map[collapse_[2 * i + 1]] = uint32_t(input_vertices_ + i);
    for (size_t v = map.size(); v-- > 0;)
        if (map[v] != v) map[v] = map[map[v]];
    return map;
}

std::vector<uint32_t> ProgressiveRecord::indexed_triangles(size_t operations) const {
    operations = std::min(operations, this->operations());
    std::vector<uint32_t> triangles = base_triangles_;
    if (strategy_ == Strategy::EdgeCollapse) {
        const std::vector<uint32_t> map = collapse_map(operations);
        size_t kept = 0;
        for (size_t t = 0; t < triangles.size(); t += 3) {
            const uint32_t a = map[triangles[t]], b = map[triangles[t + 1]],
                           c = map[triangles[t + 2]];
            if (a == b || b == c || a == c) continue; // a triangle a collapse removed
            triangles[kept++] = a, triangles[kept++] = b, triangles[kept++] = c;
        }
        triangles.resize(kept);
    } else {
        for (size_t w = 0; w < write_begin_[operations]; w += 4)
            std::copy(&writes_[w + 1], &writes_[w + 4], &triangles[3 * size_t(writes_[w])]);
        triangles.erase(std::remove(triangles.begin(), triangles.end(), 0xffffffffu),
                        triangles.end());
    }
    return triangles;
}

Surface ProgressiveRecord::after(size_t operations) const {
    return *level_after(operations, true);
}

std::optional<Surface> ProgressiveRecord::after(size_t operations,
                                                const std::function<bool(double)>& progress) const {
    return level_after(operations, true, progress);
}

Surface ProgressiveRecord::after_as_recorded(size_t operations) const {
    return *level_after(operations, false);
}

std::optional<Surface>
ProgressiveRecord::level_after(size_t operations, bool fit_data,
                               const std::function<bool(double)>& progress) const {
    operations = std::min(operations, this->operations());
    // The replay's steps are serial: the watch is checked between them.
    detail::StageWatch watch(progress, 0, 1);
    std::vector<uint32_t> triangles = indexed_triangles(operations);
    if (!watch.check()) return std::nullopt;

    // Keep the referenced vertices, in the order of their ids.
    const size_t nv = vertices_.vertex_count();
    std::vector<uint32_t> index(nv, 0xffffffffu);
    for (uint32_t v : triangles) index[v] = 0;
    Surface out;
    uint32_t count = 0;
    for (size_t v = 0; v < nv; ++v)
        if (index[v] == 0) index[v] = count++;
    out.positions.resize(3 * size_t(count));
    for (size_t v = 0; v < nv; ++v)
        if (index[v] != 0xffffffffu)
            std::copy_n(&vertices_.positions[3 * v], 3, &out.positions[3 * size_t(index[v])]);
    for (const Field& f : vertices_.fields) {
        Field g{f.name, f.components, {}, f.kind};
        const size_t nc = size_t(f.components);
        g.values.resize(size_t(count) * nc);
        for (size_t v = 0; v < nv; ++v)
            if (index[v] != 0xffffffffu)
                std::copy_n(&f.values[v * nc], nc, &g.values[size_t(index[v]) * nc]);
        out.fields.push_back(std::move(g));
    }
    if (!watch.check()) return std::nullopt;
    for (uint32_t& v : triangles) v = index[v];
    out.triangles = std::move(triangles);
    // Edge collapse fits its data components; vertex removal moves vertices and flips edges,
    // by the distance alone if there is no component.
    const bool refitted =
        strategy_ == Strategy::VertexRemoval ? refit_diagonal_ > 0 : !refit_components_.empty();
    if (fit_data && refitted && operations > 0 && !refit(operations, index, out, watch))
        return std::nullopt;
    return out;
}

bool ProgressiveRecord::refit(size_t operations, const std::vector<uint32_t>& index, Surface& level,
                              detail::StageWatch& watch) const {
    detail::RefitInput input;
    input.surface = &vertices_;
    input.vertices = input_vertices_;
    input.triangles = &base_triangles_;
    input.components = refit_components_;
    input.data_weight = refit_data_weight_;
    input.distance_weight = refit_distance_weight_;
    input.flat_cos = refit_flat_cos_;
    input.turn_cos = refit_turn_cos_;
    input.feature_cos = refit_feature_cos_;
    detail::Parallel parallel(threads_);
    const detail::Parallel::Watching watching(parallel, watch);
    if (strategy_ == Strategy::VertexRemoval) { // input vertices with their data, no value fitted
        // Ties of distances as the level's error measure has them (level_error.cpp).
        constexpr double kTie = 1e-12;
        std::vector<detail::Landing> landed =
            covered_landings(vertices_.positions, input_vertices_, base_triangles_, write_begin_,
                             writes_, operations, kTie * refit_diagonal_, parallel);
        if (parallel.stopped()) return false;
        std::vector<uint32_t> source(level.vertex_count());
        for (size_t v = 0; v < input_vertices_; ++v)
            if (index[v] != detail::kNoOwner) source[index[v]] = uint32_t(v);
        detail::settle_level(input, locked_input_, boundary_line_input_, source, landed, level,
                             parallel);
        return !parallel.stopped();
    }
    const std::vector<uint32_t> map = collapse_map(operations);
    if (!parallel.check()) return false;
    // index marks the ids the level does not keep with 0xffffffff, which is kNoOwner: an input
    // vertex no triangle uses has no owner.
    static_assert(detail::kNoOwner == 0xffffffffu);
    input.owner.resize(input_vertices_);
    for (size_t v = 0; v < input_vertices_; ++v) input.owner[v] = index[map[v]];
    // The points the run made are fitted; the input's own vertices and everything placed on a
    // locked vertex keep their data.
    std::vector<uint8_t> locked(map.size(), 0);
    if (!locked_input_.empty()) {
        std::copy(locked_input_.begin(), locked_input_.end(), locked.begin());
        for (size_t i = 0; i < operations; ++i)
            locked[input_vertices_ + i] = locked[collapse_[2 * i]] | locked[collapse_[2 * i + 1]];
    }
    input.free.assign(level.vertex_count(), 0);
    for (size_t v = input_vertices_; v < map.size(); ++v)
        if (index[v] != detail::kNoOwner && !locked[v]) input.free[index[v]] = 1;
    detail::refit_data(input, level, parallel);
    return !parallel.stopped();
}

} // namespace ddsimp
