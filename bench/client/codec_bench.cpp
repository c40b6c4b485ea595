// ddsimp_bench_codec: does meshoptimizer's codec pay for the levels the server streams? For real
// levels of one real surface: blob bytes raw vs meshopt, and the time to encode (once per level:
// the server caches encoded levels) and to decode (once per client), as medians of several runs.
// The break-even bandwidth is where the bytes saved take as long to send as the codec costs:
// below it, meshopt makes a level arrive sooner.
//
//   ddsimp_bench_codec [SURFACE] [RUNS]     (default bench/data/carotid-1m.vtp, 7 runs)
#include "ddsimp/io/surface_io.h" // io/, from the ddsimp_io target

#include "ddsimp/ddsimp.h"
#include "ddsimp/protocol/mesh_codec.h"
#include "ddsimp/protocol/refinement.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#ifndef DDSIMP_BENCH_DEFAULT_SURFACE
#define DDSIMP_BENCH_DEFAULT_SURFACE "bench/data/carotid-1m.vtp"
#endif

namespace {

using namespace ddsimp;
using Clock = std::chrono::steady_clock;

double median_seconds(int runs, const std::function<void()>& work) {
    std::vector<double> t;
    for (int i = 0; i < runs; ++i) {
        const auto start = Clock::now();
        work();
        t.push_back(std::chrono::duration<double>(Clock::now() - start).count());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

struct Measured {
    size_t bytes = 0;
    double encode = 0, decode = 0;
};

template <class Encode, class Decode> Measured measure(int runs, Encode encode, Decode decode) {
    Measured m;
    protocol::EncodedBlob blob;
    m.encode = median_seconds(runs, [&] { blob = encode(); });
    m.bytes = blob.bytes.size();
    m.decode = median_seconds(runs, [&] { decode(blob); });
    return m;
}

void report(const char* what, size_t triangles, const Measured& raw, const Measured& mo) {
    const double saved = double(raw.bytes) - double(mo.bytes);
    const double extra = (mo.encode + mo.decode) - (raw.encode + raw.decode);
    // bits per second at which sending `saved` bytes takes as long as the codec's extra time
    const double break_even = extra > 0 ? 8 * saved / extra / 1e6 : INFINITY;
    // A cached level is encoded once and decoded by every client: only decoding counts then.
    const double decode_extra = mo.decode - raw.decode;
    const double cached = decode_extra > 0 ? 8 * saved / decode_extra / 1e6 : INFINITY;
    std::printf("| %s | %zu | %.2f | %.2f | %.2f | %.1f / %.1f | %.1f / %.1f | %.0f | %.0f |\n",
                what, triangles, raw.bytes / 1e6, mo.bytes / 1e6, double(raw.bytes) / mo.bytes,
                raw.encode * 1e3, mo.encode * 1e3, raw.decode * 1e3, mo.decode * 1e3, break_even,
                cached);
}

} // namespace

int main(int argc, char** argv) {
    const std::string path = argc > 1 ? argv[1] : DDSIMP_BENCH_DEFAULT_SURFACE;
    const int runs = argc > 2 ? std::atoi(argv[2]) : 7;
    try {
        const Surface input = io::read_surface(path);
        Options o;
        o.alpha = 0.5;
        o.keep_fraction = 0;
        const auto start = Clock::now();
        const ProgressiveRecord rec = ProgressiveRecord::build(input, o);
        std::printf("%s: %zu triangles, %zu fields; progressive record in %.1f s; median of %d "
                    "runs\n\n",
                    path.c_str(), input.triangle_count(), input.fields.size(),
                    std::chrono::duration<double>(Clock::now() - start).count(), runs);
        std::printf("| blob | triangles | raw MB | meshopt MB | ratio | encode ms raw / meshopt "
                    "| decode ms raw / meshopt | break-even Mbit/s | cached: break-even Mbit/s |\n"
                    "|---|---|---|---|---|---|---|---|---|\n");
        const std::vector<double> keeps{1.0, 0.1, 0.01};
        for (double keep : keeps) {
            const size_t target = size_t(keep * double(rec.triangles_in()));
            const Surface level = rec.level(target);
            auto run = [&](v1::Encoding e) {
                return measure(
                    runs, [&] { return protocol::encode_mesh(level, e); },
                    [&](const protocol::EncodedBlob& b) {
                        protocol::decode_mesh(b.bytes, b.layout);
                    });
            };
            char what[64];
            std::snprintf(what, sizeof what, "level keep %g", keep);
            report(what, level.triangle_count(), run(v1::RAW), run(v1::MESHOPT));
        }
        // Progressive: the refinement from the 1% level to the 10% level.
        protocol::RefinementStream stream(rec.vertices());
        stream.base(rec.indexed_triangles(rec.operations_for(rec.triangles_in() / 100)));
        const protocol::Refinement r =
            stream.refine(rec.indexed_triangles(rec.operations_for(rec.triangles_in() / 10)));
        auto run = [&](v1::Encoding e) {
            return measure(
                runs, [&] { return protocol::encode_refinement(r, e); },
                [&](const protocol::EncodedBlob& b) {
                    protocol::decode_refinement(b.bytes, b.layout);
                });
        };
        report("refinement 1% -> 10%", r.writes.size() / 4, run(v1::RAW), run(v1::MESHOPT));
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ddsimp_bench_codec: %s\n", e.what());
        return 1;
    }
}
