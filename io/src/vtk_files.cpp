#include "vtk_files.h"

#include "ddsimp/io/surface_io.h"
#include "ddsimp/io/vtk_messages.h"
#include "ddsimp/io/vtk_surface.h"
#include "vtk_legacy_checks.h"

#include <vtkDataSet.h>
#include <vtkDataSetReader.h>
#include <vtkPolyData.h>
#include <vtkPolyDataWriter.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

namespace ddsimp::io {

vtkSmartPointer<vtkDataSetReader> legacy_reader(const std::string& path) {
    auto reader = vtkSmartPointer<vtkDataSetReader>::New();
    reader->SetFileName(path.c_str());
    reader->ReadAllScalarsOn();
    reader->ReadAllVectorsOn();
    reader->ReadAllNormalsOn();
    reader->ReadAllTensorsOn();
    reader->ReadAllColorScalarsOn();
    reader->ReadAllTCoordsOn();
    reader->ReadAllFieldsOn();
    return reader;
}

namespace {

Surface read_legacy(const std::string& path, const std::string& context, Notes* notes) {
    if (const std::string problem = check_legacy_vtk(path); !problem.empty())
        throw IoError(context + ": " + problem);
    VtkMessageCapture messages;
    auto reader = legacy_reader(path);
    try {
        reader->Update();
    } catch (const std::exception& e) { // VTK's readers let std::vector's exceptions through
        throw IoError(context + ": VTK's reader threw " + e.what());
    }
    vtkDataSet* data = reader->GetOutput();
    if (messages.has_error()) throw IoError(context + ": " + messages.first_error());
    if (data == nullptr) throw IoError(context + ": not a VTK legacy data set");
    return surface_from_dataset(data, context, {}, notes);
}

Surface read_xml_polydata(const std::string& path, const std::string& context, Notes* notes) {
    VtkMessageCapture messages;
    auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    if (!reader->CanReadFile(path.c_str()))
        throw IoError(context + ": not a VTK XML PolyData file");
    reader->SetFileName(path.c_str());
    reader->Update();
    if (messages.has_error()) throw IoError(context + ": " + messages.first_error());
    return surface_from_dataset(reader->GetOutput(), context, {}, notes);
}

} // namespace

Surface read_vtk_file(const std::string& path, const std::string& extension, Notes* notes) {
    const std::string context = "cannot read " + path;
    return extension == ".vtp" ? read_xml_polydata(path, context, notes)
                               : read_legacy(path, context, notes);
}

void write_vtk_file(const Surface& surface, const std::string& path, const std::string& extension) {
    const std::string context = "cannot write " + path;
    VtkMessageCapture messages;
    vtkSmartPointer<vtkPolyData> poly = polydata_from_surface(surface);
    int ok = 0;
    if (extension == ".vtp") {
        auto writer = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
        writer->SetFileName(path.c_str());
        writer->SetInputData(poly);
        writer->SetDataModeToAppended();
        writer->EncodeAppendedDataOff();
        writer->SetCompressorTypeToZLib();
        writer->SetHeaderTypeToUInt64();
        ok = writer->Write();
    } else {
        auto writer = vtkSmartPointer<vtkPolyDataWriter>::New();
        writer->SetFileName(path.c_str());
        writer->SetInputData(poly);
        writer->SetFileTypeToBinary();
        writer->SetFileVersion(vtkDataWriter::VTK_LEGACY_READER_VERSION_4_2);
        writer->SetHeader("ddsimp surface");
        ok = writer->Write();
    }
    if (messages.has_error()) throw IoError(context + ": " + messages.first_error());
    if (!ok) throw IoError(context + ": the VTK writer failed");
}

} // namespace ddsimp::io
