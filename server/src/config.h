// ddsimp-server's configuration: flags, then environment (DDSIMP_<FLAG>), then a config file
// (--config FILE, INI "key = value" with the flags' names), then the defaults.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace ddsimp::server {

struct Config {
    std::string bind = "127.0.0.1";
    uint16_t port = 7420;
    uint16_t http_port = 7421;
    std::string data_dir = "ddsimp-data";
    std::string token;    // empty: no authentication
    std::string tls_cert; // both set: TLS on the native and HTTP ports
    std::string tls_key;
    int threads = 2; // compute pool
    size_t cache_mb = 512;
    std::string web_dir; // the browser renderer's built files, served at /
    std::string sample;  // a surface file loaded at start (the built-in sample by default)

    // limits
    size_t max_frame_bytes = 4u << 20;
    size_t max_surface_triangles = 20'000'000;
    size_t max_clients = 256;
    size_t max_sessions = 64;
    size_t max_queue_mb = 256;   // per client: bytes waiting to be sent
    size_t max_upload_mb = 1024; // all clients together: uploads received but not yet stored
    double send_timeout_s = 30;  // a write that makes no progress this long drops the client
    double idle_timeout_s = 600; // nothing received or sent this long closes the connection
    double handshake_timeout_s = 10;
    std::string log_level = "info";
};

// Parses argv. Prints help or errors and exits (0 for --help/--version, 2 for bad usage).
Config parse_config(int argc, char** argv);

} // namespace ddsimp::server
