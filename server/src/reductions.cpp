#include "reductions.h"

#include "ddsimp/protocol/content_hash.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace ddsimp::server {

Options ReductionParams::options() const {
    Options o;
    o.alpha = alpha;
    o.strategy = strategy;
    o.placement = placement;
    o.gradient_fields = gradient_fields;
    o.feature_angle = feature_angle > 0 ? feature_angle : 180.0;
    o.keep_fraction = 0;
    return o;
}

std::string result_key(const ReductionParams& p) {
    char numbers[96];
    std::snprintf(numbers, sizeof numbers, "%.9g|%d|%d|%.9g", double(p.alpha), int(p.strategy),
                  int(p.placement), double(p.feature_angle));
    // The library's own version too: its output for the same options changes with it.
    std::string text = std::string(kAlgorithmVersion) + "/" + std::to_string(algorithm_version) +
                       "|" + p.surface + "|" + numbers;
    for (const std::string& f : p.gradient_fields) text += '\0' + f;
    return protocol::sha256_hex(text);
}

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

size_t target_triangles(const ProgressiveRecord& record, double keep) {
    return size_t(std::floor(keep * double(record.triangles_in()) + 1e-9));
}

std::shared_ptr<const ComputedRecord> Reductions::record(const ReductionParams& params,
                                                         const std::string& key, bool* computed) {
    return cache_.get<ComputedRecord>(
        "record/" + key,
        [&] {
            std::shared_ptr<const Surface> surface = store_.load(params.surface);
            if (!surface) throw std::invalid_argument("no surface " + params.surface);
            for (const std::string& f : params.gradient_fields)
                if (!surface->find_field(f))
                    throw std::invalid_argument("the surface has no field \"" + f + "\"");
            const auto start = std::chrono::steady_clock::now();
            auto out = std::make_shared<ComputedRecord>(
                ComputedRecord{params, ProgressiveRecord::build(*surface, params.options()), 0});
            out->seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const size_t bytes = out->bytes();
            return std::pair<std::shared_ptr<const ComputedRecord>, size_t>{std::move(out), bytes};
        },
        computed);
}

std::shared_ptr<const EncodedLevel> Reductions::level(const ComputedRecord& computed,
                                                      const std::string& key, double keep,
                                                      v1::Encoding encoding) {
    const size_t target = target_triangles(computed.record, keep);
    return cache_.get<EncodedLevel>(
        "level/" + key + "/" + std::to_string(target) + "/" + std::to_string(int(encoding)), [&] {
            const size_t operations = computed.record.operations_for(target);
            const Surface s = computed.record.after(operations);
            auto out = std::make_shared<EncodedLevel>(
                EncodedLevel{protocol::encode_mesh(s, encoding), s.triangle_count(),
                             s.triangle_count() <= target, operations});
            const size_t bytes = out->blob.bytes.size() + sizeof(EncodedLevel);
            return std::pair<std::shared_ptr<const EncodedLevel>, size_t>{std::move(out), bytes};
        });
}

} // namespace ddsimp::server
