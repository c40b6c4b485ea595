// A vertex-removal level's vertices moved to other input vertices where the input's samples fit
// better: the level still keeps a subset of the input's vertices, each with its exact position
// and data, but not always the ones the removals left (docs/algorithm.md, "Vertex removal").
#pragma once

#include "data_refit.h"

#include <cstdint>
#include <vector>

namespace ddsimp::detail {

// Moves each vertex v of the level to the input vertex, among the samples landed on its star,
// that lowers the star's weighted squared error most (RefitInput::data_weight, distance_weight):
// the samples, v's own input vertex now one of them, each landed at its closest point on the star,
// where the level's error measure finds it. An interior vertex may move to any of them; a vertex
// on the boundary, where it runs on (`boundary_line`), moves along it: only to a sample on the
// boundary's line too, on one of its two triangles with a boundary edge at v.
// Only the star's triangles change; each must keep its normal within input.flat_cos of the old
// one (input.turn_cos when there is no component: the distance alone decides) and none may
// become a sliver, so the triangles and the topology stay; a vertex on a feature edge
// (input.feature_cos) stays. Every move lowers the samples' total error.
//
// A sweep takes its vertices in order, each finding its best move as the moves before it left the
// level; the first visits the vertices `from` (sorted), one after it only the vertices next to the
// last one's moves; there are at most three. The threads take at once the vertices whose neighbours
// before them in the sweep are done (no two of them neighbours), so the moves are those of the
// sweep in order, and the bytes are the same for any number of threads.
//
// `source` (per level vertex: its input vertex) and `forward` (per input vertex: where it lies on
// the level; kNoOwner for the level's own vertices) follow the moves; `locked` (per input vertex,
// empty: none) marks vertices that stay; `boundary_line` (per input vertex, empty: none) marks
// those on the input's boundary where it runs on, neither a corner nor a complex vertex (a Line
// vertex on a boundary). Of `input`, only the surface, components, weights, flat_cos, turn_cos
// and feature_cos are read. Returns the vertices that moved, sorted.
std::vector<uint32_t>
relocate_level_vertices(const RefitInput& input, const std::vector<uint8_t>& locked,
                        const std::vector<uint8_t>& boundary_line, std::vector<uint32_t>& source,
                        std::vector<Landing>& forward, Surface& level, Parallel& parallel,
                        const std::vector<uint32_t>& from);

// A vertex-removal level's moves (relocate_level_vertices) and flips (flip_edges_for_data, with
// the same samples) in turns, since each changes the stars the other searched: first the moves of
// every vertex and the flips of every edge, then the moves of the vertices whose stars the last
// flips changed and the flips of the edges around the last moves, until a turn changes nothing
// (at most eight turns). Arguments as relocate_level_vertices's; the same bytes for any number of
// threads. Once a watch on `parallel` stops (stage_watch.h), the level is left part-way.
void settle_level(const RefitInput& input, const std::vector<uint8_t>& locked,
                  const std::vector<uint8_t>& boundary_line, std::vector<uint32_t>& source,
                  std::vector<Landing>& forward, Surface& level, Parallel& parallel);

} // namespace ddsimp::detail
