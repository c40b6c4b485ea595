#include "scheduler.h"

#include <boost/asio/post.hpp>

namespace ddsimp::server {

Scheduler::Scheduler(int threads, boost::asio::any_io_executor inline_executor, size_t max_queued)
    : inline_executor_(std::move(inline_executor)), max_queued_(max_queued) {
    for (int i = 0; i < threads; ++i) slots_.push_back(std::make_unique<Slot>());
    for (int i = 0; i < threads; ++i)
        workers_.emplace_back([this, slot = slots_[size_t(i)].get()] { work(*slot); });
}

Scheduler::~Scheduler() {
    stop();
}

uint64_t Scheduler::submit(uint64_t client, Work work) {
    if (workers_.empty()) {
        boost::asio::post(inline_executor_, std::move(work));
        return next_ticket_++;
    }
    Job job;
    job.client = client;
    job.work = [work = std::move(work)](const std::atomic<bool>&) {
        work();
        return true;
    };
    return queue_locked(std::move(job));
}

uint64_t Scheduler::submit(uint64_t client, Resumable work) {
    if (workers_.empty()) {
        static const std::atomic<bool> never{false};
        boost::asio::post(inline_executor_, [work = std::move(work)] { work(never); });
        return next_ticket_++;
    }
    Job job;
    job.client = client;
    job.work = std::move(work);
    job.resumable = true;
    return queue_locked(std::move(job));
}

uint64_t Scheduler::queue_locked(Job job) {
    uint64_t ticket = 0;
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return 0;
        std::deque<Job>& queue = queues_[job.client];
        if (queue.size() >= max_queued_) return 0; // the queue is not empty: it stays
        ticket = job.ticket = next_ticket_++;
        const uint64_t client = job.client;
        queue.push_back(std::move(job));
        ++normal_queued_;
        if (normal_queued_ > idle_) make_room_locked(client);
    }
    wake_.notify_one();
    return ticket;
}

void Scheduler::make_room_locked(uint64_t client) {
    std::map<uint64_t, size_t> running; // client jobs per client
    Slot* background = nullptr;
    for (const auto& s : slots_) {
        if (!s->busy) continue;
        if (s->yield) return; // a worker is being freed already
        if (s->job.background)
            background = s.get();
        else
            ++running[s->job.client];
    }
    if (background) {
        background->yield = true;
        return;
    }
    if (running.count(client)) return;
    uint64_t crowded = 0;
    size_t most = 1;
    for (const auto& [c, n] : running)
        if (n > most) crowded = c, most = n;
    if (most < 2) return;
    Slot* newest = nullptr;
    for (const auto& s : slots_)
        if (s->busy && s->job.client == crowded && s->job.resumable &&
            (!newest || s->started > newest->started))
            newest = s.get();
    if (newest) newest->yield = true;
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

void Scheduler::submit_background(Resumable work) {
    if (workers_.empty()) return;
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return;
        Job job;
        job.work = std::move(work);
        job.resumable = job.background = true;
        background_.push_back(std::move(job));
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
        for (const auto& s : slots_) s->yield = true;
        queues_.clear();
        background_.clear();
        normal_queued_ = 0;
    }
    wake_.notify_all();
    for (std::thread& t : workers_)
        if (t.joinable()) t.join();
    workers_.clear();
}

bool Scheduler::next_locked(Job& job) {
    if (!queues_.empty()) {
        auto it = queues_.upper_bound(last_client_);
        if (it == queues_.end()) it = queues_.begin();
        last_client_ = it->first;
        job = std::move(it->second.front());
        it->second.pop_front();
        if (it->second.empty()) queues_.erase(it);
        --normal_queued_;
        return true;
    }
    if (!background_.empty() && !background_running_) {
        job = std::move(background_.front());
        background_.pop_front();
        background_running_ = true;
        return true;
    }
    return false;
}

void Scheduler::work(Slot& me) {
    for (;;) {
        Job job;
        {
            std::unique_lock lock(mutex_);
            ++idle_;
            wake_.wait(lock, [&] { return stopping_ || next_locked(job); });
            --idle_;
            if (stopping_) return;
            me.busy = true;
            me.yield = false;
            me.started = ++starts_;
            me.job.ticket = job.ticket;
            me.job.client = job.client;
            me.job.resumable = job.resumable;
            me.job.background = job.background;
        }
        const bool done = job.work(me.yield);
        {
            std::lock_guard lock(mutex_);
            me.busy = false;
            if (job.background) background_running_ = false;
            if (!done && !stopping_) {
                if (job.background) {
                    background_.push_front(std::move(job));
                } else {
                    queues_[job.client].push_front(std::move(job));
                    ++normal_queued_;
                }
            }
        }
        wake_.notify_all();
    }
}

} // namespace ddsimp::server
