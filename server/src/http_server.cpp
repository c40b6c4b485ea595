#include "http_server.h"

#include "service.h"
#include "web_files.h"
#include "websocket_transport.h"

#include <boost/asio/post.hpp>
#include <boost/beast/http.hpp>
#include <spdlog/spdlog.h>

namespace ddsimp::server {
namespace asio = boost::asio;
namespace http = beast::http;
using tcp = asio::ip::tcp;

namespace {

constexpr size_t kMaxRequestBodyBytes = 64 * 1024;

// One HTTP connection: requests in turn (keep-alive), each within the HTTP timeout, until it
// closes or becomes a WebSocket. It holds the connection's place; a WebSocket takes it over.
template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
public:
    HttpSession(Stream stream, HttpServer& server, std::string peer, Slot slot)
        : stream_(std::move(stream)), server_(server), service_(server.service()),
          peer_(std::move(peer)), slot_(std::move(slot)) {}

    void start() {
        if constexpr (std::is_same_v<Stream, beast::tcp_stream>) {
            read();
        } else {
            beast::get_lowest_layer(stream_).expires_after(timeouts().handshake);
            stream_.async_handshake(asio::ssl::stream_base::server,
                                    [self = this->shared_from_this()](beast::error_code ec) {
                                        if (!ec) self->read();
                                    });
        }
    }

private:
    struct Durations {
        std::chrono::milliseconds handshake, http, send;
    };
    Durations timeouts() const {
        const Timeouts& t = service_.config().timeouts;
        return {to_duration(t.handshake), to_duration(t.http), to_duration(t.send)};
    }

    void read() {
        request_ = {};
        parser_.emplace();
        parser_->body_limit(kMaxRequestBodyBytes);
        beast::get_lowest_layer(stream_).expires_after(timeouts().http);
        http::async_read(stream_, buffer_, *parser_,
                         [self = this->shared_from_this()](beast::error_code ec, size_t) {
                             if (ec) return self->close();
                             self->request_ = self->parser_->release();
                             self->route();
                         });
    }

    void route() {
        const std::string target(request_.target());
        const std::string path = target.substr(0, target.find_first_of("?#"));
        if (websocket::is_upgrade(request_) && path == "/ws") return upgrade();
        HttpResponse res{http::status::ok, request_.version()};
        res.set(http::field::server, service_.server_name());
        res.keep_alive(request_.keep_alive());
        if (request_.method() != http::verb::get && request_.method() != http::verb::head) {
            res.result(http::status::method_not_allowed);
            res.body() = "only GET\n";
        } else if (const HttpServer::Route* r = server_.find_route(path)) {
            if (r->later) {
                // The session (and its place among the clients) lives until the reply.
                return r->later(request_, std::move(res),
                                [self = this->shared_from_this()](
                                    HttpResponse later, std::shared_ptr<const void> hold) {
                                    auto& stream = beast::get_lowest_layer(self->stream_);
                                    asio::post(stream.get_executor(),
                                               [self, later = std::move(later),
                                                hold = std::move(hold)]() mutable {
                                                   self->send(std::move(later), std::move(hold));
                                               });
                                });
            }
            r->now(request_, res);
        } else {
            serve_web_file(service_.config().web_dir, target, res);
            // A file's bytes count with the downloads (--max-download-mb) until they are written.
            if (auto hold = DownloadHold::take(service_.downloads(), res.body().size()))
                return send(std::move(res), std::move(hold));
            ++service_.metrics().downloads_refused;
            res = HttpResponse{http::status::service_unavailable, request_.version()};
            res.set(http::field::server, service_.server_name());
            res.set(http::field::content_type, "text/plain; charset=utf-8");
            res.set(http::field::retry_after, "10");
            res.keep_alive(request_.keep_alive());
            res.body() = "the server is sending as many downloads as it may (--max-download-mb); "
                         "try again later\n";
        }
        send(std::move(res));
    }

    // `hold`: kept until the response is written (what its body is counted in).
    void send(HttpResponse res, std::shared_ptr<const void> hold = nullptr) {
        res.prepare_payload();
        auto shared = std::make_shared<HttpResponse>(std::move(res));
        beast::get_lowest_layer(stream_).expires_after(timeouts().send);
        http::async_write(stream_, *shared,
                          [self = this->shared_from_this(), shared,
                           hold = std::move(hold)](beast::error_code ec, size_t) {
                              if (ec || !shared->keep_alive()) return self->close();
                              self->read();
                          });
    }

    void upgrade() {
        beast::get_lowest_layer(stream_).expires_never();
        auto ws = std::make_shared<websocket::stream<Stream>>(std::move(stream_));
        const Timeouts& t = service_.config().timeouts;
        websocket::stream_base::timeout options{};
        options.handshake_timeout = to_duration(t.handshake);
        options.idle_timeout = to_duration(t.idle);
        options.keep_alive_pings = true;
        ws->set_option(options);
        ws->async_accept(
            request_, [ws, &service = service_, peer = peer_, slot = slot_](beast::error_code ec) {
                if (ec) return;
                const Config& c = service.config();
                service.accept(std::make_shared<WebSocketTransport<Stream>>(
                    std::move(*ws), peer + " (WebSocket)", c.max_frame_bytes,
                    to_duration(c.timeouts.send), slot));
            });
    }

    void close() {
        beast::error_code ignored;
        beast::get_lowest_layer(stream_).socket().shutdown(tcp::socket::shutdown_both, ignored);
    }

    Stream stream_;
    HttpServer& server_;
    Service& service_;
    std::string peer_;
    Slot slot_;
    beast::flat_buffer buffer_;
    std::optional<http::request_parser<http::string_body>> parser_;
    HttpRequest request_;
};

// Tells a refused client why (503), if its socket takes it at once, then lets it go.
void refuse_with_503(tcp::socket& socket, const std::string& why, bool tls) {
    if (tls) return; // nothing can be said before a handshake
    boost::system::error_code ignored;
    socket.non_blocking(true, ignored);
    char drain[4096]; // the request, so that closing does not reset the connection
    socket.read_some(asio::buffer(drain), ignored);
    const std::string body = why + "\n";
    const std::string response = "HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain\r\n"
                                 "Connection: close\r\nRetry-After: 10\r\nContent-Length: " +
                                 std::to_string(body.size()) + "\r\n\r\n" + body;
    socket.write_some(asio::buffer(response), ignored);
    socket.shutdown(tcp::socket::shutdown_send, ignored);
}

} // namespace

HttpServer::HttpServer(Service& service, asio::ssl::context* tls) : service_(service), tls_(tls) {
    route("/healthz", [](const HttpRequest&, HttpResponse& res) {
        res.set(http::field::content_type, "text/plain");
        res.body() = "ok\n";
    });
    route("/metrics", [&service](const HttpRequest&, HttpResponse& res) {
        res.set(http::field::content_type, "text/plain; version=0.0.4");
        res.body() = service.metrics_text();
    });
}

void HttpServer::route(std::string path, HttpHandler handler) {
    routes_[std::move(path)] = Route{std::move(handler), nullptr};
}

void HttpServer::route_later(std::string path, HttpLaterHandler handler) {
    routes_[std::move(path)] = Route{nullptr, std::move(handler)};
}

const HttpServer::Route* HttpServer::find_route(const std::string& path) const {
    const Route* best = nullptr;
    size_t best_length = 0;
    for (const auto& [route, endpoint] : routes_) {
        const bool prefix = !route.empty() && route.back() == '/';
        const bool matches = prefix ? path.rfind(route, 0) == 0 : path == route;
        if (matches && route.size() >= best_length) {
            best = &endpoint;
            best_length = route.size();
        }
    }
    return best;
}

PortProtocol HttpServer::protocol() {
    PortProtocol p;
    p.name = tls_ ? "HTTPS (/healthz, /metrics, /ws)" : "HTTP (/healthz, /metrics, /ws)";
    p.serve = [this](tcp::socket socket, std::string peer, Slot slot) {
        if (tls_)
            std::make_shared<HttpSession<beast::ssl_stream<beast::tcp_stream>>>(
                beast::ssl_stream<beast::tcp_stream>(beast::tcp_stream(std::move(socket)), *tls_),
                *this, std::move(peer), std::move(slot))
                ->start();
        else
            std::make_shared<HttpSession<beast::tcp_stream>>(
                beast::tcp_stream(std::move(socket)), *this, std::move(peer), std::move(slot))
                ->start();
    };
    p.refuse = [tls = tls_ != nullptr](tcp::socket& socket, const std::string& why) {
        refuse_with_503(socket, why, tls);
    };
    return p;
}

} // namespace ddsimp::server
