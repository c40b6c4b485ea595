// The work behind a Request, run on the compute pool: one progressive record per (surface, α,
// options), cached under its content key, and every level cut from it and encoded (cached too).
#pragma once

#include "metrics.h"
#include "result_cache.h"
#include "surface_store.h"

#include "ddsimp/ddsimp.h"
#include "ddsimp/protocol/mesh_codec.h"

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace ddsimp::server {

// What a result is computed from: a stored surface and the library's options (see
// protocol/reduction_options.h for how a request becomes them and for the result key).
struct ReductionParams {
    std::string surface;
    Options options; // keep_fraction 0: record every operation
};

struct ComputedRecord {
    ReductionParams params;
    ProgressiveRecord record;
    double seconds = 0;
    size_t bytes() const;
};

struct EncodedLevel {
    protocol::EncodedBlob blob;
    size_t triangles = 0;
    bool target_reached = false;
    size_t operations = 0; // of the record, to this level
};

// The error of the level after `operations` operations of `record`, as MeshBegin carries it.
void set_level_error(v1::LevelError& out, const ProgressiveRecord& record, size_t operations);

// A computation stopped by its cancel flag (computations.h); nothing is cached.
class Cancelled : public std::runtime_error {
public:
    Cancelled() : std::runtime_error("cancelled") {}
};

class Reductions {
public:
    // `cores`: the engine's threads shared among the runs in progress when a run starts (a run
    // alone takes them all; the bytes are the same for any thread count).
    Reductions(SurfaceStore& store, ResultCache& cache, Metrics& metrics, int cores)
        : store_(store), cache_(cache), metrics_(metrics), cores_(cores) {}

    // A record of `params` that holds every level down to `depth` triangles: cached, or run now
    // to that depth (and no further: a level is ready as soon as the run has passed it).
    // Another caller's run of the same key and depth is waited for. Throws
    // std::invalid_argument for an unknown surface or field, InputError from the library,
    // Cancelled when `cancelled` (or, for a run this call waited for, its own flag) stopped it,
    // or `yield` (its worker is wanted for another client's job; counted apart). With `held`, a
    // run takes the surface from there if an earlier run of the same job loaded it, and leaves
    // the surface it loads there: a job that yielded finishes with its surface even if the
    // surface was deleted meanwhile.
    std::shared_ptr<const ComputedRecord> record(const ReductionParams& params,
                                                 const std::string& key, size_t depth,
                                                 const std::atomic<bool>& cancelled, bool* computed,
                                                 const std::atomic<bool>* yield = nullptr,
                                                 std::shared_ptr<const Surface>* held = nullptr);
    // A cached record of `key` that reaches `depth` triangles, or null (no computation).
    std::shared_ptr<const ComputedRecord> cached_record(const std::string& key, size_t depth);
    // The level of `record` for `keep`, encoded: cached, or cut and fitted now. Throws Cancelled
    // when `cancelled` (the computation's flag: nobody waits for it any more) stops the fit.
    std::shared_ptr<const EncodedLevel> level(const ComputedRecord& record, const std::string& key,
                                              float keep, v1::Encoding encoding,
                                              const std::atomic<bool>* cancelled = nullptr);

    // Drops the cached records and levels of a deleted surface. A run in progress on it still
    // caches its record when it ends; that entry goes in its turn, least recently used.
    void forget_surface(const std::string& surface);

private:
    SurfaceStore& store_;
    ResultCache& cache_;
    Metrics& metrics_;
    const int cores_;
    // Per key, the runs made: the depth each reaches (0: as far as the surface allows) -> the
    // depth it was run to, to find a cached record deep enough.
    std::mutex depths_mutex_;
    std::map<std::string, std::map<size_t, size_t>> depths_;
    std::map<std::string, std::set<std::string>> keys_of_surface_; // surface -> result keys run
};

// Reductions::record, computing the record for this caller if another caller's run of the same
// key was cancelled under it; throws Cancelled only when `cancelled` or `yield` is set.
std::shared_ptr<const ComputedRecord> record_for(Reductions& reductions,
                                                 const ReductionParams& params,
                                                 const std::string& key, size_t depth,
                                                 const std::atomic<bool>& cancelled, bool* computed,
                                                 const std::atomic<bool>* yield = nullptr,
                                                 std::shared_ptr<const Surface>* held = nullptr);

} // namespace ddsimp::server
