// The simplifiers the fidelity report compares: ddsimp and its peers, each behind one function
// that takes the same surface and triangle target and returns what it made.
#pragma once

#include <ddsimp/ddsimp.h>

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
};

struct PeerRequest {
    size_t target_triangles = 0;
    double alpha = 0.5; // ddsimp only
};

// The peers by the names the report uses: "ddsimp-edge", "ddsimp-vertex", "meshopt",
// "vtk-quadric", "vtk-decimatepro", "openmesh".
const std::vector<std::string>& peer_names();

// Runs `peer` on `input` (already repaired by ddsimp::validate). Throws std::invalid_argument for
// an unknown name; any exception from the simplifier itself is passed on.
PeerOutput run_peer(const std::string& peer, const Surface& input, const PeerRequest& request);

} // namespace ddsimp::report
