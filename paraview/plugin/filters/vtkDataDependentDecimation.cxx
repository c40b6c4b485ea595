// DataDependentDecimation (see vtkDataDependentDecimation.h).
#include "vtkDataDependentDecimation.h"

#include "polydata_surface.h"

#include "ddsimp/ddsimp.h"

#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>

#include <algorithm>
#include <thread>

vtkStandardNewMacro(vtkDataDependentDecimation);

namespace {

template <class Array, class Value>
void add_field_value(vtkFieldData* fd, const char* name, const Value& value) {
    vtkNew<Array> a;
    a->SetName(name);
    a->InsertNextValue(value);
    fd->AddArray(a);
}

} // namespace

void vtkDataDependentDecimation::AddDrivingField(const char* name) {
    if (!name) return;
    this->DrivingFields.emplace_back(name);
    this->Modified();
}

void vtkDataDependentDecimation::ClearDrivingFields() {
    if (this->DrivingFields.empty()) return;
    this->DrivingFields.clear();
    this->Modified();
}

int vtkDataDependentDecimation::RequestData(vtkInformation*, vtkInformationVector** inputs,
                                            vtkInformationVector* outputs) {
    vtkPolyData* input = vtkPolyData::GetData(inputs[0]);
    vtkPolyData* output = vtkPolyData::GetData(outputs);
    if (!input || !output) return 0;

    std::string skipped;
    const ddsimp::Surface surface = ddsimp::paraview::surface_from_polydata(input, skipped);
    if (!skipped.empty()) vtkWarningMacro(<< "left out of the decimation: " << skipped);

    ddsimp::Options options;
    options.alpha = this->Alpha;
    options.keep_fraction = this->Keep;
    options.strategy = this->Strategy == VERTEX_REMOVAL ? ddsimp::Strategy::VertexRemoval
                                                        : ddsimp::Strategy::EdgeCollapse;
    options.placement = this->Placement == MIDPOINT            ? ddsimp::Placement::Midpoint
                        : this->Placement == VOLUME_PRESERVING ? ddsimp::Placement::VolumePreserving
                                                               : ddsimp::Placement::LeastError;
    options.data_placement = this->DataPlacement == DATA_INTERPOLATED
                                 ? ddsimp::DataPlacement::Interpolated
                                 : ddsimp::DataPlacement::LeastError;
    options.feature_angle = this->FeatureAngle;
    options.gradient_fields = this->DrivingFields;
    // The output is the same at any thread count.
    options.threads = int(std::max(1u, std::thread::hardware_concurrency()));
    options.progress = [this](double done) {
        this->UpdateProgress(done);
        return this->GetAbortExecute() == 0;
    };

    ddsimp::Result result;
    try {
        result = ddsimp::simplify(surface, options);
    } catch (const ddsimp::InputError& e) {
        vtkErrorMacro(<< "cannot decimate this surface: " << e.what());
        return 0;
    }
    ddsimp::paraview::polydata_from_surface(result.surface, input, output);

    vtkFieldData* fd = output->GetFieldData();
    fd->ShallowCopy(input->GetFieldData());
    add_field_value<vtkIntArray>(fd, "TargetReached", result.target_reached ? 1 : 0);
    add_field_value<vtkStringArray>(fd, "StopReason", ddsimp::describe(result.stop));
    add_field_value<vtkIdTypeArray>(fd, "TrianglesIn", vtkIdType(result.triangles_in));
    add_field_value<vtkIdTypeArray>(fd, "TrianglesOut", vtkIdType(result.triangles_out));
    return 1;
}

void vtkDataDependentDecimation::PrintSelf(ostream& os, vtkIndent indent) {
    this->Superclass::PrintSelf(os, indent);
    os << indent << "Alpha: " << this->Alpha << "\n"
       << indent << "Keep: " << this->Keep << "\n"
       << indent << "Strategy: " << this->Strategy << "\n"
       << indent << "Placement: " << this->Placement << "\n"
       << indent << "DataPlacement: " << this->DataPlacement << "\n"
       << indent << "FeatureAngle: " << this->FeatureAngle << "\n"
       << indent << "DrivingFields:";
    for (const auto& f : this->DrivingFields) os << " " << f;
    os << "\n";
}
