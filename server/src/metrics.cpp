#include "metrics.h"

#include <sstream>

namespace ddsimp::server {

void Metrics::observe_job_seconds(double seconds) {
    std::lock_guard lock(latency_mutex_);
    for (size_t i = 0; i < kBuckets.size(); ++i)
        if (seconds <= kBuckets[i]) ++bucket_counts_[i];
    ++latency_count_;
    latency_sum_ += seconds;
}

std::string Metrics::render(const Snapshot& s) const {
    std::ostringstream out;
    const auto metric = [&](const char* name, const char* type, const char* help, auto value) {
        out << "# HELP ddsimp_" << name << ' ' << help << "\n# TYPE ddsimp_" << name << ' ' << type
            << "\nddsimp_" << name << ' ' << value << '\n';
    };
    metric("connections", "gauge", "Open protocol clients (native and WebSocket).",
           connections.load());
    metric("connections_total", "counter", "Connections accepted.", connections_total.load());
    metric("sockets", "gauge",
           "Connections holding a place: native, HTTP, WebSocket, TLS handshakes in progress.",
           sockets.load());
    metric("sockets_limit", "gauge", "The most connections at once (--max-clients, as fitted).",
           sockets_limit.load());
    metric("sockets_per_address_limit", "gauge", "The most connections at once from one address.",
           sockets_per_address_limit.load());
    metric("connections_refused_total", "counter", "Connections refused over a limit.",
           connections_refused.load());
    metric("accept_errors_total", "counter", "Accepts that failed (out of descriptors, memory).",
           accept_errors.load());
    metric("connections_dropped_total", "counter",
           "Clients dropped because they could not keep up.", connections_dropped.load());
    metric("bad_frames_total", "counter", "Malformed or oversized frames received.",
           bad_frames.load());
    metric("sessions", "gauge", "Open sessions.", s.sessions);
    metric("surfaces", "gauge", "Stored surfaces.", s.surfaces);
    metric("surfaces_resident", "gauge", "Stored surfaces held in memory (the sample aside).",
           s.surfaces_resident);
    metric("surface_bytes", "gauge", "Bytes of the stored surfaces held in memory.",
           s.surface_bytes);
    metric("surface_limit_bytes", "gauge", "The most they may take (--surfaces-mb).",
           s.surface_limit_bytes);
    metric("surface_pinned_bytes", "gauge", "Bytes of the sample, kept in memory outside it.",
           s.surface_pinned_bytes);
    metric("surface_loads_total", "counter", "Stored surfaces read from the data directory.",
           s.surface_loads);
    metric("surface_evictions_total", "counter",
           "Stored surfaces dropped from memory to stay within the bound.", s.surface_evictions);
    metric("surfaces_deleted_total", "counter",
           "Stored surfaces deleted by their clients (files, cached results and keys).",
           s.surfaces_deleted);
    metric("uploads_total", "counter", "Surfaces uploaded.", uploads.load());
    metric("requests_total", "counter", "Reduction requests received.", requests.load());
    metric("request_errors_total", "counter", "Requests ended by an error.", request_errors.load());
    metric("levels_sent_total", "counter", "Levels (or refinements) sent.", levels_sent.load());
    metric("reductions_running", "gauge", "Records being computed now.", reductions_running.load());
    metric("reductions_cancelled_total", "counter",
           "Computations cancelled because no request or session waited for them any more.",
           reductions_cancelled.load());
    metric("reductions_yielded_total", "counter",
           "Computations stopped to give their worker to another client's job or to a client "
           "(speculation); each runs again later.",
           reductions_yielded.load());
    metric("previews_sent_total", "counter", "Previews sent before an exact level.",
           previews_sent.load());
    metric("speculative_records_total", "counter",
           "Records computed while idle, at alpha 0, 0.5 and 1 of new surfaces (--speculate).",
           speculative_records.load());
    metric("speculations_pending", "gauge", "Speculative computations waiting or running.",
           s.speculations_pending);
    metric("request_jobs", "gauge",
           "Request jobs queued or running, cancelled ones included until they stop.",
           request_jobs.load());
    metric("request_job_bytes", "gauge", "Bytes the request jobs hold.", request_job_bytes.load());
    metric("session_views_skipped_total", "counter",
           "Session views not computed because a newer view came first.",
           session_views_skipped.load());
    metric("remembered_results", "gauge", "Result keys remembered for resuming.",
           remembered_results.load());
    metric("remembered_bytes", "gauge", "Bytes of the remembered result keys.",
           remembered_bytes.load());
    metric("memory_bound_bytes", "gauge",
           "The most memory clients can make the server hold beyond its size at rest, from its "
           "flags (docs/operations.md#memory).",
           memory_bound.load());
    metric("computations_total", "counter", "Records and levels computed (cache misses that ran).",
           s.computations);
    metric("cache_hits_total", "counter", "Result cache hits.", s.cache_hits);
    metric("cache_misses_total", "counter", "Result cache misses.", s.cache_misses);
    metric("cache_evictions_total", "counter", "Results evicted to stay within the bound.",
           s.evictions);
    metric("cache_bytes", "gauge", "Bytes held by cached results.", s.cache_bytes);
    metric("cache_entries", "gauge", "Cached results.", s.cache_entries);
    metric("queue_bytes", "gauge", "Bytes waiting to be sent, all clients.", queue_bytes.load());
    metric("client_queue_bytes_max", "gauge", "The most bytes one client ever had waiting.",
           queue_bytes_peak.load());
    metric("upload_bytes", "gauge", "Bytes of uploads received but not yet stored, all clients.",
           upload_bytes.load());
    metric("download_bytes", "gauge",
           "Bytes of HTTP downloads being built and sent: level.glb files (at an estimate while "
           "built) and web files, all clients.",
           s.download_bytes);
    metric("download_limit_bytes", "gauge", "The most they may take (--max-download-mb).",
           s.download_limit_bytes);
    metric("downloads_refused_total", "counter",
           "HTTP downloads refused because they would pass --max-download-mb.",
           downloads_refused.load());
    metric("quota_refusals_total", "counter",
           "Uploads refused by a token's or session's quota, or the budget of all uploads.",
           quota_refusals.load());
    metric("sent_bytes_total", "counter", "Bytes sent.", bytes_sent.load());
    metric("received_bytes_total", "counter", "Bytes received.", bytes_received.load());

    std::lock_guard lock(latency_mutex_);
    out << "# HELP ddsimp_job_latency_seconds From a request's arrival to its levels being ready.\n"
           "# TYPE ddsimp_job_latency_seconds histogram\n";
    for (size_t i = 0; i < kBuckets.size(); ++i)
        out << "ddsimp_job_latency_seconds_bucket{le=\"" << kBuckets[i] << "\"} "
            << bucket_counts_[i] << '\n';
    out << "ddsimp_job_latency_seconds_bucket{le=\"+Inf\"} " << latency_count_ << '\n'
        << "ddsimp_job_latency_seconds_sum " << latency_sum_ << '\n'
        << "ddsimp_job_latency_seconds_count " << latency_count_ << '\n';
    return out.str();
}

} // namespace ddsimp::server
