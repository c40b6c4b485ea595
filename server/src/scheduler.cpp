#include "scheduler.h"

#include <boost/asio/post.hpp>

namespace ddsimp::server {

Scheduler::Scheduler(int threads, boost::asio::any_io_executor inline_executor, size_t max_queued)
    : inline_executor_(std::move(inline_executor)), max_queued_(max_queued) {
    for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

Scheduler::~Scheduler() {
    stop();
}

bool Scheduler::submit(uint64_t client, Work work, Priority priority) {
    if (workers_.empty()) {
        boost::asio::post(inline_executor_, std::move(work));
        return true;
    }
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return false;
        if (priority == Priority::Background) {
            background_.push_back(std::move(work));
        } else {
            std::deque<Work>& queue = queues_[client];
            if (queue.size() >= max_queued_) {
                if (queue.empty()) queues_.erase(client);
                return false;
            }
            queue.push_back(std::move(work));
            ++normal_queued_;
        }
    }
    wake_.notify_one();
    return true;
}

size_t Scheduler::queued(uint64_t client) const {
    std::lock_guard lock(mutex_);
    auto it = queues_.find(client);
    return it == queues_.end() ? 0 : it->second.size();
}

size_t Scheduler::queued() const {
    std::lock_guard lock(mutex_);
    return normal_queued_;
}

void Scheduler::stop() {
    {
        std::lock_guard lock(mutex_);
        if (stopping_ && workers_.empty()) return;
        stopping_ = true;
        queues_.clear();
        background_.clear();
        normal_queued_ = 0;
    }
    wake_.notify_all();
    for (std::thread& t : workers_)
        if (t.joinable()) t.join();
    workers_.clear();
}

// The next client after the one served last (in id order, wrapping), else a background job.
bool Scheduler::next_locked(Work& out) {
    if (!queues_.empty()) {
        auto it = queues_.upper_bound(last_client_);
        if (it == queues_.end()) it = queues_.begin();
        last_client_ = it->first;
        out = std::move(it->second.front());
        it->second.pop_front();
        if (it->second.empty()) queues_.erase(it);
        --normal_queued_;
        return true;
    }
    if (!background_.empty()) {
        out = std::move(background_.front());
        background_.pop_front();
        return true;
    }
    return false;
}

void Scheduler::work() {
    for (;;) {
        Work job;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stopping_ || !queues_.empty() || !background_.empty(); });
            if (stopping_) return;
            next_locked(job);
        }
        job();
    }
}

} // namespace ddsimp::server
