// Files as users have them: every variant a format allows is generated here from one small
// quad grid (not a hand-edited copy), read back, and compared with the grid it was made from.
#include "file_test_support.h"
#include "tools_test_support.h"

#include "ddsimp/io/surface_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

using namespace ddsimp;
using namespace ddsimp::tools_test;

namespace {

// An n x n grid of quads in the plane z = x * y / 4 (so that no two points are alike), with an
// id per point, a temperature and a unit normal.
struct QuadGrid {
    int n = 4;
    size_t points() const { return size_t(n + 1) * size_t(n + 1); }
    size_t quads() const { return size_t(n) * size_t(n); }
    std::array<double, 3> point(size_t v) const {
        const double x = double(v % size_t(n + 1)) / n, y = double(v / size_t(n + 1)) / n;
        return {x, y, x * y / 4};
    }
    std::array<double, 3> normal(size_t v) const {
        const auto [x, y, z] = point(v);
        const double l = std::sqrt(y * y / 16 + x * x / 16 + 1);
        return {-y / 4 / l, -x / 4 / l, 1 / l};
    }
    double temperature(size_t v) const { return 300 + point(v)[0] * 7.5 - point(v)[1]; }
    // Counter-clockwise seen from +z.
    std::array<size_t, 4> quad(size_t q) const {
        const size_t i = q % size_t(n), j = q / size_t(n), w = size_t(n + 1);
        return {j * w + i, j * w + i + 1, (j + 1) * w + i + 1, (j + 1) * w + i};
    }
};

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// The surface read from a file made of `grid`: its points (in the grid's order, unless the
// format numbers them itself), and every quad covered by two triangles facing +z.
void expect_grid(const Surface& s, const QuadGrid& grid, bool grid_order = true) {
    ASSERT_EQ(s.vertex_count(), grid.points());
    std::set<std::array<float, 3>> read, made;
    for (size_t v = 0; v < grid.points(); ++v) {
        read.insert({s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]});
        made.insert({float(grid.point(v)[0]), float(grid.point(v)[1]), float(grid.point(v)[2])});
        for (int c = 0; c < 3 && grid_order; ++c)
            EXPECT_NEAR(s.positions[3 * v + c], grid.point(v)[c], 1e-6);
    }
    if (!grid_order) {
        EXPECT_EQ(read, made);
    }
    ASSERT_EQ(s.triangle_count(), 2 * grid.quads());
    double area = 0;
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        const float* a = &s.positions[3 * s.triangles[3 * t]];
        const float* b = &s.positions[3 * s.triangles[3 * t + 1]];
        const float* c = &s.positions[3 * s.triangles[3 * t + 2]];
        const double ux = b[0] - a[0], uy = b[1] - a[1], vx = c[0] - a[0], vy = c[1] - a[1];
        const double z = ux * vy - uy * vx; // twice the projected area, signed
        EXPECT_GT(z, 0) << "triangle " << t << " faces away from +z";
        area += z / 2;
    }
    EXPECT_NEAR(area, 1.0, 1e-6); // the unit square, covered once
}

// ------------------------------------------------------------------------------------------
// OFF
// ------------------------------------------------------------------------------------------

struct OffStyle {
    bool comments = false;         // a comment block, comment lines and trailing comments
    bool counts_on_header = false; // "OFF 25 16 0"
    bool normals = false;          // NOFF
    bool colours = false;          // COFF, and a colour after each face
    bool no_edge_count = false;    // "25 16"
    std::string name() const {
        std::string n;
        if (comments) n += "Comments";
        if (counts_on_header) n += "CountsOnHeader";
        if (normals) n += "Normals";
        if (colours) n += "Colours";
        if (no_edge_count) n += "NoEdgeCount";
        return n.empty() ? "Plain" : n;
    }
};

std::string off_text(const QuadGrid& g, const OffStyle& style) {
    std::ostringstream out;
    out.precision(9);
    if (style.comments) out << "# written by the tests\n#\n";
    out << (style.colours ? "C" : "") << (style.normals ? "N" : "") << "OFF";
    out << (style.counts_on_header ? " " : "\n");
    if (style.comments && !style.counts_on_header) out << "# counts next\n";
    out << g.points() << " " << g.quads();
    if (!style.no_edge_count) out << " " << 2 * g.quads() + 2 * g.n;
    out << (style.comments ? "  # vertices faces edges\n" : "\n");
    for (size_t v = 0; v < g.points(); ++v) {
        const auto p = g.point(v);
        out << p[0] << " " << p[1] << " " << p[2];
        if (style.normals) {
            const auto n = g.normal(v);
            out << " " << n[0] << " " << n[1] << " " << n[2];
        }
        if (style.colours) out << " 0.5 0.25 1 1";
        out << (style.comments && v % 3 == 0 ? " # a point\n" : "\n");
        if (style.comments && v == 4) out << "   # a comment line among the points\n";
    }
    for (size_t q = 0; q < g.quads(); ++q) {
        const auto c = g.quad(q);
        out << "4 " << c[0] << " " << c[1] << " " << c[2] << " " << c[3];
        if (style.colours) out << " 255 0 0";
        out << "\n";
    }
    return out.str();
}

std::vector<OffStyle> off_styles() {
    std::vector<OffStyle> styles;
    for (int bits = 0; bits < 32; ++bits)
        styles.push_back(
            {bool(bits & 1), bool(bits & 2), bool(bits & 4), bool(bits & 8), bool(bits & 16)});
    return styles;
}

} // namespace

class OffVariant : public ::testing::TestWithParam<OffStyle> {};

TEST_P(OffVariant, IsReadAsTheGridItWasMadeFrom) {
    ScratchDir dir;
    const QuadGrid grid;
    const std::string path = dir.file("grid.off");
    write_text(path, off_text(grid, GetParam()));
    io::Notes notes;
    const Surface s = io::read_surface(path, &notes);
    expect_grid(s, grid);
    EXPECT_TRUE(contains(all(notes), "16 quads triangulated into 32 triangles")) << all(notes);
    if (GetParam().normals) {
        ASSERT_EQ(s.fields.size(), 1u);
        EXPECT_EQ(s.fields[0].kind, FieldKind::Direction);
        EXPECT_NEAR(s.fields[0].values[3 * 7 + 1], grid.normal(7)[1], 1e-6);
    } else {
        EXPECT_TRUE(s.fields.empty());
    }
}

INSTANTIATE_TEST_SUITE_P(Styles, OffVariant, ::testing::ValuesIn(off_styles()),
                         [](const auto& info) { return info.param.name(); });

TEST(OffTruncation, AFileCutShortSaysWhereItEndsAndWhatItDeclares) {
    ScratchDir dir;
    const QuadGrid grid;
    const std::string text = off_text(grid, {});
    // Cut in the points, then in the faces: each cut is refused, never read short.
    for (const double keep : {0.3, 0.9}) {
        const std::string path = dir.file("cut.off");
        write_text(path, text.substr(0, size_t(double(text.size()) * keep)));
        const std::string message = io_error_of([&] { io::read_surface(path); });
        EXPECT_TRUE(contains(message, keep < 0.5 ? "the file ends in vertex" : "ends in face"))
            << message;
        EXPECT_TRUE(contains(message, "declare 25 vertices and 16 faces")) << message;
    }
}

TEST(OffErrors, AFaceIndexOutOfRangeIsNamedWithItsLine) {
    ScratchDir dir;
    const std::string path = dir.file("bad.off");
    write_text(path, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
    const std::string message = io_error_of([&] { io::read_surface(path); });
    EXPECT_TRUE(contains(message, "line 6: face 0: '3' is not a vertex index below 3")) << message;
}

// ------------------------------------------------------------------------------------------
// OBJ and PLY polygons
// ------------------------------------------------------------------------------------------

TEST(ObjPolygons, QuadsAndAPentagonAreTriangulatedAndCounted) {
    ScratchDir dir;
    const QuadGrid grid;
    std::ostringstream out;
    out.precision(9);
    for (size_t v = 0; v < grid.points(); ++v)
        out << "v " << grid.point(v)[0] << " " << grid.point(v)[1] << " " << grid.point(v)[2]
            << "\n";
    for (size_t q = 0; q < grid.quads(); ++q) {
        const auto c = grid.quad(q);
        out << "f " << c[0] + 1 << " " << c[1] + 1 << " " << c[2] + 1 << " " << c[3] + 1 << "\n";
    }
    const std::string path = dir.file("grid.obj");
    write_text(path, out.str());
    io::Notes notes;
    expect_grid(io::read_surface(path, &notes), grid);
    EXPECT_TRUE(contains(all(notes), "16 quads triangulated into 32 triangles")) << all(notes);
}

TEST(PlyPolygons, AnAsciiQuadGridIsTriangulatedAndItsIntegerIdsAreLabels) {
    ScratchDir dir;
    const QuadGrid grid;
    std::ostringstream out;
    out.precision(9);
    out << "ply\nformat ascii 1.0\nelement vertex " << grid.points()
        << "\nproperty float x\nproperty float y\nproperty float z\nproperty int GlobalNodeId\n"
           "property float temperature\nelement face "
        << grid.quads() << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (size_t v = 0; v < grid.points(); ++v)
        out << grid.point(v)[0] << " " << grid.point(v)[1] << " " << grid.point(v)[2] << " "
            << 1000 + v << " " << grid.temperature(v) << "\n";
    for (size_t q = 0; q < grid.quads(); ++q) {
        const auto c = grid.quad(q);
        out << "4 " << c[0] << " " << c[1] << " " << c[2] << " " << c[3] << "\n";
    }
    const std::string path = dir.file("grid.ply");
    write_text(path, out.str());
    io::Notes notes;
    const Surface s = io::read_surface(path, &notes);
    expect_grid(s, grid);
    EXPECT_TRUE(contains(all(notes), "16 quads")) << all(notes);
    ASSERT_EQ(s.fields.size(), 2u);
    EXPECT_EQ(s.fields[0].kind, FieldKind::Label);
    EXPECT_EQ(s.fields[1].kind, FieldKind::Continuous);
    EXPECT_EQ(default_gradient_fields(s), std::vector<std::string>{"temperature"});
}

namespace {

// PLY triangle strips ("tristrips", as Stanford's scans store them): the grid's rows as strips
// in one list, separated by -1, in each PLY format; with an integer id, a temperature and
// normals per point.
enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

std::string ply_format_name(PlyFormat f) {
    switch (f) {
    case PlyFormat::Ascii:
        return "ascii";
    case PlyFormat::BinaryLittleEndian:
        return "binary_little_endian";
    case PlyFormat::BinaryBigEndian:
        return "binary_big_endian";
    }
    return "";
}

class PlyValues {
public:
    explicit PlyValues(PlyFormat format) : format_(format) { text_.precision(9); }
    template <class T> PlyValues& operator<<(T value) {
        if (format_ == PlyFormat::Ascii) {
            text_ << (first_ ? "" : " ") << +value;
            first_ = false;
            return *this;
        }
        char bytes[sizeof(T)];
        std::memcpy(bytes, &value, sizeof(T));
        if (format_ == PlyFormat::BinaryBigEndian) std::reverse(bytes, bytes + sizeof(T));
        text_.write(bytes, sizeof(T));
        return *this;
    }
    void end_item() {
        if (format_ == PlyFormat::Ascii) text_ << "\n";
        first_ = true;
    }
    std::string str() const { return text_.str(); }

private:
    PlyFormat format_;
    std::ostringstream text_;
    bool first_ = true;
};

std::string ply_strips(const QuadGrid& g, PlyFormat format) {
    const size_t w = size_t(g.n + 1);
    const size_t indices = size_t(g.n) * 2 * w + size_t(g.n - 1); // and the -1 between strips
    std::string header = "ply\nformat " + ply_format_name(format) +
                         " 1.0\ncomment rows of the grid as strips\nelement vertex " +
                         std::to_string(g.points()) +
                         "\nproperty float x\nproperty float y\nproperty float z\n"
                         "property int PointId\nproperty float temperature\n"
                         "property float nx\nproperty float ny\nproperty float nz\n"
                         "element tristrips 1\nproperty list int int vertex_indices\nend_header\n";
    PlyValues values(format);
    for (size_t v = 0; v < g.points(); ++v) {
        const auto p = g.point(v), n = g.normal(v);
        values << float(p[0]) << float(p[1]) << float(p[2]) << int32_t(1000 + v)
               << float(g.temperature(v)) << float(n[0]) << float(n[1]) << float(n[2]);
        values.end_item();
    }
    values << int32_t(indices);
    for (size_t j = 0; j < size_t(g.n); ++j) {
        if (j > 0) values << int32_t(-1);
        for (size_t i = 0; i < w; ++i) values << int32_t((j + 1) * w + i) << int32_t(j * w + i);
    }
    values.end_item();
    return header + values.str();
}

} // namespace

class PlyStripVariant : public ::testing::TestWithParam<PlyFormat> {};

TEST_P(PlyStripVariant, IsReadAsTheGridWithANoteAndItsKinds) {
    ScratchDir dir;
    const QuadGrid grid;
    const std::string path = dir.file("strips.ply");
    write_text(path, ply_strips(grid, GetParam()));
    io::Notes notes;
    const Surface s = io::read_surface(path, &notes);
    expect_grid(s, grid);
    EXPECT_TRUE(contains(all(notes), "4 triangle strips split into 32 triangles")) << all(notes);
    ASSERT_EQ(s.fields.size(), 3u);
    EXPECT_EQ(s.fields[0].name, "PointId");
    EXPECT_EQ(s.fields[0].kind, FieldKind::Label);
    EXPECT_EQ(s.fields[0].values[7], 1007.0f);
    EXPECT_EQ(s.fields[1].kind, FieldKind::Continuous);
    EXPECT_NEAR(s.fields[1].values[7], grid.temperature(7), 1e-4);
    EXPECT_EQ(s.fields[2].name, "Normals");
    EXPECT_EQ(s.fields[2].kind, FieldKind::Direction);
    EXPECT_NEAR(s.fields[2].values[3 * 7 + 2], grid.normal(7)[2], 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Formats, PlyStripVariant,
                         ::testing::Values(PlyFormat::Ascii, PlyFormat::BinaryLittleEndian,
                                           PlyFormat::BinaryBigEndian),
                         [](const auto& info) { return ply_format_name(info.param); });

TEST(PlyStrips, AFileCutShortInItsStripsSaysWhereItEnds) {
    ScratchDir dir;
    const std::string whole = ply_strips(QuadGrid{}, PlyFormat::BinaryLittleEndian);
    const std::string path = dir.file("cut.ply");
    write_text(path, whole.substr(0, whole.size() - 10));
    const std::string message = io_error_of([&] { io::read_surface(path); });
    EXPECT_TRUE(contains(message, "tristrips 0 ends in its property 'vertex_indices'")) << message;
}

TEST(PlyStrips, AStripThatRefersToAMissingVertexIsRefused) {
    ScratchDir dir;
    std::string text = ply_strips(QuadGrid{}, PlyFormat::Ascii);
    text.replace(text.rfind(" 24"), 3, " 99"); // the last strip's last index
    const std::string path = dir.file("bad.ply");
    write_text(path, text);
    const std::string message = io_error_of([&] { io::read_surface(path); });
    EXPECT_TRUE(contains(message, "tristrips 0 refers to vertex 99; the file has 25")) << message;
}

// Face lines with a colour the header does not declare: VTK reads each element from its own line
// and ignores the rest of it; so does ddsimp, with a note.
TEST(PlyLongLines, AsciiFaceLinesWithUndeclaredValuesAreReadWithANote) {
    ScratchDir dir;
    const QuadGrid grid;
    std::ostringstream out;
    out.precision(9);
    out << "ply\nformat ascii 1.0\nelement vertex " << grid.points()
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << grid.quads()
        << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (size_t v = 0; v < grid.points(); ++v)
        out << grid.point(v)[0] << " " << grid.point(v)[1] << " " << grid.point(v)[2] << "\n";
    for (size_t q = 0; q < grid.quads(); ++q) {
        const auto c = grid.quad(q);
        out << "4 " << c[0] << " " << c[1] << " " << c[2] << " " << c[3] << " 255 128 0\n";
    }
    const std::string path = dir.file("long.ply");
    write_text(path, out.str());
    io::Notes notes;
    const Surface s = io::read_surface(path, &notes);
    expect_grid(s, grid);
    EXPECT_TRUE(contains(all(notes), "16 lines carry more values than the header declares"))
        << all(notes);
    EXPECT_TRUE(contains(all(notes), "16 quads")) << all(notes);
    EXPECT_TRUE(s.fields.empty());
}

// ------------------------------------------------------------------------------------------
// Legacy VTK and VTK XML: polygons, strips, vertex and line cells
// ------------------------------------------------------------------------------------------

namespace {

enum class VtkCells { Quads, Polygons, Strips, QuadsWithVerticesAndLines };

std::string vtk_cells_name(VtkCells c) {
    switch (c) {
    case VtkCells::Quads:
        return "Quads";
    case VtkCells::Polygons:
        return "Polygons";
    case VtkCells::Strips:
        return "Strips";
    case VtkCells::QuadsWithVerticesAndLines:
        return "QuadsWithVerticesAndLines";
    }
    return "";
}

// The grid's cells in legacy POLYDATA sections: quads; each row of quads as one polygon pair
// (a hexagon-free split: two quads as one 6-corner polygon); each row as one triangle strip;
// or quads with a vertex cell and a line cell besides.
std::string vtk_polydata(const QuadGrid& g, VtkCells cells) {
    std::ostringstream out;
    out.precision(9);
    out << "# vtk DataFile Version 3.0\ngenerated\nASCII\nDATASET POLYDATA\nPOINTS " << g.points()
        << " float\n";
    for (size_t v = 0; v < g.points(); ++v)
        out << g.point(v)[0] << " " << g.point(v)[1] << " " << g.point(v)[2] << "\n";
    const size_t w = size_t(g.n + 1);
    if (cells == VtkCells::Strips) {
        out << "TRIANGLE_STRIPS " << g.n << " " << size_t(g.n) * (1 + 2 * w) << "\n";
        for (size_t j = 0; j < size_t(g.n); ++j) {
            out << 2 * w;
            for (size_t i = 0; i < w; ++i) out << " " << (j + 1) * w + i << " " << j * w + i;
            out << "\n";
        }
    } else if (cells == VtkCells::Polygons) {
        // Two neighbouring quads of a row as one hexagon (n is even).
        const size_t hexagons = g.quads() / 2;
        out << "POLYGONS " << hexagons << " " << hexagons * 7 << "\n";
        for (size_t j = 0; j < size_t(g.n); ++j)
            for (size_t i = 0; i < size_t(g.n); i += 2)
                out << "6 " << j * w + i << " " << j * w + i + 1 << " " << j * w + i + 2 << " "
                    << (j + 1) * w + i + 2 << " " << (j + 1) * w + i + 1 << " " << (j + 1) * w + i
                    << "\n";
    } else {
        if (cells == VtkCells::QuadsWithVerticesAndLines)
            out << "VERTICES 1 2\n1 0\nLINES 1 3\n2 0 1\n";
        out << "POLYGONS " << g.quads() << " " << g.quads() * 5 << "\n";
        for (size_t q = 0; q < g.quads(); ++q) {
            const auto c = g.quad(q);
            out << "4 " << c[0] << " " << c[1] << " " << c[2] << " " << c[3] << "\n";
        }
    }
    out << "POINT_DATA " << g.points() << "\nSCALARS temperature float 1\nLOOKUP_TABLE default\n";
    for (size_t v = 0; v < g.points(); ++v) out << g.temperature(v) << "\n";
    out << "NORMALS normals float\n";
    for (size_t v = 0; v < g.points(); ++v)
        out << g.normal(v)[0] << " " << g.normal(v)[1] << " " << g.normal(v)[2] << "\n";
    out << "FIELD FieldData 1\nPedigreeNodeId 1 " << g.points() << " int\n";
    for (size_t v = 0; v < g.points(); ++v) out << 7 * v + 3 << "\n";
    return out.str();
}

} // namespace

class VtkVariant : public ::testing::TestWithParam<VtkCells> {};

TEST_P(VtkVariant, LegacyPolyDataIsReadAsTheGridWithNotesAndKinds) {
    ScratchDir dir;
    const QuadGrid grid;
    const std::string path = dir.file("grid.vtk");
    write_text(path, vtk_polydata(grid, GetParam()));
    io::Notes notes;
    const Surface s = io::read_surface(path, &notes);
    expect_grid(s, grid);
    const std::string said = all(notes);
    switch (GetParam()) {
    case VtkCells::Quads:
        EXPECT_TRUE(contains(said, "16 quads triangulated into 32 triangles")) << said;
        break;
    case VtkCells::Polygons:
        EXPECT_TRUE(contains(said, "8 polygons (6 corners) triangulated into 32 triangles"))
            << said;
        break;
    case VtkCells::Strips:
        EXPECT_TRUE(contains(said, "4 triangle strips split into 32 triangles")) << said;
        break;
    case VtkCells::QuadsWithVerticesAndLines:
        EXPECT_TRUE(contains(said, "1 vertex and 1 line cells set aside")) << said;
        break;
    }
    ASSERT_EQ(s.fields.size(), 3u);
    EXPECT_EQ(s.fields[0].name, "temperature");
    EXPECT_EQ(s.fields[0].kind, FieldKind::Continuous);
    EXPECT_EQ(s.fields[1].kind, FieldKind::Direction);
    EXPECT_EQ(s.fields[2].name, "PedigreeNodeId");
    EXPECT_EQ(s.fields[2].kind, FieldKind::Label);
    EXPECT_EQ(default_gradient_fields(s), std::vector<std::string>{"temperature"});
}

TEST_P(VtkVariant, WrittenAsVtpAndReadBackItKeepsTrianglesAndKinds) {
    ScratchDir dir;
    const QuadGrid grid;
    write_text(dir.file("grid.vtk"), vtk_polydata(grid, GetParam()));
    const Surface s = io::read_surface(dir.file("grid.vtk"));
    for (const char* ext : {".vtp", ".vtk"}) {
        const std::string path = dir.file(std::string("back") + ext);
        io::write_surface(s, path);
        const Surface back = io::read_surface(path);
        EXPECT_EQ(back.triangles, s.triangles);
        // (Legacy .vtk writes the normals attribute before the other arrays.)
        ASSERT_EQ(back.fields.size(), s.fields.size());
        for (const Field& f : s.fields) {
            const Field* b = back.find_field(f.name);
            ASSERT_NE(b, nullptr) << f.name << ext;
            EXPECT_EQ(b->kind, f.kind) << f.name << ext;
            EXPECT_EQ(b->values, f.values) << f.name << ext;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Cells, VtkVariant,
                         ::testing::Values(VtkCells::Quads, VtkCells::Polygons, VtkCells::Strips,
                                           VtkCells::QuadsWithVerticesAndLines),
                         [](const auto& info) { return vtk_cells_name(info.param); });

TEST(VtkXml, PolyDataWithVertexCellsAndStripsIsRead) {
    ScratchDir dir;
    const QuadGrid grid;
    const size_t w = size_t(grid.n + 1);
    std::ostringstream points, strips, offsets;
    points.precision(9);
    for (size_t v = 0; v < grid.points(); ++v)
        points << grid.point(v)[0] << " " << grid.point(v)[1] << " " << grid.point(v)[2] << " ";
    for (size_t j = 0; j < size_t(grid.n); ++j) {
        for (size_t i = 0; i < w; ++i) strips << (j + 1) * w + i << " " << j * w + i << " ";
        offsets << (j + 1) * 2 * w << " ";
    }
    std::ostringstream xml;
    xml << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\">\n<PolyData>\n"
        << "<Piece NumberOfPoints=\"" << grid.points()
        << "\" NumberOfVerts=\"2\" NumberOfLines=\"0\" NumberOfStrips=\"" << grid.n
        << "\" NumberOfPolys=\"0\">\n<Points><DataArray type=\"Float32\" "
           "NumberOfComponents=\"3\" format=\"ascii\">"
        << points.str()
        << "</DataArray></Points>\n<Verts><DataArray type=\"Int64\" Name=\"connectivity\" "
           "format=\"ascii\">0 5</DataArray><DataArray type=\"Int64\" Name=\"offsets\" "
           "format=\"ascii\">1 2</DataArray></Verts>\n<Strips><DataArray type=\"Int64\" "
           "Name=\"connectivity\" format=\"ascii\">"
        << strips.str()
        << "</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
        << offsets.str() << "</DataArray></Strips>\n</Piece>\n</PolyData>\n</VTKFile>\n";
    const std::string path = dir.file("strips.vtp");
    write_text(path, xml.str());
    io::Notes notes;
    expect_grid(io::read_surface(path, &notes), grid);
    EXPECT_TRUE(contains(all(notes), "2 vertex cells set aside")) << all(notes);
    EXPECT_TRUE(contains(all(notes), "4 triangle strips")) << all(notes);
}

TEST(VtkUnstructuredGrid, QuadsPixelsAndVerticesAreReadAVolumeCellIsRefused) {
    ScratchDir dir;
    const std::string head = "# vtk DataFile Version 3.0\ngrid\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                             "POINTS 6 float\n0 0 0 1 0 0 1 1 0 0 1 0 2 0 0 2 1 0\n";
    // A quad (9), a pixel (8: corners in x-y order) and a vertex cell (1).
    const std::string path = dir.file("grid.vtk");
    write_text(path, head + "CELLS 3 12\n4 0 1 2 3\n4 1 4 2 5\n1 0\nCELL_TYPES 3\n9\n8\n1\n");
    io::Notes notes;
    const Surface s = io::read_surface(path, &notes);
    EXPECT_EQ(s.triangle_count(), 4u);
    EXPECT_TRUE(contains(all(notes), "2 quads triangulated into 4 triangles")) << all(notes);
    EXPECT_TRUE(contains(all(notes), "1 vertex cell set aside")) << all(notes);
    const Topology t = analyze_topology(s);
    EXPECT_EQ(t.components, 1u);
    EXPECT_EQ(t.nonmanifold_edges, 0u);
    EXPECT_EQ(t.euler_characteristic, 1);

    write_text(path, head + "CELLS 1 5\n4 0 1 2 4\nCELL_TYPES 1\n10\n");
    const std::string message = io_error_of([&] { io::read_surface(path); });
    EXPECT_TRUE(contains(message, "cell 0 is a vtkTetra, a volume cell")) << message;
}

// ------------------------------------------------------------------------------------------
// Truncation
// ------------------------------------------------------------------------------------------

TEST(VtkTruncation, AFieldArrayCutShortIsRefusedNeverReadUninitialised) {
    ScratchDir dir;
    const QuadGrid grid;
    const std::string text = vtk_polydata(grid, VtkCells::Quads);
    // Cut inside the last array (PedigreeNodeId), then inside the SCALARS.
    const size_t pedigree = text.find("PedigreeNodeId"), normals = text.find("NORMALS");
    for (const size_t cut : {pedigree + (text.size() - pedigree) / 2, normals - 40}) {
        const std::string path = dir.file("cut.vtk");
        write_text(path, text.substr(0, cut));
        const std::string message = io_error_of([&] { io::read_surface(path); });
        EXPECT_TRUE(contains(message, "before the values it declares")) << message;
        EXPECT_TRUE(contains(message, cut > pedigree ? "PedigreeNodeId" : "temperature"))
            << message;
    }
}

namespace {

std::string binary_stl(const QuadGrid& g) {
    std::string bytes(80, ' ');
    bytes.replace(0, 15, "binary by tests");
    const uint32_t facets = uint32_t(2 * g.quads());
    bytes.append(reinterpret_cast<const char*>(&facets), 4);
    auto put = [&](float f) { bytes.append(reinterpret_cast<const char*>(&f), 4); };
    for (size_t q = 0; q < g.quads(); ++q) {
        const auto c = g.quad(q);
        for (const auto& t : {std::array<size_t, 3>{c[0], c[1], c[2]}, {c[0], c[2], c[3]}}) {
            for (int k = 0; k < 3; ++k) put(0);
            for (size_t v : t)
                for (int k = 0; k < 3; ++k) put(float(g.point(v)[k]));
            bytes.append(2, '\0');
        }
    }
    return bytes;
}

} // namespace

TEST(StlTruncation, ABinaryFileCutShortIsReadUpToItsLastWholeFacetWithANote) {
    ScratchDir dir;
    const QuadGrid grid;
    const std::string bytes = binary_stl(grid);
    const std::string path = dir.file("grid.stl");
    write_text(path, bytes);
    io::Notes notes;
    expect_grid(io::read_surface(path, &notes), grid, false);
    EXPECT_TRUE(notes.empty()) << all(notes);

    write_text(path, bytes.substr(0, bytes.size() - 30)); // into the last facet
    notes.clear();
    const Surface s = io::read_surface(path, &notes);
    EXPECT_EQ(s.triangle_count(), 31u);
    EXPECT_TRUE(contains(all(notes), "ends in facet 31 of the 32 its header declares"))
        << all(notes);

    write_text(path, bytes.substr(0, 100)); // not one whole facet
    const std::string message = io_error_of([&] { io::read_surface(path); });
    EXPECT_TRUE(contains(message, "before its first facet")) << message;
}

TEST(StlBinary, AHeaderThatStartsWithSolidIsStillBinary) {
    ScratchDir dir;
    const QuadGrid grid;
    std::string bytes = binary_stl(grid);
    bytes.replace(0, 5, "solid");
    const std::string path = dir.file("solid.stl");
    write_text(path, bytes);
    expect_grid(io::read_surface(path), grid, false);
}

// ------------------------------------------------------------------------------------------
// Writers say what they drop
// ------------------------------------------------------------------------------------------

TEST(WriterNotes, ObjAndOffNameTheFieldsTheyCannotHold) {
    ScratchDir dir;
    for (const char* ext : {".obj", ".off"}) {
        io::Notes notes;
        io::write_surface(square_with_fields(), dir.file(std::string("s") + ext), {}, &notes);
        EXPECT_TRUE(contains(all(notes), "Temp, V, uv are not written")) << all(notes);
    }
    for (const char* ext : {".vtk", ".vtp", ".ply"}) {
        io::Notes notes;
        io::write_surface(square_with_fields(), dir.file(std::string("s") + ext), {}, &notes);
        EXPECT_TRUE(notes.empty()) << ext << ": " << all(notes);
    }
}
