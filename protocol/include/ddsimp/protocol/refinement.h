// Progressive streaming: a coarse base mesh, then refinements that turn the mesh a renderer holds
// into the next finer level by sending only new vertices and the triangle slots that change.
#pragma once

#include "ddsimp/protocol/mesh_codec.h"

#include <unordered_map>

namespace ddsimp::protocol {

// The sending side. Levels are given as triangles over the stable vertex ids of a progressive
// record (ProgressiveRecord::vertices() and indexed_triangles()); each must be finer than the
// last (a superset of its vertices is not required).
class RefinementStream {
public:
    explicit RefinementStream(const Surface& all_vertices) : all_(all_vertices) {}

    // The first, coarsest level as a whole mesh (vertices numbered in order of first use).
    Surface base(const std::vector<uint32_t>& triangles);
    // What turns the previous level into this one.
    Refinement refine(const std::vector<uint32_t>& triangles);

private:
    uint32_t local_id(uint32_t global, Surface& new_vertices);

    const Surface& all_;
    std::unordered_map<uint32_t, uint32_t> local_; // record id -> id on the receiving side
    std::vector<uint32_t> slots_;                  // the receiver's triangles, record ids
};

// The receiving side: a mesh whose triangle slots may be empty (written as kDeadSlot, kept as
// a degenerate triangle 0,0,0 so an index buffer can be drawn as it is).
class SlotMesh {
public:
    explicit SlotMesh(Surface base) : mesh_(std::move(base)) {}

    // Throws BlobError (and leaves the mesh unchanged) if a write names a slot beyond the end
    // or a vertex that does not exist, or the fields do not match.
    void apply(const Refinement& refinement);

    // Vertices, fields and slots as they are (dead slots degenerate).
    const Surface& slots() const { return mesh_; }
    size_t live_triangles() const;
    // Dead slots dropped; vertices kept as they are.
    Surface live() const;

private:
    Surface mesh_;
};

} // namespace ddsimp::protocol
