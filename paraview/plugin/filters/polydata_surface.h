// vtkPolyData <-> ddsimp::Surface for the plugin's filters.
#pragma once

#include "ddsimp/ddsimp.h"

#include <string>

class vtkPolyData;

namespace ddsimp::paraview {

// The triangles of `input` (polygons triangulated, strips split; vertices and lines left out) as
// a Surface: positions as float, every named numeric point-data array as a float field with its
// components, in the input's order. `skipped` names what did not come along ("" if nothing).
Surface surface_from_polydata(vtkPolyData* input, std::string& skipped);

// `surface` as the points, triangles and point data of `output` (float arrays, the fields'
// names); the active attributes are those of `like` where the array is there.
void polydata_from_surface(const Surface& surface, vtkPolyData* like, vtkPolyData* output);

} // namespace ddsimp::paraview
