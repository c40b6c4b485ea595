// Bulk bytes: how surfaces (uploads, whole levels) and refinements are laid out as one blob that
// then travels in chunks. A blob is a sequence of sections whose sizes the Begin message lists:
//
//   whole mesh:  positions (3 float32 per vertex) | triangles (3 uint32 per triangle) |
//                one section per field (components float32 per vertex)
//   refinement:  new positions | slot writes (4 uint32 each: slot, a, b, c) | new field values
//
// All numbers little endian. With Encoding MESHOPT, positions and field sections are
// meshoptimizer vertex-codec streams and the triangle section is its index-codec stream (slot
// writes stay raw). Decoding checks every size and index before trusting it.
#pragma once

#include "ddsimp/ddsimp.h"
#include "ddsimp/v1/ddsimp.pb.h"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace ddsimp::protocol {

// A blob that does not match what its Begin message announced; what() says how.
class BlobError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

inline constexpr uint32_t kDeadSlot = 0xffffffffu;

struct FieldSpec {
    std::string name;
    uint32_t components = 1;
    FieldKind kind = FieldKind::Continuous;
};

// A field's name, components and kind from and to the wire (a kind this version does not know
// is read as Continuous).
FieldSpec field_spec_of(const v1::FieldInfo& info);
void set_field_info(v1::FieldInfo& info, const FieldSpec& spec);

// What a Begin message says about the blob that follows.
struct BlobLayout {
    v1::Encoding encoding = v1::RAW;
    uint64_t vertex_count = 0;   // refinement: new vertices
    uint64_t triangle_count = 0; // refinement: slot writes
    std::vector<FieldSpec> fields;
    std::vector<uint64_t> section_bytes;

    uint64_t total_bytes() const;
};

struct EncodedBlob {
    BlobLayout layout;
    std::string bytes;
};

// Limits a decoder enforces before allocating.
struct DecodeLimits {
    uint64_t max_vertices = 1ull << 28;
    uint64_t max_triangles = 1ull << 28;
    uint32_t max_components = 256;
    uint32_t max_fields = 256;
};

std::vector<FieldSpec> field_specs(const Surface& surface);

// A whole mesh. MESHOPT falls back to RAW where the codec cannot hold a field (over 64
// components); the layout says what was used.
EncodedBlob encode_mesh(const Surface& surface, v1::Encoding encoding);
Surface decode_mesh(std::string_view bytes, const BlobLayout& layout,
                    const DecodeLimits& limits = {});

// The raw blob size a mesh of these counts implies (an upload announces it).
uint64_t raw_mesh_bytes(uint64_t vertices, uint64_t triangles,
                        const std::vector<FieldSpec>& fields);
// The section sizes of a raw whole-mesh blob; throws BlobError if they overflow 64 bits.
std::vector<uint64_t> raw_mesh_sections(uint64_t vertices, uint64_t triangles,
                                        const std::vector<FieldSpec>& fields);

// New vertices (positions and fields, no triangles) and slot writes onto the previous level:
// a write {slot, a, b, c} sets triangle slot `slot` (appending when slot == the slot count),
// a == kDeadSlot empties it. Vertex ids continue after the previous level's.
struct Refinement {
    Surface new_vertices;
    std::vector<uint32_t> writes;
};

EncodedBlob encode_refinement(const Refinement& refinement, v1::Encoding encoding);
Refinement decode_refinement(std::string_view bytes, const BlobLayout& layout,
                             const DecodeLimits& limits = {});

// Layouts from and to the Begin messages.
BlobLayout layout_of(const v1::MeshBegin& begin);
void set_layout(v1::MeshBegin& begin, const BlobLayout& layout);

} // namespace ddsimp::protocol
