#include "reductions.h"

#include "ddsimp/protocol/reduction_options.h"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace ddsimp::server {

size_t ComputedRecord::bytes() const {
    const Surface& v = record.vertices();
    size_t b = 4 * (v.positions.size() + v.triangles.size());
    for (const Field& f : v.fields) b += 4 * f.values.size();
    // per operation: its triangle count, its collapse or writes, its level error
    return b + 24 * record.triangles_in() + 32 * record.operations() + sizeof(*this);
}

void set_level_error(v1::LevelError& out, const ProgressiveRecord& record, size_t operations) {
    const LevelError e = record.error_after(operations);
    out.set_geometric(e.geometric);
    out.set_data(e.data);
    out.set_data_components(uint32_t(e.data_components));
}

namespace {

std::string record_key(const std::string& key, size_t depth) {
    return "record/" + key + "/" + std::to_string(depth);
}

} // namespace

std::shared_ptr<const ComputedRecord> Reductions::cached_record(const std::string& key,
                                                                size_t depth) {
    std::lock_guard lock(depths_mutex_);
    auto it = depths_.find(key);
    if (it == depths_.end()) return nullptr;
    for (auto d = it->second.begin(); d != it->second.end() && d->first <= depth;) {
        if (auto found = cache_.find<ComputedRecord>(record_key(key, d->second))) return found;
        d = it->second.erase(d); // evicted
    }
    return nullptr;
}

std::shared_ptr<const ComputedRecord>
Reductions::record(const ReductionParams& params, const std::string& key, size_t depth,
                   const std::atomic<bool>& cancelled, bool* computed,
                   const std::atomic<bool>* yield, std::shared_ptr<const Surface>* held) {
    if (computed) *computed = false;
    if (auto found = cached_record(key, depth)) return found;
    auto out = cache_.get<ComputedRecord>(
        record_key(key, depth),
        [&] {
            std::shared_ptr<const Surface> surface =
                held && *held ? *held : store_.load(params.surface);
            if (!surface) throw std::invalid_argument("no surface " + params.surface);
            if (held) *held = surface;
            for (const std::string& f : params.options.gradient_fields)
                if (!surface->find_field(f))
                    throw std::invalid_argument("the surface has no field \"" + f + "\"");
            Options options = params.options;
            options.keep_fraction = 0;
            options.target_triangles = depth;
            options.progress = [&cancelled, yield](double) {
                return !cancelled.load() && !(yield && yield->load());
            };
            // A run's working memory (about 250 bytes a triangle) goes back to the system when
            // it ends; the allocator would keep it, and the server's memory at rest would grow.
            // Not under AddressSanitizer or ThreadSanitizer (GCC's macros, as in parallel.h):
            // their allocator holds the memory, and glibc's malloc_trim from threads then reads
            // an arena that was never set up and crashes (google/sanitizers#1721).
            struct TrimAfterTheRun {
                ~TrimAfterTheRun() {
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
                    malloc_trim(0);
#endif
                }
            } trim_after_the_run;
            const auto start = std::chrono::steady_clock::now();
            // The cores shared with the runs in progress: a run alone uses them all.
            const int64_t runs = ++metrics_.reductions_running;
            options.threads = std::max(1, cores_ / int(std::max<int64_t>(1, runs)));
            std::optional<ProgressiveRecord> record;
            try {
                record.emplace(ProgressiveRecord::build(*surface, options));
            } catch (...) {
                --metrics_.reductions_running;
                throw;
            }
            // Counted cancelled before it stops counting as running: whoever sees it stop sees why.
            if (record->stop() == StopReason::Cancelled) {
                ++(cancelled.load() ? metrics_.reductions_cancelled : metrics_.reductions_yielded);
                --metrics_.reductions_running;
                throw Cancelled();
            }
            --metrics_.reductions_running;
            auto out =
                std::make_shared<ComputedRecord>(ComputedRecord{params, std::move(*record), 0});
            out->seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const size_t bytes = out->bytes();
            return std::pair<std::shared_ptr<const ComputedRecord>, size_t>{std::move(out), bytes};
        },
        computed);
    std::lock_guard lock(depths_mutex_);
    // A run that stopped before its target holds every level there is.
    depths_[key][out->record.stop() == StopReason::TargetReached ? depth : 0] = depth;
    keys_of_surface_[params.surface].insert(key);
    return out;
}

void Reductions::forget_surface(const std::string& surface) {
    std::set<std::string> keys;
    {
        std::lock_guard lock(depths_mutex_);
        auto it = keys_of_surface_.find(surface);
        if (it == keys_of_surface_.end()) return;
        keys = std::move(it->second);
        keys_of_surface_.erase(it);
        for (const std::string& key : keys) depths_.erase(key);
    }
    for (const std::string& key : keys) {
        cache_.erase_prefix("record/" + key + "/");
        cache_.erase_prefix("level/" + key + "/");
    }
}

std::shared_ptr<const EncodedLevel> Reductions::level(const ComputedRecord& computed,
                                                      const std::string& key, float keep,
                                                      v1::Encoding encoding,
                                                      const std::atomic<bool>* cancelled) {
    const size_t target = protocol::target_for_keep(keep, computed.record.triangles_in());
    return cache_.get<EncodedLevel>(
        "level/" + key + "/" + std::to_string(target) + "/" + std::to_string(int(encoding)), [&] {
            const size_t operations = computed.record.operations_for(target);
            std::function<bool(double)> progress;
            if (cancelled) progress = [cancelled](double) { return !cancelled->load(); };
            const std::optional<Surface> fitted = computed.record.after(operations, progress);
            if (!fitted) {
                ++metrics_.reductions_cancelled;
                throw Cancelled();
            }
            const Surface& s = *fitted;
            auto out = std::make_shared<EncodedLevel>(
                EncodedLevel{protocol::encode_mesh(s, encoding), s.triangle_count(),
                             s.triangle_count() <= target, operations});
            const size_t bytes = out->blob.bytes.size() + sizeof(EncodedLevel);
            return std::pair<std::shared_ptr<const EncodedLevel>, size_t>{std::move(out), bytes};
        });
}

std::shared_ptr<const ComputedRecord>
record_for(Reductions& reductions, const ReductionParams& params, const std::string& key,
           size_t depth, const std::atomic<bool>& cancelled, bool* computed,
           const std::atomic<bool>* yield, std::shared_ptr<const Surface>* held) {
    for (;;) {
        try {
            return reductions.record(params, key, depth, cancelled, computed, yield, held);
        } catch (const Cancelled&) {
            if (cancelled.load() || (yield && yield->load())) throw;
        }
    }
}

} // namespace ddsimp::server
