// The state every connection shares: stored surfaces, the result cache, sessions, metrics and
// the compute pool. Its methods run on the network thread (one io_context thread); heavy work
// (validation, storing, simplification, encoding) is posted to the pool and its results posted
// back, so the shared state needs no locks beyond those of the store and cache.
#pragma once

#include "config.h"
#include "connection.h"
#include "metrics.h"
#include "reductions.h"
#include "sessions.h"
#include "surface_store.h"

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/thread_pool.hpp>

#include <deque>
#include <map>
#include <memory>
#include <optional>

namespace ddsimp::server {

class Service {
public:
    Service(boost::asio::io_context& io, const Config& config);
    ~Service();

    // A new client; refused (with an error, then closed) above the client limit.
    void accept(std::shared_ptr<Transport> transport);
    void connection_closed(Connection& c);
    size_t open_connections() const { return connections_.size(); }

    const Config& config() const { return config_; }
    Metrics& metrics() { return metrics_; }
    boost::asio::io_context& io() { return io_; }
    std::string metrics_text();
    std::string server_name() const { return "ddsimp-server 0.1.0"; }

    // The budget for uploads in progress, all clients together (--max-upload-mb): false if
    // `bytes` more do not fit.
    bool reserve_upload_bytes(uint64_t bytes);
    void release_upload_bytes(uint64_t bytes);

    // Handlers, called by Connection once the client is authenticated. upload() releases the
    // bytes' share of the upload budget once they are stored or refused.
    void upload(std::shared_ptr<Connection> c, v1::UploadBegin begin, std::string bytes);
    void request(std::shared_ptr<Connection> c, const v1::Request& request);
    void list_surfaces(Connection& c);
    void join(std::shared_ptr<Connection> c, const v1::JoinSession& join);
    void leave(Connection& c, const std::string& name);
    void set_state(std::shared_ptr<Connection> c, const v1::SetSessionState& change);

    // Closes every connection (SIGTERM) and waits for running computations.
    void stop();

private:
    void broadcast(const Session& s, const std::string& cause, uint64_t changed_by);
    // Computes the session's current level and sends it to `targets` (ids), replacing any
    // unsent older mesh of the session in their queues.
    void send_session_mesh(const Session& s, std::vector<uint64_t> targets);
    std::shared_ptr<Connection> find(uint64_t id);
    void load_sample();
    // Where heavy work runs: the compute pool, or the network thread itself when
    // config.threads is 0 (one thread, a deterministic order: the fuzz targets drive it so).
    boost::asio::any_io_executor compute();

    boost::asio::io_context& io_;
    Config config_;
    Metrics metrics_;
    SurfaceStore store_;
    ResultCache cache_;
    Reductions reductions_;
    Sessions sessions_;
    std::optional<boost::asio::thread_pool> pool_; // none when config.threads is 0
    std::map<uint64_t, std::weak_ptr<Connection>> connections_;
    // Result key -> what it computes, for resuming by key; the oldest are forgotten first.
    void remember_result(const std::string& key, const ReductionParams& params);
    std::map<std::string, ReductionParams> known_results_;
    std::deque<std::string> known_order_;
    uint64_t next_id_ = 1;
    uint64_t upload_bytes_ = 0; // reserved by uploads in progress (network thread)
    bool stopping_ = false;
};

} // namespace ddsimp::server
