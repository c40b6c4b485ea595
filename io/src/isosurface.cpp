#include "ddsimp/io/isosurface.h"

#include "ddsimp/io/surface_io.h"
#include "ddsimp/io/volume_reader.h"
#include "ddsimp/io/vtk_messages.h"
#include "ddsimp/io/vtk_surface.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkContourFilter.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkRectilinearGrid.h>
#include <vtkResampleToImage.h>
#include <vtkStructuredGrid.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace ddsimp::io {

namespace {

// Names the resampled volume's valid-point mask gets as a float, so that it interpolates.
const char* const kValidName = "ddsimp valid point";

struct PointHash {
    size_t operator()(const std::array<float, 3>& p) const {
        size_t h = 0;
        for (float x : p) {
            if (x == 0.0f) x = 0.0f; // -0 equals +0, so it must hash alike
            uint32_t bits;
            std::memcpy(&bits, &x, sizeof bits);
            h = h * 0x9E3779B97F4A7C15ull + bits;
        }
        return h;
    }
};

struct TripleHash {
    size_t operator()(const std::array<uint32_t, 3>& t) const {
        return (size_t(t[0]) * 0x9E3779B97F4A7C15ull ^ size_t(t[1])) * 0xBF58476D1CE4E5B9ull ^
               size_t(t[2]);
    }
};

std::string number(double x) {
    std::ostringstream out;
    out << x;
    return out.str();
}

// Samples per axis of the volume as it is: the grid's own for structured data, otherwise about
// as many as it has points, spread over the bounding box.
std::array<int, 3> native_dimensions(vtkDataSet* volume) {
    std::array<int, 3> dims{0, 0, 0};
    if (auto* image = vtkImageData::SafeDownCast(volume))
        image->GetDimensions(dims.data());
    else if (auto* grid = vtkStructuredGrid::SafeDownCast(volume))
        grid->GetDimensions(dims.data());
    else if (auto* rect = vtkRectilinearGrid::SafeDownCast(volume))
        rect->GetDimensions(dims.data());
    else {
        double b[6];
        volume->GetBounds(b);
        const double lengths[3] = {b[1] - b[0], b[3] - b[2], b[5] - b[4]};
        const double volume_size =
            std::max(lengths[0], 1e-30) * std::max(lengths[1], 1e-30) * std::max(lengths[2], 1e-30);
        const double h = std::cbrt(volume_size / double(volume->GetNumberOfPoints()));
        for (int a = 0; a < 3; ++a) dims[a] = std::max(2, int(std::lround(lengths[a] / h)) + 1);
    }
    return dims;
}

// Resamples onto an image with K times the resolution; points outside the input get a valid
// flag of 0 (kValidName) so that triangles there can be dropped after contouring.
vtkSmartPointer<vtkDataSet> resample(vtkDataSet* volume, int factor, const std::string& context) {
    const std::array<int, 3> dims = native_dimensions(volume);
    auto resampler = vtkSmartPointer<vtkResampleToImage>::New();
    resampler->SetInputDataObject(volume);
    resampler->UseInputBoundsOn();
    int samples[3];
    for (int a = 0; a < 3; ++a) samples[a] = std::max(1, (dims[a] - 1) * factor + 1);
    resampler->SetSamplingDimensions(samples);
    {
        VtkMessageCapture messages;
        resampler->Update();
        if (messages.has_error()) throw IoError(context + ": " + messages.first_error());
    }
    vtkSmartPointer<vtkImageData> image = resampler->GetOutput();
    vtkPointData* points = image->GetPointData();
    auto* mask =
        vtkDataArray::SafeDownCast(points->GetAbstractArray(resampler->GetMaskArrayName()));
    auto valid = vtkSmartPointer<vtkFloatArray>::New();
    valid->SetName(kValidName);
    valid->SetNumberOfValues(image->GetNumberOfPoints());
    for (vtkIdType i = 0; i < image->GetNumberOfPoints(); ++i)
        valid->SetValue(i, mask == nullptr || mask->GetComponent(i, 0) != 0 ? 1.0f : 0.0f);
    points->RemoveArray(resampler->GetMaskArrayName());
    points->RemoveArray("vtkGhostType");
    image->GetCellData()->RemoveArray("vtkGhostType");
    points->AddArray(valid);
    return image;
}

// Merges exactly coincident points (the first keeps its index: deterministic), then drops
// triangles that collapse or repeat an earlier one and, after resampling, triangles with a corner
// outside the input (valid < 1), and finally the vertices no triangle uses.
void merge_and_clean(Surface& surface) {
    std::vector<float> valid;
    auto valid_it = std::find_if(surface.fields.begin(), surface.fields.end(),
                                 [](const Field& f) { return f.name == kValidName; });
    if (valid_it != surface.fields.end()) {
        valid = std::move(valid_it->values);
        surface.fields.erase(valid_it);
    }

    const size_t n = surface.vertex_count();
    std::vector<uint32_t> representative(n);
    std::unordered_map<std::array<float, 3>, uint32_t, PointHash> first_at;
    first_at.reserve(n);
    for (size_t v = 0; v < n; ++v) {
        const std::array<float, 3> p{surface.positions[3 * v], surface.positions[3 * v + 1],
                                     surface.positions[3 * v + 2]};
        representative[v] = first_at.try_emplace(p, uint32_t(v)).first->second;
    }

    std::vector<uint32_t> kept;
    kept.reserve(surface.triangles.size());
    std::unordered_set<std::array<uint32_t, 3>, TripleHash> seen;
    seen.reserve(surface.triangle_count());
    for (size_t t = 0; t < surface.triangle_count(); ++t) {
        uint32_t c[3];
        for (int i = 0; i < 3; ++i) c[i] = representative[surface.triangles[3 * t + i]];
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
        if (!valid.empty() &&
            !(valid[c[0]] > 0.999f && valid[c[1]] > 0.999f && valid[c[2]] > 0.999f))
            continue;
        // Two cells can give the same triangle once their points are merged; keep the first.
        std::array<uint32_t, 3> key{c[0], c[1], c[2]};
        std::sort(key.begin(), key.end());
        if (!seen.insert(key).second) continue;
        kept.insert(kept.end(), c, c + 3);
    }
    surface.triangles = std::move(kept);

    std::vector<uint32_t> index(n, UINT32_MAX);
    std::vector<uint32_t> order; // new vertex -> old vertex
    for (uint32_t& v : surface.triangles) {
        if (index[v] == UINT32_MAX) {
            index[v] = uint32_t(order.size());
            order.push_back(v);
        }
        v = index[v];
    }
    std::vector<float> positions(3 * order.size());
    for (size_t i = 0; i < order.size(); ++i)
        for (int c = 0; c < 3; ++c) positions[3 * i + c] = surface.positions[3 * order[i] + c];
    surface.positions = std::move(positions);
    for (Field& field : surface.fields) {
        const size_t k = size_t(field.components);
        std::vector<float> values(k * order.size());
        for (size_t i = 0; i < order.size(); ++i)
            for (size_t c = 0; c < k; ++c) values[k * i + c] = field.values[k * order[i] + c];
        field.values = std::move(values);
    }
}

std::vector<std::string> fields_to_carry(vtkDataSet* volume, const IsosurfaceOptions& options,
                                         const std::string& context) {
    vtkPointData* points = volume->GetPointData();
    std::vector<std::string> names;
    if (options.carry.empty()) {
        for (int i = 0; i < points->GetNumberOfArrays(); ++i) {
            auto* array = vtkDataArray::SafeDownCast(points->GetAbstractArray(i));
            if (array && array->GetName() && array->GetDataType() != VTK_BIT)
                names.emplace_back(array->GetName());
        }
        return names;
    }
    for (const std::string& name : options.carry) {
        auto* array = vtkDataArray::SafeDownCast(points->GetAbstractArray(name.c_str()));
        if (array == nullptr || array->GetDataType() == VTK_BIT)
            throw IoError(context + ": no numeric field '" + name +
                          "' to carry (fields: " + list_point_fields(volume) + ")");
        names.push_back(name);
    }
    return names;
}

} // namespace

Surface extract_isosurface(const std::string& volume_path, const IsosurfaceOptions& options) {
    const std::string context = "cannot extract an isosurface from " + volume_path;
    if (options.resample < 1) throw IoError(context + ": the resample factor must be at least 1");

    vtkSmartPointer<vtkDataSet> volume =
        read_volume({volume_path, options.q_file, options.plot3d_functions});
    auto* scalars =
        vtkDataArray::SafeDownCast(volume->GetPointData()->GetAbstractArray(options.field.c_str()));
    if (scalars == nullptr)
        throw IoError(context + ": no field '" + options.field +
                      "' (fields: " + list_point_fields(volume) + ")");
    if (scalars->GetNumberOfComponents() != 1)
        throw IoError(context + ": field '" + options.field + "' has " +
                      std::to_string(scalars->GetNumberOfComponents()) +
                      " components; only a scalar field can be contoured");
    double range[2];
    scalars->GetRange(range, 0);
    if (!(options.value >= range[0] && options.value <= range[1]))
        throw IoError(context + ": the isovalue " + number(options.value) +
                      " is outside the range [" + number(range[0]) + ", " + number(range[1]) +
                      "] of '" + options.field + "'");
    std::vector<std::string> carry = fields_to_carry(volume, options, context);

    if (options.resample > 1) {
        volume = resample(volume, options.resample, context);
        carry.emplace_back(kValidName);
    }

    VtkMessageCapture messages;
    auto contour = vtkSmartPointer<vtkContourFilter>::New();
    contour->SetInputData(volume);
    contour->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS,
                                    options.field.c_str());
    contour->SetValue(0, options.value);
    contour->GenerateTrianglesOn();
    contour->ComputeNormalsOff();
    contour->ComputeGradientsOff();
    contour->ComputeScalarsOn();

    contour->Update();
    if (messages.has_error()) throw IoError(context + ": " + messages.first_error());

    vtkPolyData* poly = contour->GetOutput();
    // Lines appear only where a 2-D grid was contoured; they are not a surface.
    poly->SetLines(vtkSmartPointer<vtkCellArray>::New());
    poly->SetVerts(vtkSmartPointer<vtkCellArray>::New());
    Surface surface = surface_from_dataset(poly, context, carry);
    merge_and_clean(surface);
    if (surface.triangle_count() == 0)
        throw IoError(context + ": the isovalue " + number(options.value) + " of '" +
                      options.field + "' gives no triangles");
    return surface;
}

} // namespace ddsimp::io
