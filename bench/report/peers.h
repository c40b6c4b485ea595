// The simplifiers the fidelity report compares: ddsimp and its peers, each behind one function
// that takes the same surface and triangle target and returns what it made.
#pragma once

#include <ddsimp/ddsimp.h>

#include <optional>
#include <string>
#include <vector>

namespace ddsimp::report {

// What one simplifier made of the surface. `surface` carries the input's fields wherever the
// simplifier keeps or interpolates them; a field it drops is simply absent.
struct PeerOutput {
    Surface surface;
    bool failed = false;       // the simplifier reported an error (its output may still exist)
    std::string message;       // the error, or a note (e.g. triangles a peer could not load)
    size_t triangles_seen = 0; // triangles the simplifier actually received (OpenMesh refuses some)
    // Set by a peer that runs in another process (the WebAssembly peers under node): the time of
    // its simplification call as that process measured it, that process's peak memory, and what
    // ran the call ("wasm").
    std::optional<double> call_seconds, call_cpu_seconds;
    long long process_peak_rss_bytes = -1;
    std::string runtime;
};

struct PeerRequest {
    size_t target_triangles = 0;
    double alpha = 0.5;  // ddsimp only
    double weight = 1.0; // meshoptimizer's attribute weight (meshopt-attributes, meshopt-update)
};

// The peers by the names the report uses: "ddsimp-edge", "ddsimp-vertex", "meshopt",
// "vtk-quadric", "vtk-decimatepro", "openmesh", and the WebAssembly ones run under node,
// "meshopt-attributes" and "meshopt-update" (meshopt_js_peer.h).
const std::vector<std::string>& peer_names();

// Runs `peer` on `input` (already repaired by ddsimp::validate). Throws std::invalid_argument for
// an unknown name; any exception from the simplifier itself is passed on.
PeerOutput run_peer(const std::string& peer, const Surface& input, const PeerRequest& request);

// The surface made of `triangles` (indices of `input`'s vertices): the vertices they use, in
// order of first use, with every field's values copied. For the peers that keep a subset of the
// input's vertices in place, or whose output indexes a copy of the input's vertex arrays.
Surface subset_of(const Surface& input, const std::vector<uint32_t>& triangles);

} // namespace ddsimp::report
