// Shared by the hostile-client, fault and security tests: a well-behaved client whose levels are
// checked against the offline library, bare sockets for the hundreds of connections an attacker
// opens, and the memory bound a server's configured limits imply.
#pragma once

#include "mesh_comparison.h"
#include "server_harness.h"
#include "test_surfaces.h"

#include "ddsimp/protocol/reduction_options.h"

#include <poll.h>
#include <sys/socket.h>

#include <atomic>
#include <optional>
#include <set>

namespace ddsimp::test {

inline Surface small_surface() {
    return with_test_fields(icosphere(4)); // 5120 triangles
}

inline v1::Request level_request(const std::string& surface, std::vector<float> keeps, uint64_t id,
                                 float alpha = 0.3f) {
    v1::Request r;
    r.set_request_id(id);
    r.set_surface(surface);
    r.set_alpha(alpha);
    for (float k : keeps) r.add_keep(k);
    r.set_encoding(v1::RAW);
    return r;
}

// What `ddsimp simplify --alpha A --keep K` makes of the surface: what a level must equal (the
// request's floats read as the server reads them, the library's defaults for the rest).
inline Surface offline_level(const Surface& in, float alpha, float keep) {
    Options o;
    o.alpha = protocol::from_wire(alpha);
    o.keep_fraction = protocol::from_wire(keep);
    return simplify(in, o).surface;
}

// The client every test keeps serving: it uploads a small surface and, whenever asked, checks
// that a level it requests equals the offline library's result byte for byte.
class WellBehavedClient {
public:
    explicit WellBehavedClient(uint16_t port, const std::string& token = "") : client_(port) {
        client_.hello({"sessions"}, token);
        surface_ = client_.upload(input_, 1).surface();
    }

    // Requests one level (a new keep each time, so it is computed, not only cached) and checks it.
    void check_level() {
        const float keep = 0.1f + 0.05f * float(next_id_ % 10);
        const uint64_t id = ++next_id_;
        client_.send(level_request(surface_, {keep}, id));
        const RawClient::Level l = client_.level();
        EXPECT_EQ(l.begin.request_id(), id);
        const Surface got = protocol::decode_mesh(l.bytes, protocol::layout_of(l.begin));
        EXPECT_TRUE(same_bytes(got, offline_level(input_, 0.3f, keep))) << "keep " << keep;
        EXPECT_EQ(client_.expect<v1::RequestDone>().request_id(), id);
    }

    // Something the server answers at once, so the connection never idles out.
    void ping() {
        v1::Ping p;
        p.set_nonce(++next_id_);
        client_.send(p);
        EXPECT_EQ(client_.expect<v1::Pong>().nonce(), next_id_);
    }

    RawClient& raw() { return client_; }
    const std::string& surface() const { return surface_; }

private:
    RawClient client_;
    Surface input_ = small_surface();
    std::string surface_;
    uint64_t next_id_ = 100;
};

// A bare connection for the hundreds an attacker opens: one socket on a shared io_context (a
// RawClient has its own, which costs the test three more descriptors).
class BareConnection {
public:
    // `from`: the local address (any of 127.0.0.0/8 on Linux), to stand for another machine.
    BareConnection(asio::io_context& io, uint16_t port, const std::string& from = "")
        : socket_(io) {
        if (!from.empty()) {
            socket_.open(tcp::v4());
            socket_.bind({asio::ip::make_address(from), 0});
        }
        socket_.connect({asio::ip::make_address("127.0.0.1"), port});
    }
    // Errors are ignored: the server may have closed the connection already, as it should.
    void send_bytes(const std::string& bytes) {
        boost::system::error_code ignored;
        asio::write(socket_, asio::buffer(bytes), ignored);
    }
    template <class M> void send(const M& m) { send_bytes(protocol::encode_frame(m)); }
    // The next frame, or nothing once the server has closed the connection.
    std::optional<protocol::Frame> next() {
        std::array<unsigned char, protocol::kHeaderBytes> header;
        boost::system::error_code ec;
        asio::read(socket_, asio::buffer(header), ec);
        if (ec) return std::nullopt;
        const protocol::FrameHeader h = protocol::read_header(header.data(), 64u << 20);
        std::string payload(h.length, '\0');
        asio::read(socket_, asio::buffer(payload), ec);
        if (ec) return std::nullopt;
        return protocol::Frame{h.type, std::move(payload)};
    }
    // Reads until the server closes the connection; the error it sent last, if any.
    std::optional<v1::Error> until_closed() {
        std::optional<v1::Error> last;
        while (auto f = next())
            if (f->type == v1::ERROR) last = protocol::parse_payload<v1::Error>(*f);
        return last;
    }
    // Whether the server closes the connection within `wait` (without reading what it sent).
    bool closed_within(std::chrono::milliseconds wait) {
        pollfd p{socket_.native_handle(), POLLIN | POLLRDHUP, 0};
        if (::poll(&p, 1, int(wait.count())) <= 0) return false;
        char ch;
        return ::recv(p.fd, &ch, 1, MSG_PEEK | MSG_DONTWAIT) <= 0;
    }
    void close() { socket_.close(); }

private:
    tcp::socket socket_;
};

// An HTTP connection kept alive, for reading /metrics while every other place is taken (it holds
// one of the server's places itself).
class HttpKeepAlive {
public:
    explicit HttpKeepAlive(uint16_t port) : socket_(io_) {
        socket_.connect({asio::ip::make_address("127.0.0.1"), port});
    }
    // The body of GET `target`; throws if the connection was closed.
    std::string get(const std::string& target) {
        const std::string request = "GET " + target + " HTTP/1.1\r\nHost: localhost\r\n\r\n";
        asio::write(socket_, asio::buffer(request));
        const size_t head_end =
            asio::read_until(socket_, asio::dynamic_buffer(buffer_), "\r\n\r\n");
        const std::string head = buffer_.substr(0, head_end);
        buffer_.erase(0, head_end);
        std::smatch m;
        if (!std::regex_search(head, m, std::regex("Content-Length: ([0-9]+)", std::regex::icase)))
            throw std::runtime_error("no Content-Length in " + head);
        const size_t length = std::stoul(m[1]);
        if (buffer_.size() < length)
            asio::read(socket_, asio::dynamic_buffer(buffer_),
                       asio::transfer_exactly(length - buffer_.size()));
        std::string body = buffer_.substr(0, length);
        buffer_.erase(0, length);
        return body;
    }
    // One sample of /metrics, or -1.
    double metric(const std::string& name) {
        const std::string text = "\n" + get("/metrics");
        std::smatch m;
        if (!std::regex_search(text, m, std::regex("\n" + name + " ([0-9.e+-]+)"))) return -1;
        return std::stod(m[1]);
    }

private:
    asio::io_context io_;
    tcp::socket socket_;
    std::string buffer_;
};

// The ids of the surfaces the client may see.
inline std::set<std::string> listed(RawClient& c) {
    c.send(v1::ListSurfaces{});
    const v1::SurfaceList list = c.expect<v1::SurfaceList>();
    std::set<std::string> ids;
    for (const auto& s : list.surfaces()) ids.insert(s.surface());
    return ids;
}

// The next Error, skipping anything else (the connection must stay open for it).
inline v1::Error next_error(RawClient& c) {
    for (;;) {
        const std::optional<protocol::Frame> f = c.next();
        if (!f) throw std::runtime_error("closed while waiting for an error");
        if (f->type == v1::ERROR) return protocol::parse_payload<v1::Error>(*f);
    }
}

// A frame's header, as a client would write it before `length` bytes of payload.
inline std::string header(v1::MessageType type, uint32_t length) {
    unsigned char h[protocol::kHeaderBytes];
    protocol::write_header(h, type, length);
    return std::string(reinterpret_cast<char*>(h), sizeof h);
}

// Whether an error's message says `what`.
inline bool says(const v1::Error& e, const std::string& what) {
    return e.message().find(what) != std::string::npos;
}

inline v1::Hello hello_message() {
    v1::Hello h;
    h.set_protocol_version(1);
    h.set_client_name("hostile");
    return h;
}

// Waits (up to a minute, for a loaded machine) until a metric has the value; returns the last.
inline double await_metric(uint16_t http_port, const std::string& name, double value) {
    double now = -1;
    for (int i = 0; i < 600 && (now = metric(http_port, name)) != value; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    return now;
}

constexpr size_t kMiB = size_t(1) << 20;

// Memory the bounds allow beyond what the configured limits account for: the allocator's
// per-thread arenas and free lists, the io and compute threads' stacks. Fixed, not per client.
constexpr size_t kAllocatorSlack = 24 * kMiB;
// What an open connection holds besides the frame it is reading and its send queue: a socket,
// its transport and connection objects and timers — a few hundred bytes; allowed generously.
constexpr size_t kConnectionOverhead = 64u << 10;

// The memory bounds are the release build's. A sanitizer adds memory of its own that the
// resident set counts: ThreadSanitizer's shadow, 4 bytes per byte of application memory plus
// its meta map; AddressSanitizer's shadow, 1/8 of it, and the quarantine that holds freed blocks
// (256 MiB by default). Under a sanitizer an allowance grows by that much, so the run still
// catches memory that grows without bound.
constexpr size_t with_sanitizer_memory(size_t allowance) {
#if defined(DDSIMP_TEST_TSAN)
    return 5 * allowance;
#elif defined(DDSIMP_TEST_ASAN)
    return allowance + allowance / 8 + 256 * kMiB;
#else
    return allowance;
#endif
}

} // namespace ddsimp::test
