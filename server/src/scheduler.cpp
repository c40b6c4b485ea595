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

uint64_t Scheduler::submit(uint64_t client, Work work) {
    if (workers_.empty()) {
        boost::asio::post(inline_executor_, std::move(work));
        return next_ticket_++;
    }
    uint64_t ticket = 0;
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return 0;
        std::deque<Job>& queue = queues_[client];
        if (queue.size() >= max_queued_) return 0; // the queue is not empty: it stays
        ticket = next_ticket_++;
        queue.push_back({ticket, std::move(work)});
        ++normal_queued_;
        // More jobs waiting than free workers: the background work gives its worker up.
        if (background_running_ && normal_queued_ > size_t(idle_)) yield_ = true;
    }
    wake_.notify_one();
    return ticket;
}

bool Scheduler::withdraw(uint64_t ticket) {
    std::lock_guard lock(mutex_);
    for (auto q = queues_.begin(); q != queues_.end(); ++q)
        for (auto j = q->second.begin(); j != q->second.end(); ++j)
            if (j->ticket == ticket) {
                q->second.erase(j);
                if (q->second.empty()) queues_.erase(q);
                --normal_queued_;
                return true;
            }
    return false;
}

void Scheduler::submit_background(Background work) {
    if (workers_.empty()) return;
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return;
        background_.push_back(std::move(work));
    }
    wake_.notify_one();
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

size_t Scheduler::background() const {
    std::lock_guard lock(mutex_);
    return background_.size() + (background_running_ ? 1 : 0);
}

void Scheduler::stop() {
    {
        std::lock_guard lock(mutex_);
        if (stopping_ && workers_.empty()) return;
        stopping_ = true;
        yield_ = true;
        queues_.clear();
        background_.clear();
        normal_queued_ = 0;
    }
    wake_.notify_all();
    for (std::thread& t : workers_)
        if (t.joinable()) t.join();
    workers_.clear();
}

bool Scheduler::next_locked(Work& job, Background& background) {
    if (!queues_.empty()) {
        auto it = queues_.upper_bound(last_client_);
        if (it == queues_.end()) it = queues_.begin();
        last_client_ = it->first;
        job = std::move(it->second.front().work);
        it->second.pop_front();
        if (it->second.empty()) queues_.erase(it);
        --normal_queued_;
        return true;
    }
    if (!background_.empty() && !background_running_) {
        background = std::move(background_.front());
        background_.pop_front();
        background_running_ = true;
        yield_ = false;
        return true;
    }
    return false;
}

void Scheduler::work() {
    for (;;) {
        Work job;
        Background background;
        {
            std::unique_lock lock(mutex_);
            ++idle_;
            wake_.wait(lock, [&] { return stopping_ || next_locked(job, background); });
            --idle_;
            if (stopping_) return;
        }
        if (job) {
            job();
            continue;
        }
        const bool done = background(yield_);
        {
            std::lock_guard lock(mutex_);
            background_running_ = false;
            if (!done && !stopping_) background_.push_front(std::move(background));
        }
        wake_.notify_one();
    }
}

} // namespace ddsimp::server
