// The native protocol port: accepts TCP connections (TLS when configured) and hands each to the
// Service as a stream transport.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>

namespace ddsimp::server {

class Service;

class NativeServer {
public:
    // Listens at once; throws boost::system::system_error if the port cannot be bound.
    NativeServer(boost::asio::io_context& io, Service& service, boost::asio::ip::tcp::endpoint at,
                 boost::asio::ssl::context* tls);
    void stop();

private:
    void accept();

    Service& service_;
    boost::asio::ip::tcp::acceptor acceptor_;
    boost::asio::ssl::context* tls_;
    // Connections still in their TLS handshake: they count against --max-clients like open ones,
    // so handshakes that never finish cannot pile up beyond the limit.
    size_t handshaking_ = 0;
};

} // namespace ddsimp::server
