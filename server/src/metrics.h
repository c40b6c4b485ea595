// Counters for /metrics (Prometheus text format, names prefixed ddsimp_). Updated from the
// network thread and the compute pool.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

namespace ddsimp::server {

struct Metrics {
    std::atomic<int64_t> connections{0}; // protocol clients (native and WebSocket)
    std::atomic<uint64_t> connections_total{0};
    // Every accepted socket holds a place (admission.h): HTTP, WebSocket, native, TLS handshakes.
    std::atomic<int64_t> sockets{0};
    std::atomic<int64_t> sockets_limit{0};
    std::atomic<int64_t> sockets_per_address_limit{0};
    std::atomic<uint64_t> connections_refused{0}; // over a limit
    std::atomic<uint64_t> accept_errors{0};       // accepting failed (descriptors, memory)
    std::atomic<uint64_t> connections_dropped{0}; // slow readers, over-limit queues
    std::atomic<uint64_t> bad_frames{0};
    std::atomic<uint64_t> requests{0};
    std::atomic<uint64_t> request_errors{0};
    std::atomic<uint64_t> uploads{0};
    std::atomic<uint64_t> levels_sent{0};
    std::atomic<int64_t> queue_bytes{0};      // waiting to be sent, all clients
    std::atomic<int64_t> queue_bytes_peak{0}; // the most one client ever had waiting
    std::atomic<int64_t> upload_bytes{0};     // uploads received but not yet stored, all clients
    std::atomic<uint64_t> quota_refusals{0};  // uploads refused by a quota or the upload budget
    std::atomic<uint64_t> bytes_sent{0};
    std::atomic<uint64_t> bytes_received{0};
    std::atomic<int64_t> reductions_running{0};    // records being computed now
    std::atomic<uint64_t> reductions_cancelled{0}; // computations stopped: nobody waited any more
    std::atomic<uint64_t> reductions_yielded{0};   // stopped to free a worker; run again later
    std::atomic<uint64_t> previews_sent{0};
    std::atomic<uint64_t> speculative_records{0}; // records made while idle (--speculate)
    // Request jobs from queueing until they stop (cancelled ones too), and what they hold.
    std::atomic<int64_t> request_jobs{0};
    std::atomic<int64_t> request_job_bytes{0};
    std::atomic<uint64_t> session_views_skipped{0}; // a newer view came before the job ran
    std::atomic<int64_t> remembered_results{0};     // result keys kept for resuming
    std::atomic<int64_t> remembered_bytes{0};
    std::atomic<uint64_t> downloads_refused{0}; // HTTP downloads over --max-download-mb
    // The most clients can make the server hold beyond its size at rest (memory_bound.h).
    std::atomic<int64_t> memory_bound{0};

    // Job latency: time from a request's arrival to its levels being ready to send.
    void observe_job_seconds(double seconds);

    // The exposition text; the cache, session and surface numbers are passed in.
    struct Snapshot {
        size_t sessions = 0, surfaces = 0;
        size_t surfaces_resident = 0, surface_bytes = 0, surface_pinned_bytes = 0;
        size_t surface_limit_bytes = 0, surface_loads = 0, surface_evictions = 0;
        size_t surfaces_deleted = 0;
        size_t cache_hits = 0, cache_misses = 0, cache_bytes = 0, cache_entries = 0;
        size_t computations = 0, evictions = 0;
        size_t speculations_pending = 0; // the scheduler's background work, waiting or running
        size_t download_bytes = 0, download_limit_bytes = 0; // .glb downloads (glb_download.h)
    };
    std::string render(const Snapshot& s) const;

private:
    static constexpr std::array<double, 10> kBuckets{0.005, 0.01, 0.05, 0.1, 0.5, 1, 2, 5, 10, 30};
    mutable std::mutex latency_mutex_;
    std::array<uint64_t, kBuckets.size()> bucket_counts_{};
    uint64_t latency_count_ = 0;
    double latency_sum_ = 0;
};

} // namespace ddsimp::server
