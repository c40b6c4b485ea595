// read_surface / write_surface: round trips through every writable format, and the errors.
#include "file_test_support.h"
#include "tools_test_support.h"

#include "ddsimp/io/surface_io.h"

#include <fstream>
#include <iterator>

using namespace ddsimp;
using namespace ddsimp::tools_test;

namespace {

bool holds_fields(const std::string& extension) {
    return extension == ".vtk" || extension == ".vtp" || extension == ".ply";
}

} // namespace

class RoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(RoundTrip, KeepsCoordinatesTrianglesAndFieldsWhereTheFormatHoldsThem) {
    ScratchDir dir;
    const std::string ext = GetParam();
    const Surface s = square_with_fields();
    const std::string path = dir.file("square" + ext);
    io::write_surface(s, path);
    const Surface back = io::read_surface(path);

    EXPECT_EQ(back.positions, s.positions); // exact: binary formats, or 9 digits in text
    EXPECT_EQ(back.triangles, s.triangles);
    if (!holds_fields(ext)) {
        EXPECT_TRUE(back.fields.empty());
        return;
    }
    ASSERT_EQ(back.fields.size(), s.fields.size());
    for (size_t f = 0; f < s.fields.size(); ++f) {
        EXPECT_EQ(back.fields[f].name, s.fields[f].name);
        EXPECT_EQ(back.fields[f].components, s.fields[f].components);
        EXPECT_EQ(back.fields[f].values, s.fields[f].values);
    }
}

TEST_P(RoundTrip, NonManifoldSurfaceIsWrittenAndReadAsItIs) {
    ScratchDir dir;
    const std::string path = dir.file("fin" + GetParam());
    io::write_surface(fin_of_three(), path);
    const Surface back = io::read_surface(path);
    EXPECT_EQ(back.triangles, fin_of_three().triangles);
    EXPECT_EQ(back.positions, fin_of_three().positions);
}

TEST_P(RoundTrip, WritingTwiceGivesTheSameBytes) {
    ScratchDir dir;
    const std::string a = dir.file("a" + GetParam()), b = dir.file("b" + GetParam());
    io::write_surface(square_with_fields(), a);
    io::write_surface(square_with_fields(), b);
    EXPECT_EQ(file_bytes(a), file_bytes(b));
    EXPECT_FALSE(file_bytes(a).empty());
}

INSTANTIATE_TEST_SUITE_P(WritableFormats, RoundTrip,
                         ::testing::Values(".vtk", ".vtp", ".ply", ".obj", ".off"),
                         [](const auto& info) { return info.param.substr(1); });

TEST(SurfaceIo, RealSurfaceSurvivesVtkToPlyToVtp) {
    ScratchDir dir;
    const Surface s = io::read_surface(sample_surface());
    io::write_surface(s, dir.file("s.ply"));
    io::write_surface(io::read_surface(dir.file("s.ply")), dir.file("s.vtp"));
    const Surface back = io::read_surface(dir.file("s.vtp"));
    EXPECT_EQ(back.positions, s.positions);
    EXPECT_EQ(back.triangles, s.triangles);
    ASSERT_EQ(back.fields.size(), 7u);
    for (size_t f = 0; f < 7; ++f) {
        EXPECT_EQ(back.fields[f].name, s.fields[f].name);
        EXPECT_EQ(back.fields[f].values, s.fields[f].values);
    }
}

TEST(SurfaceIo, FieldNamesWithSpacesSurvivePlyAsUnderscores) {
    ScratchDir dir;
    Surface s = square_with_fields();
    s.fields[0].name = "Volume Fraction";
    io::write_surface(s, dir.file("s.ply"));
    const Surface back = io::read_surface(dir.file("s.ply"));
    ASSERT_EQ(back.fields.size(), 3u);
    EXPECT_EQ(back.fields[0].name, "Volume_Fraction");
    EXPECT_EQ(back.fields[0].values, s.fields[0].values);
}

TEST(SurfaceIoErrors, MissingFileNamesTheFile) {
    const std::string message = io_error_of([] { io::read_surface("/nonexistent/x.vtk"); });
    EXPECT_NE(message.find("cannot read /nonexistent/x.vtk"), std::string::npos) << message;
    EXPECT_NE(message.find("no such file"), std::string::npos) << message;
}

TEST(SurfaceIoErrors, UnknownExtension) {
    EXPECT_NE(io_error_of([] { io::read_surface("x.xyz"); }).find("unknown extension"),
              std::string::npos);
    ScratchDir dir;
    EXPECT_NE(io_error_of([&] {
                  io::write_surface(square_with_fields(), dir.file("x.stl"));
              }).find("unknown extension"),
              std::string::npos);
}

TEST(SurfaceIoErrors, MalformedLegacyVtk) {
    ScratchDir dir;
    const std::string path = dir.file("broken.vtk");
    write_text(path, "# vtk DataFile Version 3.0\nbroken\nASCII\nDATASET POLYDATA\nPOINTS 3 "
                     "float\n0 0 0 1 0\n");
    const std::string message = io_error_of([&] { io::read_surface(path); });
    EXPECT_EQ(message.rfind("cannot read " + path + ": ", 0), 0u) << message;
}

TEST(SurfaceIoErrors, GarbageVtkFile) {
    ScratchDir dir;
    const std::string path = dir.file("garbage.vtk");
    write_text(path, "this is not a VTK file at all\n");
    EXPECT_EQ(io_error_of([&] { io::read_surface(path); }).rfind("cannot read " + path, 0), 0u);
}

TEST(SurfaceIoErrors, TruncatedOffNamesTheMissingFaces) {
    ScratchDir dir;
    const std::string path = dir.file("short.off");
    write_text(path, "OFF\n4 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n");
    const std::string message = io_error_of([&] { io::read_surface(path); });
    EXPECT_EQ(message.rfind("cannot read " + path + ": ", 0), 0u) << message;
}

TEST(SurfaceIoErrors, EmptyFile) {
    ScratchDir dir;
    const std::string path = dir.file("empty.ply");
    write_text(path, "");
    EXPECT_NE(io_error_of([&] { io::read_surface(path); }).find("empty"), std::string::npos);
}

TEST(SurfaceIoErrors, UnwritableDirectory) {
    const std::string message =
        io_error_of([] { io::write_surface(square_with_fields(), "/nonexistent/dir/x.vtp"); });
    EXPECT_EQ(message.rfind("cannot write /nonexistent/dir/x.vtp: ", 0), 0u) << message;
}

TEST(SurfaceIoErrors, WrongFieldLengthIsRefusedBeforeWriting) {
    ScratchDir dir;
    Surface s = square_with_fields();
    s.fields[1].values.pop_back();
    const std::string message = io_error_of([&] { io::write_surface(s, dir.file("x.vtk")); });
    EXPECT_NE(message.find("field 'V'"), std::string::npos) << message;
}

TEST(SurfaceIoErrors, TruncatedBinaryPly) {
    ScratchDir dir;
    const std::string path = dir.file("cut.ply");
    io::write_surface(square_with_fields(), path);
    const std::string bytes = file_bytes(path);
    write_text(path, bytes.substr(0, bytes.size() - 10)); // part of the last face is gone
    const std::string message = io_error_of([&] { io::read_surface(path); });
    EXPECT_NE(message.find("ends early"), std::string::npos) << message;
}

TEST(SurfaceIoErrors, TruncatedAsciiPly) {
    ScratchDir dir;
    const std::string path = dir.file("cut.ply");
    write_text(path, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
                     "y\nproperty float z\nelement face 2\nproperty list uchar int "
                     "vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    const std::string message = io_error_of([&] { io::read_surface(path); });
    EXPECT_NE(message.find("ends early"), std::string::npos) << message;
}

// OBJ faces with texture coordinates ("f 1/1 2/2 3/3") once crashed our importer.
TEST(SurfaceIo, ObjWithTextureCoordinatesAndNormals) {
    ScratchDir dir;
    const std::string path = dir.file("textured.obj");
    write_text(path, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                     "vn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n");
    const Surface s = io::read_surface(path);
    EXPECT_EQ(s.vertex_count(), 4u);
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST(SurfaceIo, AsciiPlyPropertiesOfOtherNumericTypesBecomeFloatFields) {
    ScratchDir dir;
    const std::string path = dir.file("types.ply");
    write_text(path, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
                     "y\nproperty float z\nproperty double pressure\nproperty int label\n"
                     "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                     "0 0 0 1.5 -3\n1 0 0 2.5 4\n0 1 0 3.5 5\n3 0 1 2\n");
    const Surface s = io::read_surface(path);
    ASSERT_EQ(s.fields.size(), 2u);
    EXPECT_EQ(s.fields[0].name, "pressure");
    EXPECT_EQ(s.fields[0].values, (std::vector<float>{1.5f, 2.5f, 3.5f}));
    EXPECT_EQ(s.fields[1].values, (std::vector<float>{-3, 4, 5}));
}
