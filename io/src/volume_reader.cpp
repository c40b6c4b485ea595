#include "ddsimp/io/volume_reader.h"

#include "ddsimp/io/surface_io.h"
#include "ddsimp/io/vtk_messages.h"
#include "vtk_files.h"

#include <vtkAppendFilter.h>
#include <vtkCellData.h>
#include <vtkCellDataToPointData.h>
#include <vtkCompositeDataIterator.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataSet.h>
#include <vtkDataSetReader.h>
#include <vtkExodusIIReader.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkMultiBlockPLOT3DReader.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLRectilinearGridReader.h>
#include <vtkXMLStructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <filesystem>

namespace ddsimp::io {

namespace {

// Runs a reader with VTK's messages captured; throws IoError with VTK's first error.
void update_reader(vtkAlgorithm* reader, const std::string& context) {
    VtkMessageCapture messages;
    reader->Update();
    if (messages.has_error()) throw IoError(context + ": " + messages.first_error());
}

vtkSmartPointer<vtkDataObject> read_legacy(const std::string& path, const std::string& context) {
    auto reader = legacy_reader(path);
    update_reader(reader, context);
    if (reader->GetOutput() == nullptr) throw IoError(context + ": not a VTK legacy data set");
    return reader->GetOutput();
}

template <class Reader>
vtkSmartPointer<vtkDataObject> read_xml(const std::string& path, const std::string& context,
                                        const char* kind) {
    auto reader = vtkSmartPointer<Reader>::New();
    {
        VtkMessageCapture quiet;
        if (!reader->CanReadFile(path.c_str()))
            throw IoError(context + ": not a VTK XML " + kind + " file");
    }
    reader->SetFileName(path.c_str());
    update_reader(reader, context);
    return reader->GetOutputDataObject(0);
}

vtkSmartPointer<vtkDataObject> read_exodus(const std::string& path, const std::string& context) {
    auto reader = vtkSmartPointer<vtkExodusIIReader>::New();
    {
        VtkMessageCapture quiet;
        if (!reader->CanReadFile(path.c_str())) throw IoError(context + ": not an Exodus II file");
    }
    reader->SetFileName(path.c_str());
    // Ids would otherwise be carried as if they were data.
    reader->GenerateObjectIdCellArrayOff();
    reader->GenerateGlobalNodeIdArrayOff();
    reader->GenerateGlobalElementIdArrayOff();
    reader->GenerateImplicitNodeIdArrayOff();
    reader->GenerateImplicitElementIdArrayOff();
    {
        VtkMessageCapture messages;
        reader->UpdateInformation();
        if (messages.has_error()) throw IoError(context + ": " + messages.first_error());
    }
    reader->SetAllArrayStatus(vtkExodusIIReader::NODAL, 1);
    update_reader(reader, context);
    return reader->GetOutputDataObject(0);
}

vtkSmartPointer<vtkDataObject> read_plot3d(const VolumeSource& source, const std::string& context) {
    if (source.q_path.empty())
        throw IoError(context + ": a PLOT3D grid needs its solution file (--q FILE)");
    if (!std::filesystem::exists(source.q_path))
        throw IoError("cannot read " + source.q_path + ": no such file");
    auto reader = vtkSmartPointer<vtkMultiBlockPLOT3DReader>::New();
    reader->SetXYZFileName(source.path.c_str());
    reader->SetQFileName(source.q_path.c_str());
    reader->AutoDetectFormatOn();
    reader->SetScalarFunctionNumber(100); // density
    reader->SetVectorFunctionNumber(202); // momentum
    for (int function : source.plot3d_functions) reader->AddFunction(function);
    update_reader(reader, context);
    return reader->GetOutputDataObject(0);
}

// A composite data set's leaves as one data set (one leaf is returned as it is).
vtkSmartPointer<vtkDataSet> merge_blocks(vtkDataObject* data, const std::string& context) {
    if (auto* set = vtkDataSet::SafeDownCast(data)) return set;
    auto* composite = vtkCompositeDataSet::SafeDownCast(data);
    if (composite == nullptr) throw IoError(context + ": the file holds no data set");
    std::vector<vtkDataSet*> leaves;
    auto it = vtk::TakeSmartPointer(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
        if (auto* leaf = vtkDataSet::SafeDownCast(it->GetCurrentDataObject()))
            if (leaf->GetNumberOfPoints() > 0) leaves.push_back(leaf);
    if (leaves.empty()) throw IoError(context + ": the file holds no points");
    if (leaves.size() == 1) return leaves.front();
    auto append = vtkSmartPointer<vtkAppendFilter>::New();
    append->MergePointsOn(); // blocks share their interface nodes
    for (vtkDataSet* leaf : leaves) append->AddInputData(leaf);
    update_reader(append, context);
    return append->GetOutput();
}

// Cell arrays become point arrays (averaged over the cells around each point); a point array of
// the same name wins.
vtkSmartPointer<vtkDataSet> cell_fields_to_points(vtkDataSet* data, const std::string& context) {
    if (data->GetCellData()->GetNumberOfArrays() == 0) return data;
    auto convert = vtkSmartPointer<vtkCellDataToPointData>::New();
    convert->SetInputData(data);
    convert->PassCellDataOff();
    convert->ProcessAllArraysOn();
    update_reader(convert, context);
    vtkDataSet* converted = convert->GetOutput();
    vtkSmartPointer<vtkDataSet> result;
    result.TakeReference(data->NewInstance());
    result->ShallowCopy(data);
    result->GetCellData()->Initialize();
    vtkPointData* points = result->GetPointData();
    for (int i = 0; i < converted->GetPointData()->GetNumberOfArrays(); ++i) {
        vtkAbstractArray* array = converted->GetPointData()->GetAbstractArray(i);
        if (array->GetName() && !points->HasArray(array->GetName())) points->AddArray(array);
    }
    return result;
}

bool is_plot3d_extension(const std::string& ext) {
    return ext == ".bin" || ext == ".xyz" || ext == ".x" || ext == ".p3d";
}

} // namespace

vtkSmartPointer<vtkDataSet> read_volume(const VolumeSource& source) {
    const std::string& path = source.path;
    const std::string context = "cannot read " + path;
    if (!std::filesystem::exists(path)) throw IoError(context + ": no such file");
    if (std::filesystem::is_directory(path)) throw IoError(context + ": it is a directory");
    const std::string ext = extension_of(path);

    vtkSmartPointer<vtkDataObject> data;
    if (!source.q_path.empty() || is_plot3d_extension(ext))
        data = read_plot3d(source, context);
    else if (ext == ".vtk")
        data = read_legacy(path, context);
    else if (ext == ".vti")
        data = read_xml<vtkXMLImageDataReader>(path, context, "ImageData");
    else if (ext == ".vts")
        data = read_xml<vtkXMLStructuredGridReader>(path, context, "StructuredGrid");
    else if (ext == ".vtr")
        data = read_xml<vtkXMLRectilinearGridReader>(path, context, "RectilinearGrid");
    else if (ext == ".vtu")
        data = read_xml<vtkXMLUnstructuredGridReader>(path, context, "UnstructuredGrid");
    else if (ext == ".ex2" || ext == ".exo" || ext == ".e" || ext == ".exii")
        data = read_exodus(path, context);
    else
        throw IoError(
            context + ": unknown volume extension '" + ext +
            "' (readable: .vtk .vti .vts .vtr .vtu .ex2 .exo, PLOT3D .bin/.xyz with --q)");

    vtkSmartPointer<vtkDataSet> merged = merge_blocks(data, context);
    if (merged->GetNumberOfCells() == 0) throw IoError(context + ": the volume has no cells");
    return cell_fields_to_points(merged, context);
}

std::string list_point_fields(vtkDataSet* data) {
    std::string names;
    vtkPointData* points = data->GetPointData();
    for (int i = 0; i < points->GetNumberOfArrays(); ++i) {
        const char* name = points->GetArrayName(i);
        if (name == nullptr) continue;
        if (!names.empty()) names += ", ";
        names += name;
    }
    return names.empty() ? "none" : names;
}

} // namespace ddsimp::io
