// Property tests over the corpus of public files (tests/corpus, see its README): each is read,
// reduced by both strategies, and must keep its topology and carry its fields by their kind; the
// files that are not surfaces must be refused with a message that says why.
#include "tools_test_support.h"

#include "ddsimp/io/surface_io.h"

#include <cmath>
#include <set>

using namespace ddsimp;
using namespace ddsimp::tools_test;

namespace {

struct CorpusFile {
    std::string path;     // under tests/corpus
    size_t triangles = 0; // after reading (polygons split), 0 if refused
    std::string note;     // part of a reader's note, or of the error if refused
};

std::string corpus(const std::string& relative) {
    return std::string(DDSIMP_CORPUS) + "/" + relative;
}

// Counted from each file (its faces and their corners) apart from the reader under test.
const std::vector<CorpusFile> kFiles = {
    {"assimp/Cube.off", 12, "6 quads triangulated into 12 triangles"},
    {"assimp/Wuson.off", 3732, ""},
    {"assimp/cube.ply", 12, "6 quads triangulated into 12 triangles"},
    {"assimp/cube_binary.ply", 12, ""},
    {"assimp/float-color.ply", 1, ""},
    {"assimp/Spider_binary.stl", 1368, ""},
    {"assimp/sphereWithHole.stl", 285, ""},
    {"assimp/triangle.stl", 1, ""},
    {"assimp/3DSMaxExport.STL", 2000, ""},
    {"assimp/box.obj", 12, "6 quads triangulated into 12 triangles"},
    // Its face lists corners 31 and 32 twice; OpenMesh's OBJ reader keeps each once.
    {"assimp/concave_polygon.obj", 62, "1 polygon (64 corners) triangulated into 62 triangles"},
    {"assimp/testmixed.obj", 12, "6 point and 6 line elements set aside"},
    {"assimp/spider.obj", 1368, ""},
    {"mayavi/shuttle.obj", 616, "223 quads triangulated into 446 triangles"},
    {"mayavi/pyramid.ply", 6, ""},
    {"mayavi/polyEx.vtk", 12, "6 quads triangulated into 12 triangles"},
    // A Python line that holds an ASCII STL in a string; its 12 facets are read.
    {"mayavi/cube.stl", 12, ""},
};

const std::vector<CorpusFile> kRefused = {
    {"assimp/points.ply", 0, "holds no triangles"},
    // Its index lists belong to the vertex element: there is no face element.
    {"assimp/issue623.ply", 0, "its header declares 24 vertices and 0 faces"},
    {"assimp/number_formats.obj", 0, "line 11: a vertex needs x y z, '3.1+e2' is not a number"},

    {"mayavi/uGridEx.vtk", 0, "a volume cell"},
    {"mayavi/fieldfile.vtk", 0, "a volume cell"},
};

void expect_topology_kept(const Topology& in, const Topology& out, const std::string& what) {
    EXPECT_EQ(out.euler_characteristic, in.euler_characteristic) << what;
    EXPECT_EQ(out.boundary_loops, in.boundary_loops) << what;
    EXPECT_EQ(out.components, in.components) << what;
    EXPECT_LE(out.nonmanifold_edges, in.nonmanifold_edges) << what;
}

// Labels keep values of the input (never a mix), directions stay unit length where the input's
// were, and every field keeps its name, size and kind.
void expect_fields_by_kind(const Surface& in, const Surface& out, const std::string& what) {
    ASSERT_EQ(out.fields.size(), in.fields.size()) << what;
    for (size_t f = 0; f < in.fields.size(); ++f) {
        const Field &a = in.fields[f], &b = out.fields[f];
        EXPECT_EQ(b.name, a.name) << what;
        EXPECT_EQ(b.kind, a.kind) << what << " " << a.name;
        ASSERT_EQ(b.values.size(), out.vertex_count() * size_t(a.components)) << what;
        if (a.kind == FieldKind::Label) {
            const std::set<float> values(a.values.begin(), a.values.end());
            for (float v : b.values) EXPECT_TRUE(values.count(v)) << what << " " << a.name;
        }
        if (a.kind == FieldKind::Direction) {
            for (size_t v = 0; v < out.vertex_count(); ++v) {
                double l = 0;
                for (int c = 0; c < a.components; ++c)
                    l += double(b.values[v * a.components + c]) * b.values[v * a.components + c];
                EXPECT_NEAR(std::sqrt(l), 1.0, 1e-4) << what << " vertex " << v;
            }
        }
    }
}

} // namespace

class Corpus : public ::testing::TestWithParam<CorpusFile> {};

TEST_P(Corpus, IsReadReducedBothWaysAndKeepsTopologyAndFieldKinds) {
    const CorpusFile& file = GetParam();
    io::Notes notes;
    const Surface input = io::read_surface(corpus(file.path), &notes);
    if (file.triangles > 0) {
        EXPECT_EQ(input.triangle_count(), file.triangles);
    }
    if (!file.note.empty()) {
        EXPECT_NE(all(notes).find(file.note), std::string::npos) << all(notes);
    }

    Surface repaired = input;
    validate(repaired);
    const Topology before = analyze_topology(repaired);
    for (Strategy strategy : {Strategy::EdgeCollapse, Strategy::VertexRemoval}) {
        Options options;
        options.strategy = strategy;
        options.keep_fraction = 0.5;
        const Result r = simplify(input, options);
        const std::string what =
            file.path + (strategy == Strategy::EdgeCollapse ? " edge collapse" : " vertex removal");
        EXPECT_LE(r.triangles_out, r.triangles_in) << what;
        expect_topology_kept(before, analyze_topology(r.surface), what);
        expect_fields_by_kind(input, r.surface, what);
    }
}

TEST_P(Corpus, KeepsItsFieldKindsThroughVtp) {
    ScratchDir dir;
    const Surface input = io::read_surface(corpus(GetParam().path));
    io::write_surface(input, dir.file("back.vtp"));
    const Surface back = io::read_surface(dir.file("back.vtp"));
    EXPECT_EQ(back.triangles, input.triangles);
    ASSERT_EQ(back.fields.size(), input.fields.size());
    for (size_t f = 0; f < input.fields.size(); ++f)
        EXPECT_EQ(back.fields[f].kind, input.fields[f].kind) << input.fields[f].name;
}

INSTANTIATE_TEST_SUITE_P(Files, Corpus, ::testing::ValuesIn(kFiles), [](const auto& info) {
    std::string name = info.param.path;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
});

TEST(CorpusRefused, FilesThatAreNotSurfacesSayWhy) {
    for (const CorpusFile& file : kRefused) {
        std::string message;
        try {
            io::read_surface(corpus(file.path));
        } catch (const io::IoError& e) {
            message = e.what();
        }
        EXPECT_NE(message.find(file.note), std::string::npos) << file.path << ": " << message;
    }
}
