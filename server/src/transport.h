// What a connection speaks through: a TCP stream (plain or TLS) carrying frames, or a WebSocket
// carrying one frame per message. The transport reads and checks frames and writes one frame at
// a time; the connection above it does not know which it is.
#pragma once

#include "ddsimp/protocol/frame.h"

#include <memory>
#include <string>

namespace ddsimp::server {

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
    virtual void write(std::string frame) = 0;
    // Closes (after the outstanding write, if `graceful`).
    virtual void close(bool graceful) = 0;
    virtual std::string peer() const = 0;
};

} // namespace ddsimp::server
