// One message handler of ddsimp-server: the input is the payload of one message of the type this
// target is built for (DDSIMP_FUZZ_MESSAGE, e.g. UPLOAD_CHUNK), sent on a connection that has
// done the handshake and whatever that handler needs first (an upload begun, a session joined,
// a request running). Nothing in it may crash the server or make it write a malformed frame.
#include "fake_server.h"

using namespace ddsimp;
using namespace ddsimp::fuzz;

namespace {

constexpr v1::MessageType kType = v1::DDSIMP_FUZZ_MESSAGE;

v1::Hello hello() {
    v1::Hello h;
    h.set_protocol_version(protocol::kProtocolVersion);
    h.set_client_name("fuzz");
    h.add_capabilities("meshopt-codec");
    h.add_capabilities("progressive");
    h.add_capabilities("sessions");
    return h;
}

// One triangle with a scalar field, as an upload of id 1 sends it.
v1::UploadBegin upload_begin() {
    v1::UploadBegin b;
    b.set_upload_id(1);
    b.set_name("triangle");
    b.set_vertex_count(3);
    b.set_triangle_count(1);
    v1::FieldInfo* f = b.add_fields();
    f->set_name("t");
    f->set_components(1);
    b.set_total_bytes(3 * 12 + 12 + 3 * 4);
    return b;
}
v1::UploadChunk upload_chunk() {
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t triangle[3] = {0, 1, 2};
    const float t[3] = {1, 2, 3};
    v1::UploadChunk c;
    c.set_upload_id(1);
    c.set_offset(0);
    std::string bytes(reinterpret_cast<const char*>(positions), sizeof positions);
    bytes.append(reinterpret_cast<const char*>(triangle), sizeof triangle);
    bytes.append(reinterpret_cast<const char*>(t), sizeof t);
    c.set_data(bytes);
    return c;
}

v1::Request request() {
    v1::Request r;
    r.set_request_id(7);
    r.set_surface(sample_id());
    r.set_alpha(0.5f);
    r.add_keep(0.5f);
    r.add_keep(0.2f);
    r.set_progressive(true);
    return r;
}

v1::JoinSession join() {
    v1::JoinSession j;
    j.set_name("room");
    return j;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    FakeServer server(/*token=*/kType == v1::AUTH);
    const protocol::Frame frame{kType, std::string(reinterpret_cast<const char*>(data), size)};
    if (kType == v1::HELLO) {
        server.deliver(frame);
        v1::ListSurfaces list; // what follows a Hello that was accepted
        server.deliver(list);
        server.run();
        return 0;
    }
    server.deliver(hello());
    if (kType == v1::AUTH) {
        server.deliver(frame);
        server.deliver(v1::ListSurfaces{});
        server.run();
        return 0;
    }
    switch (kType) {
    case v1::UPLOAD_CHUNK:
        server.deliver(upload_begin());
        break;
    case v1::UPLOAD_END:
        server.deliver(upload_begin());
        server.deliver(upload_chunk());
        break;
    case v1::CANCEL: // while the request's levels are computed
        server.deliver(request());
        break;
    case v1::LEAVE_SESSION:
    case v1::SET_SESSION_STATE:
        server.deliver(join());
        break;
    default:
        break;
    }
    server.deliver(frame);
    server.run();
    // Then the same again, now that the server has acted on the first.
    server.deliver(frame);
    server.run();
    return 0;
}
