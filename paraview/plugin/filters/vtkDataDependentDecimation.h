// DataDependentDecimation: ddsimp's data-dependent simplification (Frank & Lang) as a VTK filter
// for ParaView. The input's polygons are triangulated; every numeric point-data array comes
// along (as float). The output's field data says how the run went:
//   TargetReached (int, 0/1), StopReason (string, e.g. "target reached"),
//   TrianglesIn, TrianglesOut (id type).
#ifndef vtkDataDependentDecimation_h
#define vtkDataDependentDecimation_h

#include "ddsimpParaViewFiltersModule.h" // export macro

#include <vtkPolyDataAlgorithm.h>

#include <string>
#include <vector>

class DDSIMPPARAVIEWFILTERS_EXPORT vtkDataDependentDecimation : public vtkPolyDataAlgorithm {
public:
    static vtkDataDependentDecimation* New();
    vtkTypeMacro(vtkDataDependentDecimation,
                 vtkPolyDataAlgorithm) void PrintSelf(ostream& os, vtkIndent indent) override;

    enum StrategyType { EDGE_COLLAPSE = 0, VERTEX_REMOVAL = 1 };
    enum PlacementType { LEAST_ERROR = 0, MIDPOINT = 1, VOLUME_PRESERVING = 2 };
    enum DataPlacementType { DATA_LEAST_ERROR = 0, DATA_INTERPOLATED = 1 };

    // Weight of curvature against the data gradient, in [0, 1].
    vtkSetClampMacro(Alpha, double, 0.0, 1.0);
    vtkGetMacro(Alpha, double);
    // Fraction of the triangles to keep, in [0, 1].
    vtkSetClampMacro(Keep, double, 0.0, 1.0);
    vtkGetMacro(Keep, double);
    vtkSetClampMacro(Strategy, int, EDGE_COLLAPSE, VERTEX_REMOVAL);
    vtkGetMacro(Strategy, int);
    // Where an edge collapse puts the new point.
    vtkSetClampMacro(Placement, int, LEAST_ERROR, VOLUME_PRESERVING);
    vtkGetMacro(Placement, int);
    // The data an edge collapse gives the new point (ddsimp::DataPlacement).
    vtkSetClampMacro(DataPlacement, int, DATA_LEAST_ERROR, DATA_INTERPOLATED);
    vtkGetMacro(DataPlacement, int);
    // Dihedral angle (degrees) above which an edge is a feature line; 180: none.
    vtkSetClampMacro(FeatureAngle, double, 0.0, 180.0);
    vtkGetMacro(FeatureAngle, double);

    // The point-data arrays that drive the data term; none added means all of them.
    void AddDrivingField(const char* name);
    void ClearDrivingFields();

protected:
    vtkDataDependentDecimation() = default;
    ~vtkDataDependentDecimation() override = default;
    int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

    double Alpha = 0.5;
    double Keep = 0.1;
    int Strategy = EDGE_COLLAPSE;
    int Placement = LEAST_ERROR;
    int DataPlacement = DATA_LEAST_ERROR;
    double FeatureAngle = 180.0;
    std::vector<std::string> DrivingFields;

private:
    vtkDataDependentDecimation(const vtkDataDependentDecimation&) = delete;
    void operator=(const vtkDataDependentDecimation&) = delete;
};

#endif
