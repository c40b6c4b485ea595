// Conversion between ddsimp::Surface and VTK data sets (internal to ddsimp_io).
#pragma once

#include "ddsimp/io/surface_io.h"

#include <vtkSmartPointer.h>

#include <string>
#include <vector>

class vtkDataSet;
class vtkPointData;
class vtkPolyData;

namespace ddsimp::io {

// The triangles of a poly data or unstructured grid as a surface, with the numeric point-data
// arrays as float fields (all, or those in `fields`, in that order) of the kind their type, name
// and role say (integer arrays and ids are labels, the normals directions). Quads, polygons and
// triangle strips are split into triangles, vertex and line cells set aside; `notes`, if given,
// says how many of each. Throws IoError("<context>: ...") naming the first cell that is none of
// these (e.g. a volume cell).
Surface surface_from_dataset(vtkDataSet* data, const std::string& context,
                             const std::vector<std::string>& fields = {}, Notes* notes = nullptr);

// Appends the numeric point-data arrays (bit and string arrays skipped) as float fields; if
// `names` is not empty, only those, in that order (IoError for a missing one, or one that does not
// have one tuple per vertex of `surface`).
void append_point_fields(vtkPointData* point_data, Surface& surface, const std::string& context,
                         const std::vector<std::string>& names = {});

// The surface as poly data: float points, one triangle cell per triangle, fields as float arrays
// (a label of whole numbers as an int array, the first 3-component direction as the normals).
vtkSmartPointer<vtkPolyData> polydata_from_surface(const Surface& surface);

} // namespace ddsimp::io
