// What a connection speaks through: a TCP stream (plain or TLS) carrying frames, or a WebSocket
// carrying one frame per message. The transport reads and checks frames and writes one frame at
// a time; the connection above it does not know which it is.
#pragma once

#include "ddsimp/protocol/frame.h"

#include <boost/asio/buffer.hpp>

#include <array>
#include <memory>
#include <string>

namespace ddsimp::server {

// One frame to write: `head`, then `body_bytes` bytes of `body` from `body_offset`. A chunk of
// a cached level is its frame's head (header, message, the data field's tag and length) and a
// slice of the cached blob, written without copying the blob.
struct OutgoingFrame {
    std::string head;
    std::shared_ptr<const std::string> body; // null: the frame is `head` alone
    size_t body_offset = 0, body_bytes = 0;

    size_t size() const { return head.size() + body_bytes; }
    std::array<boost::asio::const_buffer, 2> buffers() const {
        return {boost::asio::buffer(head),
                boost::asio::buffer(body ? body->data() + body_offset : nullptr, body_bytes)};
    }
};

class TransportHandler {
public:
    virtual ~TransportHandler() = default;
    virtual void on_frame(protocol::Frame frame) = 0;
    virtual void on_bad_frame(const std::string& why) = 0; // then write the error and close
    virtual void on_closed(const std::string& why) = 0;    // called once, after which nothing
    virtual void on_written(size_t bytes) = 0;             // the last write completed
    virtual void on_write_timeout() = 0; // a write made no progress for the send timeout
};

class Transport {
public:
    virtual ~Transport() = default;
    // Starts reading; the handler is kept alive until on_closed.
    virtual void start(std::shared_ptr<TransportHandler> handler) = 0;
    // Writes one frame; at most one write is outstanding. A write that makes no progress for the
    // send timeout closes the transport.
    virtual void write(OutgoingFrame frame) = 0;
    // Closes (after the outstanding write, if `graceful`).
    virtual void close(bool graceful) = 0;
    virtual std::string peer() const = 0;
};

} // namespace ddsimp::server
