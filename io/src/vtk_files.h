// Surfaces in VTK's file formats (internal to ddsimp_io; use surface_io.h).
#pragma once

#include "ddsimp/io/surface_io.h"

#include <vtkDataSetReader.h>
#include <vtkSmartPointer.h>

#include <string>

namespace ddsimp::io {

// Legacy .vtk (POLYDATA or UNSTRUCTURED_GRID, ASCII or binary) or XML .vtp; what is not a
// triangle is handled as surface_from_dataset says (vtk_surface.h), with notes.
Surface read_vtk_file(const std::string& path, const std::string& extension, Notes* notes);
// Legacy .vtk (binary POLYDATA, file version 4.2 for older readers) or XML .vtp (zlib, raw).
void write_vtk_file(const Surface& surface, const std::string& path, const std::string& extension);

// A legacy .vtk reader set to keep every array (by default it keeps only the first of each
// attribute kind); not yet updated.
vtkSmartPointer<vtkDataSetReader> legacy_reader(const std::string& path);

} // namespace ddsimp::io
