// The HTTP port (Boost.Beast): /healthz, /metrics (Prometheus text), the WebSocket endpoint /ws
// carrying protocol frames, and the browser renderer's files at /. TLS when configured. Accepting
// is the Listener's; another endpoint is added with route() (or route_later()).
#pragma once

#include "listener.h"

#include <boost/asio/ssl/context.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>

#include <functional>
#include <map>
#include <memory>
#include <string>

namespace ddsimp::server {

class Service;

using HttpRequest = boost::beast::http::request<boost::beast::http::string_body>;
using HttpResponse = boost::beast::http::response<boost::beast::http::string_body>;
// Fills the response (status 200 and keep-alive are set already) for a GET or HEAD.
using HttpHandler = std::function<void(const HttpRequest&, HttpResponse&)>;
// Sends a response that was made later (callable once, from any thread). `hold` is kept until
// the response is written (or the connection is gone): what the body's bytes are counted in.
using HttpReply = std::function<void(HttpResponse, std::shared_ptr<const void> hold)>;
// Starts a GET or HEAD that is answered later: it gets the response to fill (status 200 and
// keep-alive set) and the reply to send it with. The connection waits for the reply.
using HttpLaterHandler = std::function<void(const HttpRequest&, HttpResponse, HttpReply)>;

class HttpServer {
public:
    HttpServer(Service& service, boost::asio::ssl::context* tls);

    // Answers GET and HEAD of `path` (without its query) with `handler`; a path that ends in '/'
    // takes every path below it. The longest match wins; what matches nothing is a web file.
    void route(std::string path, HttpHandler handler);
    // The same for an endpoint whose answer takes time (computed off the network thread).
    void route_later(std::string path, HttpLaterHandler handler);
    // What the Listener of the HTTP port runs for each connection.
    PortProtocol protocol();

    // An endpoint: one of its handlers is set.
    struct Route {
        HttpHandler now;
        HttpLaterHandler later;
    };
    // The route of a request's path, or null (network thread).
    const Route* find_route(const std::string& path) const;
    Service& service() { return service_; }

private:
    Service& service_;
    boost::asio::ssl::context* tls_;
    std::map<std::string, Route> routes_;
};

} // namespace ddsimp::server
