// A scripted stand-in for ddsimp-server on a loopback socket, built only on the protocol library:
// a test writes what the server would say and checks what the client sent, frame by frame.
#pragma once

#include "ddsimp/protocol/frame.h"

#include <boost/asio.hpp>
#include <gtest/gtest.h>

#include <functional>
#include <future>
#include <thread>

namespace ddsimp::test {

class FakePeer {
public:
    explicit FakePeer(boost::asio::ip::tcp::socket socket) : socket_(std::move(socket)) {}

    // The next frame from the client; throws if the connection ends first.
    protocol::Frame read() {
        for (;;) {
            if (auto frame = decoder_.next()) return *frame;
            char buffer[64 * 1024];
            const size_t n = socket_.read_some(boost::asio::buffer(buffer));
            decoder_.feed(std::string_view(buffer, n));
        }
    }
    template <class M> M read_as() { return protocol::parse_payload<M>(read()); }
    template <class M> void send(const M& message) {
        boost::asio::write(socket_, boost::asio::buffer(protocol::encode_frame(message)));
    }
    // Answers Hello with a Welcome that agrees to `caps` (intersected with the client's).
    v1::Hello handshake(std::vector<std::string> caps = {"meshopt-codec", "progressive",
                                                         "sessions"}) {
        const auto hello = read_as<v1::Hello>();
        v1::Welcome welcome;
        welcome.set_protocol_version(1);
        welcome.set_server_name("fake peer");
        for (const std::string& c : caps)
            if (std::find(hello.capabilities().begin(), hello.capabilities().end(), c) !=
                hello.capabilities().end())
                welcome.add_capabilities(c);
        welcome.set_client_id(42);
        welcome.set_max_frame_bytes(protocol::kDefaultMaxFrameBytes);
        welcome.set_chunk_bytes(protocol::kDefaultChunkBytes);
        send(welcome);
        return hello;
    }
    // True once the client has closed its side.
    bool closed_by_client() {
        char byte;
        boost::system::error_code ec;
        socket_.read_some(boost::asio::buffer(&byte, 1), ec);
        return ec == boost::asio::error::eof || ec == boost::asio::error::connection_reset;
    }

private:
    boost::asio::ip::tcp::socket socket_;
    protocol::FrameDecoder decoder_{64u << 20};
};

// Accepts one connection on 127.0.0.1 (a free port) and runs `script` on it in a thread.
// wait() rethrows what the script threw (a failed expectation in it is reported as usual).
class FakeServer {
public:
    explicit FakeServer(std::function<void(FakePeer&)> script)
        : acceptor_(io_, {boost::asio::ip::make_address("127.0.0.1"), 0}) {
        port_ = acceptor_.local_endpoint().port();
        done_ = std::async(std::launch::async, [this, script = std::move(script)] {
            FakePeer peer(acceptor_.accept());
            script(peer);
        });
    }
    ~FakeServer() {
        if (done_.valid()) done_.wait();
    }
    uint16_t port() const { return port_; }
    void wait() { done_.get(); }

private:
    boost::asio::io_context io_;
    boost::asio::ip::tcp::acceptor acceptor_;
    uint16_t port_ = 0;
    std::future<void> done_;
};

} // namespace ddsimp::test
