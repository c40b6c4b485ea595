#include "computations.h"

namespace ddsimp::server {

CancelFlag Computations::wait(const std::string& key, const std::string& waiter) {
    Entry& e = entries_[key];
    if (!e.cancelled || e.cancelled->load())
        e.cancelled = std::make_shared<std::atomic<bool>>(false);
    e.waiters.insert(waiter);
    return e.cancelled;
}

bool Computations::leave(const std::string& key, const std::string& waiter) {
    auto it = entries_.find(key);
    if (it == entries_.end() || it->second.waiters.erase(waiter) == 0) return false;
    if (!it->second.waiters.empty()) return false;
    const bool was_running = !it->second.cancelled->exchange(true);
    entries_.erase(it);
    return was_running;
}

size_t Computations::waiters(const std::string& key) const {
    auto it = entries_.find(key);
    return it == entries_.end() ? 0 : it->second.waiters.size();
}

} // namespace ddsimp::server
