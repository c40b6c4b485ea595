// extract_isosurface on the shared volumes; expected counts are the data README's "iso check"s.
#include "tools_test_support.h"

#include "ddsimp/io/compare.h"
#include "ddsimp/io/isosurface.h"
#include "ddsimp/io/surface_io.h"

#include <algorithm>
#include <cmath>

using namespace ddsimp;
using namespace ddsimp::tools_test;

namespace {

// The README's counts come from vtkContourFilter as well; allow 1% for a different clean-up.
void expect_near_count(size_t actual, size_t expected) {
    EXPECT_NEAR(double(actual), double(expected), 0.01 * double(expected));
}

// The carotid volume's "scalars" isosurface at `value`.
io::IsosurfaceOptions carotid_scalars(double value) {
    io::IsosurfaceOptions options;
    options.field = "scalars";
    options.value = value;
    return options;
}

std::pair<float, float> range_of(const Field& f) {
    const auto [lo, hi] = std::minmax_element(f.values.begin(), f.values.end());
    return {*lo, *hi};
}

} // namespace

TEST(Isosurface, DiskOutRefTemperatureCarriesAllSevenFields) {
    const std::string path = shared_data("volumes/disk_out_ref.ex2");
    DDSIMP_REQUIRE_SHARED(path);
    io::IsosurfaceOptions options;
    options.field = "Temp";
    options.value = 400;
    const Surface s = io::extract_isosurface(path, options);
    expect_near_count(s.triangle_count(), 2056);
    expect_near_count(s.vertex_count(), 1047);
    ASSERT_EQ(s.fields.size(), 7u);
    for (const char* name : {"Temp", "Pres", "V", "AsH3", "GaMe3", "CH4", "H2"})
        ASSERT_NE(s.find_field(name), nullptr) << name;
    EXPECT_EQ(s.find_field("V")->components, 3);
    const auto [lo, hi] = range_of(*s.find_field("Temp"));
    EXPECT_NEAR(lo, 400.0f, 1e-3f);
    EXPECT_NEAR(hi, 400.0f, 1e-3f);
    // Pressure interpolated, so inside the volume's range [0.0068, 0.0288].
    const auto [plo, phi] = range_of(*s.find_field("Pres"));
    EXPECT_GE(plo, 0.0068f);
    EXPECT_LE(phi, 0.0288f);
}

TEST(Isosurface, CarryChoosesAndOrdersFields) {
    const std::string path = shared_data("volumes/disk_out_ref.ex2");
    DDSIMP_REQUIRE_SHARED(path);
    io::IsosurfaceOptions options;
    options.field = "Temp";
    options.value = 400;
    options.carry = {"V", "Pres"};
    const Surface s = io::extract_isosurface(path, options);
    ASSERT_EQ(s.fields.size(), 2u);
    EXPECT_EQ(s.fields[0].name, "V");
    EXPECT_EQ(s.fields[1].name, "Pres");
}

TEST(Isosurface, EveryTriangleIsProperAndEveryVertexUsed) {
    const std::string path = shared_data("volumes/carotid.vtk");
    DDSIMP_REQUIRE_SHARED(path);
    Surface s = io::extract_isosurface(path, carotid_scalars(175));
    expect_near_count(s.triangle_count(), 13838);
    const RepairReport repairs = validate(s);
    EXPECT_EQ(repairs.degenerate_triangles_dropped, 0u);
    EXPECT_EQ(repairs.duplicate_triangles_dropped, 0u);
    EXPECT_EQ(repairs.unused_vertices, 0u);
    EXPECT_EQ(analyze_topology(s).nonmanifold_edges, 0u);
}

TEST(Isosurface, ResampleTwiceGivesAboutFourTimesTheTriangles) {
    const std::string path = shared_data("volumes/carotid.vtk");
    DDSIMP_REQUIRE_SHARED(path);
    io::IsosurfaceOptions options = carotid_scalars(127); // merged points repeat triangles here
    const size_t plain = io::extract_isosurface(path, options).triangle_count();
    options.resample = 2;
    const Surface fine = io::extract_isosurface(path, options);
    EXPECT_GT(fine.triangle_count(), 3 * plain);
    EXPECT_LT(fine.triangle_count(), 5 * plain);
    EXPECT_EQ(fine.fields.size(), 2u); // scalars, vectors: no resampling mask arrays
    // Resampled contours pass exactly through grid points; merging must leave no duplicates.
    Surface copy = fine;
    const RepairReport repairs = validate(copy);
    EXPECT_EQ(repairs.duplicate_triangles_dropped, 0u);
    EXPECT_EQ(repairs.degenerate_triangles_dropped, 0u);
}

// The carotid at 127 (131 k triangles) has thin tubes and tetrahedra hanging on non-manifold
// edges. Edge collapse used to stop at 14.5% there (every remaining collapse would turn some
// triangle against a corner's input normal) and to fold one such tetrahedron into two triangles
// on the same three vertices, changing the topology.
TEST(Isosurface, CarotidAt127ReducesToTenPercentByEdgeCollapseWithItsTopology) {
    const std::string path = shared_data("volumes/carotid.vtk");
    DDSIMP_REQUIRE_SHARED(path);
    Surface input = io::extract_isosurface(path, carotid_scalars(127));
    validate(input);
    const Topology before = analyze_topology(input);
    ASSERT_GT(before.nonmanifold_edges, 0u);
    Options o;
    o.strategy = Strategy::EdgeCollapse;
    o.keep_fraction = 0.1;
    const Result r = simplify(input, o);
    EXPECT_TRUE(r.target_reached) << r.triangles_out << " of " << r.triangles_in;
    Surface output = r.surface; // needs no repair: no triangle repeats another's vertices
    const RepairReport repairs = validate(output);
    EXPECT_EQ(repairs.duplicate_triangles_dropped, 0u);
    EXPECT_EQ(repairs.degenerate_triangles_dropped, 0u);
    const Topology after = analyze_topology(r.surface);
    EXPECT_EQ(after.euler_characteristic, before.euler_characteristic);
    EXPECT_EQ(after.boundary_loops, before.boundary_loops);
    EXPECT_EQ(after.components, before.components);
    EXPECT_EQ(after.nonmanifold_edges, before.nonmanifold_edges);
}

TEST(Isosurface, Plot3dCombustorDensity) {
    const std::string xyz = shared_data("volumes/combxyz.bin");
    DDSIMP_REQUIRE_SHARED(xyz);
    io::IsosurfaceOptions options;
    options.field = "Density";
    options.value = 0.24;
    options.q_file = shared_data("volumes/combq.bin");
    const Surface s = io::extract_isosurface(xyz, options);
    expect_near_count(s.triangle_count(), 13228);
    ASSERT_NE(s.find_field("Momentum"), nullptr);
    EXPECT_EQ(s.find_field("Momentum")->components, 3);
}

// Edge collapse's data of least error (the default) against the paper's interpolation along the
// edge, on the combustor's density isosurface (its Momentum and the other Plot3D fields) at 10%,
// alpha = 0: the data error `ddsimp compare` measures, the mean over the fields of each field's
// RMS, is lower.
TEST(Isosurface, CombustorEdgeCollapseDataOfLeastErrorBeatsInterpolation) {
    const std::string xyz = shared_data("volumes/combxyz.bin");
    DDSIMP_REQUIRE_SHARED(xyz);
    io::IsosurfaceOptions options;
    options.field = "Density";
    options.value = 0.24;
    options.q_file = shared_data("volumes/combq.bin");
    Surface input = io::extract_isosurface(xyz, options);
    validate(input);
    auto data_error = [&](DataPlacement d) {
        Options o;
        o.alpha = 0;
        o.keep_fraction = 0.1;
        o.data_placement = d;
        const Result r = simplify(input, o);
        EXPECT_TRUE(r.target_reached);
        const tools::CompareReport report = tools::compare_surfaces(input, r.surface, {});
        double sum = 0;
        for (const tools::FieldError& f : report.fields) sum += f.error.symmetric.rms;
        EXPECT_FALSE(report.fields.empty());
        return sum / double(std::max<size_t>(1, report.fields.size()));
    };
    const double least = data_error(DataPlacement::LeastError);
    const double interpolated = data_error(DataPlacement::Interpolated);
    EXPECT_LT(least, interpolated);
}

TEST(Isosurface, CellDataOfRectilinearGridIsConvertedToPoints) {
    const std::string path = shared_data("volumes/cth.vtr");
    DDSIMP_REQUIRE_SHARED(path);
    io::IsosurfaceOptions options;
    options.field = "Volume Fraction for Armor Plate";
    options.value = 0.5;
    options.carry = {"Pressure"};
    const Surface s = io::extract_isosurface(path, options);
    expect_near_count(s.triangle_count(), 18088);
    ASSERT_EQ(s.fields.size(), 1u);
}

TEST(Isosurface, StructuredGridAndUnstructuredXml) {
    const std::string kitchen = shared_data("volumes/kitchen.vtk");
    const std::string fire = shared_data("volumes/fire_ug.vtu");
    DDSIMP_REQUIRE_SHARED(kitchen);
    DDSIMP_REQUIRE_SHARED(fire);
    io::IsosurfaceOptions options;
    options.field = "h1";
    options.value = 20750;
    const Surface k = io::extract_isosurface(kitchen, options);
    expect_near_count(k.triangle_count(), 4930);
    EXPECT_NE(k.find_field("p1"), nullptr); // needs ReadAllScalarsOn
    EXPECT_NE(k.find_field("velocity"), nullptr);
    EXPECT_EQ(k.find_field("hpor"), nullptr); // a bit mask: not data

    options.field = "t";
    options.value = 450;
    expect_near_count(io::extract_isosurface(fire, options).triangle_count(), 2826);
}

TEST(Isosurface, SameInputSameSurface) {
    const std::string path = shared_data("volumes/disk_out_ref.ex2");
    DDSIMP_REQUIRE_SHARED(path);
    io::IsosurfaceOptions options;
    options.field = "Pres";
    options.value = 0.0272;
    const Surface a = io::extract_isosurface(path, options);
    const Surface b = io::extract_isosurface(path, options);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.triangles, b.triangles);
    expect_near_count(a.triangle_count(), 1980);
}

TEST(IsosurfaceErrors, UnknownFieldIsNamedWithTheFieldsThereAre) {
    const std::string path = shared_data("volumes/carotid.vtk");
    DDSIMP_REQUIRE_SHARED(path);
    io::IsosurfaceOptions options;
    options.field = "Temperature";
    options.value = 1;
    try {
        io::extract_isosurface(path, options);
        FAIL() << "expected IoError";
    } catch (const io::IoError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("no field 'Temperature'"), std::string::npos) << message;
        EXPECT_NE(message.find("scalars, vectors"), std::string::npos) << message;
        EXPECT_NE(message.find(path), std::string::npos) << message;
    }
}

TEST(IsosurfaceErrors, ValueOutsideTheRangeAndVectorField) {
    const std::string path = shared_data("volumes/carotid.vtk");
    DDSIMP_REQUIRE_SHARED(path);
    io::IsosurfaceOptions options;
    options.field = "scalars";
    options.value = 1000;
    EXPECT_THROW(io::extract_isosurface(path, options), io::IoError);
    options.field = "vectors";
    options.value = 1;
    EXPECT_THROW(io::extract_isosurface(path, options), io::IoError);
}

TEST(IsosurfaceErrors, Plot3dWithoutSolutionFile) {
    const std::string xyz = shared_data("volumes/combxyz.bin");
    DDSIMP_REQUIRE_SHARED(xyz);
    io::IsosurfaceOptions options;
    options.field = "Density";
    options.value = 0.24;
    EXPECT_THROW(io::extract_isosurface(xyz, options), io::IoError);
}
