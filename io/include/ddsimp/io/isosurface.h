// Isosurfaces of volumes and grids, with other fields carried onto them (through VTK).
#pragma once

#include "ddsimp/ddsimp.h"

#include <string>
#include <vector>

namespace ddsimp::io {

struct IsosurfaceOptions {
    std::string field;              // the scalar point (or cell) field to contour
    double value = 0.0;             // the isovalue
    std::vector<std::string> carry; // fields to carry onto the surface; empty: every point field
    // Resample the volume to K times its resolution per axis ((n - 1) * K + 1 samples, so the
    // original samples are kept) before contouring; 1: contour the volume as it is.
    int resample = 1;
    // PLOT3D: the solution (Q) file for a grid (XYZ) file, and extra function numbers (density
    // 100 and momentum 202 are always computed; e.g. 110 pressure, 153 velocity magnitude).
    std::string q_file;
    std::vector<int> plot3d_functions;
};

// Reads the volume (see volume_reader.h for the formats) and contours `field` at `value`: a
// triangle surface, coincident points merged, degenerate and repeated triangles dropped, carried
// fields interpolated linearly. Deterministic. Throws IoError for an unreadable file, an unknown or
// non-scalar field, or an isovalue outside the field's range (no triangles).
Surface extract_isosurface(const std::string& volume_path, const IsosurfaceOptions& options);

} // namespace ddsimp::io
