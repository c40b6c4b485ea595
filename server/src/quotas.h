// What one token and one session may hold: stored surfaces (count and bytes) and uploads in
// progress (bytes), each within the configured quota, and all uploads in progress together within
// --max-upload-mb. An upload is charged to its client's token (none on a server without tokens)
// and to the session it goes into (none for a public upload) from its UploadBegin until it is
// stored, refused or expired. Uploads in progress are refused on UploadBegin; an upload that would
// pass a quota of stored surfaces is received and refused once its bytes are known, unless they
// are a surface already stored where it goes (which charges nobody again). Network thread only.
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
    // Why storing it would pass a quota of stored surfaces (set by Quotas::reserve); empty: it
    // fits. Such an upload is stored only if it is already stored where it goes.
    std::string over_quota;
};

class Quotas {
public:
    Quotas(const Config& config, const SurfaceStore& store, Metrics& metrics);

    // Reserves `bytes` of uploads in progress for `owner`: nothing, or why not (for the client).
    // Sets owner.over_quota when the stored surfaces' quotas would be passed.
    std::optional<std::string> reserve(UploadOwner& owner, uint64_t bytes);
    void release(const UploadOwner& owner, uint64_t bytes);

    struct InProgress {
        size_t uploads = 0;
        uint64_t bytes = 0;
    };

private:
    // Why one owner (`who`: "your token", "session \"S\"") may not have `bytes` more in
    // progress, and (`stored_quota`) why it may not store them.
    std::optional<std::string> over(const std::string& who, const SurfaceStore::Usage& stored,
                                    const InProgress& running, uint64_t bytes,
                                    std::string& stored_quota) const;

    const Config& config_;
    const SurfaceStore& store_;
    Metrics& metrics_;
    uint64_t reserved_ = 0;                        // all uploads in progress
    std::map<std::string, InProgress> by_token_;   // token name -> its uploads in progress
    std::map<std::string, InProgress> by_session_; // session scope -> its uploads in progress
};

} // namespace ddsimp::server
