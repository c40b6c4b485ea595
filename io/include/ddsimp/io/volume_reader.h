// Reading volumes and grids for isosurface extraction (internal to ddsimp_io).
#pragma once

#include <vtkSmartPointer.h>

#include <string>
#include <vector>

class vtkDataSet;

namespace ddsimp::io {

struct VolumeSource {
    std::string path;
    // PLOT3D only: the solution (Q) file for the grid (XYZ) file in `path`, and extra function
    // numbers to compute (density 100 and momentum 202 are always computed).
    std::string q_path;
    std::vector<int> plot3d_functions;
};

// One data set with every field as point data: legacy .vtk (all arrays), .vti, .vts, .vtr, .vtu,
// Exodus .ex2/.exo/.e (all nodal arrays, blocks merged), or PLOT3D (when q_path is set, or the
// extension is .bin/.xyz/.x). Cell arrays are converted to point arrays (unless a point array has
// the same name). Throws IoError naming the file and the problem.
vtkSmartPointer<vtkDataSet> read_volume(const VolumeSource& source);

// The names of the point arrays, for error messages ("fields: a, b, c").
std::string list_point_fields(vtkDataSet* data);

} // namespace ddsimp::io
