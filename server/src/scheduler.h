// The compute pool. Jobs wait in one queue per client and are taken a client at a time in turn,
// so one client's burst delays another client's job by at most the jobs already running;
// background jobs (speculation) run only when no client's job waits. A client may have at most
// a fixed number of jobs waiting. Cancelling is the job's own business (see Computations).
#pragma once

#include <boost/asio/any_io_executor.hpp>

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

namespace ddsimp::server {

class Scheduler {
public:
    using Work = std::function<void()>;
    enum class Priority { Normal, Background };

    // `threads` workers; with 0, jobs are posted to `inline_executor` in submission order (one
    // thread, a deterministic order: the fuzz targets drive the server so).
    Scheduler(int threads, boost::asio::any_io_executor inline_executor, size_t max_queued);
    ~Scheduler();

    // Queues `work` for `client`; false (nothing queued) if the client has max_queued jobs
    // waiting already. Background jobs are never refused.
    bool submit(uint64_t client, Work work, Priority priority = Priority::Normal);
    // Jobs waiting (not running) for `client`.
    size_t queued(uint64_t client) const;
    // Normal jobs waiting, all clients.
    size_t queued() const;
    int threads() const { return int(workers_.size()); }

    // Workers finish the job they run; waiting jobs are dropped.
    void stop();

private:
    void work();
    bool next_locked(Work& out);

    boost::asio::any_io_executor inline_executor_;
    const size_t max_queued_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::map<uint64_t, std::deque<Work>> queues_; // clients with jobs waiting
    uint64_t last_client_ = 0;                    // the client served last (round robin)
    size_t normal_queued_ = 0;
    std::deque<Work> background_;
    bool stopping_ = false;
    std::vector<std::thread> workers_;
};

} // namespace ddsimp::server
