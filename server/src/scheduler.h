// The compute pool. Jobs wait in one queue per client and are taken a client at a time in turn,
// so one client's burst delays another client's job by at most the jobs already running; and
// when a client with nothing running has to wait while another runs two jobs or more, the
// newest of those yields its worker (it runs again, first in its client's queue). A client may
// have at most a fixed number of jobs waiting; a job withdrawn before it starts frees its place
// at once. Background work (speculation) runs one at a time and only when no client's job waits,
// and yields its worker as soon as one does. Cancelling a started job is the job's own business
// (see Computations).
#pragma once

#include <boost/asio/any_io_executor.hpp>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace ddsimp::server {

class Scheduler {
public:
    using Work = std::function<void()>;
    // Work that can give its worker up: it returns false when it stopped early because `yield`
    // was set, and is then run again, from the start.
    using Resumable = std::function<bool(const std::atomic<bool>& yield)>;

    // `threads` workers; with 0, jobs are posted to `inline_executor` in submission order (one
    // thread, a deterministic order: the fuzz targets drive the server so), never yield, and
    // background work is not run.
    Scheduler(int threads, boost::asio::any_io_executor inline_executor, size_t max_queued);
    ~Scheduler();

    // Queues `work` for `client`: a ticket for withdraw(), or 0 (nothing queued) if the client
    // has max_queued jobs waiting already.
    uint64_t submit(uint64_t client, Work work);
    uint64_t submit(uint64_t client, Resumable work);
    // Takes the job back if it is waiting: true if it will not run (again).
    bool withdraw(uint64_t ticket);
    void submit_background(Resumable work);
    // Jobs waiting (not running) for `client`.
    size_t queued(uint64_t client) const;
    // Client jobs waiting, all clients.
    size_t queued() const;
    // Background work waiting or running.
    size_t background() const;
    int threads() const { return int(workers_.size()); }

    // Workers finish the job they run (resumable work is asked to yield); waiting jobs are
    // dropped.
    void stop();

private:
    struct Job {
        uint64_t ticket = 0;
        uint64_t client = 0;
        Resumable work;
        bool resumable = false;
        bool background = false;
    };
    // What a worker runs now.
    struct Slot {
        std::atomic<bool> yield{false};
        bool busy = false;
        Job job; // its ticket, client and kind (the work itself is moved out while it runs)
        uint64_t started = 0; // order of starting, to find the newest job of a client
    };
    uint64_t queue_locked(Job job);
    void work(Slot& me);
    // The next client job (round robin) or, when none waits and none runs, background work.
    bool next_locked(Job& job);
    // A client job waits for a worker: background work yields; or, if `client` runs nothing
    // and another client runs two jobs or more, the newest of those yields.
    void make_room_locked(uint64_t client);

    boost::asio::any_io_executor inline_executor_;
    const size_t max_queued_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::map<uint64_t, std::deque<Job>> queues_; // clients with jobs waiting
    uint64_t last_client_ = 0;                   // the client served last (round robin)
    uint64_t next_ticket_ = 1;
    uint64_t starts_ = 0;
    size_t normal_queued_ = 0;
    size_t idle_ = 0; // workers waiting for a job
    std::deque<Job> background_;
    bool background_running_ = false;
    bool stopping_ = false;
    std::vector<std::unique_ptr<Slot>> slots_;
    std::vector<std::thread> workers_;
};

} // namespace ddsimp::server
