// meshoptimizer's attribute-aware simplifiers as peers of the report: npm's meshoptimizer (>= 1.0,
// WebAssembly) run under node by meshopt_peer.mjs, since Debian's meshoptimizer (0.18) has neither.
#pragma once

#include "peers.h"

namespace ddsimp::report {

enum class MeshoptJsMode {
    Attributes, // simplifyWithAttributes: a subset of the input's vertices, data unchanged
    Update,     // simplifyWithUpdate: positions and data moved to their least-error values
};

// Runs one reduction in a node process. The continuous fields are the attributes, each scaled by
// its range as `ddsimp compare` measures it (a vector field's components by the diagonal of their
// bounding box, so that the attribute distance is the measured error), every component weighted
// by request.weight; no vertex lock, no flags, no error bound. For Update the moved positions and
// the moved attribute values, scaled back, are the output's. Throws std::runtime_error when node
// or the npm package is missing (with what to do) or the simplifier fails.
PeerOutput run_meshopt_js(const Surface& input, const PeerRequest& request, MeshoptJsMode mode);

} // namespace ddsimp::report
