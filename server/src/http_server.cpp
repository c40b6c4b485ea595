#include "http_server.h"

#include "service.h"
#include "websocket_transport.h"

#include <boost/beast/http.hpp>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace ddsimp::server {
namespace asio = boost::asio;
namespace http = beast::http;
using tcp = asio::ip::tcp;

namespace {

constexpr auto kReadTimeout = std::chrono::seconds(30);

std::string content_type(const std::string& path) {
    const auto ends = [&](const char* ext) {
        const std::string e(ext);
        return path.size() >= e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0;
    };
    if (ends(".html")) return "text/html; charset=utf-8";
    if (ends(".js") || ends(".mjs")) return "text/javascript; charset=utf-8";
    if (ends(".css")) return "text/css; charset=utf-8";
    if (ends(".json")) return "application/json";
    if (ends(".wasm")) return "application/wasm";
    if (ends(".png")) return "image/png";
    if (ends(".svg")) return "image/svg+xml";
    if (ends(".ico")) return "image/x-icon";
    return "application/octet-stream";
}

// A request path mapped into the web directory, or "" if it could leave it.
std::string web_file(const std::string& dir, std::string target) {
    target = target.substr(0, target.find_first_of("?#"));
    if (target.empty() || target[0] != '/' || target.find("..") != std::string::npos ||
        target.find('\\') != std::string::npos || target.find('\0') != std::string::npos)
        return "";
    if (target.back() == '/') target += "index.html";
    return dir + target;
}

bool is_page_root(const std::string& target) {
    return target == "/" || target.rfind("/?", 0) == 0 || target == "/index.html";
}

std::string html_escape(const std::string& text) {
    std::string out;
    for (char ch : text) {
        if (ch == '&')
            out += "&amp;";
        else if (ch == '<')
            out += "&lt;";
        else if (ch == '>')
            out += "&gt;";
        else
            out += ch;
    }
    return out;
}

// What / shows when the browser renderer has not been built (or --web-dir points elsewhere).
std::string no_web_page(const std::string& dir) {
    const std::string where = dir.empty() ? std::string("no --web-dir is set")
                                          : "there is no index.html in " + html_escape(dir);
    return "<!doctype html><title>ddsimp-server</title><h1>ddsimp-server</h1>"
           "<p>The browser renderer is not here: " +
           where +
           ". Build it with <code>npm ci &amp;&amp; npm run build</code> in <code>web/</code> "
           "(<code>scripts/run.sh</code> does this) and start the server with "
           "<code>--web-dir web/dist</code>.</p><p>Endpoints: <a href=\"/healthz\">/healthz</a>, "
           "<a href=\"/metrics\">/metrics</a>, WebSocket <code>/ws</code>.</p>\n";
}

template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
public:
    HttpSession(Stream stream, Service& service, std::string peer)
        : stream_(std::move(stream)), service_(service), peer_(std::move(peer)) {}

    void start() {
        if constexpr (std::is_same_v<Stream, beast::tcp_stream>) {
            read();
        } else {
            beast::get_lowest_layer(stream_).expires_after(kReadTimeout);
            stream_.async_handshake(asio::ssl::stream_base::server,
                                    [self = this->shared_from_this()](beast::error_code ec) {
                                        if (!ec) self->read();
                                    });
        }
    }

private:
    void read() {
        request_ = {};
        parser_.emplace();
        parser_->body_limit(64 * 1024);
        beast::get_lowest_layer(stream_).expires_after(kReadTimeout);
        http::async_read(stream_, buffer_, *parser_,
                         [self = this->shared_from_this()](beast::error_code ec, size_t) {
                             if (ec) return self->close();
                             self->request_ = self->parser_->release();
                             self->route();
                         });
    }

    void route() {
        const std::string target(request_.target());
        if (websocket::is_upgrade(request_) && target == "/ws") return upgrade();
        http::response<http::string_body> res{http::status::ok, request_.version()};
        res.set(http::field::server, service_.server_name());
        res.keep_alive(request_.keep_alive());
        if (request_.method() != http::verb::get && request_.method() != http::verb::head) {
            res.result(http::status::method_not_allowed);
            res.body() = "only GET\n";
        } else if (target == "/healthz") {
            res.set(http::field::content_type, "text/plain");
            res.body() = "ok\n";
        } else if (target == "/metrics") {
            res.set(http::field::content_type, "text/plain; version=0.0.4");
            res.body() = service_.metrics_text();
        } else {
            serve_file(target, res);
        }
        res.prepare_payload();
        auto shared = std::make_shared<http::response<http::string_body>>(std::move(res));
        beast::get_lowest_layer(stream_).expires_after(kReadTimeout);
        http::async_write(stream_, *shared,
                          [self = this->shared_from_this(), shared](beast::error_code ec, size_t) {
                              if (ec || !shared->keep_alive()) return self->close();
                              self->read();
                          });
    }

    void serve_file(const std::string& target, http::response<http::string_body>& res) {
        const std::string& dir = service_.config().web_dir;
        const std::string path = dir.empty() ? std::string() : web_file(dir, target);
        std::error_code ec;
        std::ifstream in;
        if (!path.empty() && std::filesystem::is_regular_file(path, ec))
            in.open(path, std::ios::binary);
        if (!in.is_open()) {
            res.set(http::field::content_type, "text/html; charset=utf-8");
            if (is_page_root(target)) {
                res.body() = no_web_page(dir);
            } else {
                res.result(http::status::not_found);
                res.set(http::field::content_type, "text/plain");
                res.body() = "not found\n";
            }
            return;
        }
        res.set(http::field::content_type, content_type(path));
        // Vite names the files under assets/ by their content: they never change. The page
        // itself must be asked for again so a rebuilt renderer is picked up.
        res.set(http::field::cache_control, target.rfind("/assets/", 0) == 0
                                                ? "public, max-age=31536000, immutable"
                                                : "no-cache");
        res.body().assign(std::istreambuf_iterator<char>(in), {});
    }

    void upgrade() {
        beast::get_lowest_layer(stream_).expires_never();
        auto ws = std::make_shared<websocket::stream<Stream>>(std::move(stream_));
        ws->set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
        ws->async_accept(request_, [ws, &service = service_, peer = peer_](beast::error_code ec) {
            if (ec) return;
            const Config& c = service.config();
            service.accept(std::make_shared<WebSocketTransport<Stream>>(
                std::move(*ws), peer + " (WebSocket)", c.max_frame_bytes,
                std::chrono::milliseconds(int64_t(1000 * c.send_timeout_s))));
        });
    }

    void close() {
        beast::error_code ignored;
        beast::get_lowest_layer(stream_).socket().shutdown(tcp::socket::shutdown_both, ignored);
    }

    Stream stream_;
    Service& service_;
    std::string peer_;
    beast::flat_buffer buffer_;
    std::optional<http::request_parser<http::string_body>> parser_;
    http::request<http::string_body> request_;
};

} // namespace

HttpServer::HttpServer(asio::io_context& io, Service& service, tcp::endpoint at,
                       asio::ssl::context* tls)
    : service_(service), acceptor_(io, at), tls_(tls) {
    spdlog::info("HTTP on {}:{} (/healthz, /metrics, /ws{})", at.address().to_string(),
                 acceptor_.local_endpoint().port(), tls ? ", TLS" : "");
    accept();
}

void HttpServer::stop() {
    beast::error_code ignored;
    acceptor_.close(ignored);
}

void HttpServer::accept() {
    acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
        if (ec == asio::error::operation_aborted) return;
        if (!ec) {
            beast::error_code ignored;
            const auto remote = socket.remote_endpoint(ignored);
            const std::string peer =
                remote.address().to_string() + ":" + std::to_string(remote.port());
            if (tls_)
                std::make_shared<HttpSession<beast::ssl_stream<beast::tcp_stream>>>(
                    beast::ssl_stream<beast::tcp_stream>(beast::tcp_stream(std::move(socket)),
                                                         *tls_),
                    service_, peer)
                    ->start();
            else
                std::make_shared<HttpSession<beast::tcp_stream>>(
                    beast::tcp_stream(std::move(socket)), service_, peer)
                    ->start();
        }
        accept();
    });
}

} // namespace ddsimp::server
