// Which connections the server takes: every accepted socket (native, HTTP, WebSocket, a TLS
// handshake in progress) holds a place until it is closed, within a limit for all and one per
// client address. The limits are sized at start below the descriptor limit, so that a flood of
// connections meets a refusal, never a server out of descriptors. Places are taken on the network
// thread; a place is given back wherever its connection's last owner goes (a compute or preview
// thread may hold the last reference to an HTTP session or a connection), so the counts are
// under a lock.
#pragma once

#include "config.h"
#include "metrics.h"

#include <boost/asio/ip/address.hpp>

#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace ddsimp::server {

// The places taken: shared with every slot, so that a slot released after the Admission is gone
// (a handler destroyed with the io_context) is harmless. Every member under `mutex`.
struct AdmissionState {
    std::mutex mutex;
    Metrics* metrics = nullptr; // null once the Admission is gone
    size_t held = 0;
    std::map<boost::asio::ip::address, size_t> per_address;
};

// A connection's place: released when the last owner (its transport or HTTP session) goes, on
// any thread.
class ConnectionSlot {
public:
    ConnectionSlot(std::shared_ptr<AdmissionState> state, boost::asio::ip::address address);
    ~ConnectionSlot();
    ConnectionSlot(const ConnectionSlot&) = delete;
    ConnectionSlot& operator=(const ConnectionSlot&) = delete;

private:
    std::shared_ptr<AdmissionState> state_;
    boost::asio::ip::address address_;
};
using Slot = std::shared_ptr<ConnectionSlot>;

// The limits that fit the process: the configured ones, lowered so that the connections and
// `reserve` descriptors for the server's own files stay within RLIMIT_NOFILE (whose soft value is
// first raised to the hard one). Logs what it lowered.
struct ConnectionLimits {
    size_t total = 0, per_address = 0;
    size_t descriptors = 0; // the soft RLIMIT_NOFILE after raising
};
ConnectionLimits fit_descriptor_limit(const Config& config);

class Admission {
public:
    Admission(ConnectionLimits limits, Metrics& metrics);
    ~Admission();
    Admission(const Admission&) = delete;
    Admission& operator=(const Admission&) = delete;

    // A place for a connection from `address`, or nullptr with `why` set.
    Slot admit(const boost::asio::ip::address& address, std::string& why);
    size_t held() const;
    const ConnectionLimits& limits() const { return limits_; }

private:
    ConnectionLimits limits_;
    Metrics& metrics_;
    std::shared_ptr<AdmissionState> state_;
};

} // namespace ddsimp::server
