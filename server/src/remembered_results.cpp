#include "remembered_results.h"

namespace ddsimp::server {

// The key three times (map, use list, surface index), the parameters and the nodes of the three
// containers.
size_t RememberedResults::bytes_of(const std::string& key, const ReductionParams& params) {
    constexpr size_t kNodes = 3 * 48;
    size_t b = sizeof(Entry) + kNodes + 3 * (sizeof(std::string) + key.capacity()) +
               params.surface.capacity();
    for (const std::string& f : params.options.gradient_fields) b += sizeof(f) + f.capacity();
    return b;
}

void RememberedResults::remember(const std::string& key, const ReductionParams& params) {
    if (auto it = entries_.find(key); it != entries_.end()) {
        uses_.splice(uses_.begin(), uses_, it->second.use);
        return;
    }
    const size_t bytes = bytes_of(key, params);
    if (bytes > max_bytes_) return;
    uses_.push_front(key);
    Entry& e = entries_[key];
    e.params = params;
    e.params.options.progress = nullptr;
    e.bytes = bytes;
    e.use = uses_.begin();
    by_surface_[params.surface].insert(key);
    bytes_ += bytes;
    while (bytes_ > max_bytes_) forget_oldest();
}

const ReductionParams* RememberedResults::find(const std::string& key) {
    auto it = entries_.find(key);
    if (it == entries_.end()) return nullptr;
    uses_.splice(uses_.begin(), uses_, it->second.use);
    return &it->second.params;
}

void RememberedResults::for_surface(
    const std::string& surface,
    const std::function<void(const std::string&, const ReductionParams&)>& f) const {
    auto keys = by_surface_.find(surface);
    if (keys == by_surface_.end()) return;
    for (const std::string& key : keys->second) f(key, entries_.at(key).params);
}

void RememberedResults::forget_surface(const std::string& surface) {
    auto keys = by_surface_.find(surface);
    if (keys == by_surface_.end()) return;
    for (const std::string& key : std::set<std::string>(keys->second)) forget(entries_.find(key));
}

void RememberedResults::forget_oldest() {
    forget(entries_.find(uses_.back()));
}

void RememberedResults::forget(std::map<std::string, Entry>::iterator it) {
    uses_.erase(it->second.use);
    auto keys = by_surface_.find(it->second.params.surface);
    keys->second.erase(it->first);
    if (keys->second.empty()) by_surface_.erase(keys);
    bytes_ -= it->second.bytes;
    entries_.erase(it);
}

} // namespace ddsimp::server
