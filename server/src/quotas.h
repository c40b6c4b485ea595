// What one token and one session may hold: stored surfaces (count and bytes) and uploads in
// progress (bytes), each within the configured quota, and all uploads in progress together within
// --max-upload-mb. An upload is charged to its client's token (none on a server without tokens)
// and to the session it goes into (none for a public upload) from its UploadBegin until it is
// stored, refused or expired. Network thread only.
#pragma once

#include "config.h"
#include "metrics.h"
#include "surface_store.h"

#include <cstdint>
#include <map>
#include <optional>
#include <string>

namespace ddsimp::server {

struct UploadOwner {
    std::string token;         // the token's name; empty: none
    std::string session;       // the session's name, for messages; empty: a public upload
    std::string session_scope; // its scope
};

class Quotas {
public:
    Quotas(const Config& config, const SurfaceStore& store, Metrics& metrics);

    // Reserves `bytes` of uploads in progress for `owner`: nothing, or why not (for the client).
    std::optional<std::string> reserve(const UploadOwner& owner, uint64_t bytes);
    void release(const UploadOwner& owner, uint64_t bytes);

    struct InProgress {
        size_t uploads = 0;
        uint64_t bytes = 0;
    };

private:
    // Why one owner (`who`: "your token", "session \"S\"") may not take `bytes` more.
    std::optional<std::string> over(const std::string& who, const SurfaceStore::Usage& stored,
                                    const InProgress& running, uint64_t bytes) const;

    const Config& config_;
    const SurfaceStore& store_;
    Metrics& metrics_;
    uint64_t reserved_ = 0;                        // all uploads in progress
    std::map<std::string, InProgress> by_token_;   // token name -> its uploads in progress
    std::map<std::string, InProgress> by_session_; // session scope -> its uploads in progress
};

} // namespace ddsimp::server
