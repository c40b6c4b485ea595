#include "native_server.h"

#include "service.h"
#include "stream_transport.h"

#include <spdlog/spdlog.h>

namespace ddsimp::server {

namespace {

// Tells a refused client why in an Error frame, if its socket takes it at once, then lets it go.
void refuse_with_error_frame(tcp::socket& socket, const std::string& why, bool tls) {
    if (tls) return; // nothing can be said before a handshake
    boost::system::error_code ignored;
    socket.non_blocking(true, ignored);
    // Read what the client sent already (its Hello), so that closing does not reset the
    // connection before it reads the answer.
    char drain[4096];
    socket.read_some(asio::buffer(drain), ignored);
    v1::Error e;
    e.set_code(v1::Error::RESOURCE_EXHAUSTED);
    e.set_message(why);
    const std::string frame = protocol::encode_frame(e);
    socket.write_some(asio::buffer(frame), ignored);
    socket.shutdown(tcp::socket::shutdown_send, ignored);
}

void serve(Service& service, asio::ssl::context* tls, tcp::socket socket, std::string peer,
           Slot slot) {
    const Config& c = service.config();
    const StreamLimits limits{c.max_frame_bytes, to_duration(c.timeouts.send)};
    if (!tls) {
        service.accept(std::make_shared<StreamTransport<tcp::socket>>(std::move(socket), peer,
                                                                      limits, std::move(slot)));
        return;
    }
    using TlsStream = asio::ssl::stream<tcp::socket>;
    auto stream = std::make_shared<TlsStream>(std::move(socket), *tls);
    auto timer = std::make_shared<asio::steady_timer>(stream->get_executor());
    timer->expires_after(to_duration(c.timeouts.handshake));
    timer->async_wait([stream](boost::system::error_code e) {
        if (!e) stream->lowest_layer().close();
    });
    // The place is held through the handshake: unfinished handshakes count like open clients.
    stream->async_handshake(
        asio::ssl::stream_base::server, [&service, stream, timer, peer, limits,
                                         slot = std::move(slot)](boost::system::error_code e) {
            timer->cancel();
            if (e) {
                spdlog::debug("TLS handshake with {} failed: {}", peer, e.message());
                return;
            }
            service.accept(std::make_shared<StreamTransport<TlsStream>>(std::move(*stream), peer,
                                                                        limits, slot));
        });
}

} // namespace

PortProtocol native_protocol(Service& service, asio::ssl::context* tls) {
    PortProtocol p;
    p.name = tls ? "native protocol (TLS)" : "native protocol";
    p.serve = [&service, tls](tcp::socket socket, std::string peer, Slot slot) {
        serve(service, tls, std::move(socket), std::move(peer), std::move(slot));
    };
    p.refuse = [tls](tcp::socket& socket, const std::string& why) {
        refuse_with_error_frame(socket, why, tls);
    };
    return p;
}

} // namespace ddsimp::server
