// The value types a PLY header names: the PLY names and their sized aliases, as OpenMesh's
// get_property_type knows them. Shared by the header checks and ddsimp's own PLY reader.
#pragma once

#include <optional>
#include <string_view>

namespace ddsimp::io {

struct PlyType {
    int size = 0;
    bool is_float = false;
    bool is_signed = false;
};

inline std::optional<PlyType> ply_type(std::string_view name) {
    if (name == "char" || name == "int8") return PlyType{1, false, true};
    if (name == "uchar" || name == "uint8") return PlyType{1, false, false};
    if (name == "short" || name == "int16") return PlyType{2, false, true};
    if (name == "ushort" || name == "uint16") return PlyType{2, false, false};
    if (name == "int" || name == "int32") return PlyType{4, false, true};
    if (name == "uint" || name == "uint32") return PlyType{4, false, false};
    if (name == "float" || name == "float32") return PlyType{4, true, true};
    if (name == "double" || name == "float64") return PlyType{8, true, true};
    return std::nullopt;
}

} // namespace ddsimp::io
