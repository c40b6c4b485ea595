// The compute pool. Jobs wait in one queue per client and are taken a client at a time in turn,
// so one client's burst delays another client's job by at most the jobs already running. A
// client may have at most a fixed number of jobs waiting; a job withdrawn before it starts frees
// its place at once. Background work (speculation) runs one at a time and only when no client's
// job waits, and yields its worker as soon as one does. Cancelling a started job is the job's own
// business (see Computations).
#pragma once

#include <boost/asio/any_io_executor.hpp>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace ddsimp::server {

class Scheduler {
public:
    using Work = std::function<void()>;
    // Background work returns false when it stopped early because `yield` was set (a client's
    // job waited for its worker); it is run again, from the start, once the pool is idle.
    using Background = std::function<bool(const std::atomic<bool>& yield)>;

    // `threads` workers; with 0, jobs are posted to `inline_executor` in submission order (one
    // thread, a deterministic order: the fuzz targets drive the server so), and background work
    // is not run.
    Scheduler(int threads, boost::asio::any_io_executor inline_executor, size_t max_queued);
    ~Scheduler();

    // Queues `work` for `client`: a ticket for withdraw(), or 0 (nothing queued) if the client
    // has max_queued jobs waiting already.
    uint64_t submit(uint64_t client, Work work);
    // Takes the job back if it has not started: true if it will never run.
    bool withdraw(uint64_t ticket);
    void submit_background(Background work);
    // Jobs waiting (not running) for `client`.
    size_t queued(uint64_t client) const;
    // Client jobs waiting, all clients.
    size_t queued() const;
    // Background work waiting or running.
    size_t background() const;
    int threads() const { return int(workers_.size()); }

    // Workers finish the job they run (background work is asked to yield); waiting jobs are
    // dropped.
    void stop();

private:
    struct Job {
        uint64_t ticket = 0;
        Work work;
    };
    void work();
    // The next client job (round robin) or, when none waits and none runs, background work.
    bool next_locked(Work& job, Background& background);

    boost::asio::any_io_executor inline_executor_;
    const size_t max_queued_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::map<uint64_t, std::deque<Job>> queues_; // clients with jobs waiting
    uint64_t last_client_ = 0;                   // the client served last (round robin)
    uint64_t next_ticket_ = 1;
    size_t normal_queued_ = 0;
    int idle_ = 0; // workers waiting for a job
    std::deque<Background> background_;
    bool background_running_ = false;
    std::atomic<bool> yield_{false}; // set for the running background work
    bool stopping_ = false;
    std::vector<std::thread> workers_;
};

} // namespace ddsimp::server
