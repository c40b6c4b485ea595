// Bare connections for ddsimp-load's hostile mode: sockets an attacker opens and writes by hand
// (frames, parts of frames, nothing at all), and a kept-alive HTTP connection for /metrics.
// Plain POSIX sockets: hundreds of them are opened, each costs one descriptor. Against a server
// with TLS (use_tls), each speaks TLS from its first read or write: one never used stays an
// unfinished handshake, as a silent socket on a TLS port is.
#pragma once

#include "ddsimp/protocol/frame.h"

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace ddsimp::load {

// Every RawConnection made after this speaks TLS (any certificate accepted: the bench's own).
void use_tls(bool on);
bool tls_in_use();

// One TCP connection to host:port, from the local address `from` (any of 127.0.0.0/8 stands for
// another machine) when it is not empty. Errors are not thrown: an attacker's socket that the
// server closes is what the attack expects.
class RawConnection {
public:
    RawConnection(const std::string& host, uint16_t port, const std::string& from = "");
    ~RawConnection();
    RawConnection(const RawConnection&) = delete;
    RawConnection& operator=(const RawConnection&) = delete;

    bool connected() const { return fd_ >= 0; }
    // Writes all of `bytes`; false once the connection is gone.
    bool send_bytes(const std::string& bytes);
    template <class M> bool send(const M& m) { return send_bytes(protocol::encode_frame(m)); }
    // The next frame (blocking), or nothing once the connection is closed or shut down.
    std::optional<protocol::Frame> next();
    // Appends the bytes that arrive next (blocking) to `out`; false once the connection is gone.
    bool receive(std::string& out);
    // Whether the server has closed the connection (checked without blocking).
    bool closed_by_server() const;
    // Wakes a thread blocked in next(); the connection is unusable afterwards.
    void shut_down();
    // Hello with `client_name`, and Auth when the server asks for a token: true once in.
    bool handshake(const std::string& client_name, const std::string& token);
    // TLS: sends the ClientHello and nothing more, leaving the handshake unfinished; false
    // without TLS or once the connection is gone.
    bool start_tls_handshake_only();

private:
    // The connection's bytes, through TLS when in use: -1 once it is gone.
    ssize_t read_some(char* buffer, size_t size);
    bool write_all(const char* data, size_t size);
    struct Tls;
    std::unique_ptr<Tls> tls_;
    std::atomic<bool> shut_{false};
    int fd_ = -1;
    protocol::FrameDecoder decoder_{size_t(64) << 20};
};

// GET requests on one kept-alive HTTP connection (it holds one of the server's places, taken
// before an attack fills them).
class HttpKeepAlive {
public:
    HttpKeepAlive(const std::string& host, uint16_t port);
    // The body of GET `target`, or nothing if the connection failed.
    std::optional<std::string> get(const std::string& target);

private:
    std::string host_;
    uint16_t port_;
    std::optional<RawConnection> connection_;
    std::string buffer_;
};

// The samples of a Prometheus text page ("name value" lines, labels kept in the name).
std::map<std::string, double> parse_metrics(const std::string& text);

// Counts by name, shared by the threads of an attack.
class Tally {
public:
    void add(const std::string& what, long n = 1) {
        std::lock_guard lock(mutex_);
        counts_[what] += n;
    }
    std::map<std::string, long> counts() const {
        std::lock_guard lock(mutex_);
        return counts_;
    }

private:
    mutable std::mutex mutex_;
    std::map<std::string, long> counts_;
};

} // namespace ddsimp::load
