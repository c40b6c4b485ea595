// The bulk blob codec: whole meshes and refinements survive both encodings bit for bit, and
// every inconsistency between a blob and its announced layout is refused with a reason.
#include "ddsimp/protocol/mesh_codec.h"

#include "mesh_comparison.h"
#include "test_surfaces.h"

namespace ddsimp::protocol {
namespace {

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const BlobError& e) {
        return e.what();
    }
    return "no error";
}

class MeshCodec : public ::testing::TestWithParam<v1::Encoding> {};
INSTANTIATE_TEST_SUITE_P(Encodings, MeshCodec, ::testing::Values(v1::RAW, v1::MESHOPT),
                         [](const auto& info) { return v1::Encoding_Name(info.param); });

TEST_P(MeshCodec, WholeMeshRoundTripsExactly) {
    const Surface s = test::with_test_fields(test::icosphere(3));
    const EncodedBlob blob = encode_mesh(s, GetParam());
    EXPECT_EQ(blob.layout.encoding, GetParam());
    EXPECT_EQ(blob.layout.total_bytes(), blob.bytes.size());
    Surface back = decode_mesh(blob.bytes, blob.layout);
    if (GetParam() == v1::MESHOPT) test::rotate_to_match(back, s); // the index codec may rotate
    EXPECT_TRUE(test::same_bytes(back, s));
}

// Sizes for a raw blob follow from the counts: 12 bytes per vertex and per triangle, 4 per
// field component and vertex.
TEST(MeshCodecRaw, SectionSizesFollowFromTheCounts) {
    const Surface s = test::with_test_fields(test::icosphere(1)); // 42 vertices, 80 triangles
    const EncodedBlob blob = encode_mesh(s, v1::RAW);
    EXPECT_EQ(blob.layout.section_bytes,
              (std::vector<uint64_t>{42 * 12, 80 * 12, 42 * 4, 42 * 12}));
    EXPECT_EQ(raw_mesh_bytes(42, 80, field_specs(s)), blob.bytes.size());
}

// The codec exists to make meshes smaller; on a smooth mesh it must.
TEST(MeshCodecMeshopt, IsSmallerThanRawOnASmoothMesh) {
    const Surface s = test::with_test_fields(test::icosphere(4));
    EXPECT_LT(encode_mesh(s, v1::MESHOPT).bytes.size(), encode_mesh(s, v1::RAW).bytes.size());
}

TEST(MeshCodecMeshopt, FallsBackToRawForWideFields) {
    Surface s = test::icosphere(1);
    test::add_field(s, "wide", 65, [](const test::Vec3&) { return std::vector<double>(65, 1.0); });
    const EncodedBlob blob = encode_mesh(s, v1::MESHOPT);
    EXPECT_EQ(blob.layout.encoding, v1::RAW);
    EXPECT_TRUE(test::same_bytes(decode_mesh(blob.bytes, blob.layout), s));
}

TEST_P(MeshCodec, RefinementRoundTripsExactly) {
    Refinement r;
    r.new_vertices = test::with_test_fields(test::fan(5));
    r.new_vertices.triangles.clear();
    r.writes = {0, 1, 2, 3, 7, kDeadSlot, kDeadSlot, kDeadSlot};
    const EncodedBlob blob = encode_refinement(r, GetParam());
    const Refinement back = decode_refinement(blob.bytes, blob.layout);
    EXPECT_TRUE(test::same_bytes(back.new_vertices, r.new_vertices));
    EXPECT_EQ(back.writes, r.writes);
}

TEST_P(MeshCodec, TruncatedBlobIsRefused) {
    const Surface s = test::with_test_fields(test::icosphere(2));
    const EncodedBlob blob = encode_mesh(s, GetParam());
    const std::string cut = blob.bytes.substr(0, blob.bytes.size() - 1);
    EXPECT_NE(error_of([&] { decode_mesh(cut, blob.layout); }).find("add up to"),
              std::string::npos);
}

TEST_P(MeshCodec, CorruptSectionsNeverCrash) {
    const Surface s = test::with_test_fields(test::icosphere(2));
    EncodedBlob blob = encode_mesh(s, GetParam());
    // Every byte of the triangle section set to 0xff: either a clear error or a mesh whose
    // indices are all in range (the decoder checks them).
    const size_t from = blob.layout.section_bytes[0];
    for (size_t i = 0; i < blob.layout.section_bytes[1]; ++i) blob.bytes[from + i] = char(0xff);
    try {
        const Surface back = decode_mesh(blob.bytes, blob.layout);
        for (uint32_t v : back.triangles) EXPECT_LT(v, back.vertex_count());
    } catch (const BlobError& e) {
        EXPECT_NE(std::string(e.what()), "");
    }
}

TEST(MeshCodecRaw, OutOfRangeIndexIsRefusedWithItsTriangle) {
    Surface s = test::single_triangle();
    s.triangles[2] = 9;
    const EncodedBlob blob = encode_mesh(s, v1::RAW);
    EXPECT_EQ(error_of([&] { decode_mesh(blob.bytes, blob.layout); }),
              "triangle 0 refers to vertex 9, but the mesh has 3 vertices");
}

TEST(MeshCodecRaw, LayoutChecks) {
    const Surface s = test::with_test_fields(test::single_triangle());
    const EncodedBlob blob = encode_mesh(s, v1::RAW);

    BlobLayout more_vertices = blob.layout;
    more_vertices.vertex_count = 4;
    EXPECT_NE(error_of([&] { decode_mesh(blob.bytes, more_vertices); }).find("do not match"),
              std::string::npos);

    BlobLayout zero_components = blob.layout;
    zero_components.fields[0].components = 0;
    EXPECT_EQ(error_of([&] { decode_mesh(blob.bytes, zero_components); }),
              "field \"pressure\" has 0 components (1 to 256 allowed)");

    BlobLayout missing_section = blob.layout;
    missing_section.section_bytes.pop_back();
    EXPECT_EQ(error_of([&] { decode_mesh(blob.bytes, missing_section); }),
              "3 sections, expected 4");

    DecodeLimits small;
    small.max_triangles = 0;
    EXPECT_EQ(error_of([&] { decode_mesh(blob.bytes, blob.layout, small); }),
              "1 triangles, over the limit of 0");

    EXPECT_THROW(raw_mesh_bytes(1ull << 62, 1, {}), BlobError);
}

TEST(MeshCodec, LayoutSurvivesAMeshBeginMessage) {
    const EncodedBlob blob = encode_mesh(test::with_test_fields(test::icosphere(1)), v1::MESHOPT);
    v1::MeshBegin begin;
    set_layout(begin, blob.layout);
    EXPECT_EQ(begin.total_bytes(), blob.bytes.size());
    const BlobLayout back = layout_of(begin);
    EXPECT_EQ(back.section_bytes, blob.layout.section_bytes);
    EXPECT_EQ(back.vertex_count, blob.layout.vertex_count);
    ASSERT_EQ(back.fields.size(), 2u);
    EXPECT_EQ(back.fields[1].name, "velocity");
    EXPECT_EQ(back.fields[1].components, 3u);
}

TEST(MeshCodec, FieldKindsSurviveAMeshBeginMessageAndTheBlob) {
    Surface s = test::with_test_fields(test::icosphere(1));
    s.fields[0].kind = FieldKind::Label;
    s.fields[1].kind = FieldKind::Direction;
    const EncodedBlob blob = encode_mesh(s, v1::RAW);
    v1::MeshBegin begin;
    set_layout(begin, blob.layout);
    EXPECT_EQ(begin.fields(0).kind(), v1::FIELD_KIND_LABEL);
    EXPECT_EQ(begin.fields(1).kind(), v1::FIELD_KIND_DIRECTION);
    const Surface back = decode_mesh(blob.bytes, layout_of(begin));
    ASSERT_EQ(back.fields.size(), 2u);
    EXPECT_EQ(back.fields[0].kind, FieldKind::Label);
    EXPECT_EQ(back.fields[1].kind, FieldKind::Direction);

    // An older peer sends no kind, a newer one may send a kind this version does not know:
    // both are continuous.
    v1::FieldInfo older, newer;
    older.set_name("p");
    newer.set_name("q");
    newer.set_kind(static_cast<v1::FieldKind>(7));
    EXPECT_EQ(field_spec_of(older).kind, FieldKind::Continuous);
    EXPECT_EQ(field_spec_of(newer).kind, FieldKind::Continuous);
}

} // namespace
} // namespace ddsimp::protocol
