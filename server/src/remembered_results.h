// The result keys the server remembers after their request, so that a client can resume a
// result by its key (Request.result) and a request can find a preview among the records of the
// same surface. A key is remembered once a level has named it; the memory the keys take is
// bounded (--max-remembered-kb), the least recently used key going first. Network thread only.
#pragma once

#include "reductions.h"

#include <cstddef>
#include <functional>
#include <list>
#include <map>
#include <set>
#include <string>

namespace ddsimp::server {

class RememberedResults {
public:
    explicit RememberedResults(size_t max_bytes) : max_bytes_(max_bytes) {}

    // Remembers (or refreshes) `key`, forgetting the least recently used keys over the bound.
    void remember(const std::string& key, const ReductionParams& params);
    // What `key` computes, or null.
    const ReductionParams* find(const std::string& key);
    // Every remembered key of `surface`.
    void
    for_surface(const std::string& surface,
                const std::function<void(const std::string&, const ReductionParams&)>& f) const;

    // Forgets every key of a deleted surface.
    void forget_surface(const std::string& surface);

    size_t size() const { return entries_.size(); }
    size_t bytes() const { return bytes_; }

private:
    struct Entry {
        ReductionParams params;
        size_t bytes = 0;
        std::list<std::string>::iterator use;
    };
    static size_t bytes_of(const std::string& key, const ReductionParams& params);
    void forget_oldest();
    void forget(std::map<std::string, Entry>::iterator it);

    const size_t max_bytes_;
    size_t bytes_ = 0;
    std::map<std::string, Entry> entries_;
    std::list<std::string> uses_; // most recent first
    std::map<std::string, std::set<std::string>> by_surface_;
};

} // namespace ddsimp::server
