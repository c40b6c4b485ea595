// The state every connection shares: stored surfaces, the result cache, sessions, metrics and
// the compute pool. Its methods run on the network thread (one io_context thread); heavy work
// (validation, storing, simplification, encoding) goes to the scheduler's pool and its results
// are posted back, so the shared state needs no locks beyond those of the store and cache.
// Requests and session meshes: service_requests.cpp.
#pragma once

#include "computations.h"
#include "config.h"
#include "connection.h"
#include "glb_download.h"
#include "metrics.h"
#include "quotas.h"
#include "reductions.h"
#include "remembered_results.h"
#include "scheduler.h"
#include "sessions.h"
#include "surface_store.h"
#include "tokens.h"

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/thread_pool.hpp>

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>

namespace ddsimp::server {

class Service {
public:
    Service(boost::asio::io_context& io, const Config& config);
    ~Service();

    // A new client (admitted by a listener).
    void accept(std::shared_ptr<Transport> transport);
    void connection_closed(Connection& c);
    size_t open_connections() const { return connections_.size(); }

    const Config& config() const { return config_; }
    Metrics& metrics() { return metrics_; }
    boost::asio::io_context& io() { return io_; }
    std::string metrics_text();
    std::string server_name() const { return "ddsimp-server 0.1.0"; }

    const Tokens& tokens() const { return tokens_; }
    // Uploads in progress, within the quotas of their token and session and the budget of all
    // (--max-upload-mb): nothing, or why `bytes` more do not fit; owner.over_quota: why storing
    // them would pass a quota of stored surfaces.
    std::optional<std::string> reserve_upload(UploadOwner& owner, uint64_t bytes) {
        return quotas_.reserve(owner, bytes);
    }
    void release_upload(const UploadOwner& owner, uint64_t bytes) { quotas_.release(owner, bytes); }

    // Handlers, called by Connection once the client is authenticated. upload() releases the
    // bytes' reservation once they are stored or refused.
    void upload(std::shared_ptr<Connection> c, v1::UploadBegin begin, std::string bytes,
                UploadOwner owner);
    void request(std::shared_ptr<Connection> c, const v1::Request& request);
    // The client cancelled request `request_id` (it has ended it): its computation stops unless
    // another request or session waits for it.
    void cancel_request(Connection& c, uint64_t request_id);
    void list_surfaces(Connection& c);
    // Takes back the client's upload of a surface (surface_store.h, SurfaceStore::remove).
    void delete_surface(std::shared_ptr<Connection> c, const v1::DeleteSurface& del);
    void join(std::shared_ptr<Connection> c, const v1::JoinSession& join);
    void leave(Connection& c, const std::string& name);
    void set_state(std::shared_ptr<Connection> c, const v1::SetSessionState& change);

    // What HTTP downloads (level.glb files, web files) being built and sent hold: any thread.
    const std::shared_ptr<DownloadBudget>& downloads() const { return downloads_; }
    // GET /surfaces/ID/level.glb (glb_download.cpp): `done` is called on the network thread.
    void download_glb(const GlbDownload& download, std::function<void(GlbAnswer)> done);

    // Closes every connection (SIGTERM) and waits for running computations.
    void stop();

private:
    void broadcast(const Session& s, const std::string& cause, uint64_t changed_by);
    // Computes the session's current level and sends it to `targets` (ids), replacing any
    // unsent older mesh of the session in their queues.
    void send_session_mesh(const Session& s, std::vector<uint64_t> targets);
    std::shared_ptr<Connection> find(uint64_t id);
    void load_sample();
    // Queues heavy work of `client` on the scheduler's pool (or the network thread itself when
    // config.threads is 0: one thread, a deterministic order, as the fuzz targets drive it);
    // false if the client has too many jobs waiting.
    // Returns the scheduler's ticket (0: refused).
    uint64_t compute(uint64_t client, Scheduler::Work work);
    uint64_t compute(uint64_t client, Scheduler::Resumable work);
    // While the pool is idle, the records of the default options at alpha 0, 0.5 and 1 of a new
    // surface (speculation.cpp).
    void speculate(const std::string& surface);
    // Where previews are cut: their own thread, so that they never wait behind computations.
    boost::asio::any_io_executor preview_executor();

    // requests (service_requests.cpp)
    struct RunningRequest {
        std::string key;
        std::string surface;
        CancelFlag ended;       // set when the request ends before its job (the job then stops)
        uint64_t ticket = 0;    // the job's, to take it back before it starts
        uint64_t job_bytes = 0; // what the job holds (Metrics::request_job_bytes)
    };
    struct RequestJob;
    struct PreparedLevel;
    // On the pool: the request's record (as deep as its coarsest level), its levels. False
    // when it gave its worker up (`yield`) before the record was done: it runs again later.
    bool run_request(const std::shared_ptr<RequestJob>& job, const std::atomic<bool>& yield);
    // Makes the levels `indices` one at a time, handing each to `emit`.
    void prepare_levels(const RequestJob& job, const ComputedRecord& rec,
                        const std::vector<size_t>& indices, bool computed,
                        const std::function<void(PreparedLevel)>& emit);
    // Queues `levels` on the network thread; `last`: the request is complete after them (or
    // ended by `error`).
    void deliver(const std::shared_ptr<RequestJob>& job, std::vector<PreparedLevel> levels,
                 v1::Error error, bool last);
    // Cuts a preview of the request's finest level on the preview thread and queues it, unless
    // an exact level went out first.
    void send_preview(const std::shared_ptr<RequestJob>& job);
    // Ends the bookkeeping of a running request; its computation stops if nobody else waits, and
    // its job, if it has not started, is taken back.
    void forget_request(uint64_t client, uint64_t request_id);
    // A request's job has stopped (or was taken back): its place and bytes are free.
    void end_request_job(Connection* c, uint64_t job_bytes); // c: null once closed
    // A request with `supersede` set ends the client's older requests for the same surface.
    void supersede(Connection& c, uint64_t request_id, const std::string& surface);

    boost::asio::io_context& io_;
    Config config_;
    Tokens tokens_;
    Metrics metrics_;
    SurfaceStore store_;
    Quotas quotas_;
    ResultCache cache_;
    Reductions reductions_;
    Sessions sessions_;
    Scheduler scheduler_;
    std::optional<boost::asio::thread_pool> preview_pool_; // none when config.threads is 0
    Computations computations_;
    std::map<std::pair<uint64_t, uint64_t>, RunningRequest> running_; // (client, request id)
    std::map<std::string, std::string> session_keys_; // session scope -> the key it waits for
    std::map<uint64_t, std::weak_ptr<Connection>> connections_;
    void remember_result(const std::string& key, const ReductionParams& params);
    RememberedResults known_results_;
    // Per session scope, the newest view's version: a job for an older view is skipped.
    std::map<std::string, std::shared_ptr<std::atomic<uint64_t>>> session_versions_;
    uint64_t next_id_ = 1;
    // All downloads take turns with the clients as this one client (connections count from 1).
    static constexpr uint64_t kDownloadsClient = ~uint64_t(0);
    uint64_t next_download_ = 1;
    // The .glb files being built and sent (--max-download-mb); shared with their holds, which
    // may outlive the Service in handlers destroyed with the io_context.
    std::shared_ptr<DownloadBudget> downloads_;
    bool stopping_ = false;
};

} // namespace ddsimp::server
