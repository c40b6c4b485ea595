// A blocking protocol connection for the service benchmark: it sends frames and reads them back,
// skipping the payload of mesh chunks without copying it, so that what is timed is the server's
// streaming and the loopback, not a client's decoding.
#pragma once

#include "ddsimp/protocol/frame.h"

#include <boost/asio.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace ddsimp::bench {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

class FrameSocket {
public:
    FrameSocket(asio::io_context& io, const std::string& host, uint16_t port);

    template <class M> void send(const M& message) {
        const std::string frame = protocol::encode_frame(message);
        asio::write(socket_, asio::buffer(frame));
    }

    // The next frame. A MESH_CHUNK's payload is skipped (the returned payload is empty); every
    // other payload is read whole. An ERROR frame is thrown as std::runtime_error with the
    // server's message. Throws on a closed connection.
    protocol::Frame next();

    // Hello (and Auth when the server asks) with these capabilities; returns the Welcome.
    v1::Welcome hello(const std::vector<std::string>& capabilities, const std::string& token);

    // Reads frames until the next one of type M and returns it parsed.
    template <class M> M expect() {
        for (;;) {
            protocol::Frame f = next();
            if (f.type == protocol::message_type_of<M>()) return protocol::parse_payload<M>(f);
        }
    }

    // Reads frames until a MESH_END; returns its request id (0: a session's mesh).
    uint64_t skip_to_mesh_end();

    // Every byte read from the server so far, headers included.
    uint64_t bytes_received() const { return received_; }

private:
    void fill(size_t at_least); // until `at_least` unconsumed bytes are buffered

    tcp::socket socket_;
    std::vector<char> buffer_;
    size_t begin_ = 0, end_ = 0;
    uint64_t received_ = 0;
};

} // namespace ddsimp::bench
