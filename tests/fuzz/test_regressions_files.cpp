// Crashes and hangs the fuzz targets found in the file readers, as tests of the code that was
// fixed (the inputs themselves are in corpus/read_*/ and replayed by fuzz_replay_read_*).
#include "surface_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

using namespace ddsimp;

namespace {

std::string write_file(const std::string& name, const std::string& bytes) {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("ddsimp-fuzz-regressions-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string path = (dir / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
}

// A corpus input (named without an extension) as a .vtk file.
std::string corpus_file_as_vtk(const std::string& name) {
    std::ifstream in(std::string(DDSIMP_FUZZ_CORPUS) + "/read_vtk/" + name, std::ios::binary);
    return write_file(name + ".vtk", std::string{std::istreambuf_iterator<char>(in), {}});
}

std::string read_error(const std::string& path) {
    try {
        io::read_surface(path);
    } catch (const io::IoError& e) {
        return e.what();
    }
    return "";
}

const char* const kTetrahedronBody = "4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                     "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

} // namespace

// read_off, timeout-3d36bee6… and oom-3d36bee6… (the seed tetra-comment.off): a "# comment" line
// in an OFF file made the header check skip comments with ignore(SIZE_MAX), which ignores
// nothing, so it looped for ever; with that fixed, OpenMesh's OFF reader took the comment for the
// counts and asked for 4.8 GB. Such files are refused with a clear error instead.
TEST(FuzzRegressions, OffFileWithACommentLineIsRefusedNotLoopedOver) {
    const std::string path =
        write_file("comment.off", std::string("OFF\n# a comment\n") + kTetrahedronBody);
    EXPECT_EQ(read_error(path), "cannot read " + path +
                                    ": comment lines are not supported (OpenMesh's OFF reader "
                                    "misreads them)");
    const Surface s =
        io::read_surface(write_file("plain.off", std::string("OFF\n") + kTetrahedronBody));
    EXPECT_EQ(s.vertex_count(), 4u);
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}));
}

// Counts no file can hold are "ends early", not sums that wrap around to pass the check.
TEST(FuzzRegressions, OffCountsThatWouldOverflowAreRefused) {
    const std::string why = read_error(
        write_file("huge.off", "OFF\n6148914691236517206 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
    EXPECT_NE(why.find("the file ends early: its header declares 6148914691236517206 vertices"),
              std::string::npos)
        << why;
}

// read_vtk, crash-01b55bbd…: a legacy file whose POLYGONS array has a cell count larger than
// the array made VTK's reader read past its end (SEGV in vtkCellArray::AppendLegacyFormat).
TEST(FuzzRegressions, LegacyVtkCellCountsPastTheirArrayAreRefused) {
    const std::string head = "# vtk DataFile Version 4.2\nbad cells\nASCII\nDATASET POLYDATA\n"
                             "POINTS 3 float\n0 0 0 1 0 0 0 1 0\n";
    const std::string path = write_file("bad-cells.vtk", head + "POLYGONS 1 4\n70000 0 1 2\n");
    EXPECT_EQ(read_error(path), "cannot read " + path +
                                    ": POLYGONS 1 4: cell 0 has 70000 points, more than the "
                                    "array holds");
    const std::string few = write_file("few-cells.vtk", head + "POLYGONS 2 4\n3 0 1 2\n");
    EXPECT_EQ(read_error(few),
              "cannot read " + few + ": POLYGONS 2 4: the array ends before cell 1");
    // The same file with the right counts reads.
    const Surface s =
        io::read_surface(write_file("good-cells.vtk", head + "POLYGONS 1 4\n3 0 1 2\n"));
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2}));
    // The binary file the fuzzer found.
    const std::string found = corpus_file_as_vtk("crash-01b55bbd99e8d12d9049eeb666e36848505a6829");
    EXPECT_NE(read_error(found).find("POLYGONS 24 96: cell"), std::string::npos)
        << read_error(found);
}

// read_vtk, crash-33599046…: an unstructured grid with a second CELL_TYPES section made VTK's
// reader dereference a null pointer (vtkUnstructuredGridReader::ReadMeshSimple).
TEST(FuzzRegressions, LegacyVtkSectionsThatRepeatAreRefused) {
    const std::string grid = "# vtk DataFile Version 4.2\ntwo cell types\nASCII\n"
                             "DATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                             "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n";
    const Surface s = io::read_surface(write_file("one-cell-types.vtk", grid));
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2}));
    const std::string twice = write_file("two-cell-types.vtk", grid + "CELL_TYPES 1\n5\n");
    EXPECT_EQ(read_error(twice), "cannot read " + twice + ": a second CELL_TYPES section");
    const std::string found = corpus_file_as_vtk("crash-33599046b3b94cdcac83bf06bc08841db153d5bd");
    EXPECT_NE(read_error(found).find(": a second CELL_TYPES section"), std::string::npos)
        << read_error(found);
}
