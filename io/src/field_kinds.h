// The kind (ddsimp::FieldKind) of a field read from a file, from what the file says about it.
#pragma once

#include "ddsimp/io/surface_io.h"

#include <string>

namespace ddsimp::io {

// Label for an array of an integer type and for a name that says id or label ("GlobalNodeId",
// "PedigreeNodeId", "vtkOriginalPointIds", "cell_id", "label", "MaterialIds"); Direction for the
// file's normals and a 3-component field named "Normals" or "normals"; Continuous otherwise.
FieldKind field_kind(const std::string& name, int components, bool integer_type,
                     bool is_normals = false);

// Scalar fields "name[0]" .. "name[k-1]" (how a k-component field is written to PLY) made one
// field "name" of k components again; its kind from the components' (a label stays a label).
void regroup_component_fields(Surface& surface);

} // namespace ddsimp::io
