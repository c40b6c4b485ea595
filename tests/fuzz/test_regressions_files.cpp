// Crashes and hangs the fuzz targets found in the file readers, as tests of the code that was
// fixed (the inputs themselves are in corpus/read_*/ and replayed by fuzz_replay_read_*).
#include "ddsimp/io/surface_io.h"

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
// counts and asked for 4.8 GB. OFF files are read by a reader of our own, which skips comments.
TEST(FuzzRegressions, OffFileWithACommentLineIsReadNotLoopedOver) {
    for (const char* head : {"OFF\n# a comment\n", "OFF\n"}) {
        const Surface s =
            io::read_surface(write_file("tetra.off", head + std::string(kTetrahedronBody)));
        EXPECT_EQ(s.vertex_count(), 4u) << head;
        EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3})) << head;
    }
}

// Counts no file can hold are "ends early", not sums that wrap around to pass the check.
TEST(FuzzRegressions, OffCountsThatWouldOverflowAreRefused) {
    const std::string why = read_error(
        write_file("huge.off", "OFF\n6148914691236517206 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
    EXPECT_NE(why.find("line 2: the vertex count: '6148914691236517206' is not a count from 0 to"),
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
    EXPECT_PRED_FORMAT2(testing::IsSubstring, "POLYGONS 24 96: cell", read_error(found));
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
    EXPECT_PRED_FORMAT2(testing::IsSubstring, ": a second CELL_TYPES section", read_error(found));
}

namespace {

// An input of tests/fuzz/corpus/<target>/ (named without an extension) as a file of that format.
std::string corpus_file(const std::string& target, const std::string& name,
                        const std::string& extension) {
    std::ifstream in(std::string(DDSIMP_FUZZ_CORPUS) + "/" + target + "/" + name, std::ios::binary);
    return write_file(name + extension, std::string{std::istreambuf_iterator<char>(in), {}});
}

const char* const kTetrahedronObjVertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";

} // namespace

// read_obj, crash-3a2b26c2…: OpenMesh's OBJ reader asserts that a face corner has a vertex index
// before it reads the texture index after it; "f /1/1 ..." aborted ddsimp (SIGABRT). Every face
// line is checked before OpenMesh reads the file.
TEST(FuzzRegressions, ObjFaceCornersWithoutAVertexIndexAreRefused) {
    const std::string path = write_file(
        "no-vertex-index.obj", std::string(kTetrahedronObjVertices) + "f /1/1 2/2/1 3/3/1\n");
    EXPECT_EQ(read_error(path),
              "cannot read " + path + ": line 5: face corner '/1/1' has no vertex index");
    const std::string normal_only = write_file(
        "normal-only.obj", std::string(kTetrahedronObjVertices) + "f 1 2 3\nf //1 2 3\n");
    EXPECT_EQ(read_error(normal_only),
              "cannot read " + normal_only + ": line 6: face corner '//1' has no vertex index");
    const std::string found =
        corpus_file("read_obj", "crash-3a2b26c23d37655144140a4080a0384a336bdf64", ".obj");
    EXPECT_EQ(read_error(found),
              "cannot read " + found + ": line 2: a vertex needs x y z, '0)0' is not a number");
}

TEST(FuzzRegressions, ObjFaceCornersOutOfRangeOrTooFewAreRefused) {
    const std::string v = kTetrahedronObjVertices;
    const std::string past = write_file("past.obj", v + "f 1 2 5\n");
    EXPECT_EQ(read_error(past), "cannot read " + past +
                                    ": line 5: face corner '5' refers to vertex 5, but the file "
                                    "has 4 vertices");
    const std::string before = write_file("before.obj", "v 0 0 0\nf -1 -2 -3\n" + v);
    EXPECT_EQ(read_error(before), "cannot read " + before +
                                      ": line 2: face corner '-2' refers to vertex -2, but only 1 "
                                      "vertices come before it");
    const std::string zero = write_file("zero.obj", v + "f 0 1 2\n");
    EXPECT_EQ(read_error(zero),
              "cannot read " + zero + ": line 5: face corner '0': OBJ vertex indices start at 1");
    const std::string two = write_file("two.obj", v + "f 1 2 # a comment\n");
    EXPECT_EQ(read_error(two),
              "cannot read " + two + ": line 5: a face needs 3 corners, this one has 2");
    // What the check lets through reads as before: negative indices, v/vt/vn corners, comments.
    const Surface s = io::read_surface(write_file(
        "good.obj", v + "vt 0 0\nvn 0 0 1\n  f -4 -2 -3 # indented, relative\nf 1/1/1 2//1 4/1\n"));
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 2, 1, 0, 1, 3}));
}

// read_off, oom-565f4f44…: a COFF file whose fourth face line is a vertex line; OpenMesh reads a
// face's corner count as an unsigned int, so "-52.4887" is 4294967244 corners and it pushes that
// many vertex handles (3 GB before libFuzzer stopped it). The file is walked as OpenMesh reads it
// first; here the third face line already has a corner that is not a number.
TEST(FuzzRegressions, OffFaceLinesThatAreNotFacesAreRefused) {
    const std::string vertices = "4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    const std::string not_face = write_file(
        "not-a-face.off",
        "OFF\n" + vertices + "3 0 2 1\n3 0 1 3\n3 0 3 2\n-52.4887 66.5 -57.2\n-52.9 67.3 -57.6\n");
    EXPECT_EQ(read_error(not_face),
              "cannot read " + not_face +
                  ": line 10: face 3: '-52.4887' is not a count from 0 to 48");
    const std::string bad_vertex =
        write_file("bad-vertex.off", "OFF\n4 4 0\n0 0 0\n1 x 0\n0 1 0\n0 0 1\n3 0 2 1\n"
                                     "3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    EXPECT_EQ(read_error(bad_vertex),
              "cannot read " + bad_vertex + ": line 4: vertex 1: 'x' is not a number");
    // A face colour after the corners is allowed without a C in the header (OpenMesh's reader
    // took it for the next face's count).
    const Surface coloured = io::read_surface(write_file(
        "face-colour.off", "OFF\n" + vertices + "3 0 2 1 255 0 0\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"));
    EXPECT_EQ(coloured.triangles, (std::vector<uint32_t>{0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}));
    const std::string found =
        corpus_file("read_off", "oom-565f4f44b002faeacbbc8e0f9e4cf3539782c424", ".off");
    EXPECT_PRED_FORMAT2(testing::IsSubstring, ": line 9: face 2: '2\\x92\\x92", read_error(found));
    // The same file with its colours on a COFF header reads.
    const Surface s = io::read_surface(write_file(
        "colours.coff.off", "COFF\n" + vertices.substr(0, 6) +
                                "0 0 0 255 0 0 255\n1 0 0 1 2 3 4\n0 1 0\n0 0 1 9 9 9 9\n"
                                "3 0 2 1 255 0 0\n3 0 1 3\n3 0 3 2\n3 1 2 3 1 1 1 1\n"));
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}));
}

// read_ply, timeout-b9d263a9…: OpenMesh's PLY reader reads its header word by word until the
// word end_header and stops early only on a stream error, not at the end of the file; a "property
// list" line whose item type runs into binary data took end_header as the property's name and
// looped for ever. The header is checked line by line first (here its line 5 already is wrong).
TEST(FuzzRegressions, PlyHeadersOpenMeshWouldMisreadAreRefused) {
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 1\n";
    const std::string body = "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const std::string swallowed =
        write_file("swallowed.ply", head + "property list uchar int\n" + body);
    EXPECT_EQ(read_error(swallowed),
              "cannot read " + swallowed +
                  ": PLY header line 8: 'property list' needs a count type, an item type and a "
                  "name");
    const std::string orphan = write_file(
        "orphan.ply", "ply\nformat ascii 1.0\nproperty float x\nelement vertex 0\nend_header\n");
    EXPECT_EQ(read_error(orphan),
              "cannot read " + orphan + ": PLY header line 3: a property before any element");
    const std::string found =
        corpus_file("read_ply", "timeout-b9d263a91e4f909baee5eec95f6dd13c4f79f24c", ".ply");
    EXPECT_EQ(read_error(found),
              "cannot read " + found + ": PLY header line 5: unknown keyword 'propertfloat'");
    const Surface s = io::read_surface(
        write_file("good.ply", head + "property list uchar int vertex_indices\n" + body));
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2}));
}

// List counts are read as unsigned ints, and OpenMesh allocates that many items: a count of -1
// (binary int) is refused, as is an ASCII word that is not a number.
TEST(FuzzRegressions, PlyListCountsTheFileCannotHoldAreRefused) {
    const std::string head = "ply\nformat binary_big_endian 1.0\nelement vertex 3\n"
                             "property float x\nproperty float y\nproperty float z\n"
                             "element face 1\nproperty list int int vertex_indices\nend_header\n";
    const std::string vertices(36, '\0');
    const std::string minus_one =
        write_file("minus-one.ply",
                   head + vertices + std::string("\xff\xff\xff\xff", 4) + std::string(12, '\0'));
    EXPECT_EQ(read_error(minus_one),
              "cannot read " + minus_one +
                  ": face 0: a list 'vertex_indices' of -1 items, more than the file holds");
    const std::string ascii =
        write_file("ascii-count.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                      "property float y\nproperty float z\nelement face 1\n"
                                      "property list uchar int vertex_indices\nend_header\n"
                                      "0 0 0\n1 0 0\n0 1 0\n3x 0 1 2\n");
    EXPECT_EQ(read_error(ascii),
              "cannot read " + ascii + ": line 13: face 0: '3x' is not a list count");
}

// read_vtk, crash-97e5beb2…: an unstructured grid whose data-set FIELD section VTK cannot read
// (a garbled line in a char array; VTK then meets a data type "0"); ReadFieldData returns null and
// vtkUnstructuredGridReader::ReadMeshSimple calls Delete() on it (SEGV). Each such section is
// read with VTK's own parser first.
TEST(FuzzRegressions, LegacyVtkFieldSectionsVtkCannotReadAreRefused) {
    const std::string grid = "# vtk DataFile Version 4.2\nfield data\nASCII\n"
                             "DATASET UNSTRUCTURED_GRID\nFIELD FieldData 1\nInfo 1 3 char\n";
    const std::string rest = "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nCELLS 1 4\n3 0 1 2\n"
                             "CELL_TYPES 1\n5\n";
    const Surface s = io::read_surface(write_file("good-field.vtk", grid + "65 66 67\n" + rest));
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2}));
    std::string bad_grid = grid;
    bad_grid.replace(bad_grid.find("char"), 4, "nonsense");
    const std::string bad = write_file("bad-field.vtk", bad_grid + "65 66 67\n" + rest);
    EXPECT_EQ(read_error(bad), "cannot read " + bad +
                                   ": the data set's FIELD section (line 5) cannot be read: "
                                   "array 0 'Info' (1 x 3 nonsense): Unsupported data type: "
                                   "nonsense");
    const std::string found = corpus_file_as_vtk("crash-97e5beb213d49333db52a86bb176c3a52a3d2319");
    EXPECT_PRED_FORMAT2(
        testing::IsSubstring,
        ": the data set's FIELD section (line 5) cannot be read: ", read_error(found));
}

// read_off, oom-0e5df420…: a header "COFF\xffBINARY..." is binary OFF to OpenMesh ("BINARY" one
// character after OFF), whose counts are raw uint32s it reserves memory for (3 GB here) and whose
// corner counts it trusts. Binary OFF is walked by its byte counts first.
TEST(FuzzRegressions, BinaryOffCountsTheFileCannotHoldAreRefused) {
    auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    std::string vertices;
    for (float x : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f})
        vertices += std::string(reinterpret_cast<const char*>(&x), 4);
    const std::string huge =
        write_file("huge-binary.off", "OFF BINARY\n" + u32(3) + u32(100000000) + u32(0) + vertices +
                                          u32(3) + u32(0) + u32(1) + u32(2));
    EXPECT_EQ(read_error(huge), "cannot read " + huge +
                                    ": the file ends early: its header declares 3 vertices and "
                                    "100000000 faces");
    const std::string corners =
        write_file("corners-binary.off", "OFF BINARY\n" + u32(3) + u32(1) + u32(0) + vertices +
                                             u32(4000000000u) + u32(0) + u32(1) + u32(2));
    EXPECT_EQ(read_error(corners), "cannot read " + corners +
                                       ": face 0 has 4000000000 corners, more than the file holds");
    const Surface s = io::read_surface(
        write_file("good-binary.off", "OFF BINARY\n" + u32(3) + u32(1) + u32(0) + vertices +
                                          u32(3) + u32(0) + u32(1) + u32(2)));
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2}));
    const std::string found =
        corpus_file("read_off", "oom-0e5df42011f33a74c5c3fa56a26a54b8b16671e5", ".off");
    EXPECT_PRED_FORMAT2(testing::IsSubstring, "is neither an OFF header nor a vertex count",
                        read_error(found));
}

// read_vtk, crash-41ebe6c9…: VTK's legacy reader kept a point-data array shorter than the points
// (the fuzz target's check of every field's length failed). A field must have one tuple per
// point.
TEST(FuzzRegressions, LegacyVtkPointFieldsOfTheWrongLengthAreRefused) {
    const std::string head = "# vtk DataFile Version 4.2\nshort field\nASCII\nDATASET POLYDATA\n"
                             "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2\n"
                             "POINT_DATA 3\nFIELD FieldData 1\n";
    const Surface s =
        io::read_surface(write_file("good-point-field.vtk", head + "T 1 3 float\n1 2 3\n"));
    ASSERT_EQ(s.fields.size(), 1u);
    EXPECT_EQ(s.fields[0].values, (std::vector<float>{1, 2, 3}));
    const std::string short_field =
        write_file("short-point-field.vtk", head + "T 1 2 float\n1 2\n");
    EXPECT_EQ(read_error(short_field),
              "cannot read " + short_field +
                  ": point field 'T' has 2 tuples of 1 components for 3 points");
    // The file the fuzzer found: its point data's FIELD section, which VTK read without checking
    // that it had read array 2's counts and type, is now refused as the walk meets it.
    const std::string found = corpus_file_as_vtk("crash-41ebe6c908e44efda2ae9c25addef044eb81ff7a");
    EXPECT_EQ(read_error(found), "cannot read " + found +
                                     ": line 36: FIELD of POINT_DATA cannot be read: array 2 has "
                                     "no component count, tuple count and type");
}

// read_vtk, crash-81fb946d…: VTK's ReadFieldData does not check that it could read an array's
// component and tuple counts, sized a std::vector from what it had and the std::length_error went
// through VTK's reader into ddsimp (std::terminate; caught, it leaks what VTK had built). The
// FIELD section is read with VTK's primitives and checked count by count first, and a count no
// file of this size can hold is refused before VTK allocates it.
TEST(FuzzRegressions, LegacyVtkCountsTheFileCannotHoldAreRefused) {
    const std::string head = "# vtk DataFile Version 4.2\nhuge\nASCII\nDATASET POLYDATA\n";
    const std::string rest = "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2\n";
    const std::string tuples = write_file(
        "huge-tuples.vtk", head + "FIELD FieldData 1\nInfo 1 4000000000 double\n1\n" + rest);
    EXPECT_EQ(read_error(tuples), "cannot read " + tuples +
                                      ": line 6: array Info declares 1 components of 4000000000 "
                                      "tuples, more than the file holds");
    const std::string points = write_file(
        "huge-points.vtk", head + "POINTS 900000000 float\n0 0 0\nPOLYGONS 1 4\n3 0 1 2\n");
    EXPECT_EQ(read_error(points), "cannot read " + points +
                                      ": line 5: POINTS declares 900000000 points, more than the "
                                      "file holds");
    // The file the fuzzer found has no DATASET line (its third line runs on into the data), which
    // the data-set walk now refuses before the FIELD section is reached.
    const std::string found = corpus_file_as_vtk("crash-81fb946d06cc41a25ea2316e77026bce5a296e14");
    EXPECT_EQ(read_error(found), "cannot read " + found + ": line 3: '0' where DATASET should be");
}

// Found again while these were fixed, by the same faults: read_obj crash-7148c4a1… (OpenMesh's
// face-corner assertion), read_off oom-49064fca… (a vertex line read as a face's corner count),
// read_ply crash-f772e9e1… (a property before any element: OpenMesh's PLY reader dereferenced
// the end of its empty element list, SEGV), read_vtk leak-1c2f8d42… (a FIELD section misread up
// to a word "cells0", which VTK took for CELLS; its error return after that leaks the cells).
TEST(FuzzRegressions, MoreInputsOfTheSameFaultsAreRefused) {
    const std::string obj =
        corpus_file("read_obj", "crash-7148c4a1f56ef6d47a9d1060c23aaab4f7b462de", ".obj");
    EXPECT_EQ(read_error(obj),
              "cannot read " + obj + ": line 2: a vertex needs x y z, 'v0' is not a number");
    const std::string off =
        corpus_file("read_off", "oom-49064fca10d1d0449e98be42d8636b2775bb5e7f", ".off");
    EXPECT_EQ(read_error(off),
              "cannot read " + off + ": line 8: face 0: '-36.4873' is not a count from 0 to 579");
    const std::string ply =
        corpus_file("read_ply", "crash-f772e9e1ca0916c604f0314af8d5b037e35faac2", ".ply");
    EXPECT_EQ(read_error(ply),
              "cannot read " + ply + ": PLY header line 3: unknown keyword 'elemetn'");
    const std::string vtk = corpus_file_as_vtk("leak-1c2f8d429814927e25a18fd245556983939aa629");
    EXPECT_EQ(read_error(vtk), "cannot read " + vtk +
                                   ": the data set's FIELD section (line 5) cannot be read: "
                                   "array 2 'Info_Records' (81 x 10 char): the file ends, or has "
                                   "a word that is not a number, before the values it declares");
}

// read_vtk, crash-d5148a79…: vtkPolyDataReader ignores a failure to read the points and takes
// the next word for a keyword; "-4.20128FieldData" in the coordinates made it read a FIELD
// section from "FieldData" on, which failed, and Delete() the null it got back (SEGV). ASCII
// point coordinates must all be numbers.
TEST(FuzzRegressions, LegacyVtkPointCoordinatesThatAreNotNumbersAreRefused) {
    const std::string head = "# vtk DataFile Version 4.2\npoints\nASCII\nDATASET POLYDATA\n";
    const std::string bad =
        write_file("bad-points.vtk", head + "POINTS 3 float\n0 0 0\n1 0 0\n0 1x 0\nPOLYGONS 1 "
                                            "4\n3 0 1 2\n");
    EXPECT_EQ(read_error(bad),
              "cannot read " + bad + ": line 8: POINTS 3: point 2 has '1x', not a number");
    const Surface s = io::read_surface(
        write_file("good-points.vtk",
                   head + "POINTS 3 float\n0 0 0 1 0\n0 0 +1e0 0\nPOLYGONS 1 4\n3 0 1 2\n"));
    EXPECT_EQ(s.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}));
    const std::string found = corpus_file_as_vtk("crash-d5148a79d06a0276201072390abbfcd75a9f090c");
    EXPECT_EQ(read_error(found), "cannot read " + found +
                                     ": line 8: POINTS 56: point 3 has '-4.20128FieldData', not "
                                     "a number");
}

// read_vtk, crash-7c03abec…: VTK's readers compare a keyword's start only, so "FIELDvtkidty" was a
// FIELD section to them (and, unreadable, a null Delete()) but not to the checks, which compared
// whole words. The checks take sections the way VTK does.
TEST(FuzzRegressions, LegacyVtkKeywordsAreMatchedByTheirStartAsVtkDoes) {
    const std::string file = write_file(
        "field-prefix.vtk", "# vtk DataFile Version 4.2\nprefix\nASCII\nDATASET POLYDATA\n"
                            "FIELDS FieldData 1\nInfo 1 3 nonsense\n1 2 3\nPOINTS 3 float\n"
                            "0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2\n");
    EXPECT_EQ(read_error(file), "cannot read " + file +
                                    ": the data set's FIELD section (line 5) cannot be read: "
                                    "array 0 'Info' (1 x 3 nonsense): Unsupported data type: "
                                    "nonsense");
    const std::string found = corpus_file_as_vtk("crash-7c03abecd0b7a0169d2f4d05d19eebd313019fa9");
    EXPECT_PRED_FORMAT2(
        testing::IsSubstring,
        ": the data set's FIELD section (line 5) cannot be read: ", read_error(found));
}

namespace {

// Why read_surface refuses `bytes` written as the file `name`, without "cannot read <path>: ".
std::string refusal(const std::string& name, const std::string& bytes) {
    const std::string path = write_file(name, bytes);
    const std::string error = read_error(path), prefix = "cannot read " + path + ": ";
    return error.rfind(prefix, 0) == 0 ? error.substr(prefix.size()) : "not refused: " + error;
}

std::string corpus_refusal(const std::string& name) {
    std::ifstream in(std::string(DDSIMP_FUZZ_CORPUS) + "/read_vtk/" + name, std::ios::binary);
    return refusal(name + ".vtk", std::string{std::istreambuf_iterator<char>(in), {}});
}

const char* const kTriangle = "POINTS 3 float\n0 0 0 1 0 0 0 1 0\n";

} // namespace

// read_vtk, leak-a71564cb… (the open finding until now): an unstructured grid whose CELL_TYPES
// section holds more values than it declares. VTK 9.1's vtkUnstructuredGridReader::ReadMeshSimple
// met the extra "17" where a section keyword should be and returned on "Unrecognized keyword"
// without freeing the cell types it had read (LeakSanitizer). The data set is walked section by
// section with VTK's own parser first, and each word VTK would not know is refused.
TEST(FuzzRegressions, LegacyVtkWordsThatAreNotSectionsAreRefusedBeforeVtkLeaks) {
    const std::string grid = "# vtk DataFile Version 4.2\nextra type\nASCII\n"
                             "DATASET UNSTRUCTURED_GRID\n" +
                             std::string(kTriangle) + "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n";
    const Surface s = io::read_surface(write_file("one-type.vtk", grid + "5\n"));
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(refusal("extra-type.vtk", grid + "5\n5\n"),
              "line 11: '5' is not a section keyword; the section before it is CELL_TYPES "
              "(line 9)");
    // A misspelt keyword after the cells, in the format 5.1 layout.
    EXPECT_EQ(refusal("misspelt.vtk", "# vtk DataFile Version 5.1\nmisspelt\nASCII\n"
                                      "DATASET UNSTRUCTURED_GRID\n" +
                                          std::string(kTriangle) +
                                          "CELLS 2 3\nOFFSETS vtktypeint64\n0 3\n"
                                          "CONNECTIVITY vtktypeint64\n0 1 2\nCELL_TYPE 1\n5\n"),
              "line 12: 'CELL_TYPE' is not a section keyword; the section before it is CELLS "
              "(line 7)");
    // The file found by the fuzzer is now refused earlier, at an array cut short.
    EXPECT_EQ(corpus_refusal("leak-a71564cb6e594e278eac29c1100762ba9a438157"),
              "the data set's FIELD section (line 5) cannot be read: array 2 'Info_Records' "
              "(81 x 10 char): the file ends, or has a word that is not a number, before the "
              "values it declares");
}

// Found while walking VTK 9.1's readers for the finding above: vtkPolyDataReader's legacy cell
// reading closes the file when ReadCellsLegacy fails (here on a point id no int holds) but
// reports success, and the reader goes on reading the closed stream (SEGV in ReadString).
TEST(FuzzRegressions, LegacyVtkCellArraysVtkCannotReadAreRefused) {
    const std::string head =
        "# vtk DataFile Version 4.2\nids\nASCII\nDATASET POLYDATA\n" + std::string(kTriangle);
    EXPECT_EQ(refusal("big-id.vtk", head + "POLYGONS 1 4\n3 0 1 3000000000\n"),
              "line 7: POLYGONS 1 4: the file ends, or has a word that is not an integer, in its "
              "4 numbers");
    // Counts VTK reads from the words after the keyword, wherever the lines break.
    EXPECT_EQ(refusal("split.vtk", head + "POLYGONS\n1\n4\n4 0 1 2\n"),
              "line 7: POLYGONS 1 4: cell 0 has 4 points, more than the array holds");
}

// VTK 9.1 checks neither that a grid has a cell type for each cell (vtkUnstructuredGrid::SetCells
// copies one for each cell from the CELL_TYPES it read, past its end) nor that format 5 offsets
// stay inside their connectivity; a second CELLS section leaks the first.
TEST(FuzzRegressions, LegacyVtkCellsVtkWouldReadPastAreRefused) {
    const std::string points = "POINTS 4 float\n0 0 0 1 0 0 0 1 0 0 0 1\n";
    const std::string grid = "# vtk DataFile Version 4.2\ntypes\nASCII\n"
                             "DATASET UNSTRUCTURED_GRID\n" +
                             points + "CELLS 2 8\n3 0 1 2\n3 0 1 3\n";
    EXPECT_EQ(refusal("few-types.vtk", grid + "CELL_TYPES 1\n5\n"),
              "line 10: CELL_TYPES has 1 types for the 2 cells of CELLS");
    const Surface s = io::read_surface(write_file("two-types.vtk", grid + "CELL_TYPES 2\n5 5\n"));
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 1, 3}));

    const std::string v51 = "# vtk DataFile Version 5.1\noffsets\nASCII\nDATASET POLYDATA\n" +
                            points + "POLYGONS 3 6\nOFFSETS vtktypeint64\n";
    const std::string cells = "CONNECTIVITY vtktypeint64\n0 1 2 0 1 3\n";
    const Surface good = io::read_surface(write_file("offsets.vtk", v51 + "0 3 6\n" + cells));
    EXPECT_EQ(good.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 1, 3}));
    EXPECT_EQ(refusal("offsets-past.vtk", v51 + "0 3 9\n" + cells),
              "line 7: POLYGONS 3 6: offset 2 is 9 (offsets go from 0 up to the 6 ids of the "
              "connectivity)");
    EXPECT_EQ(refusal("offsets-short.vtk", v51 + "0 3 3\n" + cells),
              "line 7: POLYGONS 3 6: the offsets end at 3, not at the 6 ids of the connectivity");

    const std::string cells51 =
        "CELLS 2 3\nOFFSETS vtktypeint64\n0 3\nCONNECTIVITY vtktypeint64\n0 1 2\n";
    EXPECT_EQ(refusal("two-cells.vtk", "# vtk DataFile Version 5.1\ntwice\nASCII\n"
                                       "DATASET UNSTRUCTURED_GRID\n" +
                                           points + cells51 + cells51 + "CELL_TYPES 1\n5\n"),
              "line 12: a second CELLS section");
}

// The data set's counts VTK compares, and what vtkDataSetReader cannot read as a data set, are
// refused with the line that is wrong (VTK's own message for a file without DATASET names the
// reader by its address, which differs from run to run).
TEST(FuzzRegressions, LegacyVtkDataSetLevelErrorsAreNamed) {
    const std::string head = "# vtk DataFile Version 4.2\ncounts\nASCII\n";
    const std::string poly =
        "DATASET POLYDATA\n" + std::string(kTriangle) + "POLYGONS 1 4\n3 0 1 2\n";
    EXPECT_EQ(refusal("point-data.vtk", head + poly + "POINT_DATA 4\n"),
              "line 9: POINT_DATA 4 for a data set of 3 points");
    EXPECT_EQ(refusal("cell-data.vtk", head + poly + "CELL_DATA 2\n"),
              "line 9: CELL_DATA 2 for a data set of 1 cells");
    EXPECT_EQ(refusal("no-dataset.vtk", head + "POINT_DATA 3\n"),
              "line 4: 'POINT_DATA' where DATASET should be");
    EXPECT_EQ(refusal("kind.vtk", head + "DATASET TRIANGLES\n"),
              "line 4: 'TRIANGLES' is not a data set type (POLYDATA, UNSTRUCTURED_GRID, "
              "STRUCTURED_POINTS, STRUCTURED_GRID, RECTILINEAR_GRID)");
    EXPECT_EQ(refusal("string-points.vtk", head + "DATASET POLYDATA\nPOINTS 1\nstring\na\nb\nc\n"),
              "line 5: POINTS 1: 'string' is not a numeric type");
    const Surface s = io::read_surface(write_file("counts.vtk", head + poly + "POINT_DATA 3\n"));
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2}));
}

// Found while walking VTK 9.1's attribute readers: ReadScalarData (and the vectors, normals,
// tensors, texture coordinates and global ids readers) lose the array ReadArray made when it is
// not numeric, and ReadLutData its lookup table when the colours end early (LeakSanitizer, both).
// The point and cell data are walked too, attribute by attribute.
TEST(FuzzRegressions, LegacyVtkAttributesVtkWouldLeakAreRefused) {
    const std::string head = "# vtk DataFile Version 4.2\nattributes\nASCII\nDATASET POLYDATA\n" +
                             std::string(kTriangle) + "POLYGONS 1 4\n3 0 1 2\nPOINT_DATA 3\n";
    const std::string scalars = "SCALARS s float 1\nLOOKUP_TABLE default\n1 2 3\n";
    EXPECT_EQ(
        refusal("string-scalars.vtk", head + "SCALARS s string 1\nLOOKUP_TABLE default\na\nb\nc\n"),
        "line 10: SCALARS s: 'string' is not a numeric type");
    EXPECT_EQ(refusal("short-table.vtk", head + scalars + "LOOKUP_TABLE t 2\n0 0 0 1\n0 0\n"),
              "line 13: LOOKUP_TABLE t 2: colour 1 is not 4 numbers, or the file ends in it");
    EXPECT_EQ(refusal("unknown.vtk", head + scalars + "SCALAR t float\n"),
              "line 13: 'SCALAR' is not an attribute of POINT_DATA");
    // The same attributes, whole, read; so do pedigree ids of strings, which VTK keeps as they
    // are.
    const Surface s =
        io::read_surface(write_file("attributes.vtk", head + scalars +
                                                          "LOOKUP_TABLE t 2\n0 0 0 1\n0 0 1 1\n"
                                                          "PEDIGREE_IDS p string\na\nb\nc\n"));
    ASSERT_EQ(s.fields.size(), 1u);
    EXPECT_EQ(s.fields[0].name, "s");
    EXPECT_EQ(s.fields[0].values, (std::vector<float>{1, 2, 3}));
}

// read_vtk, crash-b065681c…: VTK 9.1's DecodeString (which turns "%20" into " " in the names and
// strings it reads) reads and writes past a string of one or two characters with a '%' in it:
// here the value "0%" of a variant array (heap-buffer-overflow in strncpy, under the data-set
// walk's own ReadArray). Such words are refused before VTK sees them; so is a binary string whose
// length is more than the file holds (VTK allocates the length it reads: 1 TB here).
TEST(FuzzRegressions, LegacyVtkStringsVtkWouldOverrunAreRefused) {
    const std::string ascii = "# vtk DataFile Version 4.2\nstrings\nASCII\nDATASET POLYDATA\n" +
                              std::string(kTriangle) +
                              "POLYGONS 1 4\n3 0 1 2\nPOINT_DATA 3\nFIELD FieldData 1\n"
                              "names 1 3 string\nab\n";
    EXPECT_EQ(refusal("percent.vtk", ascii + "%\ncd\n"),
              "line 13: '%': VTK 9.1 reads past a name or string of one or two characters with "
              "a '%'");
    const Surface s = io::read_surface(write_file("strings.vtk", ascii + "%41\ncd\n"));
    EXPECT_EQ(s.triangles, (std::vector<uint32_t>{0, 1, 2}));

    auto be32 = [](uint32_t v) {
        return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    };
    std::string binary = "# vtk DataFile Version 4.2\nstrings\nBINARY\nDATASET POLYDATA\n"
                         "POINTS 3 int\n";
    for (uint32_t v : {0, 0, 0, 1, 0, 0, 0, 1, 0}) binary += be32(v);
    binary += "\nPOLYGONS 1 4\n" + be32(3) + be32(0) + be32(1) + be32(2) + "\nFIELD FieldData 1\n";
    // A string of 2 bytes has the length byte 0xc2; a length byte 0 is followed by 8 bytes.
    EXPECT_EQ(refusal("long-string.vtk", binary +
                                             "names 1 2 string\n\xc2"
                                             "ab" +
                                             std::string("\0\0\1\0\0\0\0\0", 8) + "\n"),
              "the data set's FIELD section (line 9) cannot be read: array 0: string 1 is "
              "1099511627776 bytes long, more than the file holds");
    EXPECT_EQ(refusal("percent-name.vtk", binary + "a% 1 1 int\n" + be32(7) + "\n"),
              "the data set's FIELD section (line 9) cannot be read: array 0 is named 'a%': VTK "
              "9.1 reads past a name of one or two characters with a '%'");
    const Surface b = io::read_surface(write_file("string.vtk", binary + "names 1 2 string\n\xc2"
                                                                         "ab\xc2"
                                                                         "cd\n"));
    EXPECT_EQ(b.triangles, (std::vector<uint32_t>{0, 1, 2}));

    EXPECT_EQ(corpus_refusal("crash-b065681c280e767680f9e89b79bebd37e23b1744"),
              "line 29: '0%': VTK 9.1 reads past a name or string of one or two characters with "
              "a '%'");
}
