// vtkPolyData <-> ddsimp::Surface (see polydata_surface.h).
#include "polydata_surface.h"

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>

namespace ddsimp::paraview {

namespace {

// True if every polygon is a triangle and there are no strips (no triangulation needed).
bool only_triangles(vtkPolyData* input) {
    if (input->GetNumberOfStrips() > 0) return false;
    return input->GetPolys()->IsHomogeneous() == 3 || input->GetNumberOfPolys() == 0;
}

} // namespace

Surface surface_from_polydata(vtkPolyData* input, std::string& skipped) {
    vtkSmartPointer<vtkPolyData> triangles = input;
    if (!only_triangles(input)) {
        vtkNew<vtkTriangleFilter> triangulate;
        triangulate->SetInputData(input);
        triangulate->PassVertsOff();
        triangulate->PassLinesOff();
        triangulate->Update();
        triangles = triangulate->GetOutput();
    }
    skipped.clear();
    if (input->GetNumberOfVerts() > 0 || input->GetNumberOfLines() > 0)
        skipped = "vertex and line cells";

    Surface s;
    const vtkIdType points = triangles->GetNumberOfPoints();
    s.positions.resize(size_t(points) * 3);
    for (vtkIdType i = 0; i < points; ++i) {
        double p[3];
        triangles->GetPoint(i, p);
        for (int c = 0; c < 3; ++c) s.positions[size_t(i) * 3 + c] = float(p[c]);
    }
    s.triangles.reserve(size_t(triangles->GetNumberOfPolys()) * 3);
    auto cells = vtk::TakeSmartPointer(triangles->GetPolys()->NewIterator());
    for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell()) {
        vtkIdType size = 0;
        const vtkIdType* ids = nullptr;
        cells->GetCurrentCell(size, ids);
        for (vtkIdType k = 0; k < size; ++k) s.triangles.push_back(uint32_t(ids[k]));
    }
    vtkPointData* pd = triangles->GetPointData();
    for (int a = 0; a < pd->GetNumberOfArrays(); ++a) {
        vtkDataArray* array = pd->GetArray(a); // null for string and other non-numeric arrays
        const char* name = pd->GetArrayName(a);
        if (!array || !name || !*name) {
            skipped += std::string(skipped.empty() ? "" : ", ") + "array " +
                       (name && *name ? name : std::to_string(a)) + " (not numeric or unnamed)";
            continue;
        }
        Field f;
        f.name = name;
        f.components = array->GetNumberOfComponents();
        f.values.resize(size_t(points) * size_t(f.components));
        for (vtkIdType i = 0; i < points; ++i)
            for (int c = 0; c < f.components; ++c)
                f.values[size_t(i) * size_t(f.components) + size_t(c)] =
                    float(array->GetComponent(i, c));
        s.fields.push_back(std::move(f));
    }
    return s;
}

void polydata_from_surface(const Surface& surface, vtkPolyData* like, vtkPolyData* output) {
    vtkNew<vtkFloatArray> coordinates;
    coordinates->SetNumberOfComponents(3);
    coordinates->SetNumberOfTuples(vtkIdType(surface.vertex_count()));
    std::copy(surface.positions.begin(), surface.positions.end(), coordinates->GetPointer(0));
    vtkNew<vtkPoints> points;
    points->SetData(coordinates);
    output->SetPoints(points);

    const auto count = vtkIdType(surface.triangle_count());
    vtkNew<vtkIdTypeArray> offsets, connectivity;
    offsets->SetNumberOfValues(count + 1);
    for (vtkIdType t = 0; t <= count; ++t) offsets->SetValue(t, 3 * t);
    connectivity->SetNumberOfValues(3 * count);
    for (vtkIdType k = 0; k < 3 * count; ++k) connectivity->SetValue(k, surface.triangles[k]);
    vtkNew<vtkCellArray> polys;
    polys->SetData(offsets, connectivity);
    output->SetPolys(polys);

    vtkPointData* pd = output->GetPointData();
    for (const Field& f : surface.fields) {
        vtkNew<vtkFloatArray> array;
        array->SetName(f.name.c_str());
        array->SetNumberOfComponents(f.components);
        array->SetNumberOfTuples(vtkIdType(surface.vertex_count()));
        std::copy(f.values.begin(), f.values.end(), array->GetPointer(0));
        pd->AddArray(array);
    }
    vtkPointData* in = like->GetPointData();
    for (int attribute = 0; attribute < vtkDataSetAttributes::NUM_ATTRIBUTES; ++attribute)
        if (vtkAbstractArray* active = in->GetAbstractAttribute(attribute))
            if (active->GetName() && pd->GetArray(active->GetName()))
                pd->SetActiveAttribute(active->GetName(), attribute);
}

} // namespace ddsimp::paraview
