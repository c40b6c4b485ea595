// The work behind a Request, run on the compute pool: one progressive record per (surface, α,
// options), cached under its content key, and every level cut from it and encoded (cached too).
#pragma once

#include "result_cache.h"
#include "surface_store.h"

#include "ddsimp/ddsimp.h"
#include "ddsimp/protocol/mesh_codec.h"

#include <memory>
#include <string>
#include <vector>

namespace ddsimp::server {

// Bumped whenever the library's output for the same input and options may change, so cached
// keys from another version never match.
inline constexpr const char* kAlgorithmVersion = "ddsimp-0.1.0/1";

struct ReductionParams {
    std::string surface;
    float alpha = 0.5f;
    Strategy strategy = Strategy::EdgeCollapse;
    Placement placement = Placement::Midpoint;
    std::vector<std::string> gradient_fields;
    float feature_angle = 0; // 0: off

    Options options() const; // the library's options (keep_fraction 0: record every operation)
};

// hex SHA-256 of the surface id, α, options and algorithm version.
std::string result_key(const ReductionParams& params);

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

// The triangle count a keep fraction asks for, as `ddsimp simplify --keep` counts it.
size_t target_triangles(const ProgressiveRecord& record, double keep);

class Reductions {
public:
    Reductions(const SurfaceStore& store, ResultCache& cache) : store_(store), cache_(cache) {}

    // Throws std::invalid_argument for an unknown surface or field, InputError from the library.
    std::shared_ptr<const ComputedRecord> record(const ReductionParams& params,
                                                 const std::string& key, bool* computed);
    std::shared_ptr<const EncodedLevel> level(const ComputedRecord& record, const std::string& key,
                                              double keep, v1::Encoding encoding);

private:
    const SurfaceStore& store_;
    ResultCache& cache_;
};

} // namespace ddsimp::server
