// Crashes the fuzz targets found in the blob codec, as tests of the code that was fixed (the inputs
// themselves are in corpus/<target>/ and replayed by fuzz_replay_<target>). Each test names the
// target and the input; the asan preset turns undefined behaviour into a failure here too.
#include "ddsimp/protocol/mesh_codec.h"

#include <gtest/gtest.h>

using namespace ddsimp;
using namespace ddsimp::protocol;

namespace {

BlobLayout layout(v1::Encoding encoding, uint64_t vertices, uint64_t triangles,
                  std::vector<FieldSpec> fields, std::vector<uint64_t> sections) {
    BlobLayout l;
    l.encoding = encoding;
    l.vertex_count = vertices;
    l.triangle_count = triangles;
    l.fields = std::move(fields);
    l.section_bytes = std::move(sections);
    return l;
}

std::string decode_error(std::string_view bytes, const BlobLayout& l) {
    try {
        decode_mesh(bytes, l);
    } catch (const BlobError& e) {
        return e.what();
    }
    return "";
}

} // namespace

// mesh_blob, crash-c2abbf10…: an empty mesh (no vertices, no triangles) copied its empty
// sections with memcpy from and to null pointers (undefined behaviour, caught by UBSan).
TEST(FuzzRegressions, EmptyRawMeshDecodesToAnEmptySurface) {
    const Surface s = decode_mesh("", layout(v1::RAW, 0, 0, {}, {0, 0}));
    EXPECT_TRUE(s.positions.empty());
    EXPECT_TRUE(s.triangles.empty());
    const Refinement r = decode_refinement("", layout(v1::RAW, 0, 0, {}, {0, 0}));
    EXPECT_TRUE(r.writes.empty());
}

// A meshopt blob may not announce more vertices than its bytes can hold: 2^28 vertices in a
// 64-byte position section would have allocated 3 GiB before the codec refused it. The smallest
// meshopt stream of n vertices of s bytes has 1 + s * ceil(n / 64) + max(32, s) bytes.
TEST(FuzzRegressions, MeshoptSectionsTooShortForTheirCountAreRefusedBeforeAllocating) {
    const uint64_t n = 1u << 28;
    const std::string blob(64 + 17 + 1, '\0');
    const std::string why = decode_error(blob, layout(v1::MESHOPT, n, 1, {}, {64, 18}));
    EXPECT_NE(why.find("positions: 64 bytes, too few for a meshopt vertex stream of 268435456"),
              std::string::npos)
        << why;
    // Triangles: at least 17 bytes and one per triangle.
    const std::string few(45 + 100, '\0'); // 45: the least 3 vertices take
    const std::string tri = decode_error(few, layout(v1::MESHOPT, 3, 100, {}, {45, 100}));
    EXPECT_NE(tri.find("triangles: 100 bytes, too few for a meshopt index stream of 100"),
              std::string::npos)
        << tri;
    // The bound is not above what the codec really needs: a real stream still decodes.
    Surface s;
    for (int i = 0; i < 130; ++i) s.positions.insert(s.positions.end(), {float(i), 0, 1});
    s.triangles = {0, 1, 2, 2, 1, 129};
    const EncodedBlob encoded = encode_mesh(s, v1::MESHOPT);
    ASSERT_EQ(encoded.layout.encoding, v1::MESHOPT);
    EXPECT_EQ(decode_mesh(encoded.bytes, encoded.layout).positions, s.positions);
}

// Raw refinements had no size check before their vertices were allocated.
TEST(FuzzRegressions, RawRefinementSectionsAreCheckedBeforeAllocating) {
    try {
        decode_refinement(std::string(12, '\0'), layout(v1::RAW, 1u << 28, 0, {}, {12, 0}));
        FAIL() << "a refinement of 2^28 vertices in 12 bytes decoded";
    } catch (const BlobError& e) {
        EXPECT_STREQ(e.what(), "positions: 12 bytes, expected 3221225472");
    }
}

// refinement, crash-8c9e33cd…: a meshopt blob with a field of more than 64 components (a vertex
// of more than 256 bytes) reached meshopt_decodeVertexBuffer, which asserts against it (an abort
// in Debian's build; without assertions it would overrun a 256-byte buffer). It is refused: the
// encoder never makes one, it falls back to raw.
TEST(FuzzRegressions, MeshoptFieldsOfMoreThan64ComponentsAreRefused) {
    const std::string blob(2000, '\0');
    const std::string why =
        decode_error(blob, layout(v1::MESHOPT, 1, 0, {{"wide", 65}}, {1000, 17, 983}));
    EXPECT_EQ(why, "a meshopt blob with a field of more than 64 components");
}
