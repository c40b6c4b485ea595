// ddsimp-mpi run under `mpirun --oversubscribe -np N` (mpirun.sh) on real surfaces: target,
// topology, fields, same bytes twice, data error against the single-process result, and errors.
#include "ddsimp/io/compare.h"
#include "ddsimp/io/isosurface.h"
#include "ddsimp/io/surface_io.h"
#include "pieces.h"
#include "test_surfaces.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <unistd.h>

namespace ddsimp::test {
namespace {

namespace fs = std::filesystem;

std::string shared(const std::string& relative) {
    return std::string(DDSIMP_SHARED_DATA) + "/" + relative;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// One scratch directory for the whole run (the inputs are made once), removed at exit.
struct ScratchDir {
    fs::path path = fs::temp_directory_path() / ("ddsimp_mpi_tests_" + std::to_string(getpid()));
    ScratchDir() { fs::create_directories(path); }
    ~ScratchDir() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
};
const fs::path& scratch() {
    static const ScratchDir dir;
    return dir.path;
}

struct MpiRun {
    int status = -1;
    std::string out, err;
};

// mpirun.sh NP ddsimp-mpi ARGS, stdout and stderr captured.
MpiRun run_mpi(int ranks, const std::string& args) {
    static int count = 0;
    const std::string stem = (scratch() / ("run" + std::to_string(++count))).string();
    const std::string command = std::string(DDSIMP_MPIRUN) + " " + std::to_string(ranks) + " " +
                                DDSIMP_MPI + " " + args + " >" + stem + ".out 2>" + stem + ".err";
    MpiRun r;
    const int raw = std::system(command.c_str());
    r.status = raw != -1 && WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = read_file(stem + ".out");
    r.err = read_file(stem + ".err");
    return r;
}

// Lines of `text` that start with `prefix`.
size_t lines_starting(const std::string& text, const std::string& prefix) {
    std::istringstream in(text);
    size_t n = 0;
    for (std::string line; std::getline(in, line);) n += line.rfind(prefix, 0) == 0;
    return n;
}

// A real surface written where ddsimp-mpi can read it, and its repaired copy.
struct Input {
    std::string path;
    Surface repaired;
};

const Input& carotid() { // isosurface of the carotid volume at 127: 130 k triangles, 2 fields
    static const Input input = [] {
        Input in;
        io::IsosurfaceOptions o;
        o.field = "scalars";
        o.value = 127;
        in.path = (scratch() / "carotid.vtp").string();
        Surface s = io::extract_isosurface(shared("volumes/carotid.vtk"), o);
        io::write_surface(s, in.path);
        in.repaired = io::read_surface(in.path);
        validate(in.repaired);
        return in;
    }();
    return input;
}

const Input& motorbike() { // a cutting plane: boundaries, non-manifold edges, duplicates
    static const Input input = [] {
        Input in;
        in.path = shared("surfaces/motorBike_cuttingPlane_500/p_yNormal.vtk");
        in.repaired = io::read_surface(in.path);
        validate(in.repaired);
        return in;
    }();
    return input;
}

struct CliCase {
    const char* name;
    const Input& (*input)();
    const char* options;
    Options single; // the same options for the single-process run
};
void PrintTo(const CliCase& c, std::ostream* os) {
    *os << c.name;
}

Options vertex_removal(double keep) {
    Options o;
    o.strategy = Strategy::VertexRemoval;
    o.keep_fraction = keep;
    return o;
}
Options edge_collapse(double keep) {
    Options o;
    o.keep_fraction = keep;
    return o;
}

class FourRanks : public ::testing::TestWithParam<CliCase> {
protected:
    void SetUp() override {
        if (!fs::exists(shared("volumes/carotid.vtk")))
            GTEST_SKIP() << "shared data not found under " << DDSIMP_SHARED_DATA;
    }
    // ddsimp-mpi on 4 ranks, output `name`, with the case's options.
    std::string run(const std::string& name, nlohmann::json* report = nullptr) {
        const CliCase& c = GetParam();
        const std::string out = (scratch() / (std::string(c.name) + "_" + name)).string();
        const MpiRun r =
            run_mpi(4, "simplify " + c.input().path + " -o " + out + " " + c.options + " --json");
        EXPECT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(r.err, "");
        if (report) *report = nlohmann::json::parse(r.out);
        return out;
    }
};

INSTANTIATE_TEST_SUITE_P(
    Real, FourRanks,
    // One process reaches 20% on both (edge collapse stops near 15% on this isosurface).
    ::testing::Values(CliCase{"carotid_edge", carotid, "--keep 0.2", edge_collapse(0.2)},
                      CliCase{"carotid_vertex", carotid, "--keep 0.2 --strategy vertex",
                              vertex_removal(0.2)},
                      CliCase{"motorbike_edge", motorbike, "--keep 0.2", edge_collapse(0.2)}),
    [](const auto& info) { return std::string(info.param.name); });

TEST_P(FourRanks, ReachesTheTargetKeepsTopologyAndFields) {
    nlohmann::json report;
    const Surface out = io::read_surface(run("a.vtp", &report));
    const Surface& in = GetParam().input().repaired;
    const size_t target =
        size_t(std::floor(GetParam().single.keep_fraction * double(in.triangle_count()) + 1e-9));
    EXPECT_TRUE(report["split"].get<bool>()) << report.dump();
    EXPECT_EQ(report["pieces"].size(), 4u);
    EXPECT_TRUE(report["target_reached"].get<bool>()) << report.dump();
    EXPECT_LE(out.triangle_count(), target);
    EXPECT_GE(out.triangle_count() + 2, target); // one operation removes at most 2 triangles
    EXPECT_EQ(report["triangles_out"].get<size_t>(), out.triangle_count());
    EXPECT_EQ(report["triangles_in"].get<size_t>(), in.triangle_count());
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(out)));
    EXPECT_TRUE(fields_carried(in, out));
}

TEST_P(FourRanks, SameBytesTwice) {
    EXPECT_EQ(read_file(run("first.vtp")), read_file(run("second.vtp")));
}

// Each field's RMS data error (both ways, divided by the field's range) is at most 1.25 times
// that of the single-process result for the same options.
TEST_P(FourRanks, DataErrorWithinAQuarterOfOneProcess) {
    const Surface& in = GetParam().input().repaired;
    const Surface out = io::read_surface(run("b.vtp"));
    const Result single = simplify(in, GetParam().single);
    const tools::CompareReport one = tools::compare_surfaces(in, single.surface, {});
    const tools::CompareReport four = tools::compare_surfaces(in, out, {});
    ASSERT_EQ(one.fields.size(), in.fields.size());
    ASSERT_EQ(four.fields.size(), in.fields.size());
    for (size_t i = 0; i < one.fields.size(); ++i) {
        const double a = one.fields[i].error.symmetric.rms, b = four.fields[i].error.symmetric.rms;
        EXPECT_LE(b, 1.25 * a) << one.fields[i].name << ": 1 process " << a << ", 4 ranks " << b;
        RecordProperty(one.fields[i].name + "_rms_ratio", std::to_string(b / a));
    }
}

// A label field (ids) crosses the ranks as a label: every value of the stitched result is one of
// the input's ids, never a mix of two, and it is written back as integers (read as a label).
TEST(FourRanksKinds, ALabelFieldIsCarriedNotInterpolated) {
    Surface s = carotid().repaired;
    Field ids{"PointId", 1, {}, FieldKind::Label};
    for (size_t v = 0; v < s.vertex_count(); ++v) ids.values.push_back(float(10 * v + 1));
    s.fields.push_back(ids);
    const std::string in = (scratch() / "carotid-ids.vtp").string();
    const std::string out = (scratch() / "carotid-ids-out.vtp").string();
    io::write_surface(s, in);
    const MpiRun r = run_mpi(4, "simplify " + in + " -o " + out + " --keep 0.2");
    ASSERT_EQ(r.status, 0) << r.err;
    const Surface reduced = io::read_surface(out);
    const Field* got = reduced.find_field("PointId");
    ASSERT_NE(got, nullptr);
    EXPECT_EQ(got->kind, FieldKind::Label);
    const std::set<float> input_ids(ids.values.begin(), ids.values.end());
    for (size_t v = 0; v < got->values.size(); ++v)
        ASSERT_TRUE(input_ids.count(got->values[v])) << "vertex " << v << ": " << got->values[v];
}

TEST(OneRank, SameBytesAsTheLibrary) {
    if (!fs::exists(shared("surfaces/earth.vtp"))) GTEST_SKIP() << "no shared data";
    const std::string in = shared("surfaces/earth.vtp");
    const std::string out = (scratch() / "earth1.vtp").string();
    const MpiRun r = run_mpi(1, "simplify " + in + " -o " + out + " --keep 0.2");
    ASSERT_EQ(r.status, 0) << r.err;
    Options o;
    o.keep_fraction = 0.2;
    const std::string expected = (scratch() / "earth_library.vtp").string();
    io::write_surface(simplify(io::read_surface(in), o).surface, expected);
    EXPECT_EQ(read_file(out), read_file(expected));
}

// The carotid isosurface cut into 4 files (each with its copies of the border vertices), as a
// simulation writes it one file per rank; written once.
std::string carotid_pieces() {
    static const std::string pattern = [] {
        const Surface& s = carotid().repaired;
        const auto pieces = mpi::split_surface(s, mpi::bisect_triangles(s, 4), 4);
        for (size_t r = 0; r < pieces.size(); ++r)
            io::write_surface(pieces[r].surface,
                              (scratch() / ("part-" + std::to_string(r) + ".vtp")).string());
        return (scratch() / "part-{rank}.vtp").string();
    }();
    return pattern;
}

TEST(Pieces, OneFilePerRank) {
    if (!fs::exists(shared("volumes/carotid.vtk"))) GTEST_SKIP() << "no shared data";
    const std::string out = (scratch() / "from_pieces.vtp").string();
    const MpiRun r =
        run_mpi(4, "simplify '" + carotid_pieces() + "' --pieces -o " + out + " --keep 0.2 --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json report = nlohmann::json::parse(r.out);
    const Surface& in = carotid().repaired;
    const Surface result = io::read_surface(out);
    EXPECT_TRUE(report["target_reached"].get<bool>()) << report.dump();
    EXPECT_EQ(report["triangles_in"].get<size_t>(), in.triangle_count());
    EXPECT_LE(result.triangle_count(), size_t(0.2 * double(in.triangle_count())));
    EXPECT_TRUE(topology_kept(analyze_topology(in), analyze_topology(result)));
    EXPECT_TRUE(fields_carried(in, result));
}

// Every failure: exit status, one "ddsimp-mpi:" line naming the problem, and no rank left behind
// (mpirun returns).
void expect_failure(const MpiRun& r, int status, const std::string& says) {
    EXPECT_EQ(r.status, status) << r.err;
    EXPECT_EQ(lines_starting(r.err, "ddsimp-mpi: "), 1u) << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
}

TEST(Errors, MissingInput) {
    const std::string missing = (scratch() / "no_such_file.vtp").string();
    expect_failure(run_mpi(4, "simplify " + missing + " -o " + (scratch() / "x.vtp").string()), 1,
                   "no_such_file.vtp");
}

TEST(Errors, MalformedInput) {
    const std::string bad = (scratch() / "garbage.vtk").string();
    std::ofstream(bad) << "# vtk DataFile Version 3.0\nnot really\nASCII\nDATASET POLYDATA\n"
                          "POINTS 3 float\n0 0 0 1 0\n";
    expect_failure(run_mpi(4, "simplify " + bad + " -o " + (scratch() / "x.vtp").string()), 1,
                   "garbage.vtk");
}

TEST(Errors, UnknownField) {
    const std::string in = shared("surfaces/earth.vtp");
    if (!fs::exists(in)) GTEST_SKIP() << "no shared data";
    expect_failure(run_mpi(4, "simplify " + in + " -o " + (scratch() / "x.vtp").string() +
                                  " --fields nosuchfield"),
                   1, "nosuchfield");
}

TEST(Errors, UnwritableOutput) {
    const std::string in = shared("surfaces/earth.vtp");
    if (!fs::exists(in)) GTEST_SKIP() << "no shared data";
    expect_failure(run_mpi(4, "simplify " + in + " -o /nonexistent/dir/out.vtp"), 1, "out.vtp");
}

// Rank 2's file is broken: rank 0 reports it, every rank stops.
TEST(Errors, BadPieceOnOneRank) {
    const fs::path dir = scratch() / "broken_pieces";
    fs::create_directories(dir);
    for (int r = 0; r < 4; ++r) {
        const std::string file = (dir / ("p-" + std::to_string(r) + ".vtk")).string();
        if (r == 2)
            std::ofstream(file) << "# vtk DataFile Version 3.0\nbroken\nASCII\nDATASET POLYDATA\n";
        else
            io::write_surface(with_test_fields(grid(8, 8)), file);
    }
    const MpiRun r = run_mpi(4, "simplify '" + (dir / "p-{rank}.vtk").string() + "' --pieces -o " +
                                    (dir / "out.vtp").string());
    expect_failure(r, 1, "rank 2: ");
    EXPECT_NE(r.err.find("p-2.vtk"), std::string::npos) << r.err;
}

// Every file reads, but they do not fit together: rank 0 finds out after the others are done
// reading, and still every rank stops.
TEST(Errors, PiecesWithDifferentFields) {
    const fs::path dir = scratch() / "mismatched_pieces";
    fs::create_directories(dir);
    for (int r = 0; r < 4; ++r)
        io::write_surface(r == 2 ? grid(8, 8) : with_test_fields(grid(8, 8)),
                          (dir / ("q-" + std::to_string(r) + ".vtp")).string());
    expect_failure(run_mpi(4, "simplify '" + (dir / "q-{rank}.vtp").string() + "' --pieces -o " +
                                  (dir / "out.vtp").string()),
                   1, "piece 2 has 0 fields");
}

TEST(Errors, PiecesNeedARankPattern) {
    expect_failure(run_mpi(2, "simplify in.vtp --pieces -o out.vtp"), 2, "{rank}");
}

TEST(Errors, BadOptionIsAUsageError) {
    expect_failure(run_mpi(4, "simplify in.vtp -o out.vtp --keep 2"), 2, "--keep");
    expect_failure(run_mpi(2, "simplfy in.vtp -o out.vtp"), 2, "unknown command 'simplfy'");
}

} // namespace
} // namespace ddsimp::test
