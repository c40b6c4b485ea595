#include "ddsimp/protocol/mesh_codec.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cstring>
#include <numeric>

namespace ddsimp::protocol {
namespace {

// a * b, or BlobError if it overflows
uint64_t checked_mul(uint64_t a, uint64_t b, const char* what) {
    uint64_t r = 0;
    if (__builtin_mul_overflow(a, b, &r)) throw BlobError(std::string(what) + " overflows");
    return r;
}

void append_bytes(std::string& out, const void* data, size_t bytes) {
    out.append(static_cast<const char*>(data), bytes);
}

// Appends `count` vertices of `size` bytes, raw or through the vertex codec; returns the bytes
// appended.
uint64_t append_vertex_stream(std::string& out, const float* data, size_t count, size_t size,
                              bool meshopt) {
    const size_t before = out.size();
    if (!meshopt) {
        append_bytes(out, data, count * size);
    } else {
        std::string buffer(meshopt_encodeVertexBufferBound(count, size), '\0');
        const size_t n = meshopt_encodeVertexBuffer(reinterpret_cast<unsigned char*>(buffer.data()),
                                                    buffer.size(), data, count, size);
        append_bytes(out, buffer.data(), n);
    }
    return out.size() - before;
}

// memcpy of a section (which may be empty, and then `out` may be null).
void copy_section(void* out, std::string_view section) {
    if (!section.empty()) std::memcpy(out, section.data(), section.size());
}

// The fewest bytes meshopt's vertex codec (version 0) encodes `count` vertices of `size` bytes in:
// a header byte, per block and byte of a vertex at least one 2-bit header per 16 vertices (so per
// 64 vertices a byte), and the tail. Checked before the vertices are allocated, so that a short
// section cannot make the decoder allocate more than 64 times what arrived.
uint64_t min_meshopt_vertex_bytes(uint64_t count, uint64_t size) {
    return 1 + size * ((count + 63) / 64) + std::max<uint64_t>(32, size);
}

// Throws unless `section` can hold `count` vertices of `size` bytes (before they are allocated).
void check_vertex_section(std::string_view section, uint64_t count, uint64_t size, bool meshopt,
                          const std::string& what) {
    if (!meshopt && section.size() != count * size)
        throw BlobError(what + ": " + std::to_string(section.size()) + " bytes, expected " +
                        std::to_string(count * size));
    if (meshopt && section.size() < min_meshopt_vertex_bytes(count, size))
        throw BlobError(what + ": " + std::to_string(section.size()) +
                        " bytes, too few for a meshopt vertex stream of " + std::to_string(count) +
                        " vertices");
}

// Decodes a section that check_vertex_section accepted.
void read_vertex_stream(std::string_view section, float* out, size_t count, size_t size,
                        bool meshopt, const std::string& what) {
    if (!meshopt) {
        copy_section(out, section);
    } else if (meshopt_decodeVertexBuffer(out, count, size,
                                          reinterpret_cast<const unsigned char*>(section.data()),
                                          section.size()) != 0) {
        throw BlobError(what + ": not a valid meshopt vertex stream of " + std::to_string(count) +
                        " vertices");
    }
}

bool codec_holds(const std::vector<FieldSpec>& fields) {
    // meshopt's vertex codec takes vertices of at most 256 bytes
    for (const FieldSpec& f : fields)
        if (f.components > 64) return false;
    return true;
}

void check_fields(const BlobLayout& layout, const DecodeLimits& limits) {
    if (layout.fields.size() > limits.max_fields)
        throw BlobError(std::to_string(layout.fields.size()) + " fields, over the limit of " +
                        std::to_string(limits.max_fields));
    for (const FieldSpec& f : layout.fields)
        if (f.components == 0 || f.components > limits.max_components)
            throw BlobError("field \"" + f.name + "\" has " + std::to_string(f.components) +
                            " components (1 to " + std::to_string(limits.max_components) +
                            " allowed)");
    if (layout.encoding != v1::RAW && layout.encoding != v1::MESHOPT)
        throw BlobError("unknown encoding " + std::to_string(int(layout.encoding)));
    // The codec itself only asserts it (and would overrun a 256-byte buffer without assertions).
    if (layout.encoding == v1::MESHOPT && !codec_holds(layout.fields))
        throw BlobError("a meshopt blob with a field of more than 64 components");
    if (layout.section_bytes.size() != 2 + layout.fields.size())
        throw BlobError(std::to_string(layout.section_bytes.size()) + " sections, expected " +
                        std::to_string(2 + layout.fields.size()));
}

// Cuts the blob into its sections after checking that their sizes add up.
std::vector<std::string_view> sections_of(std::string_view bytes, const BlobLayout& layout) {
    uint64_t total = 0;
    for (uint64_t s : layout.section_bytes)
        if (__builtin_add_overflow(total, s, &total)) throw BlobError("section sizes overflow");
    if (total != bytes.size())
        throw BlobError("the sections add up to " + std::to_string(total) + " bytes, but " +
                        std::to_string(bytes.size()) + " arrived");
    std::vector<std::string_view> out;
    size_t at = 0;
    for (uint64_t s : layout.section_bytes) {
        out.push_back(bytes.substr(at, s));
        at += s;
    }
    return out;
}

Surface decode_vertices(const std::vector<std::string_view>& sections, size_t field_section,
                        const BlobLayout& layout) {
    const bool meshopt = layout.encoding == v1::MESHOPT;
    check_vertex_section(sections[0], layout.vertex_count, 12, meshopt, "positions");
    for (size_t f = 0; f < layout.fields.size(); ++f)
        check_vertex_section(sections[field_section + f], layout.vertex_count,
                             4 * uint64_t(layout.fields[f].components), meshopt,
                             "field \"" + layout.fields[f].name + "\"");
    Surface s;
    s.positions.resize(3 * layout.vertex_count);
    read_vertex_stream(sections[0], s.positions.data(), layout.vertex_count, 12, meshopt,
                       "positions");
    for (size_t f = 0; f < layout.fields.size(); ++f) {
        const FieldSpec& spec = layout.fields[f];
        Field field{spec.name, int(spec.components), {}, spec.kind};
        field.values.resize(layout.vertex_count * spec.components);
        read_vertex_stream(sections[field_section + f], field.values.data(), layout.vertex_count,
                           4 * spec.components, meshopt, "field \"" + spec.name + "\"");
        s.fields.push_back(std::move(field));
    }
    return s;
}

} // namespace

uint64_t BlobLayout::total_bytes() const {
    return std::accumulate(section_bytes.begin(), section_bytes.end(), uint64_t(0));
}

std::vector<FieldSpec> field_specs(const Surface& surface) {
    std::vector<FieldSpec> out;
    for (const Field& f : surface.fields) out.push_back({f.name, uint32_t(f.components), f.kind});
    return out;
}

FieldSpec field_spec_of(const v1::FieldInfo& info) {
    FieldKind kind = FieldKind::Continuous;
    if (info.kind() == v1::FIELD_KIND_LABEL) kind = FieldKind::Label;
    if (info.kind() == v1::FIELD_KIND_DIRECTION) kind = FieldKind::Direction;
    return {info.name(), info.components(), kind};
}

void set_field_info(v1::FieldInfo& info, const FieldSpec& spec) {
    info.set_name(spec.name);
    info.set_components(spec.components);
    info.set_kind(spec.kind == FieldKind::Label       ? v1::FIELD_KIND_LABEL
                  : spec.kind == FieldKind::Direction ? v1::FIELD_KIND_DIRECTION
                                                      : v1::FIELD_KIND_CONTINUOUS);
}

std::vector<uint64_t> raw_mesh_sections(uint64_t vertices, uint64_t triangles,
                                        const std::vector<FieldSpec>& fields) {
    std::vector<uint64_t> out{checked_mul(vertices, 12, "positions"),
                              checked_mul(triangles, 12, "triangles")};
    for (const FieldSpec& f : fields)
        out.push_back(checked_mul(checked_mul(vertices, f.components, "field"), 4, "field"));
    return out;
}

uint64_t raw_mesh_bytes(uint64_t vertices, uint64_t triangles,
                        const std::vector<FieldSpec>& fields) {
    uint64_t total = 0;
    for (uint64_t s : raw_mesh_sections(vertices, triangles, fields))
        if (__builtin_add_overflow(total, s, &total)) throw BlobError("the blob size overflows");
    return total;
}

EncodedBlob encode_mesh(const Surface& surface, v1::Encoding encoding) {
    EncodedBlob blob;
    BlobLayout& layout = blob.layout;
    layout.fields = field_specs(surface);
    const bool meshopt = encoding == v1::MESHOPT && codec_holds(layout.fields);
    layout.encoding = meshopt ? v1::MESHOPT : v1::RAW;
    layout.vertex_count = surface.vertex_count();
    layout.triangle_count = surface.triangle_count();
    const size_t nv = surface.vertex_count();

    layout.section_bytes.push_back(
        append_vertex_stream(blob.bytes, surface.positions.data(), nv, 12, meshopt));
    if (!meshopt) {
        append_bytes(blob.bytes, surface.triangles.data(), 4 * surface.triangles.size());
        layout.section_bytes.push_back(4 * surface.triangles.size());
    } else {
        std::string buffer(meshopt_encodeIndexBufferBound(surface.triangles.size(), nv), '\0');
        const size_t n = meshopt_encodeIndexBuffer(reinterpret_cast<unsigned char*>(buffer.data()),
                                                   buffer.size(), surface.triangles.data(),
                                                   surface.triangles.size());
        append_bytes(blob.bytes, buffer.data(), n);
        layout.section_bytes.push_back(n);
    }
    for (const Field& f : surface.fields)
        layout.section_bytes.push_back(append_vertex_stream(blob.bytes, f.values.data(), nv,
                                                            4 * size_t(f.components), meshopt));
    return blob;
}

Surface decode_mesh(std::string_view bytes, const BlobLayout& layout, const DecodeLimits& limits) {
    check_fields(layout, limits);
    if (layout.vertex_count > limits.max_vertices)
        throw BlobError(std::to_string(layout.vertex_count) + " vertices, over the limit of " +
                        std::to_string(limits.max_vertices));
    if (layout.triangle_count > limits.max_triangles)
        throw BlobError(std::to_string(layout.triangle_count) + " triangles, over the limit of " +
                        std::to_string(limits.max_triangles));
    const std::vector<std::string_view> sections = sections_of(bytes, layout);
    if (layout.encoding == v1::RAW &&
        layout.section_bytes !=
            raw_mesh_sections(layout.vertex_count, layout.triangle_count, layout.fields))
        throw BlobError("the section sizes do not match " + std::to_string(layout.vertex_count) +
                        " vertices and " + std::to_string(layout.triangle_count) + " triangles");

    // meshopt's index codec takes at least a byte per triangle, a header and a 16-byte table.
    if (layout.encoding == v1::MESHOPT && sections[1].size() < 17 + layout.triangle_count)
        throw BlobError("triangles: " + std::to_string(sections[1].size()) +
                        " bytes, too few for a meshopt index stream of " +
                        std::to_string(layout.triangle_count) + " triangles");
    Surface s = decode_vertices(sections, 2, layout);
    s.triangles.resize(3 * layout.triangle_count);
    if (layout.encoding == v1::RAW) {
        copy_section(s.triangles.data(), sections[1]);
    } else if (meshopt_decodeIndexBuffer(s.triangles.data(), s.triangles.size(), 4,
                                         reinterpret_cast<const unsigned char*>(sections[1].data()),
                                         sections[1].size()) != 0) {
        throw BlobError("triangles: not a valid meshopt index stream of " +
                        std::to_string(layout.triangle_count) + " triangles");
    }
    for (size_t i = 0; i < s.triangles.size(); ++i)
        if (s.triangles[i] >= layout.vertex_count)
            throw BlobError("triangle " + std::to_string(i / 3) + " refers to vertex " +
                            std::to_string(s.triangles[i]) + ", but the mesh has " +
                            std::to_string(layout.vertex_count) + " vertices");
    return s;
}

EncodedBlob encode_refinement(const Refinement& refinement, v1::Encoding encoding) {
    EncodedBlob blob;
    BlobLayout& layout = blob.layout;
    const Surface& v = refinement.new_vertices;
    layout.fields = field_specs(v);
    const bool meshopt = encoding == v1::MESHOPT && codec_holds(layout.fields);
    layout.encoding = meshopt ? v1::MESHOPT : v1::RAW;
    layout.vertex_count = v.vertex_count();
    layout.triangle_count = refinement.writes.size() / 4;
    const size_t nv = v.vertex_count();
    layout.section_bytes.push_back(
        append_vertex_stream(blob.bytes, v.positions.data(), nv, 12, meshopt));
    append_bytes(blob.bytes, refinement.writes.data(), 4 * refinement.writes.size());
    layout.section_bytes.push_back(4 * refinement.writes.size());
    for (const Field& f : v.fields)
        layout.section_bytes.push_back(append_vertex_stream(blob.bytes, f.values.data(), nv,
                                                            4 * size_t(f.components), meshopt));
    return blob;
}

Refinement decode_refinement(std::string_view bytes, const BlobLayout& layout,
                             const DecodeLimits& limits) {
    check_fields(layout, limits);
    if (layout.vertex_count > limits.max_vertices || layout.triangle_count > limits.max_triangles)
        throw BlobError("a refinement of " + std::to_string(layout.vertex_count) +
                        " vertices and " + std::to_string(layout.triangle_count) +
                        " writes is over the limits");
    const std::vector<std::string_view> sections = sections_of(bytes, layout);
    if (sections[1].size() != 16 * layout.triangle_count)
        throw BlobError("slot writes: " + std::to_string(sections[1].size()) + " bytes, expected " +
                        std::to_string(16 * layout.triangle_count));
    Refinement r;
    r.new_vertices = decode_vertices(sections, 2, layout);
    r.writes.resize(4 * layout.triangle_count);
    copy_section(r.writes.data(), sections[1]);
    return r;
}

BlobLayout layout_of(const v1::MeshBegin& begin) {
    BlobLayout layout;
    layout.encoding = begin.encoding() == v1::ENCODING_UNSPECIFIED ? v1::RAW : begin.encoding();
    layout.vertex_count = begin.vertex_count();
    layout.triangle_count = begin.triangle_count();
    for (const v1::FieldInfo& f : begin.fields()) layout.fields.push_back(field_spec_of(f));
    layout.section_bytes.assign(begin.section_bytes().begin(), begin.section_bytes().end());
    return layout;
}

void set_layout(v1::MeshBegin& begin, const BlobLayout& layout) {
    begin.set_encoding(layout.encoding);
    begin.set_vertex_count(layout.vertex_count);
    begin.set_triangle_count(layout.triangle_count);
    begin.clear_fields();
    for (const FieldSpec& f : layout.fields) set_field_info(*begin.add_fields(), f);
    begin.clear_section_bytes();
    for (uint64_t s : layout.section_bytes) begin.add_section_bytes(s);
    begin.set_total_bytes(layout.total_bytes());
}

} // namespace ddsimp::protocol
