// ddsimp::to_openmesh / from_openmesh: fields as vertex properties, refused triangles reported.
#include "tools_test_support.h"

#include <ddsimp/openmesh.h>

using namespace ddsimp;
using namespace ddsimp::tools_test;

TEST(OpenMeshInterop, FieldsBecomePropertiesOfTheDocumentedTypes) {
    const Surface s = square_with_fields();
    const TriMesh mesh = to_openmesh(s);
    ASSERT_EQ(mesh.n_vertices(), 4u);
    ASSERT_EQ(mesh.n_faces(), 2u);

    OpenMesh::VPropHandleT<float> temp;
    OpenMesh::VPropHandleT<OpenMesh::Vec3f> velocity;
    OpenMesh::VPropHandleT<std::vector<float>> uv;
    ASSERT_TRUE(mesh.get_property_handle(temp, "Temp"));
    ASSERT_TRUE(mesh.get_property_handle(velocity, "V"));
    ASSERT_TRUE(mesh.get_property_handle(uv, "uv"));
    EXPECT_EQ(mesh.property(temp, TriMesh::VertexHandle(3)), 1.0f / 3.0f);
    EXPECT_EQ(mesh.property(velocity, TriMesh::VertexHandle(1)), OpenMesh::Vec3f(-4, 5.5f, 6));
    EXPECT_EQ(mesh.property(uv, TriMesh::VertexHandle(2)), (std::vector<float>{4, 5}));
}

TEST(OpenMeshInterop, RoundTripKeepsEverything) {
    const Surface s = square_with_fields();
    const Surface back = from_openmesh(to_openmesh(s));
    EXPECT_EQ(back.positions, s.positions);
    EXPECT_EQ(back.triangles, s.triangles);
    ASSERT_EQ(back.fields.size(), 3u);
    for (size_t f = 0; f < 3; ++f) {
        EXPECT_EQ(back.fields[f].name, s.fields[f].name);
        EXPECT_EQ(back.fields[f].components, s.fields[f].components);
        EXPECT_EQ(back.fields[f].values, s.fields[f].values);
    }
}

TEST(OpenMeshInterop, NonManifoldTriangleIsAnErrorNamingCountAndFirst) {
    try {
        to_openmesh(fin_of_three());
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("refused 1 of 3"), std::string::npos) << message;
        EXPECT_NE(message.find("triangle 2"), std::string::npos) << message;
    }
}

TEST(OpenMeshInterop, DegenerateAndOutOfRangeTrianglesAreRefused) {
    Surface s = square_with_fields();
    s.triangles.insert(s.triangles.end(), {1, 1, 2, 0, 2, 99});
    EXPECT_THROW(to_openmesh(s), InputError);
}

TEST(OpenMeshInterop, FromOpenMeshSkipsDeletedElementsAndForeignProperties) {
    TriMesh mesh = to_openmesh(square_with_fields());
    OpenMesh::VPropHandleT<int> ids; // not a field type: skipped
    mesh.add_property(ids, "ids");
    mesh.request_vertex_status();
    mesh.request_edge_status();
    mesh.request_face_status();
    mesh.delete_face(TriMesh::FaceHandle(1), true); // vertex 3 becomes isolated and is deleted
    const Surface back = from_openmesh(mesh);
    EXPECT_EQ(back.triangle_count(), 1u);
    EXPECT_EQ(back.vertex_count(), 3u);
    ASSERT_EQ(back.fields.size(), 3u);
    EXPECT_EQ(back.fields[0].values, (std::vector<float>{300.125f, 301.7f, 299.9f}));
}
