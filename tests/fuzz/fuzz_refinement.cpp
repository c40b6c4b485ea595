// Progressive levels as the client receives them: a base mesh, then a refinement applied to the
// slots it holds. Input: 16-bit length + MeshBegin and 32-bit length + blob of the base, then
// 16-bit length + MeshBegin and the refinement blob. A refinement that does not fit must be a
// BlobError and leave the mesh as it was; one that fits leaves every live slot in range.
#include "fuzz_check.h"
#include "fuzz_input.h"
#include "fuzz_messages.h"
#include "fuzz_surface.h"

#include "ddsimp/protocol/refinement.h"

#include <optional>

using namespace ddsimp;
using namespace ddsimp::protocol;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz::FuzzInput in(data, size);
    v1::MeshBegin base_begin, refinement_begin;
    if (!base_begin.ParseFromString(std::string(in.take_chunk()))) return 0;
    const std::string_view base_blob = in.take_bytes(in.take<uint32_t>());
    if (!refinement_begin.ParseFromString(std::string(in.take_chunk()))) return 0;
    const std::string_view refinement_blob = in.rest();

    std::optional<SlotMesh> mesh;
    try {
        mesh.emplace(decode_mesh(base_blob, layout_of(base_begin)));
    } catch (const BlobError&) {
        return 0;
    }
    Refinement refinement;
    try {
        refinement = decode_refinement(refinement_blob, layout_of(refinement_begin));
    } catch (const BlobError&) {
        return 0;
    }
    FUZZ_CHECK(refinement.writes.size() % 4 == 0);
    const Surface before = mesh->slots();
    try {
        mesh->apply(refinement);
    } catch (const BlobError&) {
        FUZZ_CHECK(fuzz::same_bits(mesh->slots(), before));
        return 0;
    }
    const Surface& after = mesh->slots();
    FUZZ_CHECK(after.vertex_count() ==
               before.vertex_count() + refinement.new_vertices.vertex_count());
    FUZZ_CHECK(after.triangle_count() >= before.triangle_count());
    for (size_t t = 0; t < after.triangles.size(); t += 3) {
        const uint32_t* c = &after.triangles[t];
        const bool dead = c[0] == c[1] && c[1] == c[2]; // kept as 0,0,0
        if (!dead)
            for (int k = 0; k < 3; ++k) FUZZ_CHECK(c[k] < after.vertex_count());
    }
    const Surface live = mesh->live();
    FUZZ_CHECK(live.triangle_count() == mesh->live_triangles());
    FUZZ_CHECK(live.triangle_count() <= after.triangle_count());
    return 0;
}
