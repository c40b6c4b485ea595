// Computed results, content-addressed and bounded in memory: progressive records (one per
// surface, α and options) and the encoded levels cut from them. Least recently used entries go
// first. A computation asked for while it runs is not started again: the second caller waits
// for the first's result. Thread-safe.
#pragma once

#include <cstddef>
#include <functional>
#include <future>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace ddsimp::server {

class ResultCache {
public:
    struct Stats {
        size_t hits = 0, misses = 0, computations = 0, evictions = 0, bytes = 0, entries = 0;
    };
    explicit ResultCache(size_t max_bytes) : max_bytes_(max_bytes) {}

    // The value under `key`, computing it with `compute` (which returns the value and its size
    // in bytes) if it is neither cached nor being computed. `computed` tells whether this call
    // ran the computation. Exceptions from `compute` reach every waiting caller and are not
    // cached.
    template <class T>
    std::shared_ptr<const T>
    get(const std::string& key,
        const std::function<std::pair<std::shared_ptr<const T>, size_t>()>& compute,
        bool* computed = nullptr) {
        auto value = get_erased(
            key,
            [&]() -> std::pair<std::shared_ptr<const void>, size_t> {
                auto [v, bytes] = compute();
                return {std::move(v), bytes};
            },
            computed);
        return std::static_pointer_cast<const T>(value);
    }

    // The value under `key` if it is cached (not counted as a hit or miss); null otherwise.
    template <class T> std::shared_ptr<const T> find(const std::string& key) {
        return std::static_pointer_cast<const T>(find_erased(key));
    }

    // Drops every cached entry whose key starts with `prefix` (a value in use stays with its
    // holders); returns how many.
    size_t erase_prefix(const std::string& prefix);

    Stats stats() const;

private:
    using Erased = std::shared_ptr<const void>;
    Erased get_erased(const std::string& key,
                      const std::function<std::pair<Erased, size_t>()>& compute, bool* computed);
    Erased find_erased(const std::string& key);
    void evict_locked();

    struct Entry {
        Erased value;
        size_t bytes = 0;
        std::list<std::string>::iterator use;
    };
    const size_t max_bytes_;
    mutable std::mutex mutex_;
    std::map<std::string, Entry> entries_;
    std::list<std::string> uses_; // most recent first
    std::map<std::string, std::shared_future<Erased>> running_;
    Stats stats_;
};

} // namespace ddsimp::server
