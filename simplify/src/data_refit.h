// An edge-collapse level's made points and their data fitted to the input by least squares, over
// the whole level at once, and its edges flipped where the data fits better (docs/algorithm.md,
// "Edge collapse": the data at the new point).
#pragma once

#include "ddsimp/ddsimp.h"
#include "parallel.h"

#include <array>
#include <cstdint>
#include <vector>

namespace ddsimp::detail {

inline constexpr uint32_t kNoOwner = 0xffffffffu;

// Where a sample lies on a level triangle: the triangle and the weights of its corners.
struct Landing {
    uint32_t triangle = kNoOwner;
    std::array<double, 3> weights{};
};

// Offsets of a compressed list: begin[i] .. begin[i + 1] for each i, from counts in begin[1..].
inline void prefix_sum(std::vector<uint32_t>& begin) {
    for (size_t i = 1; i < begin.size(); ++i) begin[i] += begin[i - 1];
}

// Each level vertex's triangles, in triangle order.
struct Stars {
    std::vector<uint32_t> begin, triangle;
    explicit Stars(const Surface& level)
        : begin(level.vertex_count() + 1, 0), triangle(level.triangles.size()) {
        for (uint32_t v : level.triangles) ++begin[v + 1];
        prefix_sum(begin);
        std::vector<uint32_t> fill(begin.begin(), begin.end() - 1);
        for (size_t t = 0; t < level.triangle_count(); ++t)
            for (int c = 0; c < 3; ++c) triangle[fill[level.triangles[3 * t + c]]++] = uint32_t(t);
    }
};

// Which of a level's vertices and data components the fit sets, and what it fits them to.
struct RefitInput {
    // The repaired input: its vertices are the first `vertices` of `surface` (a record's
    // vertices, whose fields hold the input's values first), its triangles `triangles`.
    const Surface* surface = nullptr;
    size_t vertices = 0;
    const std::vector<uint32_t>* triangles = nullptr;
    // Per input vertex: the level's vertex it went into, or kNoOwner if no triangle uses it.
    std::vector<uint32_t> owner;
    // Per level vertex: whether the fit sets its data (a point the run made, not a locked one);
    // the others keep theirs and the fit works around them.
    std::vector<uint8_t> free;
    // The components fitted, as (field index, component) pairs.
    std::vector<std::pair<uint32_t, uint32_t>> components;
    // What an edge flip weighs (data_flips.h), in the units of the run's error quadrics: per
    // fitted component, the weight of a squared data difference; the weight of a squared
    // distance; and the least cosine between the normals of two triangles that a flip may
    // join or make (above 1: no flips).
    std::vector<double> data_weight;
    double distance_weight = 0;
    double flat_cos = 2;
    // The least cosine between a triangle's normals before and after a vertex-removal level's
    // move where no data weighs (no component): the run's normal-turn limit
    // (Options::max_normal_turn), as for any of its operations (level_relocation.h).
    double turn_cos = 2;
    // The least cosine between the normals of two triangles across an edge that is no feature
    // edge (Options::feature_angle; -2: none): a vertex-removal level's vertex on a feature edge
    // is not moved (level_relocation.h).
    double feature_cos = -2;
};

// Input vertex i's joint error (input.distance_weight, data_weight) where it lands with weights w
// on a level triangle whose corners are the level's vertices `corner`, placed at `at`.
double landed_sample_error(const RefitInput& input, const Surface& level, uint32_t i,
                           const std::array<uint32_t, 3>& corner,
                           const std::array<std::array<double, 3>, 3>& at,
                           const std::array<double, 3>& w);

// Fits the free vertices of `level` (the points the run made) to the input. First their
// positions: each input vertex lands at the closest point of its owner's star and each free
// vertex at the closest point of the input triangles it replaced; with those landings kept, each
// free vertex's least-squares position puts the landed points nearest their input vertices and
// itself nearest its own. A vertex takes it where no triangle of its star turns further than
// flat_cos and its star's samples, each at its closest point on the star, have a lower joint
// error (distance_weight, data_weight) than where they were landed; the moves are found on the
// level as it stands and made together, and where neighbours' moves together turn a triangle
// too far, its corners go back; then the samples land again. Then their data, so that over both
// sets of samples at once the squared data differences are least: each input vertex against the
// level's data interpolated at its landing, each level vertex against the input's data interpolated
// at its own. Each value is then clamped to the range the component spans over the input, so a
// level shows no value the data does not reach (within it, a value may lie beyond the samples
// around its point: a peak between the level's vertices needs that). Then the level's edges are
// flipped where that lowers the samples' error (flip_edges_for_data), and if any was, the data is
// fitted once more. The input's own vertices and locked ones keep their positions and data. The
// same bytes for any number of threads. Once a watch on `parallel` stops (stage_watch.h), the fit
// ends part-way.
void refit_data(const RefitInput& input, Surface& level, Parallel& parallel);

} // namespace ddsimp::detail
