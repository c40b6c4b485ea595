#include "listener.h"

#include <spdlog/spdlog.h>

namespace ddsimp::server {
namespace asio = boost::asio;
using tcp = asio::ip::tcp;

namespace {

constexpr std::chrono::milliseconds kFirstBackoff{10};

// Whether `interval` has passed since `last` (then `last` becomes now).
bool due(std::chrono::steady_clock::time_point& last, double interval) {
    const auto now = std::chrono::steady_clock::now();
    if (last != std::chrono::steady_clock::time_point{} && now - last < to_duration(interval))
        return false;
    last = now;
    return true;
}

} // namespace

Listener::Listener(asio::io_context& io, tcp::endpoint at, PortProtocol protocol,
                   Admission& admission, Metrics& metrics, const Timeouts& timeouts)
    : acceptor_(io, at), protocol_(std::move(protocol)), admission_(admission), metrics_(metrics),
      timeouts_(timeouts), backoff_timer_(io) {
    spdlog::info("{} on {}:{}", protocol_.name, at.address().to_string(), port());
    accept();
}

uint16_t Listener::port() const {
    boost::system::error_code ignored;
    return acceptor_.local_endpoint(ignored).port();
}

void Listener::stop() {
    boost::system::error_code ignored;
    acceptor_.close(ignored);
    backoff_timer_.cancel();
}

void Listener::accept() {
    acceptor_.async_accept([this](boost::system::error_code ec, tcp::socket socket) {
        if (ec == asio::error::operation_aborted || !acceptor_.is_open()) return;
        if (ec) return on_accept_error(ec);
        backoff_ = std::chrono::milliseconds(0);
        boost::system::error_code failed;
        const tcp::endpoint remote = socket.remote_endpoint(failed);
        if (failed) return accept(); // the client has gone already
        const std::string peer = remote.address().to_string() + ":" + std::to_string(remote.port());
        std::string why;
        if (Slot slot = admission_.admit(remote.address(), why)) {
            socket.set_option(tcp::no_delay(true), failed);
            protocol_.serve(std::move(socket), peer, std::move(slot));
        } else {
            ++refusals_unlogged_;
            if (due(refusals_logged_, timeouts_.accept_log_interval)) {
                spdlog::warn("{}: refused {} connection{} (the last from {}): {}", protocol_.name,
                             refusals_unlogged_, refusals_unlogged_ == 1 ? "" : "s", peer, why);
                refusals_unlogged_ = 0;
            }
            protocol_.refuse(socket, why);
            socket.close(failed);
        }
        accept();
    });
}

void Listener::on_accept_error(const boost::system::error_code& ec) {
    ++metrics_.accept_errors;
    ++errors_unlogged_;
    if (due(errors_logged_, timeouts_.accept_log_interval)) {
        spdlog::error("{}: accepting failed {} time{} ({}); {} connections open, pausing",
                      protocol_.name, errors_unlogged_, errors_unlogged_ == 1 ? "" : "s",
                      ec.message(), admission_.held());
        errors_unlogged_ = 0;
    }
    backoff_ =
        std::min(std::max(2 * backoff_, kFirstBackoff), to_duration(timeouts_.accept_backoff));
    backoff_timer_.expires_after(backoff_);
    backoff_timer_.async_wait([this](boost::system::error_code e) {
        if (!e) accept();
    });
}

} // namespace ddsimp::server
