// The HTTP port (Boost.Beast): /healthz, /metrics (Prometheus text), the WebSocket endpoint /ws
// carrying protocol frames, and the browser renderer's files at /. TLS when configured.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>

#include <memory>

namespace ddsimp::server {

class Service;

class HttpServer {
public:
    // Listens at once; throws boost::system::system_error if the port cannot be bound.
    HttpServer(boost::asio::io_context& io, Service& service, boost::asio::ip::tcp::endpoint at,
               boost::asio::ssl::context* tls);
    void stop();

private:
    void accept();

    Service& service_;
    boost::asio::ip::tcp::acceptor acceptor_;
    boost::asio::ssl::context* tls_;
};

} // namespace ddsimp::server
