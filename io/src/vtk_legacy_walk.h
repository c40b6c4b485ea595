// The data set of a legacy .vtk file walked with VTK's own parser, as VTK 9.1's POLYDATA and
// UNSTRUCTURED_GRID readers take it, to find what they would fail on, read past or leak.
#pragma once

#include "ddsimp/io/vtk_messages.h"

#include <cstdint>
#include <ios>
#include <map>
#include <optional>
#include <string>

#include <vtkAbstractArray.h>
#include <vtkDataReader.h>
#include <vtkSmartPointer.h>

namespace ddsimp::io::legacy_vtk {

// Walks the data set of a POLYDATA or UNSTRUCTURED_GRID file the way VTK 9.1's
// vtkPolyDataReader::ReadMeshSimple and vtkUnstructuredGridReader::ReadMeshSimple do, section
// by section, with VTK's own ReadString, Read, ReadArray and ReadCellsLegacy on VTK's own stream
// (so every word is the word VTK meets), then its point and cell data as vtkDataReader's
// ReadPointData and ReadCellData do, to the end of the file. Those readers
// return on each error they find without freeing what they have read (the grid reader's cell
// types and cells; the poly data reader goes on reading a closed stream after a cell array it
// cannot read), so every such error is found here first. Besides, the walk refuses what VTK does
// not check and would read past: CELL_TYPES with fewer types than the cells of CELLS, format 5
// offsets that leave their connectivity, a second CELLS or CELL_TYPES in a grid (the first
// leaks), string arrays where VTK needs numbers (it loses them). Every array is read once more
// than VTK reads it (and freed at once).
class DataSetWalk {
public:
    DataSetWalk(const std::string& path, int64_t most_values)
        : path_(path), limit_(most_values), file_size_(most_values / 8),
          reader_(vtkSmartPointer<vtkDataReader>::New()) {}
    ~DataSetWalk() { reader_->CloseVTKFile(); }
    DataSetWalk(const DataSetWalk&) = delete;
    DataSetWalk& operator=(const DataSetWalk&) = delete;

    // "" if VTK reads the data set without an error, else what is wrong.
    std::string problem();

private:
    static std::string not_a_surface(const std::string& type);

    // Where VTK's stream is: just after the word it read last (found without disturbing the
    // stream's state).
    std::streamoff here() const;

    std::string sections();

    int major_version() const { return reader_->GetFileMajorVersion(); }

    // "line n: ", n the line of `offset`.
    std::string at(std::streamoff offset) const;

    std::string field_problem(std::streamoff field_at, const std::string& problem) const;

    bool too_many(vtkIdType tuples, vtkIdType components) const;

    // ReadArray of a `tuples` x `components` array of `type`; `what` names it. The array, or
    // null and `problem` says why. `numeric`: the reader needs a vtkDataArray (VTK's attribute
    // and point readers leak a string array they cannot use).
    vtkSmartPointer<vtkAbstractArray> read_array(const std::string& what, const char* type,
                                                 vtkIdType tuples, vtkIdType components,
                                                 bool numeric, std::string& problem);

    // The same, its type the next word.
    vtkSmartPointer<vtkAbstractArray> read_array(const std::string& what, vtkIdType tuples,
                                                 vtkIdType components, bool numeric,
                                                 std::string& problem);

    std::string points(const std::string& word);

    // VERTICES, LINES, POLYGONS, TRIANGLE_STRIPS or CELLS, in the layout of the file's version;
    // `cells` is how many cells VTK makes of it.
    std::string cell_array(const std::string& word, vtkIdType& cells);

    static std::string number(double value);

    std::string cell_types(const std::string& word);

    // VTK's grid copies one type for each cell of CELLS, whatever CELL_TYPES holds.
    std::string types_for_cells() const;

    vtkIdType poly_cell_count() const;

    // POINT_DATA or CELL_DATA and its count, which VTK compares with the data set's.
    std::string data_count(const std::string& word, vtkIdType expected, const char* of,
                           vtkIdType& count) const;

    // The point data (or cell data) of `count` tuples, as vtkDataReader::ReadPointData and
    // ReadCellData read it, up to the end of the file: each attribute's header, then its array.
    // Their errors do not leak, but what VTK reads past an array it cannot use does: an
    // attribute whose type is not numeric (ReadScalarData and the others lose the string array
    // they cannot use) and a LOOKUP_TABLE that ends early (ReadLutData).
    std::string attributes(bool point_data, vtkIdType count);

    // An attribute "KEYWORD name type" of `components` components (SCALARS, VECTORS, ...);
    // `numeric`: VTK needs a vtkDataArray for it.
    std::string named_array(const std::string& word, vtkIdType count, vtkIdType components,
                            bool numeric);

    // ReadArray's problem with the array whose type comes next, "" if none.
    std::string array_problem(const std::string& what, vtkIdType tuples, vtkIdType components,
                              bool numeric);

    static std::string name_overrun(const std::string& word, const char* name);

    // "SCALARS name type [components]" then "LOOKUP_TABLE name", then the array.
    std::string scalars(const std::string& word, vtkIdType count);

    // "TEXTURE_COORDINATES name dimension type".
    std::string texture_coordinates(const std::string& word, vtkIdType count);

    // "COLOR_SCALARS name components", then unsigned chars (binary) or floats (ASCII).
    std::string color_scalars(const std::string& word, vtkIdType count);

    // "LOOKUP_TABLE name size", then size RGBA colours: VTK leaks the table if they end early.
    std::string lookup_table(const std::string& word);

    std::string path_;
    int64_t limit_;
    std::streamoff file_size_;
    vtkSmartPointer<vtkDataReader> reader_;
    VtkMessageCapture messages_;
    bool grid_ = false;
    vtkIdType points_ = 0;
    std::map<std::string, vtkIdType> poly_cells_;
    std::optional<vtkIdType> grid_cells_, types_;
    vtkIdType last_count_ = 0; // VTK's ncells: the last count of a legacy CELLS or of CELL_TYPES
    // VTK reads POINT_DATA after CELL_DATA (and back) in a call nested in the one before: a file
    // of thousands of switches overflows the stack. No real file has more than one.
    static constexpr int kMostSwitches = 100;
    int switches_ = 0;
};

} // namespace ddsimp::io::legacy_vtk
