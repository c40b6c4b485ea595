// The server's fixed limits on what clients choose. Every size a client chooses is bounded, by
// these or by a configured limit (config.h); docs/security.md lists them all.
#pragma once

#include <cstddef>

namespace ddsimp::server {

// Per connection: work a client may have in progress at once.
inline constexpr size_t kMaxUploadsPerConnection = 4;
inline constexpr size_t kMaxRequestsPerConnection = 16;
inline constexpr size_t kMaxSessionsPerConnection = 16;

// Strings a client chooses: surface labels, field names, session names and keys.
inline constexpr size_t kMaxNameBytes = 200;
inline constexpr size_t kMaxSessionKeyBytes = 1024;

// The shape of a surface beyond its triangle count (--max-surface-triangles).
inline constexpr size_t kMaxFields = 64;
inline constexpr size_t kMaxFieldComponents = 256;
inline constexpr size_t kMaxVerticesPerTriangle = 3; // vertices <= 3 x triangles

// A request: levels asked for and gradient fields named.
inline constexpr size_t kMaxLevelsPerRequest = 64;

} // namespace ddsimp::server
