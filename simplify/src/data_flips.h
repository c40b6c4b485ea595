// A level's edges flipped where the other diagonal of their quad fits the input's samples better:
// a data-dependent triangulation of the level's vertices (docs/algorithm.md, "Edge collapse": the
// data at the new point; "Vertex removal").
#pragma once

#include "data_refit.h"

#include <vector>

namespace ddsimp::detail {

// The most two triangles' normals may turn apart, in degrees, for the edge between them to be
// flipped (and for the two it makes). Creases stay; a flat region's triangulation follows the
// data.
inline constexpr double kFlipFlatDegrees = 20;

// Sweeps over the level's edges, in order, flipping each edge between two triangles that are
// nearly coplanar (their normals' cosine at least input.flat_cos, before the flip and after)
// when the other diagonal lowers the weighted squared error (RefitInput::data_weight,
// distance_weight) of the input samples landed on the two triangles, each moved to the nearer of
// the new two. A sweep after the first tries only the edges around the last one's flips, until
// a sweep flips nothing: every flip lowers the samples' total error, so none is undone.
// The topology stays: an edge is flipped only if it has exactly two triangles, oriented alike,
// and its quad's other diagonal is no edge yet. `forward` (per input vertex, where it lies on
// the level: refit_data's landing, or the triangle that covers a removed vertex) follows the
// samples it moves; of `input`, only the surface, components, weights and flat_cos are read.
// The first sweep tries every edge, or with `near` (sorted level vertices) only the edges of the
// triangles at them. Returns the corners of the flipped quads, sorted: the vertices whose stars
// the flips changed. The same bytes for any number of threads: the threads only find the edges
// worth trying, which are then tried and flipped one by one in order. Once a watch on `parallel`
// stops (stage_watch.h), the flips end part-way and return nothing.
std::vector<uint32_t> flip_edges_for_data(const RefitInput& input, std::vector<Landing>& forward,
                                          Surface& level, Parallel& parallel,
                                          const std::vector<uint32_t>* near = nullptr);

} // namespace ddsimp::detail
