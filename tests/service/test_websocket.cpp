// ddsimp-server's HTTP port as browsers meet it: the WebSocket endpoint /ws carries the same
// frames as the native port (one frame per binary message) and gives the same bytes; a bad
// message ends only its own connection; WebSocket and native members share a session; and with
// --tls-cert/--tls-key the HTTP port speaks HTTPS and wss:// (checked against the certificate).
#include "self_signed_certificate.h"
#include "server_harness.h"

#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

namespace ddsimp::test {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace ssl = asio::ssl;

// Blocking frames over a WebSocket, plain or TLS (Stream: tcp::socket or ssl::stream<...>).
template <class Stream> class WsClient {
public:
    template <class... Args>
    explicit WsClient(uint16_t port, Args&&... args) : ws_(io_, std::forward<Args>(args)...) {
        beast::get_lowest_layer(ws_).connect({asio::ip::make_address("127.0.0.1"), port});
        if constexpr (!std::is_same_v<Stream, tcp::socket>)
            ws_.next_layer().handshake(ssl::stream_base::client);
        ws_.handshake("localhost:" + std::to_string(port), "/ws");
        ws_.binary(true);
    }

    void send_bytes(const std::string& bytes) { ws_.write(asio::buffer(bytes)); }
    void send_text(const std::string& text) {
        ws_.text(true);
        ws_.write(asio::buffer(text));
        ws_.binary(true);
    }
    template <class M> void send(const M& m) { send_bytes(protocol::encode_frame(m)); }

    // The next frame, or nothing once the server closed the WebSocket.
    std::optional<protocol::Frame> next() {
        beast::flat_buffer buffer;
        beast::error_code ec;
        ws_.read(buffer, ec);
        if (ec) return std::nullopt;
        return protocol::decode_single_frame(beast::buffers_to_string(buffer.data()), 64u << 20);
    }

    template <class M> M expect() {
        for (;;) {
            auto f = next();
            if (!f) throw std::runtime_error("closed waiting for a message");
            if (f->type == protocol::message_type_of<M>()) return protocol::parse_payload<M>(*f);
            if (f->type == v1::ERROR)
                throw std::runtime_error(protocol::parse_payload<v1::Error>(*f).message());
        }
    }

    v1::Welcome hello(std::vector<std::string> caps = {"sessions"}) {
        v1::Hello h;
        h.set_protocol_version(1);
        h.set_client_name("websocket test");
        h.set_kind(v1::DESKTOP);
        for (const auto& c : caps) h.add_capabilities(c);
        send(h);
        return expect<v1::Welcome>();
    }

    // MeshBegin, the chunks' bytes and MeshEnd of the next level.
    RawClient::Level level() {
        RawClient::Level l;
        for (;;) {
            auto f = next();
            if (!f) throw std::runtime_error("closed waiting for a level");
            if (f->type == v1::MESH_BEGIN) l.begin = protocol::parse_payload<v1::MeshBegin>(*f);
            if (f->type == v1::MESH_CHUNK)
                l.bytes += protocol::parse_payload<v1::MeshChunk>(*f).data();
            if (f->type == v1::MESH_END) return l;
            if (f->type == v1::ERROR)
                throw std::runtime_error(protocol::parse_payload<v1::Error>(*f).message());
        }
    }

private:
    asio::io_context io_;
    websocket::stream<Stream> ws_;
};

using PlainWs = WsClient<tcp::socket>;

v1::Request sample_request(const std::string& surface, uint64_t id) {
    v1::Request r;
    r.set_request_id(id);
    r.set_surface(surface);
    r.set_alpha(0.25f);
    r.add_keep(0.1f);
    r.add_keep(0.5f);
    r.set_encoding(v1::RAW);
    return r;
}

std::string sample_id(RawClient& c) {
    c.send(v1::ListSurfaces{});
    const v1::SurfaceList list = c.expect<v1::SurfaceList>();
    if (list.surfaces_size() != 1) throw std::runtime_error("expected the built-in sample only");
    return list.surfaces(0).surface();
}

class WebSocket : public ::testing::Test {
protected:
    void SetUp() override {
        server_ = std::make_unique<ServerProcess>(
            temp_dir(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    }
    std::unique_ptr<ServerProcess> server_;
};

TEST_F(WebSocket, GivesTheSameBytesAsTheNativePort) {
    RawClient native(server_->port);
    native.hello({});
    const std::string sample = sample_id(native);
    native.send(sample_request(sample, 1));
    // Not cached yet: the finest level comes first (as soon as a run has passed it).
    const RawClient::Level native_fine = native.level();
    const RawClient::Level native_coarse = native.level();
    EXPECT_FLOAT_EQ(native_fine.begin.keep(), 0.5f);

    PlainWs ws(server_->http_port);
    const v1::Welcome w = ws.hello({"meshopt-codec", "sessions"});
    EXPECT_EQ(w.capabilities_size(), 2);
    ws.send(sample_request(sample, 7));
    const RawClient::Level coarse = ws.level();
    const RawClient::Level fine = ws.level();
    ws.expect<v1::RequestDone>();

    EXPECT_EQ(coarse.begin.request_id(), 7u);
    EXPECT_FLOAT_EQ(coarse.begin.keep(), 0.1f); // cached now: coarsest first, over WebSocket too
    EXPECT_FLOAT_EQ(fine.begin.keep(), 0.5f);
    EXPECT_EQ(coarse.begin.total_triangles(), native_coarse.begin.total_triangles());
    EXPECT_FALSE(coarse.bytes.empty());
    EXPECT_EQ(coarse.bytes, native_coarse.bytes);
    EXPECT_EQ(fine.bytes, native_fine.bytes);
}

TEST_F(WebSocket, BadMessagesEndOnlyTheirConnection) {
    PlainWs bystander(server_->http_port);
    bystander.hello();

    const auto expect_refused = [&](const std::string& message, bool text) {
        PlainWs bad(server_->http_port);
        bad.hello();
        if (text)
            bad.send_text(message);
        else
            bad.send_bytes(message);
        auto f = bad.next();
        ASSERT_TRUE(f) << "no answer to a bad message";
        ASSERT_EQ(f->type, v1::ERROR);
        EXPECT_EQ(protocol::parse_payload<v1::Error>(*f).code(), v1::Error::BAD_FRAME);
        EXPECT_FALSE(bad.next()) << "the connection stays open after a bad frame";
    };
    expect_refused("not a frame at all, just some bytes", false);
    v1::Ping ping;
    ping.set_nonce(5);
    const std::string frame = protocol::encode_frame(ping);
    expect_refused(frame + frame, false);                     // two frames in one message
    expect_refused(frame.substr(0, frame.size() - 1), false); // a truncated frame
    expect_refused(frame, true);                              // a frame in a text message

    ping.set_nonce(42);
    bystander.send(ping);
    EXPECT_EQ(bystander.expect<v1::Pong>().nonce(), 42u);
}

TEST_F(WebSocket, MembersOnBothTransportsShareASession) {
    RawClient native(server_->port);
    native.hello({"sessions"});
    const std::string sample = sample_id(native);
    PlainWs browser(server_->http_port);
    browser.hello();

    v1::JoinSession join;
    join.set_name("review");
    native.send(join);
    native.expect<v1::SessionState>();
    browser.send(join);
    const v1::SessionState joined = browser.expect<v1::SessionState>();
    EXPECT_EQ(joined.members_size(), 2);

    v1::SetSessionState change;
    change.set_name("review");
    change.mutable_view()->set_surface(sample);
    change.mutable_view()->set_keep(0.2f);
    change.mutable_view()->set_alpha(0.4f);
    change.set_set_alpha(true);
    native.send(change);

    v1::SessionState state;
    do {
        state = browser.expect<v1::SessionState>();
    } while (state.cause() != "view");
    EXPECT_EQ(state.view().surface(), sample);
    EXPECT_FLOAT_EQ(state.view().keep(), 0.2f);
    const RawClient::Level mesh = browser.level();
    EXPECT_EQ(mesh.begin.request_id(), 0u);
    EXPECT_EQ(mesh.begin.session(), "review");
    const RawClient::Level native_mesh = native.level();
    EXPECT_EQ(mesh.begin.total_triangles(), native_mesh.begin.total_triangles());
    EXPECT_EQ(mesh.bytes, native_mesh.bytes);
}

// --tls-cert and --tls-key put TLS on the HTTP port as on the native one.
class TlsHttp : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = temp_dir("tls-http");
        write_self_signed(dir_ / "cert.pem", dir_ / "key.pem", "localhost");
        server_ = std::make_unique<ServerProcess>(
            dir_ / "data", std::vector<std::string>{"--tls-cert", (dir_ / "cert.pem").string(),
                                                    "--tls-key", (dir_ / "key.pem").string()});
        tls_.load_verify_file((dir_ / "cert.pem").string());
        tls_.set_verify_mode(ssl::verify_peer);
        tls_.set_verify_callback(ssl::host_name_verification("localhost"));
    }
    std::filesystem::path dir_;
    std::unique_ptr<ServerProcess> server_;
    ssl::context tls_{ssl::context::tls_client};
};

TEST_F(TlsHttp, ServesHealthOverHttpsAndNotInTheClear) {
    asio::io_context io;
    beast::ssl_stream<beast::tcp_stream> stream(io, tls_);
    stream.next_layer().connect({asio::ip::make_address("127.0.0.1"), server_->http_port});
    stream.handshake(ssl::stream_base::client); // throws if the certificate does not check out
    http::request<http::empty_body> req{http::verb::get, "/healthz", 11};
    req.set(http::field::host, "localhost");
    http::write(stream, req);
    beast::flat_buffer buffer;
    http::response<http::string_body> res;
    http::read(stream, buffer, res);
    EXPECT_EQ(res.result(), http::status::ok);

    // Plain HTTP to the TLS port gets no HTTP answer.
    const std::string clear = [&] {
        try {
            return http_get(server_->http_port, "/healthz");
        } catch (const std::exception&) {
            return std::string();
        }
    }();
    EXPECT_EQ(clear.find("200 OK"), std::string::npos);
}

TEST_F(TlsHttp, CarriesFramesOverSecureWebSocket) {
    WsClient<ssl::stream<tcp::socket>> ws(server_->http_port, tls_);
    const v1::Welcome w = ws.hello();
    EXPECT_EQ(w.protocol_version(), 1u);
    v1::ListSurfaces list;
    ws.send(list);
    const v1::SurfaceList surfaces = ws.expect<v1::SurfaceList>();
    ASSERT_EQ(surfaces.surfaces_size(), 1); // the built-in sample
    v1::Request r = sample_request(surfaces.surfaces(0).surface(), 3);
    r.clear_keep();
    r.add_keep(0.2f);
    ws.send(r);
    const RawClient::Level level = ws.level();
    EXPECT_GT(level.begin.total_triangles(), 0u);
    EXPECT_EQ(level.bytes.size(), level.begin.total_bytes());
}

} // namespace
} // namespace ddsimp::test
