#include "result_cache.h"

namespace ddsimp::server {

ResultCache::Erased
ResultCache::get_erased(const std::string& key,
                        const std::function<std::pair<Erased, size_t>()>& compute, bool* computed) {
    if (computed) *computed = false;
    std::unique_lock lock(mutex_);
    if (auto it = entries_.find(key); it != entries_.end()) {
        ++stats_.hits;
        uses_.splice(uses_.begin(), uses_, it->second.use);
        return it->second.value;
    }
    ++stats_.misses;
    if (auto it = running_.find(key); it != running_.end()) {
        std::shared_future<Erased> running = it->second;
        lock.unlock();
        return running.get(); // rethrows the computation's exception
    }
    std::promise<Erased> promise;
    running_.emplace(key, promise.get_future().share());
    ++stats_.computations;
    lock.unlock();

    if (computed) *computed = true;
    std::pair<Erased, size_t> result;
    try {
        result = compute();
    } catch (...) {
        promise.set_exception(std::current_exception());
        lock.lock();
        running_.erase(key);
        throw;
    }
    promise.set_value(result.first);
    lock.lock();
    running_.erase(key);
    if (result.second <= max_bytes_) {
        uses_.push_front(key);
        entries_[key] = Entry{result.first, result.second, uses_.begin()};
        stats_.bytes += result.second;
        evict_locked();
    }
    return result.first;
}

ResultCache::Erased ResultCache::find_erased(const std::string& key) {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(key);
    if (it == entries_.end()) return nullptr;
    uses_.splice(uses_.begin(), uses_, it->second.use);
    return it->second.value;
}

void ResultCache::evict_locked() {
    while (stats_.bytes > max_bytes_ && !uses_.empty()) {
        auto it = entries_.find(uses_.back());
        stats_.bytes -= it->second.bytes;
        entries_.erase(it);
        uses_.pop_back();
        ++stats_.evictions;
    }
}

size_t ResultCache::erase_prefix(const std::string& prefix) {
    std::lock_guard lock(mutex_);
    size_t n = 0;
    for (auto it = entries_.lower_bound(prefix);
         it != entries_.end() && it->first.compare(0, prefix.size(), prefix) == 0; ++n) {
        stats_.bytes -= it->second.bytes;
        uses_.erase(it->second.use);
        it = entries_.erase(it);
    }
    return n;
}

ResultCache::Stats ResultCache::stats() const {
    std::lock_guard lock(mutex_);
    Stats s = stats_;
    s.entries = entries_.size();
    return s;
}

} // namespace ddsimp::server
