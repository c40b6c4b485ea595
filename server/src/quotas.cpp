#include "quotas.h"

#include <fmt/format.h>

namespace ddsimp::server {
namespace {

std::string mib(uint64_t bytes) {
    return fmt::format("{:.1f} MiB", double(bytes) / double(1 << 20));
}

// An owner's uploads in progress (none when it has none).
Quotas::InProgress running(const std::map<std::string, Quotas::InProgress>& by,
                           const std::string& key) {
    auto it = by.find(key);
    return it == by.end() ? Quotas::InProgress{} : it->second;
}

} // namespace

Quotas::Quotas(const Config& config, const SurfaceStore& store, Metrics& metrics)
    : config_(config), store_(store), metrics_(metrics) {}

std::optional<std::string> Quotas::over(const std::string& who, const SurfaceStore::Usage& stored,
                                        const InProgress& running, uint64_t bytes,
                                        std::string& stored_quota) const {
    const uint64_t upload_quota = uint64_t(config_.quota_upload_mb) << 20;
    const uint64_t bytes_quota = uint64_t(config_.quota_surfaces_mb) << 20;
    if (running.bytes + bytes > upload_quota)
        return fmt::format("{} has {} of uploads in progress; this one's {} would pass its quota "
                           "of {} (--quota-upload-mb): finish those first",
                           who, mib(running.bytes), mib(bytes), mib(upload_quota));
    if (!stored_quota.empty()) return std::nullopt;
    if (stored.surfaces + running.uploads + 1 > config_.quota_surfaces)
        stored_quota =
            fmt::format("{} has {} stored surfaces and {} uploads in progress, its quota is {} "
                        "(--quota-surfaces)",
                        who, stored.surfaces, running.uploads, config_.quota_surfaces);
    else if (stored.bytes + running.bytes + bytes > bytes_quota)
        stored_quota =
            fmt::format("{} has {} of stored surfaces and {} of uploads in progress; this "
                        "one's {} would pass its quota of {} (--quota-surfaces-mb)",
                        who, mib(stored.bytes), mib(running.bytes), mib(bytes), mib(bytes_quota));
    return std::nullopt;
}

std::optional<std::string> Quotas::reserve(UploadOwner& owner, uint64_t bytes) {
    const uint64_t budget = uint64_t(config_.max_upload_mb) << 20;
    std::optional<std::string> why;
    if (bytes > budget - reserved_)
        why = fmt::format("{} bytes do not fit in the server's {} MiB for uploads in progress; "
                          "try again later",
                          bytes, config_.max_upload_mb);
    if (!why && !owner.token.empty())
        why = over("your token", store_.usage_of_token(owner.token),
                   running(by_token_, owner.token), bytes, owner.over_quota);
    if (!why && !owner.session_scope.empty())
        why = over("session \"" + owner.session + "\"", store_.usage_of_scope(owner.session_scope),
                   running(by_session_, owner.session_scope), bytes, owner.over_quota);
    if (why) {
        ++metrics_.quota_refusals;
        return why;
    }
    reserved_ += bytes;
    metrics_.upload_bytes = int64_t(reserved_);
    for (InProgress* p :
         {owner.token.empty() ? nullptr : &by_token_[owner.token],
          owner.session_scope.empty() ? nullptr : &by_session_[owner.session_scope]})
        if (p) ++p->uploads, p->bytes += bytes;
    return std::nullopt;
}

void Quotas::release(const UploadOwner& owner, uint64_t bytes) {
    reserved_ -= std::min(bytes, reserved_);
    metrics_.upload_bytes = int64_t(reserved_);
    const auto give_back = [&](std::map<std::string, InProgress>& by, const std::string& key) {
        auto it = by.find(key);
        if (it == by.end()) return;
        it->second.uploads -= std::min<size_t>(1, it->second.uploads);
        it->second.bytes -= std::min(bytes, it->second.bytes);
        if (it->second.uploads == 0) by.erase(it);
    };
    if (!owner.token.empty()) give_back(by_token_, owner.token);
    if (!owner.session_scope.empty()) give_back(by_session_, owner.session_scope);
}

} // namespace ddsimp::server
