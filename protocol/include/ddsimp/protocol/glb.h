// Binary glTF 2.0 (.glb) of a surface, for renderers that read glTF (Unity, Unreal, Godot,
// three.js, Blender). Used by the server's HTTP download and by `ddsimp simplify -o out.glb`;
// no VTK, no protobuf.
//
// One scene, one node, one mesh of one triangle primitive with
//   POSITION, NORMAL    float VEC3; normals are the area-weighted averages of the triangles'
//   COLOR_0             float VEC3 (linear): the colour field through viridis, as the page
//                       colours it (a vector field by its length)
//   _NAME               every field as a custom float attribute (SCALAR..VEC4); a field of more
//                       than 4 components as _NAME_0, _NAME_1, ... of up to 4 components each
//   indices             uint16 below 65536 vertices, else uint32
// The mesh's extras say which field the colours show, over which range, and which attribute
// holds which field. With `meshopt`, every buffer view is compressed with
// EXT_meshopt_compression (a required extension; three.js reads it with its MeshoptDecoder).
#pragma once

#include "ddsimp/ddsimp.h"

#include <optional>
#include <stdexcept>
#include <string>

namespace ddsimp::protocol {

// A surface the writer cannot write (no triangles, wrong sizes, an unknown colour field).
class GlbError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct ColourRange {
    float min = 0;
    float max = 1;
};

struct GlbOptions {
    // The field shown as vertex colours. Empty: the first continuous scalar field whose values
    // vary, else the first scalar that varies, else the first field; without fields, grey.
    std::string colour_field;
    // The values mapped to viridis' ends; default: the range of the values written.
    std::optional<ColourRange> colour_range;
    bool meshopt = false; // EXT_meshopt_compression
    std::string name = "surface";
};

// The .glb bytes. Deterministic: the same surface and options give the same bytes.
// Throws GlbError.
std::string write_glb(const Surface& surface, const GlbOptions& options = {});

// The field write_glb colours by for `requested` (see GlbOptions::colour_field); nullptr when the
// surface has no fields. Throws GlbError if `requested` names no field.
const Field* glb_colour_field(const Surface& surface, const std::string& requested);

} // namespace ddsimp::protocol
