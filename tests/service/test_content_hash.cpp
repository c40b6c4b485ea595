// Content hashes: SHA-256 as published, and surface ids that follow content only.
#include "ddsimp/protocol/content_hash.h"

#include "test_surfaces.h"

namespace ddsimp::protocol {
namespace {

// FIPS 180-2, appendix B.1.
TEST(ContentHash, Sha256OfAbc) {
    EXPECT_EQ(sha256_hex("abc"),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(ContentHash, SurfaceIdFollowsContent) {
    const Surface s = test::with_test_fields(test::icosphere(2));
    Surface copy = s;
    EXPECT_EQ(surface_hash(s), surface_hash(copy));
    EXPECT_EQ(surface_hash(s).size(), 64u);

    Surface moved = s;
    moved.positions[5] += 1e-3f;
    Surface data = s;
    data.fields[1].values[7] += 1e-3f;
    Surface renamed = s;
    renamed.fields[0].name = "Pressure";
    Surface turned = s;
    std::swap(turned.triangles[0], turned.triangles[1]);
    Surface labelled = s;
    labelled.fields[0].kind = FieldKind::Label;
    Surface directed = s;
    directed.fields[0].kind = FieldKind::Direction;
    for (const Surface* other : {&moved, &data, &renamed, &turned, &labelled, &directed})
        EXPECT_NE(surface_hash(s), surface_hash(*other));
    EXPECT_NE(surface_hash(labelled), surface_hash(directed));
}

} // namespace
} // namespace ddsimp::protocol
