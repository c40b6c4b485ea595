// ddsimp <-> OpenMesh: conversion between ddsimp::Surface and OpenMesh's TriMesh.
//
// Kept out of ddsimp.h so that the core library needs no OpenMesh. Link ddsimp::openmesh.
#pragma once

#include "ddsimp/ddsimp.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace ddsimp {

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// The surface as an OpenMesh TriMesh, vertex i and face i in the surface's order. Every field
// becomes a vertex property named after it: float (1 component), OpenMesh::Vec3f (3) or
// std::vector<float> (any other count). Throws InputError if OpenMesh refuses triangles
// (non-manifold, degenerate or out-of-range), naming how many and the first one.
TriMesh to_openmesh(const Surface& surface);

// The mesh's (non-deleted) vertices and faces as a surface, in handle order; faces must be
// triangles. Vertex properties of type float, OpenMesh::Vec3f and std::vector<float> (one length
// for all vertices) become fields, in property order; OpenMesh's own ("v:...") are skipped.
Surface from_openmesh(const TriMesh& mesh);

} // namespace ddsimp
