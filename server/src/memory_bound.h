// The most memory clients can make the server hold beyond its size at rest, from its flags: each
// part bounded by a flag and shown in /metrics as it is, their sum shown as
// ddsimp_memory_bound_bytes and logged at start. docs/operations.md#memory states the same formula.
#pragma once

#include "config.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace ddsimp::server {

// The engine's working memory per triangle of a run in progress (measured on the 1.18 M carotid:
// 244 bytes for edge collapse, 279 for vertex removal), rounded up.
inline constexpr uint64_t kEngineBytesPerTriangle = 300;
// What an open connection holds besides the frame it is reading and its send queue: its socket,
// transport, connection objects, timers and HTTP request (at most 64 KiB of body).
inline constexpr uint64_t kConnectionBytes = 96u << 10;
// A request job: what its levels need (about 600 bytes), 16 per connection.
inline constexpr uint64_t kRequestJobBytes = 1u << 10;

struct MemoryBound {
    // (what, bytes), in the order of docs/operations.md's formula.
    std::vector<std::pair<std::string, uint64_t>> parts;
    uint64_t total() const;
    // "surfaces 192 MiB + connections ... = N MiB", for the start-up log.
    std::string describe() const;
};

// `clients`: the connection limit as fitted to the descriptor limit (admission.h).
MemoryBound memory_bound(const Config& config, uint64_t clients);

} // namespace ddsimp::server
