// The native protocol port's side of a connection: the TLS handshake when configured (within the
// handshake timeout), then a stream transport handed to the Service. Accepting is the Listener's.
#pragma once

#include "listener.h"

#include <boost/asio/ssl/context.hpp>

namespace ddsimp::server {

class Service;

// What the Listener of the native port runs for each connection.
PortProtocol native_protocol(Service& service, boost::asio::ssl::context* tls);

} // namespace ddsimp::server
