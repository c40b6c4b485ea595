// A whole mesh as the client receives it (and the server an upload): a MeshBegin, then the blob
// its layout describes, decoded with decode_mesh. Input: 16-bit length, MeshBegin payload, blob.
// Anything bad must be a BlobError, caught before a byte is trusted; what decodes must survive a
// raw round trip bit for bit.
#include "fuzz_check.h"
#include "fuzz_input.h"
#include "fuzz_messages.h"
#include "fuzz_surface.h"

#include "ddsimp/protocol/mesh_codec.h"

using namespace ddsimp;
using namespace ddsimp::protocol;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz::FuzzInput in(data, size);
    v1::MeshBegin begin;
    if (!begin.ParseFromString(std::string(in.take_chunk()))) return 0;
    const std::string_view blob = in.rest();
    const BlobLayout layout = layout_of(begin);
    try {
        const Surface s = decode_mesh(blob, layout);
        FUZZ_CHECK(s.vertex_count() == layout.vertex_count);
        FUZZ_CHECK(s.triangle_count() == layout.triangle_count);
        FUZZ_CHECK(s.fields.size() == layout.fields.size());
        for (uint32_t v : s.triangles) FUZZ_CHECK(v < s.vertex_count());
        const EncodedBlob raw = encode_mesh(s, v1::RAW);
        FUZZ_CHECK(fuzz::same_bits(decode_mesh(raw.bytes, raw.layout), s));
        if (layout.encoding == v1::RAW) FUZZ_CHECK(raw.bytes == blob);
    } catch (const BlobError&) {
    }
    return 0;
}
