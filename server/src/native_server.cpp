#include "native_server.h"

#include "service.h"
#include "stream_transport.h"

#include <spdlog/spdlog.h>

namespace ddsimp::server {

NativeServer::NativeServer(asio::io_context& io, Service& service, tcp::endpoint at,
                           asio::ssl::context* tls)
    : service_(service), acceptor_(io, at), tls_(tls) {
    spdlog::info("native protocol on {}:{}{}", at.address().to_string(),
                 acceptor_.local_endpoint().port(), tls ? " (TLS)" : "");
    accept();
}

void NativeServer::stop() {
    boost::system::error_code ignored;
    acceptor_.close(ignored);
}

void NativeServer::accept() {
    acceptor_.async_accept([this](boost::system::error_code ec, tcp::socket socket) {
        if (ec == asio::error::operation_aborted) return;
        if (ec) {
            spdlog::warn("accept failed: {}", ec.message());
            return accept();
        }
        boost::system::error_code ignored;
        socket.set_option(tcp::no_delay(true), ignored);
        const auto remote = socket.remote_endpoint(ignored);
        const std::string peer = remote.address().to_string() + ":" + std::to_string(remote.port());
        const Config& c = service_.config();
        const StreamLimits limits{c.max_frame_bytes,
                                  std::chrono::milliseconds(int64_t(1000 * c.send_timeout_s))};
        if (!tls_) {
            service_.accept(
                std::make_shared<StreamTransport<tcp::socket>>(std::move(socket), peer, limits));
            return accept();
        }
        if (handshaking_ + service_.open_connections() >= c.max_clients) {
            spdlog::warn("refusing {}: {} clients connected or in the TLS handshake", peer,
                         c.max_clients);
            socket.close(ignored);
            return accept();
        }
        ++handshaking_;
        using TlsStream = asio::ssl::stream<tcp::socket>;
        auto stream = std::make_shared<TlsStream>(std::move(socket), *tls_);
        auto timer = std::make_shared<asio::steady_timer>(acceptor_.get_executor());
        timer->expires_after(std::chrono::milliseconds(int64_t(1000 * c.handshake_timeout_s)));
        timer->async_wait([stream](boost::system::error_code e) {
            if (!e) stream->lowest_layer().close();
        });
        stream->async_handshake(asio::ssl::stream_base::server, [this, stream, timer, peer, limits](
                                                                    boost::system::error_code e) {
            timer->cancel();
            --handshaking_;
            if (e) {
                spdlog::warn("TLS handshake with {} failed: {}", peer, e.message());
                return;
            }
            service_.accept(
                std::make_shared<StreamTransport<TlsStream>>(std::move(*stream), peer, limits));
        });
        accept();
    });
}

} // namespace ddsimp::server
