#include "memory_bound.h"

#include "client_limits.h"

#include <fmt/format.h>

#include <algorithm>

namespace ddsimp::server {

uint64_t MemoryBound::total() const {
    uint64_t sum = 0;
    for (const auto& [what, bytes] : parts) sum += bytes;
    return sum;
}

std::string MemoryBound::describe() const {
    std::string out;
    for (const auto& [what, bytes] : parts)
        out += fmt::format("{}{} {:.0f} MiB", out.empty() ? "" : " + ", what,
                           double(bytes) / double(1 << 20));
    return out + fmt::format(" = {:.0f} MiB", double(total()) / double(1 << 20));
}

MemoryBound memory_bound(const Config& c, uint64_t clients) {
    constexpr uint64_t MiB = 1 << 20, KiB = 1 << 10;
    const uint64_t T = uint64_t(c.threads), C = clients;
    // The largest surface in memory: an upload's raw bytes, or a stored surface read back.
    const uint64_t X = uint64_t(c.max_surface_mb) * MiB;
    const uint64_t N = c.max_surface_triangles;
    const uint64_t queues =
        std::min(C * uint64_t(c.max_queue_mb) * MiB, uint64_t(c.max_queue_total_mb) * MiB);
    MemoryBound b;
    // Resident surfaces, and one in use beyond them per computation and the preview thread.
    b.parts.emplace_back("surfaces", uint64_t(c.surfaces_mb) * MiB + (T + 1) * X);
    // The frame each connection is reading, its objects, and every send queue together.
    b.parts.emplace_back("connections", C * (uint64_t(c.max_frame_bytes) + kConnectionBytes));
    b.parts.emplace_back("send queues", queues);
    // HTTP downloads being built and sent: level.glb files, web files.
    b.parts.emplace_back("downloads", uint64_t(c.max_download_mb) * MiB);
    // Uploads in progress, and each being decoded, checked and written (two copies).
    b.parts.emplace_back("uploads", uint64_t(c.max_upload_mb) * MiB + T * 2 * X);
    // Cached records and levels, and each run in progress.
    b.parts.emplace_back("results", uint64_t(c.cache_mb) * MiB + T * kEngineBytesPerTriangle * N);
    b.parts.emplace_back("request jobs", C * kMaxRequestsPerConnection * kRequestJobBytes);
    b.parts.emplace_back("remembered keys", uint64_t(c.max_remembered_kb) * KiB);
    return b;
}

} // namespace ddsimp::server
