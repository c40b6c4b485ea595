// One acceptor for every port: accepts TCP connections, gives each a place (Admission) or
// refuses it, and hands the admitted ones to the port's protocol (native frames, or HTTP).
// When accepting fails (out of descriptors or memory) it pauses, doubling the pause up to a
// bound, instead of spinning, and logs the failures once per interval.
#pragma once

#include "admission.h"
#include "config.h"

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>

#include <chrono>
#include <functional>
#include <string>

namespace ddsimp::server {

// What a port speaks: `serve` takes an admitted connection (with its peer "address:port" and its
// place, to be held as long as the connection is open); `refuse` may tell a refused one why
// before it is closed (it must not block).
struct PortProtocol {
    std::string name; // "native protocol", "HTTP"
    std::function<void(boost::asio::ip::tcp::socket, std::string peer, Slot slot)> serve;
    std::function<void(boost::asio::ip::tcp::socket&, const std::string& why)> refuse;
};

class Listener {
public:
    // Listens at once; throws boost::system::system_error if the address cannot be bound.
    Listener(boost::asio::io_context& io, boost::asio::ip::tcp::endpoint at, PortProtocol protocol,
             Admission& admission, Metrics& metrics, const Timeouts& timeouts);
    void stop();
    uint16_t port() const;

private:
    void accept();
    void on_accept_error(const boost::system::error_code& ec);

    boost::asio::ip::tcp::acceptor acceptor_;
    PortProtocol protocol_;
    Admission& admission_;
    Metrics& metrics_;
    const Timeouts& timeouts_;
    boost::asio::steady_timer backoff_timer_;
    std::chrono::milliseconds backoff_{0};
    // Failed accepts and refusals since they were last logged, and when that was.
    size_t errors_unlogged_ = 0, refusals_unlogged_ = 0;
    std::chrono::steady_clock::time_point errors_logged_{}, refusals_logged_{};
};

} // namespace ddsimp::server
