// ddsimp_bench: time to reduce one real surface to 10% of its triangles for meshoptimizer's
// meshopt_simplify (geometry only, one thread: the baseline) and both ddsimp strategies, each on
// 1, 2, 4, 8 and 16 threads (the argument `threads`); and vertex removal to 0.1%, the coarse end
// of a record, where each level vertex stands for a thousand input vertices.
//
//   ddsimp_bench [--surface=PATH | PATH] [Google Benchmark flags]
//
// The surface comes from --surface, else $DDSIMP_BENCH_SURFACE, else bench/data/carotid-1m.vtp
// (made by bench/make-data.sh). It is loaded once, before any timing. Each benchmark reports the
// triangles it actually reached as counters, ddsimp's also the longest stretch without a progress
// call (longest_silence_s); a ddsimp failure (an exception) marks the benchmark as errored and
// makes the program exit with status 1.
#include "ddsimp/io/surface_io.h" // io/, from the ddsimp_io target

#include <ddsimp/ddsimp.h>

#include "pass_counts.h" // the engine's, from simplify/src

#include <benchmark/benchmark.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#ifndef DDSIMP_BENCH_DEFAULT_SURFACE
#define DDSIMP_BENCH_DEFAULT_SURFACE "bench/data/carotid-1m.vtp"
#endif

namespace {

constexpr double kKeepFraction = 0.1; // reduce to 10% of the input's triangles
constexpr double kAlpha = 0.5;

ddsimp::Surface g_surface; // loaded once in main, never modified
bool g_failed = false;     // a benchmark reported an error

// The same triangle target for every simplifier: at most 10% of the input's triangles.
size_t target_triangles(double keep = kKeepFraction) {
    return static_cast<size_t>(static_cast<double>(g_surface.triangle_count()) * keep);
}

void report_triangles(benchmark::State& state, size_t in, size_t out, double keep = kKeepFraction) {
    state.counters["triangles_in"] = static_cast<double>(in);
    state.counters["target"] = static_cast<double>(target_triangles(keep));
    state.counters["triangles_out"] = static_cast<double>(out);
    state.counters["reached_fraction"] =
        in ? static_cast<double>(out) / static_cast<double>(in) : 0;
}

// meshoptimizer 0.18: meshopt_simplify(destination, indices, index_count, vertex_positions,
// vertex_count, vertex_positions_stride, target_index_count, target_error, options, result_error).
// target_error is relative to the mesh extents (1 = 100%); FLT_MAX makes sure the error bound is
// never what stops it, so only the target (or its own topology rules) can.
void BM_meshopt_simplify(benchmark::State& state) {
    const ddsimp::Surface& s = g_surface;
    const size_t index_count = s.triangles.size();
    const size_t target_index_count = target_triangles() * 3;
    std::vector<unsigned int> destination(index_count); // worst case is index_count
    size_t result_index_count = 0;
    float result_error = 0;
    for (auto _ : state) {
        result_index_count = meshopt_simplify(
            destination.data(), s.triangles.data(), index_count, s.positions.data(),
            s.vertex_count(), 3 * sizeof(float), target_index_count, FLT_MAX, 0, &result_error);
        benchmark::DoNotOptimize(destination.data());
        benchmark::ClobberMemory();
    }
    report_triangles(state, s.triangle_count(), result_index_count / 3);
    state.counters["result_error"] = result_error;
}

void BM_ddsimp(benchmark::State& state, ddsimp::Strategy strategy,
               ddsimp::Placement placement = ddsimp::Placement::Midpoint,
               double keep = kKeepFraction) {
    ddsimp::Options options;
    options.alpha = kAlpha;
    options.strategy = strategy;
    options.placement = placement;
    options.target_triangles = target_triangles(keep);
    options.threads = int(state.range(0));
    // The longest stretch without a progress call (from the start, between calls, to the end):
    // how long a cancel may wait, as a user's progress bar or the server sees it.
    using Clock = std::chrono::steady_clock;
    Clock::time_point last;
    double longest_silence = 0;
    auto silence_until = [&](Clock::time_point now) {
        longest_silence =
            std::max(longest_silence, std::chrono::duration<double>(now - last).count());
        last = now;
    };
    options.progress = [&](double) {
        silence_until(Clock::now());
        return true;
    };
    size_t in = 0, out = 0, operations = 0;
    bool reached = false;
    ddsimp::detail::PassCounts& passes = ddsimp::detail::pass_counts();
    for (auto _ : state) {
        try {
            passes.reset(); // the last run's
            last = Clock::now();
            ddsimp::Result result = ddsimp::simplify(g_surface, options);
            silence_until(Clock::now());
            in = result.triangles_in;
            out = result.triangles_out;
            operations = result.operations;
            reached = result.target_reached;
            benchmark::DoNotOptimize(result.surface.triangles.data());
        } catch (const std::exception& e) {
            g_failed = true;
            state.SkipWithError(e.what());
            break;
        }
    }
    if (state.error_occurred()) return;
    report_triangles(state, in, out, keep);
    state.counters["operations"] = static_cast<double>(operations);
    state.counters["target_reached"] = reached ? 1 : 0;
    state.counters["longest_silence_s"] = longest_silence;
    // How the passes went: a check that waits or is refused, and a visit of the walk that selects
    // nothing, is work that removes nothing.
    auto per_operation = [&](const std::atomic<size_t>& count) {
        return operations > 0 ? double(count.load()) / double(operations) : 0.0;
    };
    state.counters["passes"] = double(passes.passes.load());
    state.counters["walked_per_op"] = per_operation(passes.walked);
    state.counters["waited_per_op"] = per_operation(passes.waited);
    state.counters["refused_per_op"] = per_operation(passes.refused);
}

void BM_ddsimp_edge_collapse(benchmark::State& state) {
    BM_ddsimp(state, ddsimp::Strategy::EdgeCollapse);
}
// The library's and the command line's default placement: the least-error point, which may
// leave the edge sideways (a solve per key).
void BM_ddsimp_edge_collapse_least_error(benchmark::State& state) {
    BM_ddsimp(state, ddsimp::Strategy::EdgeCollapse, ddsimp::Placement::LeastError);
}
void BM_ddsimp_vertex_removal(benchmark::State& state) {
    BM_ddsimp(state, ddsimp::Strategy::VertexRemoval);
}
void BM_ddsimp_vertex_removal_coarse(benchmark::State& state) {
    BM_ddsimp(state, ddsimp::Strategy::VertexRemoval, ddsimp::Placement::Midpoint, 0.001);
}

// Wall time (a threaded run's CPU time is the sum over its threads), and the process CPU time as
// a counter. Seconds, since one run on a million triangles takes about one.
BENCHMARK(BM_meshopt_simplify)->Name("meshopt_simplify")->UseRealTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_ddsimp_edge_collapse)
    ->Name("ddsimp_EdgeCollapse")
    ->ArgName("threads")
    ->RangeMultiplier(2)
    ->Range(1, 16)
    ->UseRealTime()
    ->Unit(benchmark::kSecond);
BENCHMARK(BM_ddsimp_edge_collapse_least_error)
    ->Name("ddsimp_EdgeCollapse_LeastError")
    ->ArgName("threads")
    ->RangeMultiplier(2)
    ->Range(1, 16)
    ->UseRealTime()
    ->Unit(benchmark::kSecond);
BENCHMARK(BM_ddsimp_vertex_removal)
    ->Name("ddsimp_VertexRemoval")
    ->ArgName("threads")
    ->RangeMultiplier(2)
    ->Range(1, 16)
    ->UseRealTime()
    ->Unit(benchmark::kSecond);
BENCHMARK(BM_ddsimp_vertex_removal_coarse)
    ->Name("ddsimp_VertexRemoval_Keep0.001")
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kSecond);

// Takes --surface=PATH, --surface PATH or a lone PATH out of argv; returns "" if none.
std::string take_surface_argument(int& argc, char** argv) {
    std::string path;
    int kept = 1;
    for (int i = 1; i < argc; ++i) {
        const char* arg = argv[i];
        if (std::strncmp(arg, "--surface=", 10) == 0) {
            path = arg + 10;
        } else if (std::strcmp(arg, "--surface") == 0 && i + 1 < argc) {
            path = argv[++i];
        } else if (arg[0] != '-' && path.empty()) {
            path = arg;
        } else {
            argv[kept++] = argv[i];
        }
    }
    argc = kept;
    return path;
}

} // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv); // removes the flags it knows
    std::string path = take_surface_argument(argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
    if (path.empty()) {
        const char* env = std::getenv("DDSIMP_BENCH_SURFACE");
        path = env && *env ? env : DDSIMP_BENCH_DEFAULT_SURFACE;
    }

    try {
        g_surface = ddsimp::io::read_surface(path);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ddsimp_bench: cannot read %s: %s (make it with bench/make-data.sh)\n",
                     path.c_str(), e.what());
        return 2;
    }
    benchmark::AddCustomContext("surface", path);
    benchmark::AddCustomContext("surface_triangles", std::to_string(g_surface.triangle_count()));
    benchmark::AddCustomContext("surface_vertices", std::to_string(g_surface.vertex_count()));
    benchmark::AddCustomContext("meshoptimizer_version", std::to_string(MESHOPTIMIZER_VERSION));

    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return g_failed ? 1 : 0;
}
