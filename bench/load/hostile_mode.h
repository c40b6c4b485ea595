// ddsimp-load --hostile: every attack of hostile_attacks.h at once against one server while
// normal clients ask for a cached level of the main surface, and the goals measured:
// the normal clients' latency during the attack, the server's peak memory against the total it
// states for its flags (ddsimp_memory_bound_bytes, docs/operations.md#memory), forged log lines,
// and its memory after the attack against its memory at idle.
#pragma once

#include <string>
#include <vector>

namespace ddsimp::load {

struct HostileSettings {
    std::string host = "127.0.0.1";
    uint16_t port = 7420;
    uint16_t http_port = 0;
    std::string token;
    std::string surface;    // the big surface's file; uploaded first
    int server_pid = 0;     // required: memory is read from /proc
    std::string server_log; // the server's log (stderr) to scan; empty: not scanned
    double alpha = 0.5;
    std::vector<double> keeps{0.1}; // the cached levels the normal clients ask for
    int normal_clients = 4;
    double attack_seconds = 60;
    bool tls = false; // the server has TLS (its certificate is not checked)
    bool json = false;
};

// Runs it and prints the report; 0 when every goal is met.
int run_hostile(const HostileSettings& settings);

} // namespace ddsimp::load
