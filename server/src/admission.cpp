#include "admission.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <sys/resource.h>

namespace ddsimp::server {

ConnectionSlot::ConnectionSlot(std::shared_ptr<AdmissionState> state,
                               boost::asio::ip::address address)
    : state_(std::move(state)), address_(std::move(address)) {}

ConnectionSlot::~ConnectionSlot() {
    std::lock_guard lock(state_->mutex);
    auto it = state_->per_address.find(address_);
    if (it != state_->per_address.end() && --it->second == 0) state_->per_address.erase(it);
    --state_->held;
    if (state_->metrics) state_->metrics->sockets = int64_t(state_->held);
}

ConnectionLimits fit_descriptor_limit(const Config& config) {
    ConnectionLimits out{config.max_clients, config.max_clients_per_address, 0};
    rlimit limit{};
    if (::getrlimit(RLIMIT_NOFILE, &limit) != 0) return out;
    if (limit.rlim_cur < limit.rlim_max) {
        rlimit raised = limit;
        raised.rlim_cur = limit.rlim_max;
        if (::setrlimit(RLIMIT_NOFILE, &raised) == 0) limit = raised;
    }
    out.descriptors = limit.rlim_cur == RLIM_INFINITY ? SIZE_MAX : size_t(limit.rlim_cur);
    const size_t room =
        out.descriptors > config.fd_reserve ? out.descriptors - config.fd_reserve : 0;
    if (out.total > room) {
        spdlog::warn("--max-clients {} lowered to {}: {} descriptors (ulimit -n), {} kept for the "
                     "server's own files (--fd-reserve)",
                     out.total, room, out.descriptors, config.fd_reserve);
        out.total = room;
    }
    out.per_address = std::min(out.per_address, out.total);
    return out;
}

Admission::Admission(ConnectionLimits limits, Metrics& metrics)
    : limits_(limits), metrics_(metrics), state_(std::make_shared<AdmissionState>()) {
    state_->metrics = &metrics_;
    metrics_.sockets_limit = int64_t(limits_.total);
    metrics_.sockets_per_address_limit = int64_t(limits_.per_address);
}

Admission::~Admission() {
    std::lock_guard lock(state_->mutex);
    state_->metrics = nullptr;
}

size_t Admission::held() const {
    std::lock_guard lock(state_->mutex);
    return state_->held;
}

Slot Admission::admit(const boost::asio::ip::address& address, std::string& why) {
    std::lock_guard lock(state_->mutex);
    if (state_->held >= limits_.total) {
        why = "the server has its maximum of " + std::to_string(limits_.total) + " clients";
        ++metrics_.connections_refused;
        return nullptr;
    }
    auto from = state_->per_address.find(address);
    if (from != state_->per_address.end() && from->second >= limits_.per_address) {
        why = "the server has its maximum of " + std::to_string(limits_.per_address) +
              " clients from one address";
        ++metrics_.connections_refused;
        return nullptr;
    }
    ++state_->per_address[address];
    ++state_->held;
    metrics_.sockets = int64_t(state_->held);
    return std::make_shared<ConnectionSlot>(state_, address);
}

} // namespace ddsimp::server
