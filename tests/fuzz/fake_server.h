// ddsimp-server without sockets, for the server's fuzz targets: a Service on an io_context of its
// own with its heavy work on the network thread (config.threads = 0, so one input always runs
// the same way), and one client whose FakeTransport hands frames to the Connection as the real
// transports do and checks every frame the server writes back.
#pragma once

#include "ddsimp/ddsimp.h"
#include "ddsimp/protocol/frame.h"

#include <boost/asio/io_context.hpp>

#include <memory>
#include <string>
#include <string_view>

namespace ddsimp::server {
class Service;
struct Config;
} // namespace ddsimp::server

namespace ddsimp::fuzz {

class FakeTransport;

// The sample every FakeServer starts with: a 6 x 6 grid of 50 triangles with a scalar and a
// 3-component field, so that requests and sessions have a surface to work on.
const Surface& sample_surface();
const std::string& sample_id(); // its id on the server (protocol::surface_hash)
inline constexpr const char* kToken = "fuzz-token";

class FakeServer {
public:
    // `token`: whether clients must authenticate with kToken.
    explicit FakeServer(bool token = false);
    ~FakeServer(); // closes the client, finishes the work, removes the data directory

    // One frame from the client (run() makes the server act on it).
    void deliver(const protocol::Frame& frame);
    template <class M> void deliver(const M& message) {
        deliver(protocol::Frame{protocol::message_type_of<M>(), message.SerializeAsString()});
    }
    // Bytes from the client as a stream (FrameDecoder, as StreamTransport reads); a bad header
    // goes to the connection as a bad frame. Runs the server after every frame if `step`.
    void deliver_stream(std::string_view bytes, bool step);
    // Runs everything the server has to do until it waits for the client.
    void run();

private:
    boost::asio::io_context io_;
    std::string data_dir_;
    std::unique_ptr<server::Service> service_;
    std::shared_ptr<FakeTransport> transport_;
};

} // namespace ddsimp::fuzz
