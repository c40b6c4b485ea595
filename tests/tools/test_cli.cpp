// The ddsimp command line, run as a separate process: exit statuses, one-line errors, --json.
#include "file_test_support.h"
#include "tools_test_support.h"

#include "ddsimp/io/surface_io.h"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sys/wait.h>

using namespace ddsimp;
using namespace ddsimp::tools_test;

namespace {

struct CliRun {
    int status = -1;
    std::string out, err;
};

std::string quote(const std::string& s) {
    std::string q(1, '\'');
    for (char c : s) {
        if (c == '\'')
            q.append("'\\''");
        else
            q.push_back(c);
    }
    q.push_back('\'');
    return q;
}

std::string read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

CliRun ddsimp_cli(const ScratchDir& dir, const std::vector<std::string>& args) {
    std::string command = quote(DDSIMP_CLI);
    for (const std::string& a : args) command.append(" ").append(quote(a));
    const std::string out = dir.file("stdout.txt"), err = dir.file("stderr.txt");
    command.append(" >").append(quote(out)).append(" 2>").append(quote(err));
    command.append(" </dev/null");
    const int raw = std::system(command.c_str());
    CliRun run;
    run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    run.out = read_all(out);
    run.err = read_all(err);
    return run;
}

// One line on stderr, "ddsimp: ..." containing every piece of `expected`.
void expect_one_line_error(const CliRun& run, int status, std::vector<std::string> expected) {
    EXPECT_EQ(run.status, status) << run.err;
    EXPECT_EQ(run.err.rfind("ddsimp: ", 0), 0u) << run.err;
    ASSERT_FALSE(run.err.empty());
    EXPECT_EQ(run.err.back(), '\n');
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    for (const std::string& piece : expected)
        EXPECT_NE(run.err.find(piece), std::string::npos)
            << "missing '" << piece << "' in " << run.err;
}

} // namespace

TEST(Cli, MissingFile) {
    ScratchDir dir;
    const std::string missing = dir.file("missing.vtk");
    expect_one_line_error(ddsimp_cli(dir, {"simplify", missing, "-o", dir.file("o.vtk")}), 1,
                          {missing, "no such file"});
    expect_one_line_error(ddsimp_cli(dir, {"info", missing}), 1, {missing});
}

TEST(Cli, MalformedVtkAndOff) {
    ScratchDir dir;
    const std::string vtk = dir.file("broken.vtk");
    write_text(vtk, "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0");
    expect_one_line_error(ddsimp_cli(dir, {"info", vtk}), 1, {"cannot read " + vtk});
    const std::string off = dir.file("broken.off");
    write_text(off, "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    expect_one_line_error(ddsimp_cli(dir, {"simplify", off, "-o", dir.file("o.off")}), 1,
                          {"cannot read " + off});
    EXPECT_FALSE(std::filesystem::exists(dir.file("o.off")));
}

TEST(Cli, UsageErrorsExitTwo) {
    ScratchDir dir;
    const std::string in = sample_surface();
    expect_one_line_error(ddsimp_cli(dir, {"simplify", in, "-o", dir.file("o.vtk"), "--bogus"}), 2,
                          {"--bogus"});
    expect_one_line_error(ddsimp_cli(dir, {"simplify", in}), 2, {"--output"});
    expect_one_line_error(ddsimp_cli(dir, {"simplify", in, "-o", dir.file("o.vtk"), "--keep", "0.5",
                                           "--triangles", "9"}),
                          2, {});
    expect_one_line_error(
        ddsimp_cli(dir, {"simplify", in, "-o", dir.file("o.vtk"), "--alpha", "2"}), 2, {"alpha"});
    expect_one_line_error(
        ddsimp_cli(dir, {"simplify", in, "-o", dir.file("o.vtk"), "--strategy", "fast"}), 2, {});
    expect_one_line_error(ddsimp_cli(dir, {"frobnicate"}), 2, {"frobnicate"});
    expect_one_line_error(ddsimp_cli(dir, {}), 2, {});
}

TEST(Cli, HelpExitsZero) {
    ScratchDir dir;
    const CliRun run = ddsimp_cli(dir, {"simplify", "--help"});
    EXPECT_EQ(run.status, 0);
    EXPECT_NE(run.out.find("--strategy"), std::string::npos);
}

TEST(Cli, UnknownFieldNamesFieldAndFile) {
    ScratchDir dir;
    const std::string in = sample_surface();
    expect_one_line_error(
        ddsimp_cli(dir, {"simplify", in, "-o", dir.file("o.vtk"), "--fields", "Temp,Nope"}), 1,
        {"'Nope'", in});
    expect_one_line_error(ddsimp_cli(dir, {"compare", in, in, "--field", "Nope"}), 1, {"'Nope'"});
    const std::string volume = shared_data("volumes/disk_out_ref.ex2");
    if (std::filesystem::exists(volume))
        expect_one_line_error(ddsimp_cli(dir, {"isosurface", volume, "--field", "Nope", "--value",
                                               "1", "-o", dir.file("iso.vtk")}),
                              1, {"'Nope'", volume});
}

TEST(Cli, SimplifyReachesTheTargetAndReportsJson) {
    ScratchDir dir;
    const std::string out = dir.file("reduced.vtp");
    const CliRun run =
        ddsimp_cli(dir, {"simplify", sample_surface(), "-o", out, "--triangles", "200", "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    EXPECT_TRUE(run.err.empty()) << run.err; // no progress output when stderr is not a terminal
    const nlohmann::json j = nlohmann::json::parse(run.out);
    for (const char* key : {"triangles_in", "triangles_out", "vertices_out", "seconds", "strategy",
                            "alpha", "target_reached", "stop_reason", "repairs"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["triangles_in"], 756);
    EXPECT_EQ(j["target_reached"], true);
    EXPECT_LE(j["triangles_out"].get<int>(), 200);
    EXPECT_EQ(j["strategy"], "edge");

    const Surface reduced = io::read_surface(out);
    EXPECT_EQ(reduced.triangle_count(), j["triangles_out"].get<size_t>());
    EXPECT_EQ(reduced.vertex_count(), j["vertices_out"].get<size_t>());
    EXPECT_EQ(reduced.fields.size(), 7u);
}

TEST(Cli, SimplifyBothStrategiesHumanSummary) {
    ScratchDir dir;
    for (const char* strategy : {"edge", "vertex"}) {
        const CliRun run =
            ddsimp_cli(dir, {"simplify", sample_surface(), "-o", dir.file("r.off"), "--keep", "0.3",
                             "--strategy", strategy, "--alpha", "0.2"});
        ASSERT_EQ(run.status, 0) << run.err;
        EXPECT_NE(run.out.find("756 ->"), std::string::npos) << run.out;
        EXPECT_NE(run.out.find("target reached"), std::string::npos) << run.out;
    }
}

TEST(Cli, SimplifyOutputIsDeterministic) {
    ScratchDir dir;
    for (const char* name : {"a.vtk", "b.vtk"})
        ASSERT_EQ(ddsimp_cli(dir, {"simplify", sample_surface(), "-o", dir.file(name), "--keep",
                                   "0.25", "--threads", "2"})
                      .status,
                  0);
    EXPECT_EQ(read_all(dir.file("a.vtk")), read_all(dir.file("b.vtk")));
}

TEST(Cli, InfoJson) {
    ScratchDir dir;
    const CliRun run = ddsimp_cli(dir, {"info", sample_surface(), "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    const nlohmann::json j = nlohmann::json::parse(run.out);
    EXPECT_EQ(j["vertices"], 434);
    EXPECT_EQ(j["triangles"], 756);
    EXPECT_EQ(j["fields"].size(), 7u);
    EXPECT_EQ(j["fields"][0]["name"], "V");
    EXPECT_EQ(j["fields"][0]["components"], 3);
    EXPECT_EQ(j["topology"]["boundary_edges"], 110);
    EXPECT_EQ(j["topology"]["boundary_loops"], 1);
    EXPECT_EQ(j["topology"]["components"], 1);
    EXPECT_EQ(j["topology"]["euler_characteristic"], 1); // a disk
    EXPECT_EQ(j["topology"]["nonmanifold_edges"], 0);
}

TEST(Cli, CompareJsonOfASurfaceWithItself) {
    ScratchDir dir;
    const CliRun run = ddsimp_cli(dir, {"compare", sample_surface(), sample_surface(), "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    const nlohmann::json j = nlohmann::json::parse(run.out);
    EXPECT_EQ(j["distance"]["symmetric"]["max"], 0.0);
    EXPECT_EQ(j["fields"].size(), 7u);
    EXPECT_TRUE(j.contains("diagonal"));
}

// The lines of the table that starts at the line holding `header_start` (titles, dashes, rows):
// up to the first blank line or the end.
std::vector<std::string> table_lines(const std::string& out, const std::string& header_start) {
    std::vector<std::string> lines;
    size_t at = out.find(header_start);
    if (at == std::string::npos) return lines;
    at = out.rfind('\n', at) + 1;
    while (at < out.size()) {
        const size_t end = out.find('\n', at);
        const std::string line = out.substr(at, end - at);
        if (line.empty()) break;
        lines.push_back(line);
        at = end + 1;
    }
    return lines;
}

// A table whose last column is right-aligned: every line as long as the rule of dashes, and each
// column's rule as wide as its widest cell, so the columns line up.
void expect_aligned(const std::vector<std::string>& lines, size_t rows) {
    ASSERT_EQ(lines.size(), 2 + rows);
    EXPECT_NE(lines[1].find("--"), std::string::npos) << lines[1];
    for (const std::string& line : lines) EXPECT_EQ(line.size(), lines[1].size()) << line;
}

TEST(Cli, InfoPrintsAnAlignedFieldTable) {
    ScratchDir dir;
    const CliRun run = ddsimp_cli(dir, {"info", sample_surface()});
    ASSERT_EQ(run.status, 0) << run.err;
    EXPECT_NE(run.out.find("triangles              756"), std::string::npos) << run.out;
    const auto lines = table_lines(run.out, "field "); // not the "fields  7" line
    expect_aligned(lines, 9);                          // V's three components and six scalars
    EXPECT_EQ(lines[2].substr(2, 4), "V[0]");
    EXPECT_NE(lines.back().find("H2"), std::string::npos);
}

TEST(Cli, ComparePrintsAnAlignedTable) {
    ScratchDir dir;
    const CliRun run = ddsimp_cli(dir, {"compare", sample_surface(), sample_surface()});
    ASSERT_EQ(run.status, 0) << run.err;
    const auto lines = table_lines(run.out, "error of");
    expect_aligned(lines, 8); // distance and seven fields
    EXPECT_NE(lines[2].find("distance"), std::string::npos);
    EXPECT_NE(lines[2].find("0.0000e+00"), std::string::npos) << lines[2]; // itself: no error
}

TEST(Cli, IsosurfaceWritesTheSurfaceWithFields) {
    const std::string volume = shared_data("volumes/disk_out_ref.ex2");
    DDSIMP_REQUIRE_SHARED(volume);
    ScratchDir dir;
    const std::string out = dir.file("iso.ply");
    const CliRun run = ddsimp_cli(dir, {"isosurface", volume, "--field", "Temp", "--value", "400",
                                        "--carry", "Pres,V", "-o", out, "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    const nlohmann::json j = nlohmann::json::parse(run.out);
    const Surface s = io::read_surface(out);
    EXPECT_EQ(j["triangles"].get<size_t>(), s.triangle_count());
    ASSERT_EQ(s.fields.size(), 2u);
    EXPECT_EQ(s.fields[1].name, "V");
    EXPECT_EQ(s.fields[1].components, 3);
}
