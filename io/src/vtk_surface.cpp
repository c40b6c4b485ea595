#include "ddsimp/io/vtk_surface.h"

#include "ddsimp/io/surface_io.h"

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellType.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

namespace ddsimp::io {

namespace {

[[noreturn]] void fail(const std::string& context, const std::string& problem) {
    throw IoError(context + ": " + problem);
}

std::string cell_name(int type) {
    const char* name = vtkCellTypes::GetClassNameFromTypeId(type);
    return name ? std::string(name) : "cell of type " + std::to_string(type);
}

void append_triangle(Surface& surface, vtkIdType a, vtkIdType b, vtkIdType c) {
    surface.triangles.push_back(uint32_t(a));
    surface.triangles.push_back(uint32_t(b));
    surface.triangles.push_back(uint32_t(c));
}

// A strip (p0 p1 p2 p3 ...) holds triangles (p0 p1 p2), (p2 p1 p3), ...: every other one is
// reversed to keep a consistent orientation.
void append_strip(Surface& surface, vtkIdType n, const vtkIdType* p) {
    for (vtkIdType i = 0; i + 2 < n; ++i) {
        if (i % 2 == 0)
            append_triangle(surface, p[i], p[i + 1], p[i + 2]);
        else
            append_triangle(surface, p[i + 1], p[i], p[i + 2]);
    }
}

void append_polydata_triangles(vtkPolyData* poly, Surface& surface, const std::string& context) {
    // VTK numbers poly data cells as verts, then lines, then polys, then strips.
    const vtkIdType verts = poly->GetNumberOfVerts();
    const vtkIdType lines = poly->GetNumberOfLines();
    if (verts > 0) fail(context, "cell 0 is a vertex; only triangles are supported");
    if (lines > 0) fail(context, "cell 0 is a line; only triangles are supported");
    surface.triangles.reserve(3 * size_t(poly->GetNumberOfPolys()));
    vtkIdType cell = 0;
    auto polys = vtk::TakeSmartPointer(poly->GetPolys()->NewIterator());
    for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell(), ++cell) {
        vtkIdType n;
        const vtkIdType* p;
        polys->GetCurrentCell(n, p);
        if (n != 3)
            fail(context, "cell " + std::to_string(cell) + " is a polygon with " +
                              std::to_string(n) + " points; only triangles are supported");
        append_triangle(surface, p[0], p[1], p[2]);
    }
    auto strips = vtk::TakeSmartPointer(poly->GetStrips()->NewIterator());
    for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell()) {
        vtkIdType n;
        const vtkIdType* p;
        strips->GetCurrentCell(n, p);
        append_strip(surface, n, p);
    }
}

void append_grid_triangles(vtkUnstructuredGrid* grid, Surface& surface,
                           const std::string& context) {
    const vtkIdType cells = grid->GetNumberOfCells();
    surface.triangles.reserve(3 * size_t(cells));
    for (vtkIdType cell = 0; cell < cells; ++cell) {
        const int type = grid->GetCellType(cell);
        vtkIdType n;
        const vtkIdType* p;
        grid->GetCellPoints(cell, n, p);
        if (type == VTK_TRIANGLE)
            append_triangle(surface, p[0], p[1], p[2]);
        else if (type == VTK_TRIANGLE_STRIP)
            append_strip(surface, n, p);
        else
            fail(context, "cell " + std::to_string(cell) + " is a " + cell_name(type) +
                              "; only triangles are supported");
    }
}

void append_field(vtkDataArray* array, const std::string& name, Surface& surface) {
    Field field;
    field.name = name;
    field.components = array->GetNumberOfComponents();
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
                        const std::string& context) {
    const vtkIdType tuples = array->GetNumberOfTuples(), points = vtkIdType(surface.vertex_count());
    if (array->GetNumberOfComponents() < 1 || tuples != points)
        fail(context, "point field '" + name + "' has " + std::to_string(tuples) + " tuples of " +
                          std::to_string(array->GetNumberOfComponents()) + " components for " +
                          std::to_string(points) + " points");
    append_field(array, name, surface);
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
                               context);
        }
        return;
    }
    for (const std::string& name : names) {
        vtkDataArray* array =
            vtkDataArray::SafeDownCast(point_data->GetAbstractArray(name.c_str()));
        if (!is_numeric(array)) fail(context, "no numeric point field '" + name + "'");
        append_point_field(array, name, surface, context);
    }
}

Surface surface_from_dataset(vtkDataSet* data, const std::string& context,
                             const std::vector<std::string>& fields) {
    Surface surface;
    if (auto* poly = vtkPolyData::SafeDownCast(data))
        append_polydata_triangles(poly, surface, context);
    else if (auto* grid = vtkUnstructuredGrid::SafeDownCast(data))
        append_grid_triangles(grid, surface, context);
    else
        fail(context, std::string("it holds a ") + data->GetClassName() +
                          ", not a triangle surface (for a volume, use `ddsimp isosurface`)");

    const vtkIdType points = data->GetNumberOfPoints();
    surface.positions.resize(3 * size_t(points));
    double x[3];
    for (vtkIdType i = 0; i < points; ++i) {
        data->GetPoint(i, x);
        for (int c = 0; c < 3; ++c) surface.positions[3 * size_t(i) + c] = float(x[c]);
    }
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
    for (const Field& field : surface.fields) {
        auto array = vtkSmartPointer<vtkFloatArray>::New();
        array->SetName(field.name.c_str());
        array->SetNumberOfComponents(field.components);
        array->SetNumberOfTuples(vtkIdType(surface.vertex_count()));
        std::copy(field.values.begin(), field.values.end(), array->GetPointer(0));
        poly->GetPointData()->AddArray(array);
    }
    return poly;
}

} // namespace ddsimp::io
