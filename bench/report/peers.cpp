#include "peers.h"

#include "meshopt_js_peer.h"

#include "ddsimp/io/vtk_messages.h" // io/, from the ddsimp_io target
#include "ddsimp/io/vtk_surface.h"

#include <meshoptimizer.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <vtkAlgorithm.h>
#include <vtkDataArray.h>
#include <vtkDecimatePro.h>
#include <vtkIdTypeArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkQuadricDecimation.h>

#include <cfloat>
#include <stdexcept>
#include <unordered_map>

namespace ddsimp::report {

Surface subset_of(const Surface& input, const std::vector<uint32_t>& triangles) {
    Surface out;
    std::unordered_map<uint32_t, uint32_t> new_index;
    std::vector<uint32_t> kept; // input vertex of each output vertex
    out.triangles.reserve(triangles.size());
    for (uint32_t v : triangles) {
        auto [it, added] = new_index.try_emplace(v, static_cast<uint32_t>(kept.size()));
        if (added) kept.push_back(v);
        out.triangles.push_back(it->second);
    }
    out.positions.reserve(kept.size() * 3);
    for (uint32_t v : kept)
        for (int c = 0; c < 3; ++c) out.positions.push_back(input.positions[3 * v + c]);
    for (const Field& f : input.fields) {
        Field g{f.name, f.components, {}};
        g.values.reserve(kept.size() * f.components);
        for (uint32_t v : kept)
            for (int c = 0; c < f.components; ++c)
                g.values.push_back(f.values[size_t(v) * f.components + c]);
        out.fields.push_back(std::move(g));
    }
    return out;
}

namespace {

PeerOutput run_ddsimp(const Surface& input, const PeerRequest& request, Strategy strategy) {
    Options options;
    options.alpha = request.alpha;
    options.strategy = strategy;
    options.target_triangles = request.target_triangles;
    options.threads = 1;
    Result result = simplify(input, options);
    PeerOutput out;
    out.surface = std::move(result.surface);
    out.triangles_seen = result.triangles_in;
    if (!result.target_reached) out.message = describe(result.stop);
    return out;
}

// meshoptimizer 0.18 has no attribute-aware simplifier (meshopt_simplifyWithAttributes came in
// 0.20): geometry only, the data follows the kept vertices. FLT_MAX: only the target stops it.
PeerOutput run_meshopt(const Surface& input, const PeerRequest& request) {
    std::vector<uint32_t> destination(input.triangles.size());
    float error = 0;
    const size_t count = meshopt_simplify(
        destination.data(), input.triangles.data(), input.triangles.size(), input.positions.data(),
        input.vertex_count(), 3 * sizeof(float), request.target_triangles * 3, FLT_MAX, 0, &error);
    destination.resize(count);
    PeerOutput out;
    out.surface = subset_of(input, destination);
    out.triangles_seen = input.triangle_count();
    return out;
}

// The poly data handed to VTK's filters: the fields as point arrays, the first 1-component field
// as the active scalars and the first 3-component one as the active vectors (the attributes
// vtkQuadricDecimation's error metric can weigh).
vtkSmartPointer<vtkPolyData> vtk_input(const Surface& input) {
    vtkSmartPointer<vtkPolyData> poly = io::polydata_from_surface(input);
    vtkPointData* pd = poly->GetPointData();
    bool scalars = false, vectors = false;
    for (const Field& f : input.fields) {
        if (f.components == 1 && !scalars) scalars = pd->SetActiveScalars(f.name.c_str()) >= 0;
        if (f.components == 3 && !vectors) vectors = pd->SetActiveVectors(f.name.c_str()) >= 0;
    }
    return poly;
}

// VTK's filters aim at a reduction: the fraction of the triangles to remove.
double target_reduction(const Surface& input, const PeerRequest& request) {
    return 1.0 - double(request.target_triangles) / double(input.triangle_count());
}

// Runs the filter; an error VTK reports (only by printing it) marks the output as failed.
void update_reporting_errors(vtkAlgorithm* filter, PeerOutput& out) {
    io::VtkMessageCapture messages;
    filter->Update();
    if (messages.has_error()) {
        out.failed = true;
        out.message = messages.first_error();
    }
}

// vtkQuadricDecimation with its attribute error metric (Hoppe's): the active scalars and vectors
// count in the quadrics and are interpolated at the new points.
PeerOutput run_vtk_quadric(const Surface& input, const PeerRequest& request) {
    auto filter = vtkSmartPointer<vtkQuadricDecimation>::New();
    filter->SetInputData(vtk_input(input));
    filter->SetTargetReduction(target_reduction(input, request));
    filter->AttributeErrorMetricOn();
    filter->ScalarsAttributeOn();
    filter->VectorsAttributeOn();
    filter->NormalsAttributeOff();
    filter->TCoordsAttributeOff();
    filter->TensorsAttributeOff();
    PeerOutput out;
    update_reporting_errors(filter, out);
    out.surface = io::surface_from_dataset(filter->GetOutput(), "vtkQuadricDecimation output");
    out.triangles_seen = input.triangle_count();
    return out;
}

// vtkDecimatePro with the topology preserved (no splitting): it keeps a subset of the points in
// place and passes their point data on.
PeerOutput run_vtk_decimatepro(const Surface& input, const PeerRequest& request) {
    vtkSmartPointer<vtkPolyData> poly = vtk_input(input);
    auto ids = vtkSmartPointer<vtkIdTypeArray>::New();
    ids->SetName("ddsimp report input id");
    ids->SetNumberOfTuples(poly->GetNumberOfPoints());
    for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) ids->SetValue(i, i);
    poly->GetPointData()->AddArray(ids);

    auto filter = vtkSmartPointer<vtkDecimatePro>::New();
    filter->SetInputData(poly);
    filter->SetTargetReduction(target_reduction(input, request));
    filter->PreserveTopologyOn();
    filter->SplittingOff();
    filter->BoundaryVertexDeletionOn();
    PeerOutput out;
    update_reporting_errors(filter, out);
    vtkPolyData* result = filter->GetOutput();
    vtkDataArray* kept = result->GetPointData()->GetArray("ddsimp report input id");
    if (!kept) throw std::runtime_error("vtkDecimatePro dropped the point ids");
    // Back to input vertex indices, so that the data is the input's exact values.
    Surface geometry =
        io::surface_from_dataset(result, "vtkDecimatePro output", {"ddsimp report input id"});
    std::vector<uint32_t> triangles;
    triangles.reserve(geometry.triangles.size());
    for (uint32_t v : geometry.triangles)
        triangles.push_back(static_cast<uint32_t>(kept->GetTuple1(v)));
    out.surface = subset_of(input, triangles);
    out.triangles_seen = input.triangle_count();
    return out;
}

using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// OpenMesh's Decimater with a quadric priority and a normal-flip guard (the classic set-up). The
// mesh is built face by face: OpenMesh refuses a face that would make an edge or vertex
// non-manifold, so such parts are left out (and say so); the collapses are half-edge collapses
// onto kept vertices, so the data follows the vertices.
PeerOutput run_openmesh(const Surface& input, const PeerRequest& request) {
    OMesh mesh;
    OpenMesh::VPropHandleT<int> origin;
    mesh.add_property(origin);
    std::vector<OMesh::VertexHandle> handles(input.vertex_count());
    for (size_t v = 0; v < input.vertex_count(); ++v) {
        const float* p = &input.positions[3 * v];
        handles[v] = mesh.add_vertex(OMesh::Point(p[0], p[1], p[2]));
        mesh.property(origin, handles[v]) = static_cast<int>(v);
    }
    size_t refused = 0;
    {
        // OpenMesh prints "complex edge/vertex" for each refused face; not useful here.
        omerr().disable();
        for (size_t t = 0; t < input.triangle_count(); ++t) {
            const uint32_t* c = &input.triangles[3 * t];
            if (!mesh.add_face(handles[c[0]], handles[c[1]], handles[c[2]]).is_valid()) ++refused;
        }
        omerr().enable();
    }
    const size_t loaded = input.triangle_count() - refused;

    using Decimater = OpenMesh::Decimater::DecimaterT<OMesh>;
    using Quadric = OpenMesh::Decimater::ModQuadricT<OMesh>;
    using NormalFlipping = OpenMesh::Decimater::ModNormalFlippingT<OMesh>;
    mesh.request_face_normals();
    mesh.update_face_normals();
    Decimater decimater(mesh);
    Quadric::Handle quadric;
    NormalFlipping::Handle flipping;
    decimater.add(quadric);
    decimater.add(flipping);
    decimater.module(quadric).unset_max_err();
    decimater.initialize();
    // The target counts the triangles it could load; the full input's target is what counts.
    decimater.decimate_to_faces(0, request.target_triangles);
    mesh.garbage_collection();

    std::vector<uint32_t> triangles;
    triangles.reserve(mesh.n_faces() * 3);
    for (OMesh::FaceHandle f : mesh.faces())
        for (OMesh::VertexHandle v : mesh.fv_range(f))
            triangles.push_back(static_cast<uint32_t>(mesh.property(origin, v)));
    PeerOutput out;
    out.surface = subset_of(input, triangles);
    out.triangles_seen = loaded;
    if (refused)
        out.message = "OpenMesh refused " + std::to_string(refused) + " of " +
                      std::to_string(input.triangle_count()) + " triangles (non-manifold)";
    return out;
}

} // namespace

const std::vector<std::string>& peer_names() {
    static const std::vector<std::string> names = {
        "ddsimp-edge", "ddsimp-vertex",      "meshopt",       "vtk-quadric", "vtk-decimatepro",
        "openmesh",    "meshopt-attributes", "meshopt-update"};
    return names;
}

PeerOutput run_peer(const std::string& peer, const Surface& input, const PeerRequest& request) {
    if (peer == "ddsimp-edge") return run_ddsimp(input, request, Strategy::EdgeCollapse);
    if (peer == "ddsimp-vertex") return run_ddsimp(input, request, Strategy::VertexRemoval);
    if (peer == "meshopt") return run_meshopt(input, request);
    if (peer == "vtk-quadric") return run_vtk_quadric(input, request);
    if (peer == "vtk-decimatepro") return run_vtk_decimatepro(input, request);
    if (peer == "openmesh") return run_openmesh(input, request);
    if (peer == "meshopt-attributes")
        return run_meshopt_js(input, request, MeshoptJsMode::Attributes);
    if (peer == "meshopt-update") return run_meshopt_js(input, request, MeshoptJsMode::Update);
    throw std::invalid_argument("unknown peer '" + peer + "'");
}

} // namespace ddsimp::report
