#include "ddsimp/io/vtk_surface.h"

#include "ddsimp/io/surface_io.h"
#include "field_kinds.h"
#include "polygons.h"

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellType.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkGenericCell.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ddsimp::io {

namespace {

[[noreturn]] void fail(const std::string& context, const std::string& problem) {
    throw IoError(context + ": " + problem);
}

int cell_dimension(int type) {
    vtkNew<vtkGenericCell> cell;
    cell->SetCellType(type);
    return cell->GetCellDimension();
}

std::string cell_name(int type) {
    const char* name = vtkCellTypes::GetClassNameFromTypeId(type);
    return name ? std::string(name) : "cell of type " + std::to_string(type);
}

// What a data set holds besides triangles, counted for the reader's notes.
struct CellTally {
    PolygonSplitter polygons;
    size_t strips = 0, strip_triangles = 0;
    size_t vertex_cells = 0, line_cells = 0;

    void add_notes(Notes* notes) const {
        if (notes == nullptr) return;
        if (const std::string note = polygons.note(); !note.empty()) notes->push_back(note);
        if (strips > 0)
            notes->push_back(std::to_string(strips) +
                             (strips == 1 ? " triangle strip" : " triangle strips") +
                             " split into " + std::to_string(strip_triangles) + " triangles");
        if (vertex_cells + line_cells > 0) {
            std::string cells;
            if (vertex_cells > 0) cells = std::to_string(vertex_cells) + " vertex";
            if (line_cells > 0)
                cells += (cells.empty() ? "" : " and ") + std::to_string(line_cells) + " line";
            notes->push_back(cells + (vertex_cells + line_cells == 1 ? " cell" : " cells") +
                             " set aside (a surface is made of its triangles and polygons)");
        }
    }
};

// A strip (p0 p1 p2 p3 ...) holds triangles (p0 p1 p2), (p2 p1 p3), ...: every other one is
// reversed to keep a consistent orientation.
void append_strip(Surface& surface, vtkIdType n, const vtkIdType* p, CellTally& tally) {
    ++tally.strips;
    for (vtkIdType i = 0; i + 2 < n; ++i) {
        const vtkIdType a = i % 2 == 0 ? p[i] : p[i + 1], b = i % 2 == 0 ? p[i + 1] : p[i];
        for (vtkIdType v : {a, b, p[i + 2]}) surface.triangles.push_back(uint32_t(v));
        ++tally.strip_triangles;
    }
}

void append_polygon(Surface& surface, vtkIdType n, const vtkIdType* p, CellTally& tally) {
    if (n == 3) {
        for (int c = 0; c < 3; ++c) surface.triangles.push_back(uint32_t(p[c]));
        return;
    }
    const std::vector<uint32_t> corners(p, p + n);
    tally.polygons.split(surface.positions, corners.data(), corners.size(), surface.triangles);
}

void append_polydata_triangles(vtkPolyData* poly, Surface& surface, CellTally& tally) {
    // VTK numbers poly data cells as verts, then lines, then polys, then strips.
    tally.vertex_cells += size_t(poly->GetNumberOfVerts());
    tally.line_cells += size_t(poly->GetNumberOfLines());
    surface.triangles.reserve(3 * size_t(poly->GetNumberOfPolys()));
    auto polys = vtk::TakeSmartPointer(poly->GetPolys()->NewIterator());
    for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell()) {
        vtkIdType n;
        const vtkIdType* p;
        polys->GetCurrentCell(n, p);
        append_polygon(surface, n, p, tally);
    }
    auto strips = vtk::TakeSmartPointer(poly->GetStrips()->NewIterator());
    for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell()) {
        vtkIdType n;
        const vtkIdType* p;
        strips->GetCurrentCell(n, p);
        append_strip(surface, n, p, tally);
    }
}

void append_grid_triangles(vtkUnstructuredGrid* grid, Surface& surface, CellTally& tally,
                           const std::string& context) {
    const vtkIdType cells = grid->GetNumberOfCells();
    surface.triangles.reserve(3 * size_t(cells));
    for (vtkIdType cell = 0; cell < cells; ++cell) {
        const int type = grid->GetCellType(cell);
        vtkIdType n;
        const vtkIdType* p;
        grid->GetCellPoints(cell, n, p);
        if (type == VTK_TRIANGLE || type == VTK_QUAD || type == VTK_POLYGON) {
            append_polygon(surface, n, p, tally);
        } else if (type == VTK_PIXEL && n == 4) { // a quad with its corners in x-y order
            const vtkIdType quad[4] = {p[0], p[1], p[3], p[2]};
            append_polygon(surface, 4, quad, tally);
        } else if (type == VTK_TRIANGLE_STRIP) {
            append_strip(surface, n, p, tally);
        } else if (type == VTK_VERTEX || type == VTK_POLY_VERTEX) {
            ++tally.vertex_cells;
        } else if (type == VTK_LINE || type == VTK_POLY_LINE) {
            ++tally.line_cells;
        } else if (cell_dimension(type) == 3) {
            fail(context, "cell " + std::to_string(cell) + " is a " + cell_name(type) +
                              ", a volume cell (for a volume, use `ddsimp isosurface`)");
        } else {
            fail(context, "cell " + std::to_string(cell) + " is a " + cell_name(type) +
                              "; only triangles, polygons, strips, vertices and lines are read");
        }
    }
}

void append_field(vtkDataArray* array, const std::string& name, Surface& surface, bool is_normals) {
    Field field;
    field.name = name;
    field.components = array->GetNumberOfComponents();
    field.kind = field_kind(name, field.components,
                            array->GetDataType() != VTK_FLOAT && array->GetDataType() != VTK_DOUBLE,
                            is_normals);
    const vtkIdType tuples = array->GetNumberOfTuples();
    field.values.resize(size_t(tuples) * size_t(field.components));
    std::vector<double> tuple(size_t(field.components));
    for (vtkIdType i = 0; i < tuples; ++i) {
        array->GetTuple(i, tuple.data());
        for (int c = 0; c < field.components; ++c)
            field.values[size_t(i) * field.components + c] = float(tuple[c]);
    }
    surface.fields.push_back(std::move(field));
}

bool is_numeric(vtkDataArray* array) {
    return array && array->GetDataType() != VTK_BIT;
}

// VTK's legacy reader keeps a point-data array of another length than the points when the file
// says so (a fuzzed POINT_DATA section): a field must have one tuple per point.
void append_point_field(vtkDataArray* array, const std::string& name, Surface& surface,
                        const std::string& context, bool is_normals) {
    const vtkIdType tuples = array->GetNumberOfTuples(), points = vtkIdType(surface.vertex_count());
    if (array->GetNumberOfComponents() < 1 || tuples != points)
        fail(context, "point field '" + name + "' has " + std::to_string(tuples) + " tuples of " +
                          std::to_string(array->GetNumberOfComponents()) + " components for " +
                          std::to_string(points) + " points");
    append_field(array, name, surface, is_normals);
}

// Whether a label's values are whole numbers an int holds, so that it can be written as one.
bool holds_integers(const Field& field) {
    return std::all_of(field.values.begin(), field.values.end(), [](float v) {
        return v == std::floor(v) && std::abs(v) <= float(std::numeric_limits<int>::max() / 2);
    });
}

} // namespace

void append_point_fields(vtkPointData* point_data, Surface& surface, const std::string& context,
                         const std::vector<std::string>& names) {
    if (names.empty()) {
        for (int i = 0; i < point_data->GetNumberOfArrays(); ++i) {
            vtkDataArray* array = vtkDataArray::SafeDownCast(point_data->GetAbstractArray(i));
            if (!is_numeric(array)) continue;
            const char* name = array->GetName();
            append_point_field(array, name && *name ? name : "array" + std::to_string(i), surface,
                               context, array == point_data->GetNormals());
        }
        return;
    }
    for (const std::string& name : names) {
        vtkDataArray* array =
            vtkDataArray::SafeDownCast(point_data->GetAbstractArray(name.c_str()));
        if (!is_numeric(array)) fail(context, "no numeric point field '" + name + "'");
        append_point_field(array, name, surface, context, array == point_data->GetNormals());
    }
}

Surface surface_from_dataset(vtkDataSet* data, const std::string& context,
                             const std::vector<std::string>& fields, Notes* notes) {
    Surface surface;
    const vtkIdType points = data->GetNumberOfPoints();
    surface.positions.resize(3 * size_t(points));
    double x[3];
    for (vtkIdType i = 0; i < points; ++i) {
        data->GetPoint(i, x);
        for (int c = 0; c < 3; ++c) surface.positions[3 * size_t(i) + c] = float(x[c]);
    }

    CellTally tally;
    if (auto* poly = vtkPolyData::SafeDownCast(data))
        append_polydata_triangles(poly, surface, tally);
    else if (auto* grid = vtkUnstructuredGrid::SafeDownCast(data))
        append_grid_triangles(grid, surface, tally, context);
    else
        fail(context, std::string("it holds a ") + data->GetClassName() +
                          ", not a triangle surface (for a volume, use `ddsimp isosurface`)");
    tally.add_notes(notes);
    append_point_fields(data->GetPointData(), surface, context, fields);
    return surface;
}

vtkSmartPointer<vtkPolyData> polydata_from_surface(const Surface& surface) {
    auto coordinates = vtkSmartPointer<vtkFloatArray>::New();
    coordinates->SetNumberOfComponents(3);
    coordinates->SetNumberOfTuples(vtkIdType(surface.vertex_count()));
    std::copy(surface.positions.begin(), surface.positions.end(), coordinates->GetPointer(0));
    auto points = vtkSmartPointer<vtkPoints>::New();
    points->SetData(coordinates);

    const vtkIdType triangles = vtkIdType(surface.triangle_count());
    auto offsets = vtkSmartPointer<vtkIdTypeArray>::New();
    offsets->SetNumberOfValues(triangles + 1);
    for (vtkIdType t = 0; t <= triangles; ++t) offsets->SetValue(t, 3 * t);
    auto connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
    connectivity->SetNumberOfValues(3 * triangles);
    for (vtkIdType i = 0; i < 3 * triangles; ++i)
        connectivity->SetValue(i, vtkIdType(surface.triangles[size_t(i)]));
    auto cells = vtkSmartPointer<vtkCellArray>::New();
    cells->SetData(offsets, connectivity);

    auto poly = vtkSmartPointer<vtkPolyData>::New();
    poly->SetPoints(points);
    poly->SetPolys(cells);
    bool normals_set = false;
    for (const Field& field : surface.fields) {
        vtkSmartPointer<vtkDataArray> array;
        if (field.kind == FieldKind::Label && holds_integers(field)) {
            auto ints = vtkSmartPointer<vtkIntArray>::New();
            ints->SetNumberOfComponents(field.components);
            ints->SetNumberOfTuples(vtkIdType(surface.vertex_count()));
            std::transform(field.values.begin(), field.values.end(), ints->GetPointer(0),
                           [](float v) { return int(v); });
            array = ints;
        } else {
            auto floats = vtkSmartPointer<vtkFloatArray>::New();
            floats->SetNumberOfComponents(field.components);
            floats->SetNumberOfTuples(vtkIdType(surface.vertex_count()));
            std::copy(field.values.begin(), field.values.end(), floats->GetPointer(0));
            array = floats;
        }
        array->SetName(field.name.c_str());
        poly->GetPointData()->AddArray(array); // in the surface's order
        if (field.kind == FieldKind::Direction && field.components == 3 && !normals_set)
            poly->GetPointData()->SetActiveNormals(field.name.c_str()), normals_set = true;
    }
    return poly;
}

} // namespace ddsimp::io
