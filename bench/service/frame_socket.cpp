#include "frame_socket.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace ddsimp::bench {

namespace {
// Frames larger than the server could send are a protocol error here too.
constexpr size_t kMaxFrameBytes = 64u << 20;
} // namespace

FrameSocket::FrameSocket(asio::io_context& io, const std::string& host, uint16_t port)
    : socket_(io), buffer_(1u << 20) {
    tcp::resolver resolver(io);
    asio::connect(socket_, resolver.resolve(host, std::to_string(port)));
    socket_.set_option(tcp::no_delay(true));
}

void FrameSocket::fill(size_t at_least) {
    if (end_ - begin_ >= at_least) return;
    std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
    while (end_ < at_least) {
        const size_t n =
            socket_.read_some(asio::buffer(buffer_.data() + end_, buffer_.size() - end_));
        end_ += n;
        received_ += n;
    }
}

protocol::Frame FrameSocket::next() {
    fill(protocol::kHeaderBytes);
    const protocol::FrameHeader header = protocol::read_header(
        reinterpret_cast<const unsigned char*>(buffer_.data() + begin_), kMaxFrameBytes);
    begin_ += protocol::kHeaderBytes;

    protocol::Frame frame;
    frame.type = header.type;
    const size_t buffered = std::min<size_t>(header.length, end_ - begin_);
    size_t remaining = header.length - buffered;
    if (header.type == v1::MESH_CHUNK) {
        begin_ += buffered;
        if (remaining > 0) begin_ = end_ = 0; // everything buffered was this chunk's
        while (remaining > 0) {
            const size_t n = socket_.read_some(asio::buffer(buffer_));
            received_ += n;
            if (n > remaining) { // the next frame has begun
                begin_ = remaining;
                end_ = n;
                remaining = 0;
            } else {
                remaining -= n;
            }
        }
        return frame;
    }
    frame.payload.assign(buffer_.data() + begin_, buffered);
    begin_ += buffered;
    if (remaining > 0) {
        frame.payload.resize(header.length);
        asio::read(socket_, asio::buffer(frame.payload.data() + buffered, remaining));
        received_ += remaining;
    }
    if (frame.type == v1::ERROR)
        throw std::runtime_error("server error: " +
                                 protocol::parse_payload<v1::Error>(frame).message());
    return frame;
}

v1::Welcome FrameSocket::hello(const std::vector<std::string>& capabilities,
                               const std::string& token) {
    v1::Hello hello;
    hello.set_protocol_version(protocol::kProtocolVersion);
    hello.set_client_name("ddsimp_bench_service");
    hello.set_kind(v1::TOOL);
    for (const auto& c : capabilities) hello.add_capabilities(c);
    send(hello);
    v1::Welcome welcome = expect<v1::Welcome>();
    if (welcome.auth_required()) {
        v1::Auth auth;
        auth.set_token(token);
        send(auth);
        expect<v1::AuthOk>();
    }
    return welcome;
}

uint64_t FrameSocket::skip_to_mesh_end() {
    for (;;) {
        protocol::Frame f = next();
        if (f.type == v1::MESH_END) return protocol::parse_payload<v1::MeshEnd>(f).request_id();
    }
}

} // namespace ddsimp::bench
