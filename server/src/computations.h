// Who waits for which record computation (requests and session views), and the flag that stops a
// computation nobody waits for any more: a newer request that supersedes an older one, a cancel,
// a closed connection or a session's newer view takes its waiter away, and the engine (which
// checks the flag through its progress callback) stops within a few milliseconds. A computation
// two clients wait for goes on while either still waits. Network thread only; the flags are read
// by the compute pool.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <set>
#include <string>

namespace ddsimp::server {

using CancelFlag = std::shared_ptr<std::atomic<bool>>;

class Computations {
public:
    // Registers `waiter` for the computation of `key` and returns the flag that computation
    // checks (a fresh one if the last computation of `key` was cancelled).
    CancelFlag wait(const std::string& key, const std::string& waiter);
    // `waiter` no longer needs `key`. True if that cancelled the computation (nobody else waits).
    bool leave(const std::string& key, const std::string& waiter);
    // Waiters of `key` (for tests of the bookkeeping and for logs).
    size_t waiters(const std::string& key) const;

    static std::string request_waiter(uint64_t client, uint64_t request_id) {
        return "request/" + std::to_string(client) + "/" + std::to_string(request_id);
    }
    static std::string session_waiter(const std::string& scope) { return "session/" + scope; }

private:
    struct Entry {
        CancelFlag cancelled;
        std::set<std::string> waiters;
    };
    std::map<std::string, Entry> entries_;
};

} // namespace ddsimp::server
