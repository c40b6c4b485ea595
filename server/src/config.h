// ddsimp-server's configuration: flags, then environment (DDSIMP_<FLAG>), then a config file
// (--config FILE, INI "key = value" with the flags' names), then the defaults.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>

namespace ddsimp::server {

// Every timeout of the server, in seconds (flags --NAME-timeout). A wait without one is a place
// where a client could hold the server's memory or a descriptor for as long as it likes.
struct Timeouts {
    double handshake = 10; // a new connection: TLS, then Hello and Auth (or a WebSocket upgrade)
    double idle = 600;     // nothing received or sent: the connection is closed
    double send = 30;      // a write that makes no progress: the client is dropped
    double http = 30;      // an HTTP request's head and body, and a keep-alive wait for the next
    double upload = 300;   // an upload in progress that receives no chunk: it is forgotten
    // Accepting fails (out of descriptors, memory): the listener waits, doubling from 10 ms up to
    // this, and logs the failures once per log interval.
    double accept_backoff = 1;
    double accept_log_interval = 10;
};

// Seconds as a duration for the timers.
inline std::chrono::milliseconds to_duration(double seconds) {
    return std::chrono::milliseconds(int64_t(1000 * seconds));
}

struct Config {
    std::string bind = "127.0.0.1";
    std::string http_bind; // empty: the same as bind
    uint16_t port = 7420;
    uint16_t http_port = 7421;
    std::string data_dir = "ddsimp-data";
    std::string token;       // empty: no authentication (unless tokens_file names some)
    std::string tokens_file; // one token per user: lines "NAME TOKEN" (tokens.h)
    std::string tls_cert;    // both set: TLS on the native and HTTP ports
    std::string tls_key;
    int threads = 2;       // compute pool
    bool speculate = true; // records at alpha 0, 0.5, 1 after an upload, while idle
    size_t cache_mb = 512;
    size_t surfaces_mb = 512; // stored surfaces kept in memory (the rest are read when needed)
    std::string web_dir;      // the browser renderer's built files, served at /
    std::string sample;       // a surface file loaded at start (the built-in sample by default)

    // limits
    size_t max_frame_bytes = 4u << 20;
    size_t max_surface_triangles = 20'000'000;
    size_t max_surface_mb = 1024; // the largest surface in memory: an upload's raw bytes
    // Connections at once, every kind counted (native, HTTP, WebSocket, TLS handshakes), and from
    // one address. At start both are lowered to fit the descriptor limit (RLIMIT_NOFILE) less
    // fd_reserve, kept for the server's own files.
    size_t max_clients = 256;
    size_t max_clients_per_address = 64;
    size_t fd_reserve = 64;
    size_t max_sessions = 64;
    size_t max_queue_mb = 256;        // per client: bytes waiting to be sent
    size_t max_queue_total_mb = 1024; // all clients together
    size_t max_upload_mb = 1024;      // all clients together: uploads received but not yet stored
    size_t max_download_mb = 512;     // all clients together: HTTP downloads built and being sent
    size_t max_remembered_kb = 16384; // result keys remembered after their requests, for resuming
    // Per token and per session (quotas.h): stored surfaces, their MiB, and MiB of uploads in
    // progress.
    size_t quota_surfaces = 1000;
    size_t quota_surfaces_mb = 8192;
    size_t quota_upload_mb = 512;
    Timeouts timeouts;
    std::string log_level = "info";
    std::string log_format = "text"; // or "json": one JSON object per line
};

// Parses argv. Prints help or errors and exits (0 for --help/--version, 2 for bad usage).
Config parse_config(int argc, char** argv);

} // namespace ddsimp::server
