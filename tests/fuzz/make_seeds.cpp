// Writes the seed corpus of the protocol, server and validation fuzz targets into
// tests/fuzz/corpus/<target>/: valid frames, blobs, refinements, sessions and surfaces made by
// the project's own encoders, each in the input layout its target reads.
//
//   build/<dir>/tests/fuzz/fuzz_make_seeds tests/fuzz/corpus
#include "fake_server.h"

#include "surface_file.h"

#include "ddsimp/protocol/refinement.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

using namespace ddsimp;
using namespace ddsimp::protocol;
namespace fs = std::filesystem;

namespace {

fs::path corpus;

void put(const std::string& target, const std::string& name, const std::string& bytes) {
    fs::create_directories(corpus / target);
    std::ofstream(corpus / target / name, std::ios::binary) << bytes;
}

std::string u16(size_t n) {
    return {char(n & 0xff), char((n >> 8) & 0xff)};
}
std::string u32(size_t n) {
    return u16(n & 0xffff) + u16(n >> 16);
}
template <class M> std::string chunk(const M& m) {
    const std::string bytes = m.SerializeAsString();
    return u16(bytes.size()) + bytes;
}

// ----- messages -----

v1::Hello hello() {
    v1::Hello h;
    h.set_protocol_version(kProtocolVersion);
    h.set_client_name("seed");
    h.set_kind(v1::DESKTOP);
    for (const char* c : {"meshopt-codec", "progressive", "sessions"}) h.add_capabilities(c);
    return h;
}

// The whole upload of `s` as id `id`: begin, chunks of at most `piece` bytes, end.
std::string upload_frames(const Surface& s, uint64_t id, size_t piece, const std::string& session) {
    const EncodedBlob blob = encode_mesh(s, v1::RAW);
    v1::UploadBegin begin;
    begin.set_upload_id(id);
    begin.set_name("seed surface");
    begin.set_vertex_count(s.vertex_count());
    begin.set_triangle_count(s.triangle_count());
    for (const Field& f : s.fields) {
        v1::FieldInfo* info = begin.add_fields();
        info->set_name(f.name);
        info->set_components(uint32_t(f.components));
    }
    begin.set_total_bytes(blob.bytes.size());
    begin.set_session(session);
    std::string out = encode_frame(begin);
    for (size_t at = 0; at < blob.bytes.size(); at += piece) {
        v1::UploadChunk c;
        c.set_upload_id(id);
        c.set_offset(at);
        c.set_data(blob.bytes.substr(at, piece));
        out += encode_frame(c);
    }
    v1::UploadEnd end;
    end.set_upload_id(id);
    return out + encode_frame(end);
}

Surface tetrahedron() {
    Surface s;
    s.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    s.triangles = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    s.fields = {{"p", 1, {1, 2, 3, 4}}};
    return s;
}

v1::Request request(uint64_t id, bool progressive, v1::Encoding encoding) {
    v1::Request r;
    r.set_request_id(id);
    r.set_surface(fuzz::sample_id());
    r.set_alpha(0.3f);
    r.set_strategy(id % 2 ? v1::VERTEX_REMOVAL : v1::EDGE_COLLAPSE);
    r.add_keep(0.5f);
    r.add_keep(0.1f);
    r.add_gradient_fields("temperature");
    r.set_progressive(progressive);
    r.set_encoding(encoding);
    return r;
}

v1::SetSessionState view(const std::string& session) {
    v1::SetSessionState s;
    s.set_name(session);
    s.set_set_alpha(true);
    v1::View* v = s.mutable_view();
    v->set_surface(fuzz::sample_id());
    v->set_alpha(0.7f);
    v->set_keep(0.4f);
    v->set_field("velocity");
    v->set_strategy(v1::VERTEX_REMOVAL);
    return s;
}

template <class M> M with_name(const std::string& name) {
    M m;
    m.set_name(name);
    return m;
}

// ----- targets -----

void frame_seeds() {
    // options: limit 3 (the default), pieces of 1 + byte
    const std::string all = encode_frame(hello()) + encode_frame(v1::ListSurfaces{}) +
                            encode_frame(request(1, true, v1::MESHOPT)) +
                            upload_frames(tetrahedron(), 2, 20, "");
    put("frame", "session-in-7-byte-pieces", std::string("\x03\x06", 2) + all);
    put("frame", "session-whole", std::string("\x03\xff", 2) + all);
    v1::Auth auth;
    auth.set_token(fuzz::kToken);
    put("frame", "single-auth", std::string("\x02\x00", 2) + encode_frame(auth));
    v1::MeshBegin begin;
    set_layout(begin, encode_mesh(tetrahedron(), v1::MESHOPT).layout);
    put("frame", "single-mesh-begin", std::string("\x02\x00", 2) + encode_frame(begin));
    put("frame", "bad-magic", std::string("\x03\x00", 2) + "DDSQ" + all.substr(4));
}

void blob_seeds() {
    for (const v1::Encoding e : {v1::RAW, v1::MESHOPT}) {
        for (const auto& [name, s] :
             {std::pair<std::string, Surface>{"tetrahedron", tetrahedron()},
              std::pair<std::string, Surface>{"grid", fuzz::sample_surface()}}) {
            const EncodedBlob blob = encode_mesh(s, e);
            v1::MeshBegin begin;
            set_layout(begin, blob.layout);
            put("mesh_blob", name + (e == v1::RAW ? "-raw" : "-meshopt"),
                chunk(begin) + blob.bytes);
        }
        // Levels as the server streams them: a base and the refinement to the next level.
        Options options;
        options.keep_fraction = 0;
        const ProgressiveRecord record = ProgressiveRecord::build(fuzz::sample_surface(), options);
        RefinementStream stream(record.vertices());
        const EncodedBlob base =
            encode_mesh(stream.base(record.indexed_triangles(record.operations_for(10))), e);
        const EncodedBlob next = encode_refinement(
            stream.refine(record.indexed_triangles(record.operations_for(30))), e);
        v1::MeshBegin base_begin, next_begin;
        set_layout(base_begin, base.layout);
        set_layout(next_begin, next.layout);
        put("refinement", e == v1::RAW ? "grid-10-to-30-raw" : "grid-10-to-30-meshopt",
            chunk(base_begin) + u32(base.bytes.size()) + base.bytes + chunk(next_begin) +
                next.bytes);
    }
}

void server_seeds() {
    const std::string session = upload_frames(tetrahedron(), 5, 16, "room") +
                                encode_frame(with_name<v1::JoinSession>("room")) +
                                encode_frame(view("room"));
    const std::string steps = encode_frame(v1::ListSurfaces{}) +
                              encode_frame(request(1, true, v1::MESHOPT)) +
                              encode_frame(request(2, false, v1::RAW)) +
                              [] {
                                  v1::Cancel c;
                                  c.set_request_id(2);
                                  return encode_frame(c);
                              }() +
                              upload_frames(tetrahedron(), 3, 1000, "") + session +
                              encode_frame(with_name<v1::LeaveSession>("room")) + [] {
                                  v1::Ping p;
                                  p.set_nonce(42);
                                  return encode_frame(p);
                              }();
    v1::Auth auth;
    auth.set_token(fuzz::kToken);
    put("server_stream", "everything-at-once", "\x00" + encode_frame(hello()) + steps);
    put("server_stream", "everything-step-by-step", "\x02" + encode_frame(hello()) + steps);
    put("server_stream", "with-token", "\x03" + encode_frame(hello()) + encode_frame(auth) + steps);
    put("server_stream", "truncated", "\x02" + (encode_frame(hello()) + steps).substr(0, 300));

    put("server_hello", "hello", hello().SerializeAsString());
    put("server_auth", "right-token", auth.SerializeAsString());
    v1::Ping ping;
    ping.set_nonce(7);
    put("server_ping", "ping", ping.SerializeAsString());
    v1::UploadBegin begin;
    begin.ParseFromString(upload_frames(tetrahedron(), 1, 1000, "room").substr(kHeaderBytes));
    put("server_upload_begin", "tetrahedron", begin.SerializeAsString());
    // What follows the begin of the one-triangle upload in fuzz_server_message.cpp.
    const float triangle[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t corners[3] = {0, 1, 2};
    const float t[3] = {1, 2, 3};
    v1::UploadChunk chunk;
    chunk.set_upload_id(1);
    chunk.set_data(std::string(reinterpret_cast<const char*>(triangle), sizeof triangle) +
                   std::string(reinterpret_cast<const char*>(corners), sizeof corners) +
                   std::string(reinterpret_cast<const char*>(t), sizeof t));
    put("server_upload_chunk", "whole-triangle", chunk.SerializeAsString());
    v1::UploadEnd end;
    end.set_upload_id(1);
    put("server_upload_end", "end", end.SerializeAsString());
    put("server_list_surfaces", "list", v1::ListSurfaces{}.SerializeAsString());
    put("server_request", "progressive-meshopt", request(3, true, v1::MESHOPT).SerializeAsString());
    put("server_request", "levels-raw", request(4, false, v1::RAW).SerializeAsString());
    v1::Cancel cancel;
    cancel.set_request_id(7);
    put("server_cancel", "cancel", cancel.SerializeAsString());
    put("server_join_session", "room", with_name<v1::JoinSession>("room").SerializeAsString());
    put("server_leave_session", "room", with_name<v1::LeaveSession>("room").SerializeAsString());
    put("server_set_session_state", "view", view("room").SerializeAsString());

    put("surface_file", "grid", server::encode_surface_file("grid", fuzz::sample_surface()));
    put("surface_file", "tetrahedron", server::encode_surface_file("tetra", tetrahedron()));
}

// Bytes in the order fuzz_surface.h's surface_from reads them, after fuzz_validate's options.
std::string validate_seed(const Surface& s, uint8_t alpha, uint8_t strategy) {
    std::string out{char(alpha), char(strategy), 0, 5, 0}; // options: keep 0.5
    out += '\0';                                           // shape: consistent
    const auto u64 = [](uint64_t n) { return u32(n & 0xffffffff) + u32(n >> 32); };
    out += u64(s.vertex_count()) + u64(s.triangle_count()) + u64(s.fields.size());
    out += char(1); // indices below the vertex count
    for (uint32_t i : s.triangles) out += char(i);
    for (float p : s.positions) out += char(int(p * 8));
    for (const Field& f : s.fields) {
        out += u64(f.name.size()) + f.name + char(f.components);
        for (float v : f.values) out += char(int(v));
    }
    return out;
}

void validate_seeds() {
    put("validate", "tetrahedron-edge", validate_seed(tetrahedron(), 2, 0));
    Surface grid = fuzz::sample_surface();
    grid.fields.resize(1);
    grid.fields[0].name = "t";
    put("validate", "grid-vertex-removal", validate_seed(grid, 0, 1));
    Surface flipped = grid;
    std::swap(flipped.triangles[1], flipped.triangles[2]);
    flipped.triangles.insert(flipped.triangles.end(), {0, 1, 6, 3, 3, 4});
    put("validate", "grid-to-repair", validate_seed(flipped, 4, 0));
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
        return 2;
    }
    corpus = argv[1];
    frame_seeds();
    blob_seeds();
    server_seeds();
    validate_seeds();
    return 0;
}
